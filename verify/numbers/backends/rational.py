"""Exact rationals: gmpy2 or python-flint when installed, pure-Python Fraction otherwise.

>>> K = RationalBackend("python")
>>> x = K.convert(Fraction(1, 3)) - K.convert(Fraction(1, 2))
>>> K.sign(x), K.to_decimal(x, 5), K.to_number(x)
(-1, '-0.16667', Fraction(-1, 6))
"""

from __future__ import annotations

import functools
import os
from fractions import Fraction
from typing import Any

from verify.errors import BadNumber, InvalidInput
from verify.numbers.backends.base import Backend
from verify.numbers.format import format_decimal
from verify.numbers.parse import Number


@functools.cache
def rational_impls() -> dict[str, Any]:
    """The installed rational types by name, fastest first (looked up once): ``"gmpy2"``
    (``mpq``), ``"flint"`` (``fmpq``) when installed, and ``"python"`` (Fraction) always.

    >>> list(rational_impls())[-1], rational_impls()["python"]
    ('python', <class 'fractions.Fraction'>)
    """
    impls: dict[str, Any] = {}
    try:
        import gmpy2

        impls["gmpy2"] = gmpy2.mpq
    except ImportError:
        pass
    try:
        import flint

        impls["flint"] = flint.fmpq
    except ImportError:
        pass
    impls["python"] = Fraction
    return impls


def _same(value: Fraction) -> Fraction:
    return value


class RationalBackend(Backend):
    """Exact rationals. ``impl`` is ``"gmpy2"``, ``"flint"``, ``"python"`` or ``"auto"``.

    ``"auto"`` takes the fastest installed one (the environment variable
    ``VERIFY_RATIONALS`` can force a choice); every implementation gives the same results.
    Irrational inputs are refused with a clear error: run them on ``interval`` or ``mp``.
    """

    name = "exact"
    is_exact = True
    is_rigorous = True
    rationals = True
    widens_to_inputs = True
    fraction_free = True  #: the rule may run over integers here (:mod:`verify.laws.loops.integer`)

    def __init__(self, impl: str = "auto"):
        impls = rational_impls()
        if impl == "auto":
            impl = os.environ.get("VERIFY_RATIONALS", "") or next(iter(impls))
        if impl not in impls:
            raise InvalidInput(f"rational implementation {impl!r} is not installed (have: {', '.join(impls)})")
        self.impl = impl
        self._q = impls[impl]
        self.zero = self._q(0)
        self.one = self._q(1)
        if impl == "gmpy2":
            self._from_fraction = self._q  # mpq takes a Fraction as it is
        elif impl == "python":
            self._from_fraction = _same  # Fractions are immutable: kept as they are
        else:
            self._from_fraction = self._numerator_denominator

    def convert(self, value: Number) -> Any:
        if type(value) is Fraction:  # the common case: one call into the implementation
            return self._from_fraction(value)
        if isinstance(value, Fraction):
            return self._q(value.numerator, value.denominator)
        if isinstance(value, int):
            return self._q(value, 1)
        if getattr(value, "is_Rational", False):  # a SymPy Integer or Rational: exact
            return self._q(int(value.p), int(value.q))
        if isinstance(value, float) or getattr(value, "is_Float", False):
            raise BadNumber(
                f"{value} is a float: the exact backend takes exact numbers (a string such as '0.1' is 1/10)"
            )
        raise BadNumber(
            f"{value} is irrational: the exact backend computes over the rationals; "
            'use backend="interval" (certified) or backend="mp"'
        )

    def convert_all(self, values: list[Number]) -> list[Any]:
        if set(map(type, values)) <= {Fraction}:  # Fractions only: each distinct object converted once
            ids = list(map(id, values))
            distinct = dict(zip(ids, values))  # a matrix repeats its 0 and 1 objects
            converted = dict(zip(distinct, map(self._from_fraction, distinct.values())))
            return list(map(converted.__getitem__, ids))
        return [self.convert(x) for x in values]

    def sign(self, x: Any) -> int:
        s: int = (x > 0) - (x < 0)
        return s

    def _numerator_denominator(self, value: Fraction) -> Any:
        return self._q(value.numerator, value.denominator)

    def known_zero(self, x: Any) -> bool:
        return not x

    def from_integers(self, numerator: Any, denominator: Any) -> Any:
        """The element ``numerator / denominator`` (integers, denominator non-zero)."""
        if self.impl == "gmpy2":
            return self._q(numerator, denominator)
        return self._q(int(numerator), int(denominator))

    def to_number(self, x: Any) -> Fraction:
        return Fraction(int(x.numerator), int(x.denominator))

    def size(self, x: Any) -> int:
        return int(x.numerator).bit_length() + int(x.denominator).bit_length()

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return format_decimal(self.to_number(x), digits)

    def describe(self) -> str:
        return f"exact (rationals, {self.impl}), rigorous"
