"""Numbers: parsing and printing exact values, the arithmetic backends (the one contract the rule is
written against), algebraic numbers and small exact linear algebra. Imports nothing of verify but
:mod:`verify.errors` and :mod:`verify.bounds`."""
