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

>>> from verify.maps.backends.plane import polys, X, Y
>>> P = polys()
>>> cells = decompose(P, [P.from_expr(X - Y)], (Fraction(0), Fraction(1), Fraction(0), Fraction(1)))
>>> sorted(c.dim for c in cells)
[0, 0, 0, 0, 1, 1, 1, 1, 1, 2, 2]
>>> low, high = sum(c.area[0] for c in cells), sum(c.area[1] for c in cells)
>>> low <= 1 <= high, float(low), float(high)
(True, 0.968..., 1.031...)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.maps.backends.eliminate import Stop
from verify.maps.backends.plane import Polys
from verify.numbers.algebraic import RealAlgebraic, X
from verify.numbers.backends.ratfunc import FLINT, flint
from verify.numbers.backends.symbolic import RootCache
from verify.numbers.format import format_decimal


class Roots(RootCache):
    """The real roots of univariate polynomials, computed once each: with python-flint, each irreducible factor's
    real roots come from FLINT's certified root isolation (``arb_fmpz_poly_complex_roots``: each ball holds
    exactly one root, real roots with an imaginary part of exactly 0), its ball's exact ends as the isolating
    interval; else SymPy's, as :class:`~verify.numbers.backends.symbolic.RootCache` does.

    >>> [str(r) for r in Roots().roots_of((Fraction(-2), Fraction(0), Fraction(1)))]
    ['-sqrt(2)', 'sqrt(2)']
    """

    def __init__(self) -> None:
        super().__init__()
        self._flint: dict[tuple[Any, ...], list[RealAlgebraic]] = {}

    def roots_of(self, coeffs: tuple[Any, ...]) -> list[RealAlgebraic]:
        if not FLINT or len(coeffs) < 2:
            return super().roots_of(coeffs)
        if coeffs not in self._flint:
            self._flint[coeffs] = _flint_roots(coeffs)
        return self._flint[coeffs]


def _flint_roots(coeffs: Sequence[Fraction]) -> list[RealAlgebraic]:
    scale = math.lcm(*(Fraction(c).denominator for c in coeffs))
    f = flint.fmpz_poly([int(Fraction(c) * scale) for c in coeffs])
    out = []
    for g, _ in f.factor()[1]:
        ints = [int(g[i]) for i in range(g.degree() + 1)]
        if g.degree() == 1:
            out.append(RealAlgebraic.rational(Fraction(-ints[0], ints[1])))
            continue
        poly = sp.Poly(ints[::-1], X, domain="QQ").monic()
        for c, _m in g.complex_roots():
            if not c.imag.is_zero():
                continue
            (mm, me), (rm, re) = c.real.mid().man_exp(), c.real.rad().man_exp()
            mid, rad = Fraction(int(mm)) * Fraction(2) ** int(me), Fraction(int(rm)) * Fraction(2) ** int(re)
            out.append(RealAlgebraic(poly, mid - rad, mid + rad))
    return sorted(out)


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

    def contains(self, P: Polys, x: Fraction, y: Fraction, box: Box, cache: RootCache) -> bool:
        """Whether the rational point (x, y) lies in the cell, exactly."""
        if self.sample is None:  # an irrational x: no rational point
            return False
        rx = RealAlgebraic.rational(x)
        if self.on_line:
            if self.x_lo.cmp(rx) != 0:
                return False
        elif not self.x_lo.cmp(rx) < 0 < self.x_hi.cmp(rx):
            return False
        ry = RealAlgebraic.rational(y)
        low = bound_at(P, self.y_lo, x, box, cache).cmp(ry)
        if self.y_lo == self.y_hi:
            return low == 0
        return low < 0 < bound_at(P, self.y_hi, x, box, cache).cmp(ry)

    @property
    def on_line(self) -> bool:
        """Whether the cell lies on one vertical line x = x_lo."""
        return self.x_lo.cmp(self.x_hi) == 0

    def describe(self, P: Polys, names: tuple[str, str], *, digits: int | None = None) -> str:
        """The cell in words: its x (an exact number, or between two; with ``digits``, an irrational x as that
        many decimal digits, as the text of a map shows it: SymPy's exact form of a root of high degree is slow
        to write), then its y."""
        x, y = names

        def shown(r: RealAlgebraic) -> str:
            return str(r) if digits is None or r.is_rational else format_decimal(r, digits)

        xs = f"{x} = {shown(self.x_lo)}" if self.on_line else f"{shown(self.x_lo)} < {x} < {shown(self.x_hi)}"
        if self.sample is None:
            where = (self.y_lo.describe(P, names) if self.y_lo == self.y_hi
                     else f"{self.y_lo.value_text(P, names)} < {y} < {self.y_hi.value_text(P, names)}")  # fmt: skip
            return f"{xs}, {where} (an irrational {x}: no rational point)"
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


