"""The paper's claims: Table 1, the cradle map, the corner claims, float against exact."""
