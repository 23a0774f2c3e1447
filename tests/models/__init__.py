"""verify/models/: Newton's cradle (the corner's tests are the paper's, tests/paper/)."""