def critical_x(P: Polys, polys: Sequence[Any], box: Box, cache: RootCache, stop: Stop = None) -> list[RealAlgebraic]:
    """The critical x of ``polys`` in [a, b] (see the module), in increasing order, a and b among them. ``stop`` is
    called between the projections and inside the long ones (it may raise: a map's wall-clock budget)."""
    if stop is not None:
        stop()
    a, b, c, d = box
    projected: list[tuple[Fraction, ...]] = []
    curves = [f for f in polys if P.degree_y(f) > 0]
    for f in polys:
        if P.degree_y(f) == 0:
            projected.append(P.in_x(f))
            continue
        projected += [P.leading_in_y(f), P.at_y(f, c), P.at_y(f, d), P.in_x(P.resultant(f, P.derivative_x(f), stop))]
        if P.degree_y(f) >= 2:
            projected.append(P.in_x(P.discriminant(f, stop)))
    for i, f in enumerate(curves):
        for g in curves[i + 1 :]:
            if stop is not None:
                stop()
            projected.append(P.in_x(P.resultant(f, g, stop)))
    found = [RealAlgebraic.rational(a), RealAlgebraic.rational(b)]
    for coeffs in dict.fromkeys(_trim(p) for p in projected):
        found += _roots(cache, coeffs, a, b, open_=True)
    return _distinct(found)


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


def bound_at(P: Polys, bound: Bound, x: Fraction, box: Box, cache: RootCache) -> RealAlgebraic:
    """The y of a side at the rational x (where the side is defined: inside its cell's x)."""
    if bound.value is not None:
        return RealAlgebraic.rational(bound.value)
    _, _, c, d = box
    return _roots(cache, P.in_y(bound.poly, x), c, d, open_=True)[bound.index]


def _y(r: RealAlgebraic) -> Fraction | RealAlgebraic:
    return r.rational_value() if r.is_rational else r


def _lift(
    P: Polys,
    polys: Sequence[Any],
    box: Box,
    cache: RootCache,
    ends: tuple[RealAlgebraic, RealAlgebraic],
    *,
    x: Fraction,
    sides: tuple[Bound, Bound],
    closed: bool,
) -> list[Cell]:
    """The cells over one x-interval (or one rational line, x_lo = x_hi) between two sides, lifted at the
    rational x: the sections of ``polys`` strictly between the sides and the sectors between them; the
    sides themselves too when ``closed``."""
    x_lo, x_hi = ends
    line = x_lo.cmp(x_hi) == 0
    below, above = (bound_at(P, side, x, box, cache) for side in sides)
    ys = [(r, b) for r, b in sections(P, polys, x, box, cache) if below.cmp(r) < 0 < above.cmp(r)]
    points = [(below, sides[0]), *ys, (above, sides[1])]
    zero = (Fraction(0), Fraction(0))
    out = []
    for k, (r, bound) in enumerate(points):
        if closed or 0 < k < len(points) - 1:
            out.append(Cell(x_lo, x_hi, bound, bound, (x, _y(r)), zero, 0 if line else 1))
        if k + 1 < len(points):
            s = points[k + 1][0]
            out.append(Cell(x_lo, x_hi, bound, points[k + 1][1], (x, r.between(s)), zero, 1 if line else 2))
    return out


