"""verify/properties/: the property suite."""
