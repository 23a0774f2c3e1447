"""Numbers of a cell of eps: certified enclosures of a function of eps on a whole interval, by the mean value.

A long run of the rule over an interval [lo, hi] of eps, computed on balls (``flint.arb``), loses its digits:
each impulse mixes the rates, the box of the rates turns, and its corners grow by a constant factor an impulse
(the wrapping effect), far beyond what the rates truly spread over the interval. A :class:`MeanValue` carries,
for one function f of eps, its value at the midpoint m (a ball of the working precision), a ball ``value``
holding f on the whole cell, and a ball ``slope`` holding f' on the whole cell (forward differentiation). By the
mean value theorem every f(eps) of the cell lies in ``f(m) + slope * [-h, h]`` (h the half-width): an
enclosure as wide as f truly spreads, to first order, however many operations made f. Its sign is certified
when that enclosure (met with ``value``) excludes 0; a function that is 0 by construction (an untouched rate)
keeps the exact sign 0.

This needs python-flint (the ``fast`` extra); :func:`cell` says so when it is missing.

>>> from fractions import Fraction
>>> with working_precision():
...     e = cell(Fraction(1, 4) + Fraction(1, 10**9), Fraction(1, 4) + Fraction(2, 10**9))
...     x = (e * e - e * 2 + 1) / (e + 1)  # (1 - eps)^2 / (1 + eps): 9/20 at 1/4, decreasing
...     signs = x.sign(), (x - Fraction(9, 20)).sign(), (e - Fraction(1, 4) - Fraction(3, 2 * 10**9)).sign()
>>> signs
(1, -1, None)
>>> x.below(Fraction(46, 100)), x.enclosure().rad() < ball(Fraction(1, 10**8))
(True, True)
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from fractions import Fraction
from typing import Any

from verify.errors import require

#: bits of the balls
PRECISION = 160


def _flint() -> Any:
    return require("flint", "the certified cells of eps")


_ARB: list[Any] = []  # flint.arb, once found


def ball(x: Any) -> Any:
    """An exact ``flint.arb`` for an int or a Fraction (a ball is returned as it is)."""
    if not _ARB:
        _ARB.append(_flint().arb)
    arb = _ARB[0]
    if type(x) is arb:
        return x
    if isinstance(x, Fraction):
        return arb(x.numerator) / x.denominator
    return arb(x)


class MeanValue:
    """f on a cell: ``point`` = f(m), ``value`` holds f on the cell, ``slope`` holds f' on the cell, ``h`` is the
    ball [-h, h] of the cell's half-width (shared by every number of the cell)."""

    __slots__ = ("h", "point", "slope", "value")

    def __init__(self, point: Any, value: Any, slope: Any, h: Any):
        self.point, self.value, self.slope, self.h = point, value, slope, h

    def constant(self, x: Any) -> MeanValue:
        """The constant x on this number's cell."""
        b = ball(x)
        return MeanValue(b, b, ball(0), self.h)

    def _lift(self, other: Any) -> MeanValue:
        return other if type(other) is MeanValue else self.constant(other)

    def __add__(self, other: Any) -> MeanValue:
        if type(other) is not MeanValue:  # a constant: its slope is 0, which adds nothing (exactly)
            b = ball(other)
            return MeanValue(self.point + b, self.value + b, self.slope, self.h)
        return MeanValue(self.point + other.point, self.value + other.value, self.slope + other.slope, self.h)

    __radd__ = __add__

    def __sub__(self, other: Any) -> MeanValue:
        if type(other) is not MeanValue:
            b = ball(other)
            return MeanValue(self.point - b, self.value - b, self.slope, self.h)
        return MeanValue(self.point - other.point, self.value - other.value, self.slope - other.slope, self.h)

    def __rsub__(self, other: Any) -> MeanValue:
        return self._lift(other) - self

    def __neg__(self) -> MeanValue:
        return MeanValue(-self.point, -self.value, -self.slope, self.h)

    def __mul__(self, other: Any) -> MeanValue:
        if type(other) is not MeanValue:
            b = ball(other)
            return MeanValue(self.point * b, self.value * b, self.slope * b, self.h)
        return MeanValue(self.point * other.point, self.value * other.value,
                         self.slope * other.value + self.value * other.slope, self.h)  # fmt: skip

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> MeanValue:
        if not isinstance(other, MeanValue):
            b = ball(other)
            return MeanValue(self.point / b, self.value / b, self.slope / b, self.h)
        q = self.value / other.value
        return MeanValue(self.point / other.point, q, (self.slope - q * other.slope) / other.value, self.h)

    def __rtruediv__(self, other: Any) -> MeanValue:
        return self._lift(other) / self

    def sin(self) -> MeanValue:
        return MeanValue(self.point.sin(), self.value.sin(), self.value.cos() * self.slope, self.h)

    def acos(self) -> MeanValue:
        """arccos, for a number whose values lie in (-1, 1) (the caller checks it)."""
        derivative = -self.slope / (1 - self.value * self.value).sqrt()
        return MeanValue(self.point.acos(), self.value.acos(), derivative, self.h)

    def enclosure(self) -> Any:
        """A ball holding f on the whole cell: the mean-value form, met with ``value``."""
        e = self.point + self.slope * self.h
        return e.intersection(self.value) if e.overlaps(self.value) else e

    def is_zero(self) -> bool:
        """f is 0 by construction (every part exactly 0)."""
        return bool(self.point == 0 and self.value == 0 and self.slope == 0)

    def sign(self) -> int | None:
        """The sign of f on the whole cell (0 only for a number that is 0 by construction), None if undecided."""
        if self.is_zero():
            return 0
        e = self.enclosure()
        if e > 0:
            return 1
        if e < 0:
            return -1
        return None

    def below(self, bound: Any) -> bool:
        """|f| < bound on the whole cell, certified."""
        return bool(abs(self.enclosure()) < ball(bound))


@contextmanager
def working_precision(bits: int = PRECISION) -> Iterator[None]:
    """Balls of ``bits`` bits inside the block (FLINT's precision is global: it is restored after)."""
    flint = _flint()
    before = flint.ctx.prec
    flint.ctx.prec = bits
    try:
        yield
    finally:
        flint.ctx.prec = before


def combination(pairs: list[tuple[MeanValue, MeanValue]]) -> MeanValue:
    """sum a * b over the pairs (a number of each pair's cell), without the numbers in between.

    >>> with working_precision():
    ...     e = cell(Fraction(1, 4), Fraction(1, 2))
    ...     x = combination([(e, e), (e.constant(2), e)]) - (e * e + e * 2)
    >>> x.is_zero() or x.enclosure().contains(0)
    True
    """
    a, b = pairs[0]
    point, value, slope = a.point * b.point, a.value * b.value, a.slope * b.value + a.value * b.slope
    for a, b in pairs[1:]:
        point += a.point * b.point
        value += a.value * b.value
        slope += a.slope * b.value + a.value * b.slope
    return MeanValue(point, value, slope, a.h)


def cell(lo: Fraction, hi: Fraction) -> MeanValue:
    """eps itself on the cell [lo, hi] (rationals, lo < hi), in the working precision."""
    flint = _flint()
    a, b = ball(lo), ball(hi)
    m = (a + b) / 2
    h = (b - a) / 2 * flint.arb(0, 1)
    return MeanValue(m, m + h, ball(1), h)