def refine(
    P: Polys, cell: Cell, polys: Sequence[Any], box: Box, cache: RootCache | None = None, *, stop: Stop = None
) -> list[Cell]:
    """The cell cut by the zero sets of ``polys`` (irreducible) into cells on which each of them has one sign,
    and its own sides keep theirs (a point, or a cell of irrational x, comes back whole). The parts' areas
    are not set (:func:`set_areas`: once the cells are final). ``stop`` as for :func:`critical_x`.

    >>> from verify.maps.backends.plane import polys, X, Y
    >>> P = polys()
    >>> box = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
    >>> square = next(c for c in decompose(P, [], box) if c.dim == 2)
    >>> [c.dim for c in refine(P, square, [P.from_expr(X - Y)], box)]
    [2, 1, 2]
    """
    cache = cache or Roots()
    if cell.dim == 0 or cell.sample is None:
        return [cell]
    zero = (Fraction(0), Fraction(0))
    if cell.on_line:  # a vertical segment at a rational x
        return _lift(P, polys, box, cache, (cell.x_lo, cell.x_hi), x=cell.sample[0], sides=(cell.y_lo, cell.y_hi),
                     closed=False)  # fmt: skip
    if cell.y_lo == cell.y_hi:  # an arc: cut where a curve meets it
        side = cell.y_lo
        meets = [P.at_y(f, side.value) if side.value is not None else P.in_x(P.resultant(f, side.poly)) for f in polys]
        xs = [r for coeffs in meets for r in _roots(cache, coeffs, box[0], box[1], open_=False)
              if cell.x_lo.cmp(r) < 0 < cell.x_hi.cmp(r)]  # fmt: skip
        ends = _distinct([cell.x_lo, *xs, cell.x_hi])
        out = []
        for i in range(len(ends) - 1):
            u, v = ends[i], ends[i + 1]
            x = u.between(v)
            out.append(Cell(u, v, side, side, (x, _y(bound_at(P, side, x, box, cache))), zero, 1))
            if i + 2 < len(ends):
                sample = (
                    (v.rational_value(), _y(bound_at(P, side, v.rational_value(), box, cache)))
                    if v.is_rational
                    else None
                )
                out.append(Cell(v, v, side, side, sample, zero, 0))
        return out
    curves = [*polys, *(s.poly for s in (cell.y_lo, cell.y_hi) if s.poly is not None)]
    xs = [r for r in critical_x(P, curves, box, cache, stop) if cell.x_lo.cmp(r) < 0 < cell.x_hi.cmp(r)]
    ends = [cell.x_lo, *xs, cell.x_hi]
    out = []
    for i in range(len(ends) - 1):
        u, v = ends[i], ends[i + 1]
        strip = _lift(P, polys, box, cache, (u, v), x=u.between(v), sides=(cell.y_lo, cell.y_hi), closed=False)
        out += strip
        if i + 2 < len(ends):
            if v.is_rational:
                out += _lift(P, polys, box, cache, (v, v), x=v.rational_value(), sides=(cell.y_lo, cell.y_hi),
                             closed=False)  # fmt: skip
            else:
                out.append(Cell(v, v, cell.y_lo, cell.y_hi, None, zero, 1))
    return out


def meets(P: Polys, cell: Cell, poly: Any, box: Box, cache: RootCache | None = None, *, stop: Stop = None) -> bool:
    """Whether the curve ``poly = 0`` (irreducible) may meet the cell, so that its sign may change there: False only
    when the cell cut by it (:func:`refine`) has no part on it and every critical line of the cut was lifted (a line
    at an irrational x is not, and a curve may touch the cell there). A curve that does not meet a cell keeps one
    sign on it, and need not cut it.

    >>> from verify.maps.backends.plane import polys, X, Y
    >>> P = polys()
    >>> box = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
    >>> square = next(c for c in decompose(P, [], box) if c.dim == 2)
    >>> meets(P, square, P.from_expr(X - Y), box), meets(P, square, P.from_expr(X + Y + 1), box)
    (True, False)
    """
    if cell.dim == 0:
        return False
    parts = refine(P, cell, [poly], box, cache, stop=stop)
    if cell.y_lo == cell.y_hi:  # an arc or a segment of a side: cut only where the curve meets it
        return len(parts) > 1
    key = P.key(poly)
    return any(
        c.sample is None or (c.y_lo == c.y_hi and c.y_lo.poly is not None and P.key(c.y_lo.poly) == key) for c in parts
    )


def _distinct(xs: list[RealAlgebraic]) -> list[RealAlgebraic]:
    out: list[RealAlgebraic] = []
    for r in sorted(xs):
        if not out or out[-1].cmp(r) != 0:
            out.append(r)
    return out


