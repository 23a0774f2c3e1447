"""The core: numbers, arithmetic backends, linear algebra, the system, the rule and its engines,
termination certificates. Imports nothing else of verify but :mod:`verify.errors`."""
