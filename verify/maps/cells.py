"""A cylindrical decomposition of a box of the plane: cells on which every polynomial of a set has one sign.

For a set of irreducible polynomials in (x, y) and a box [a, b] x [c, d] with rational corners,
:func:`decompose` cuts the box into cells (points, arcs, open regions):

1. **Projection.** The x where something happens: the real roots in [a, b] of each polynomial's leading
   coefficient in y and discriminant in y, of its values on the box's edges y = c and y = d, of the
   resultant of each pair in y, and of the resultant of each polynomial with its x-derivative (where a
   curve turns back in y, so that between two such x every curve is monotone); a polynomial in x alone
   gives its own roots. With a and b, these are the *critical* x, exact real algebraic numbers.
2. **Lifting.** Over each open interval between two critical x, the curves do not meet and do not turn:
   at a rational sample x their real roots in (c, d), in order, are the *sections*, and between them
   lie the *sectors*. A rational critical x gets the same column. A line x = x0 at an irrational
   critical x0 holds no rational point; it is one cell (of measure 0), not cut further.

Each cell has an exact description (its x: a point or an open interval with algebraic ends; its y: the
edges or the k-th root in (c, d) of a polynomial, counted from below, or between two of them), a sample
point (a rational x, and a rational or real algebraic y), and bounds of its area (exact rationals; 0 for
points and arcs). The cells are disjoint and their union is the box.

>>> from verify.core.backends.plane import polys, X, Y
>>> P = polys()
>>> cells = decompose(P, [P.from_expr(X - Y)], (Fraction(0), Fraction(1), Fraction(0), Fraction(1)))
>>> sorted(c.dim for c in cells)
[0, 0, 0, 0, 1, 1, 1, 1, 1, 2, 2]
>>> low, high = sum(c.area[0] for c in cells), sum(c.area[1] for c in cells)
>>> low <= 1 <= high, float(low), float(high)
(True, 0.968..., 1.031...)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from verify.core.algebraic import RealAlgebraic
from verify.core.backends.plane import Polys
from verify.core.backends.symbolic import RootCache

Box = tuple[Fraction, Fraction, Fraction, Fraction]  # a, b, c, d: [a, b] x [c, d]
#: how many rational points of a strip bound the areas of its cells (the bounds tighten with it)
AREA_STEPS = 32


@dataclass(frozen=True)
class Bound:
    """A lower or upper side of a cell in y: the edge ``y = value`` or the ``index``-th real root in (c, d)
    (from 0, counted from below) of ``poly`` in y, at the cell's x."""

    value: Fraction | None = None
    poly: Any = None
    index: int = 0

    def describe(self, P: Polys, names: tuple[str, str]) -> str:
        """The side as an equation of y (``y = 1/2``, ``y = root 1 of ... = 0``)."""
        return f"{names[1]} = {self.value_text(P, names)}"

    def value_text(self, P: Polys, names: tuple[str, str]) -> str:
        """The side's y: a rational, or the k-th root in y of a polynomial, counted from below in the box."""
        if self.value is not None:
            return str(self.value)
        return f"root {self.index + 1} of {P.show(self.poly, names)} = 0"


@dataclass
class Cell:
    """One cell: ``x_lo``/``x_hi`` (equal for a vertical line or a point; open ends otherwise),
    ``y_lo``/``y_hi`` (:class:`Bound`; equal for an arc or a point: the cell lies on it), the sample point
    (None on a line of irrational x) and bounds of its area."""

    x_lo: RealAlgebraic
    x_hi: RealAlgebraic
    y_lo: Bound
    y_hi: Bound
    sample: tuple[Fraction, Fraction | RealAlgebraic] | None
    area: tuple[Fraction, Fraction]
    dim: int

    @property
    def on_line(self) -> bool:
        """Whether the cell lies on one vertical line x = x_lo."""
        return self.x_lo.cmp(self.x_hi) == 0

    def describe(self, P: Polys, names: tuple[str, str]) -> str:
        x, y = names
        xs = f"{x} = {self.x_lo}" if self.on_line else f"{self.x_lo} < {x} < {self.x_hi}"
        if self.sample is None:
            return f"{xs}, every {y} of the box (an irrational {x}: no rational point)"
        if self.y_lo == self.y_hi:
            return f"{xs}, {self.y_lo.describe(P, names)}"
        return f"{xs}, {self.y_lo.value_text(P, names)} < {y} < {self.y_hi.value_text(P, names)}"


