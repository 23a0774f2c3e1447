"""The exceptions of :mod:`verify`, all derived from :class:`VerifyError`.

The command line turns :class:`InvalidInput` (and its subclasses) into one line on
stderr and exit code 2; :class:`Undecided` and :class:`NoConvergence` are reported
the same way, because they mean that the input cannot be decided at the requested
precision, not that the program is wrong.
"""

from __future__ import annotations

import importlib
from typing import Any


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


class MissingExtra(InvalidInput):
    """An optional dependency that a command needs is not installed (see :func:`require`)."""


#: the optional dependencies, each with the extra of ``verify-impacts`` that installs it
EXTRAS = {"matplotlib": "figures", "numpy": "fast", "flint": "fast", "gmpy2": "fast", "dask": "cluster"}


def require(module: str, purpose: str, extra: str | None = None) -> Any:
    """The module ``module`` imported, or :class:`MissingExtra` naming what needs it and the extra that
    installs it (``extra``, by default the one :data:`EXTRAS` gives).

    >>> require("math", "a test").sqrt(4)
    2.0
    >>> require("no_such_module", "drawing", "figures")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    verify.errors.MissingExtra: drawing: no_such_module is not installed: pip install ...
    """
    try:
        return importlib.import_module(module)
    except ImportError:
        extra = extra or EXTRAS[module]
        raise MissingExtra(
            f"{purpose}: {module} is not installed: pip install '.[{extra}]' in a clone of the repository "
            f"(pip install 'verify-impacts[{extra}]' from a package index)"
        ) from None


class Undecided(VerifyError, ArithmeticError):
    """A sign that the backend cannot decide (an interval that contains 0)."""


class NoConvergence(Undecided):
    """Raising the precision up to its limit still left a sign undecided."""
