"""The property suite: strategies, the printed formulas, the properties, SymPy proofs, verdicts."""
