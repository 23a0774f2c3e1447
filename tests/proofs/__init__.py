"""verify/proofs/ and verify/bounds.py: cones, their linear programming, termination certificates, the bounds."""
