"""Backends of fixed precision over mpmath: ``mp`` (heuristic signs) and ``interval``
(certified signs, precision raised on demand), each over a private mpmath context.

>>> K = IntervalBackend(20)
>>> x = K.convert(Fraction(1, 3)) - K.convert(Fraction(1, 2))
>>> K.sign(x), K.to_decimal(x, 5)
(-1, '-0.16667')
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput, Undecided
from verify.numbers.backends.base import Backend
from verify.numbers.format import certified_decimal, format_decimal
from verify.numbers.numeric import evaluate, mpf_to_fraction
from verify.numbers.parse import Number

DEFAULT_DPS = 50  #: decimal digits of ``mp`` and of ``interval`` at the start
MAX_INTERVAL_DPS = 3200  #: the precision beyond which ``interval`` stops refining
MIN_DPS = 5  #: the least precision a backend accepts


class _ContextBackend(Backend):
    """A backend over a private mpmath context (precision is part of the backend's value)."""

    dps: int

    def __init__(self, dps: int = DEFAULT_DPS):
        if not isinstance(dps, int) or dps < MIN_DPS:
            raise InvalidInput(f"dps must be an integer >= {MIN_DPS}, got {dps!r}")
        self.dps = dps
        self.ctx = self._context()
        self.ctx.dps = dps
        self.zero = self.ctx.mpf(0)
        self.one = self.ctx.mpf(1)

    def _context(self) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def convert(self, value: Number) -> Any:
        return evaluate(value, self.ctx)


class MPBackend(_ContextBackend):
    """mpmath floating point at ``dps`` decimal digits; signs are heuristic (not rigorous).

    ``prec`` sets the binary precision (bits of mantissa) instead, for a run in a given
    binary format; ``dps`` is then the decimal precision mpmath derives from it.

    >>> K = MPBackend(prec=128)
    >>> K.ctx.prec, K.dps
    (128, 38)
    """

    name = "mp"

    def __init__(self, dps: int = DEFAULT_DPS, *, prec: int | None = None):
        super().__init__(dps)
        if prec is not None:
            if not isinstance(prec, int) or prec < 4 * MIN_DPS:
                raise InvalidInput(f"prec must be an integer >= {4 * MIN_DPS}, got {prec!r}")
            self.ctx.prec = prec
            self.dps = int(self.ctx.dps)
            self.zero = self.ctx.mpf(0)
            self.one = self.ctx.mpf(1)

    def _context(self) -> Any:
        from mpmath import MPContext

        return MPContext()

    def sign(self, x: Any) -> int:
        s: int = (x > 0) - (x < 0)
        return s

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return str(self.ctx.nstr(x, min(digits, self.dps)))


class IntervalBackend(_ContextBackend):
    """mpmath intervals at ``dps`` digits: every sign is certified or raises Undecided.

    :meth:`refined` doubles the precision up to ``max_dps``; :func:`verify.laws.rule.solve`
    retries with it when a sign is undecided and says so in the result's notes.
    """

    name = "interval"
    is_rigorous = True
    encloses = True
    refinable = True
    ball_form = True  #: untraced runs take :mod:`verify.laws.loops.balls`

    def __init__(self, dps: int = DEFAULT_DPS, max_dps: int = MAX_INTERVAL_DPS):
        super().__init__(dps)
        self.max_dps = max(max_dps, dps)

    def _context(self) -> Any:
        from mpmath.ctx_iv import MPIntervalContext

        return MPIntervalContext()

    def sign(self, x: Any) -> int:
        if x.a > 0:
            return 1
        if x.b < 0:
            return -1
        if x.a == 0 and x.b == 0:
            return 0
        if not all(bound._mpi_[0][1] or not bound._mpi_[0][2] for bound in (x.a, x.b)):  # inf or nan
            raise Undecided(f"an unbounded interval at {self.dps} digits (a division by an interval around 0)")
        lo, hi = self._bounds(x)
        raise Undecided(
            f"the interval [{format_decimal(lo, 6, 'floor')}, {format_decimal(hi, 6, 'ceiling')}] "
            f"contains 0 at {self.dps} digits"
        )

    def _bounds(self, x: Any) -> tuple[Fraction, Fraction]:
        return mpf_to_fraction(x.a), mpf_to_fraction(x.b)

    def bounds(self, x: Any) -> tuple[Fraction, Fraction]:
        """The ends of the interval x, as exact rationals.

        >>> K = IntervalBackend(20)
        >>> lo, hi = K.bounds(K.one / K.convert(Fraction(3)))
        >>> lo < Fraction(1, 3) < hi
        True
        """
        return self._bounds(x)

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        """Only the digits that the enclosure certifies (at most ``digits``; see
        :func:`~verify.numbers.format.certified_decimal`): ``"4.7625000000000000"`` when the
        bounds agree to 17 digits, the value itself for a point, ``"0e-19"`` for an
        enclosure of 0. The midpoint's further digits would be noise.

        >>> K = IntervalBackend(20)
        >>> third = K.one / K.convert(Fraction(3))
        >>> K.to_decimal(third, 30), K.to_decimal(K.convert(Fraction(1, 4)), 30)
        ('0.333333333333333333333', '0.25')
        >>> K.to_decimal(third * K.convert(Fraction(3)) - K.one)
        '0e-20'
        """
        lo, hi = self._bounds(x)
        return certified_decimal(lo, hi, digits)

    def enclosure(self, x: Any, digits: int = 30) -> tuple[str, str]:
        lo, hi = self._bounds(x)
        return format_decimal(lo, digits, "floor"), format_decimal(hi, digits, "ceiling")

    def contains(self, x: Any, value: Fraction) -> bool:
        """Whether the exact rational ``value`` lies in the interval ``x``."""
        lo, hi = self._bounds(x)
        return lo <= value <= hi

    def refined(self) -> IntervalBackend | None:
        if self.dps >= self.max_dps:
            return None
        return IntervalBackend(min(2 * self.dps, self.max_dps), self.max_dps)