def _trim(coeffs: Sequence[Fraction]) -> tuple[Fraction, ...]:
    out = list(coeffs)
    while out and out[-1] == 0:
        out.pop()
    return tuple(out)


def _roots(
    cache: RootCache, coeffs: Sequence[Fraction], lo: Fraction, hi: Fraction, open_: bool
) -> list[RealAlgebraic]:
    """The real roots of a univariate polynomial (coefficients, lowest degree first) in [lo, hi] or (lo, hi)."""
    c = _trim(coeffs)
    if len(c) < 2:
        return []
    a, b = RealAlgebraic.rational(lo), RealAlgebraic.rational(hi)
    out = []
    for r in cache.roots_of(c):
        s, t = r.cmp(a), r.cmp(b)
        if (s > 0 and t < 0) or (not open_ and (s == 0 or t == 0)):
            out.append(r)
    return out


def critical_x(P: Polys, polys: Sequence[Any], box: Box, cache: RootCache) -> list[RealAlgebraic]:
    """The critical x of ``polys`` in [a, b] (see the module), in increasing order, a and b among them."""
    a, b, c, d = box
    projected: list[tuple[Fraction, ...]] = []
    curves = [f for f in polys if P.degree_y(f) > 0]
    for f in polys:
        if P.degree_y(f) == 0:
            projected.append(P.in_x(f))
            continue
        projected += [P.leading_in_y(f), P.at_y(f, c), P.at_y(f, d), P.in_x(P.resultant(f, P.derivative_x(f)))]
        if P.degree_y(f) >= 2:
            projected.append(P.in_x(P.discriminant(f)))
    for i, f in enumerate(curves):
        for g in curves[i + 1 :]:
            projected.append(P.in_x(P.resultant(f, g)))
    found = [RealAlgebraic.rational(a), RealAlgebraic.rational(b)]
    for coeffs in dict.fromkeys(_trim(p) for p in projected):
        found += _roots(cache, coeffs, a, b, open_=True)
    found.sort()
    out: list[RealAlgebraic] = []
    for r in found:
        if not out or out[-1].cmp(r) != 0:
            out.append(r)
    return out


def sections(
    P: Polys, polys: Sequence[Any], x: Fraction, box: Box, cache: RootCache
) -> list[tuple[RealAlgebraic, Bound]]:
    """The real roots in (c, d) of every polynomial at the rational x, in increasing order, each with its
    :class:`Bound` (its polynomial and its index among that polynomial's roots there)."""
    _, _, c, d = box
    out = []
    for f in polys:
        if P.degree_y(f) == 0:
            continue
        for k, r in enumerate(_roots(cache, P.in_y(f, x), c, d, open_=True)):
            out.append((r, Bound(poly=f, index=k)))
    out.sort(key=lambda t: t[0])
    distinct: list[tuple[RealAlgebraic, Bound]] = []
    for r, bound in out:  # on a critical line two curves may meet: one point, named by the first curve
        if not distinct or distinct[-1][0].cmp(r) != 0:
            distinct.append((r, bound))
    return distinct


def _column(
    P: Polys,
    polys: Sequence[Any],
    box: Box,
    cache: RootCache,
    ends: tuple[RealAlgebraic, RealAlgebraic],
    *,
    x: Fraction,
) -> list[Cell]:
    """The cells over one x-interval (or one rational line, x_lo = x_hi), lifted at the rational x."""
    _, _, c, d = box
    x_lo, x_hi = ends
    line = x_lo.cmp(x_hi) == 0
    ys = sections(P, polys, x, box, cache)
    bottom, top = (RealAlgebraic.rational(c), Bound(value=c)), (RealAlgebraic.rational(d), Bound(value=d))
    points = [bottom, *ys, top]
    zero = (Fraction(0), Fraction(0))
    out = []
    for k, (r, bound) in enumerate(points):
        out.append(Cell(x_lo, x_hi, bound, bound, (x, r if not r.is_rational else r.rational_value()), zero,
                        0 if line else 1))  # fmt: skip
        if k + 1 < len(points):
            s = points[k + 1][0]
            out.append(Cell(x_lo, x_hi, bound, points[k + 1][1], (x, r.between(s)), zero, 1 if line else 2))
    return out


