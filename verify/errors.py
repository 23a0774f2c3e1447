"""The exceptions of :mod:`verify`, all derived from :class:`VerifyError`.

The command line turns :class:`InvalidInput` (and its subclasses) into one line on
stderr and exit code 2; :class:`Undecided` and :class:`NoConvergence` are reported
the same way, because they mean that the input cannot be decided at the requested
precision, not that the program is wrong.
"""

from __future__ import annotations


class VerifyError(Exception):
    """Base class of every error raised on purpose by :mod:`verify`."""


class InvalidInput(VerifyError, ValueError):
    """Input that the rule cannot be applied to (raised before anything is computed)."""


class BadNumber(InvalidInput):
    """A number string that the restricted parser rejects (``"1/0"``, ``"__import__"``)."""


class InvalidSystem(InvalidInput):
    """A mechanical system that violates the paper's assumptions.

    For instance a mass matrix that is not symmetric positive definite, a coefficient
    of restitution outside [0, 1], dependent constraint normals, or vectors of the
    wrong length.
    """


class Undecided(VerifyError, ArithmeticError):
    """A sign that the backend cannot decide (an interval that contains 0)."""


class NoConvergence(Undecided):
    """Raising the precision up to its limit still left a sign undecided."""
