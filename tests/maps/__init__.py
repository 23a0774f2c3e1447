"""verify/maps/: the exact maps over one or two parameters."""
