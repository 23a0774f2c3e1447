"""verify/oracle/: the reference oracle."""
