"""Arithmetic backends: the one contract that the rule is written against.

The contract and the capabilities through which a backend says what it can do are
:class:`~verify.numbers.backends.base.Backend`'s. Backends here: ``exact`` (rationals, gmpy2
or python-flint when installed, pure-Python :class:`~fractions.Fraction` otherwise, same
results: :mod:`~verify.numbers.backends.rational`; a real number field for algebraic inputs:
:mod:`~verify.numbers.backends.field`), ``mp`` (mpmath at ``dps`` digits, heuristic signs) and
``interval`` (mpmath intervals, certified signs, precision raised automatically), both in
:mod:`~verify.numbers.backends.precision`, and ``float`` (fast, not rigorous:
:mod:`~verify.numbers.backends.floating`). The symbolic-parameter backend
(:mod:`verify.numbers.backends.symbolic`, imported from there: it loads SymPy) fits the same
contract: its elements support ``+ - * /`` and its ``sign`` decides exactly or raises.

>>> K = get_backend("exact")
>>> x = K.convert(Fraction(1, 3)) - K.convert(Fraction(1, 2))
>>> K.sign(x), K.to_decimal(x, 5), K.to_number(x)
(-1, '-0.16667', Fraction(-1, 6))
"""

from __future__ import annotations

import functools
import os
from collections.abc import Iterable
from fractions import Fraction

from verify.errors import BadNumber, InvalidInput
from verify.numbers.backends.base import Backend
from verify.numbers.backends.field import NumberFieldBackend, algebraic_generators
from verify.numbers.backends.floating import FloatBackend
from verify.numbers.backends.precision import DEFAULT_DPS, MAX_INTERVAL_DPS, MIN_DPS, IntervalBackend, MPBackend
from verify.numbers.backends.rational import RationalBackend, rational_impls
from verify.numbers.parse import Number

__all__ = [
    "BACKENDS",
    "DEFAULT_DPS",
    "MAX_INTERVAL_DPS",
    "MIN_DPS",
    "Backend",
    "FloatBackend",
    "IntervalBackend",
    "MPBackend",
    "NumberFieldBackend",
    "RationalBackend",
    "algebraic_generators",
    "exact_for",
    "get_backend",
    "rational_impls",
    "rationals",
]

BACKENDS = ("exact", "mp", "interval", "float")  #: the backends that get_backend knows by name


def get_backend(name: str | Backend = "exact", *, dps: int | None = None, prec: int | None = None) -> Backend:
    """A backend by name: ``exact``, ``mp``, ``interval`` or ``float``.

    ``prec`` (``mp`` only) sets the binary precision in bits instead of ``dps``.

    >>> get_backend("interval", dps=30).describe()
    'interval, 30 digits, rigorous'
    """
    if not isinstance(name, str):  # a backend already
        return name
    if name == "exact":
        return rationals()
    if name == "mp":
        return MPBackend(dps or DEFAULT_DPS, prec=prec)
    if prec is not None:
        raise InvalidInput(f"prec applies to the mp backend only, not {name!r}")
    if name == "interval":
        return IntervalBackend(dps or DEFAULT_DPS)
    if name == "float":
        return FloatBackend()
    raise InvalidInput(f"unknown backend {name!r} (choose from {', '.join(BACKENDS)})")


def rationals() -> RationalBackend:
    """The default rational backend (the fastest installed implementation, or the one that
    ``VERIFY_RATIONALS`` names), one shared instance: a backend holds no state.

    >>> rationals() is rationals(), rationals().name
    (True, 'exact')
    """
    return _rationals(os.environ.get("VERIFY_RATIONALS", ""))


@functools.cache
def _rationals(choice: str) -> RationalBackend:
    return RationalBackend(choice or "auto")


def exact_for(values: Iterable[Number]) -> Backend:
    """The exact backend for these parsed numbers: rationals when they all are, else their
    number field; BadNumber when one is not algebraic (such as tan(3/10)).

    >>> import sympy as sp
    >>> exact_for([Fraction(1, 2)]).describe(), exact_for([sp.sqrt(2)]).describe()
    ('exact (rationals, ...), rigorous', 'exact (number field Q(sqrt(2))), rigorous')
    """
    values = list(values)
    gens = algebraic_generators(values)
    if gens is None:
        bad = next(v for v in values if not isinstance(v, Fraction) and v.is_algebraic is not True)
        raise BadNumber(
            f"{bad} is not an algebraic number, so the exact backend cannot hold it: "
            'use backend="interval" (certified) or backend="mp"'
        )
    if not gens:
        return rationals()
    key = tuple(str(g) for g in gens)
    if key not in _FIELDS:  # building a field (primitive element, isolation) costs more than a short run
        _FIELDS[key] = NumberFieldBackend(gens)
    return _FIELDS[key]


_FIELDS: dict[tuple[str, ...], NumberFieldBackend] = {}