def decompose(P: Polys, polys: Sequence[Any], box: Box, cache: RootCache | None = None) -> list[Cell]:
    """The cells of ``box`` on which every polynomial of ``polys`` (irreducible) has one sign (see the
    module), each with its area bounds, in order of x then y."""
    cache = cache or RootCache()
    xs = critical_x(P, polys, box, cache)
    cells: list[Cell] = []
    for i, x0 in enumerate(xs):
        if x0.is_rational:
            cells += _column(P, polys, box, cache, (x0, x0), x=x0.rational_value())
        else:
            _, _, c, d = box
            cells.append(Cell(x0, x0, Bound(value=c), Bound(value=d), None, (Fraction(0), Fraction(0)), 1))
        if i + 1 < len(xs):
            strip = _column(P, polys, box, cache, (x0, xs[i + 1]), x=x0.between(xs[i + 1]))
            _areas(P, box, cache, strip)
            cells += strip
    return cells


def _value_bounds(P: Polys, bound: Bound, x: Fraction, box: Box, cache: RootCache) -> tuple[Fraction, Fraction]:
    """Rational bounds of a side of a cell at the rational x."""
    if bound.value is not None:
        return bound.value, bound.value
    _, _, c, d = box
    r = _roots(cache, P.in_y(bound.poly, x), c, d, open_=True)[bound.index]
    r = RealAlgebraic(r.poly, r.lo, r.hi)
    while r.hi - r.lo > (d - c) / 2**20:
        r.refine()
    return r.lo, r.hi


def _areas(P: Polys, box: Box, cache: RootCache, strip: list[Cell]) -> None:
    """Set the area bounds of a strip's open cells: every side is monotone in x inside the strip (the
    curves' turning x are critical), so between two rational x a side lies between its values there; the
    two end pieces, next to the strip's algebraic ends, count from 0 to their whole height."""
    _, _, c, d = box
    lo, hi = strip[0].x_lo, strip[0].x_hi
    inner_lo, inner_hi, outer_lo, outer_hi = _inside(lo, hi)
    step = (inner_hi - inner_lo) / AREA_STEPS
    ts = [inner_lo + k * step for k in range(AREA_STEPS + 1)]
    ends = (inner_lo - outer_lo) + (outer_hi - inner_hi)  # an upper bound of the end pieces' widths
    for cell in strip:
        if cell.dim != 2:
            continue
        low = [_value_bounds(P, cell.y_lo, t, box, cache) for t in ts]
        up = [_value_bounds(P, cell.y_hi, t, box, cache) for t in ts]
        area_lo = area_hi = Fraction(0)
        for k in range(AREA_STEPS):
            top_min, top_max = min(up[k][0], up[k + 1][0]), max(up[k][1], up[k + 1][1])
            bot_min, bot_max = min(low[k][0], low[k + 1][0]), max(low[k][1], low[k + 1][1])
            area_lo += step * max(Fraction(0), top_min - bot_max)
            area_hi += step * min(d - c, max(Fraction(0), top_max - bot_min))
        cell.area = (area_lo, area_hi + ends * (d - c))


def _inside(lo: RealAlgebraic, hi: RealAlgebraic) -> tuple[Fraction, Fraction, Fraction, Fraction]:
    """Two rationals strictly inside (lo, hi), with the pieces outside them a little more than 1/4096 of the
    interval, and a rational at most lo and one at least hi (the isolating intervals are refined on copies)."""
    a, b = RealAlgebraic(lo.poly, lo.lo, lo.hi), RealAlgebraic(hi.poly, hi.lo, hi.hi)
    while True:
        width = b.lo - a.hi
        if width > 0 and (a.hi - a.lo) * 4096 <= width and (b.hi - b.lo) * 4096 <= width:
            return a.hi + width / 4096, b.lo - width / 4096, a.lo, b.hi
        a.refine()
        b.refine()
