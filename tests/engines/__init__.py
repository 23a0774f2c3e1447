"""verify/engines/: the physics engines' adapters, runs and explanations."""
