"""verify/paper/: Table 1 and the corner's claims."""