def decompose(P: Polys, polys: Sequence[Any], box: Box, cache: RootCache | None = None) -> list[Cell]:
    """The cells of ``box`` on which every polynomial of ``polys`` (irreducible) has one sign (see the
    module), each with its area bounds, in order of x then y."""
    cache = cache or Roots()
    xs = critical_x(P, polys, box, cache)
    edges = (Bound(value=box[2]), Bound(value=box[3]))
    cells: list[Cell] = []
    for i, x0 in enumerate(xs):
        if x0.is_rational:
            cells += _lift(P, polys, box, cache, (x0, x0), x=x0.rational_value(), sides=edges, closed=True)
        else:
            zero = (Fraction(0), Fraction(0))
            cells += [Cell(x0, x0, edges[0], edges[0], None, zero, 0), Cell(x0, x0, edges[0], edges[1], None, zero, 1),
                      Cell(x0, x0, edges[1], edges[1], None, zero, 0)]  # fmt: skip
        if i + 1 < len(xs):
            cells += _lift(P, polys, box, cache, (x0, xs[i + 1]), x=x0.between(xs[i + 1]), sides=edges, closed=True)
    set_areas(P, cells, box, cache)
    return cells


def _value_bounds(P: Polys, bound: Bound, x: Fraction, box: Box, cache: RootCache) -> tuple[Fraction, Fraction]:
    """Rational bounds, at most 2^-14 of the box's height apart, of a side of a cell at the rational x."""
    if bound.value is not None:
        return bound.value, bound.value
    _, _, c, d = box
    return bound_at(P, bound, x, box, cache).narrowed((d - c) / 2**14)


def set_areas(P: Polys, cells: Sequence[Cell], box: Box, cache: RootCache | None = None) -> None:
    """Set the area bounds of the open cells among ``cells``: every side is monotone in x inside a cell (the
    curves' turning x are critical), so between two rational x a side lies between its values there; the
    two end pieces, next to the cell's algebraic ends, count from 0 to their whole height."""
    cache = cache or Roots()
    _, _, c, d = box
    values: dict[tuple[Any, ...], tuple[Fraction, Fraction]] = {}

    def at(bound: Bound, t: Fraction) -> tuple[Fraction, Fraction]:
        key = (bound.value, None if bound.poly is None else P.key(bound.poly), bound.index, t)
        if key not in values:
            values[key] = _value_bounds(P, bound, t, box, cache)
        return values[key]

    for cell in cells:
        if cell.dim != 2:
            continue
        inner_lo, inner_hi, outer_lo, outer_hi = inside(cell.x_lo, cell.x_hi)
        step = (inner_hi - inner_lo) / AREA_STEPS
        ts = [inner_lo + k * step for k in range(AREA_STEPS + 1)]
        ends = (inner_lo - outer_lo) + (outer_hi - inner_hi)  # an upper bound of the end pieces' widths
        low, up = [at(cell.y_lo, t) for t in ts], [at(cell.y_hi, t) for t in ts]
        area_lo = area_hi = Fraction(0)
        for k in range(AREA_STEPS):
            top_min, top_max = min(up[k][0], up[k + 1][0]), max(up[k][1], up[k + 1][1])
            bot_min, bot_max = min(low[k][0], low[k + 1][0]), max(low[k][1], low[k + 1][1])
            area_lo += step * max(Fraction(0), top_min - bot_max)
            area_hi += step * min(d - c, max(Fraction(0), top_max - bot_min))
        cell.area = (area_lo, area_hi + ends * (d - c))


def inside(lo: RealAlgebraic, hi: RealAlgebraic) -> tuple[Fraction, Fraction, Fraction, Fraction]:
    """Two rationals strictly inside (lo, hi), with the pieces outside them a little more than 1/4096 of the
    interval, and a rational at most lo and one at least hi (the isolating intervals are refined on copies)."""
    a, b = RealAlgebraic(lo.poly, lo.lo, lo.hi), RealAlgebraic(hi.poly, hi.lo, hi.hi)
    while True:
        width = b.lo - a.hi
        if width > 0 and (a.hi - a.lo) * 4096 <= width and (b.hi - b.lo) * 4096 <= width:
            return a.hi + width / 4096, b.lo - width / 4096, a.lo, b.hi
        a.refine()
        b.refine()
