"""verify/dynamics/: the system's geometry, systems from functions, the rate form."""
