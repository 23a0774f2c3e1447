"""verify/records/: case records, their annotations and numbers."""
