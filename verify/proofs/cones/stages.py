"""A cone for four or more rates: boxes turned to the period's eigenvectors, carried stage by stage.

In three or more dimensions of the chart (:class:`verify.proofs.cones.shape.Chart`) the polar values of a polytope's
corners (:mod:`verify.proofs.cones.polar`) are many, and so are the corners of their cone: a search cannot carry them
through a period. So the cone here is a product: in the real eigenbasis of the period's linear part at the
direction d the rates tend to, an interval for each real eigenvector and a polygon for each complex pair
(:func:`verify.proofs.cones.shape.real_blocks`), all of one size R. A linear map sends such a product to the same
product in the basis it maps the eigenbasis to; after each impulse of the period but the last, the polar values are
therefore enclosed in the product of the same blocks in the basis carried so far (by exact central differences of
the rule's impulses, rounded: a shape), each block as wide as its largest gauge among them (:func:`product_cone`).
Only the nonlinear terms widen a stage, by O(R^2); the last impulse's polar values must lie in the cone of the
generators, which the period's contraction leaves room for. Every inclusion is checked exactly by the search
(:func:`verify.proofs.cones.period.close`) and, without this module, by ``tests/certificate_check.py``.

A linear map on four rates that keeps the direction (-1, 0, 0, 0) and halves, thirds and quarters the rest, one
impulse a period: the generators are the 8 corners of a box around the direction, and no stage is enclosed (the
period's last impulse goes back to the generators):

>>> from verify.numbers.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> q = lambda *xs: [K.convert(Fraction(x)) for x in xs]
>>> shrink = lambda x: [x[0], x[1] / 2, x[2] / 3, x[3] / 4]
>>> corners, outer, combine = product_cone(K, q(-1, 0, 0, 0), [0, 1, 2, 3], shrink, p=1,
...                                        points=[q(-1, "1/100", "1/100", 0)])
>>> len(corners), {str(v[0]) for v in corners}, sorted({str(v[1]) for v in corners})
(8, {'-1'}, ['-41/2048', '41/2048'])

Three rates drawn in while a fourth, never hit, stays positive (the run lies by a face of the outgoing rates): the
square around the direction in a chart of two dimensions, lifted by 4 along the fourth rate, and a point of the run
as a combination of its corners and the fourth unit vector (generator 5):

>>> u = q(0, 0, 0, 1)
>>> corners, outer, combine = product_cone(K, q(-1, 0, 0, 0), [0, 1, 2], lambda x: [x[0], x[1] / 2, x[2] / 3, 0],
...                                        p=1, points=[q(-1, "1/100", "1/100", 5)], lift=(u, Fraction(4)))
>>> [[str(x) for x in c] for c in corners[:2]]
[['-1', '41/2048', '41/2048', '4'], ['-1', '41/2048', '-41/2048', '4']]
>>> str(combine(q(-1, "1/100", "1/100", 5), 1, [q(-1, "1/100", "1/100", 5), *corners, u])[5])
'1'
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from verify.numbers.backends.base import Backend
from verify.proofs.cones.lp import solve_columns
from verify.proofs.cones.shape import (
    Block,
    Chart,
    circle,
    jacobian,
    real_blocks,
    round_down,
    round_up,
    rounded_direction,
)

Vector = list[Any]
Carried = list[tuple[Vector, bool]]
Step = Callable[[Vector], "Vector | None"]
Outer = Callable[[int, Carried], "Carried | None"]
Combine = Callable[[Vector, int, Sequence[Vector]], "dict[int, Any] | None"]
#: the rates off the chart that the run holds positive, as a vector u (0 on the chart's rates, its largest
#: entry 1), and the level L of u on the generators: each corner c becomes c + L u (see :func:`product_cone`)
Lift = tuple[Vector, Fraction]


class _Stage:
    """The chart, the carried basis and the blocks' corners and gauges at one impulse of the period."""

    def __init__(self, chart: Chart, basis: list[list[Fraction]], blocks: list[Block], lift: Vector | None = None):
        self.chart, self.basis, self.shapes, self.lift = chart, basis, [], lift
        self._inverse: list[Any] | None = None  # the basis' inverse, by columns, found when first needed
        at = 0
        for cols, sides in blocks:
            width = len(cols)
            self.shapes.append((at, width, circle(sides) if sides else None))
            at += width

    def gauges(self, x: Sequence[Any]) -> list[Fraction] | None:
        """Each block's gauge of x (its size in the block's own shape), or None outside the chart."""
        chart = self.chart
        if self.lift is None and any(x[i] != chart.K.zero for i in chart.off):
            return None  # a rate the chart does not see (a weak generator's): not enclosed here
        y = chart.coords(x)
        if y is None:
            return None
        u = self.coordinates(y)
        if u is None:
            return None
        return [_gauge(u[at : at + width], polygon) for at, width, polygon in self.shapes]

    def coordinates(self, y: Sequence[Fraction]) -> list[Fraction] | None:
        """The chart point y in the carried basis, around the center (the basis' inverse found once, by one exact
        solve for each unit vector); None when the basis is singular."""
        if self._inverse is None:
            from verify.numbers.backends.rational import RationalBackend

            K, n = RationalBackend("python"), len(self.basis)
            self._inverse = [solve_columns(K, self.basis, [Fraction(int(i == j)) for i in range(n)]) for j in range(n)]
        cols = self._inverse
        d = [a - b for a, b in zip(y, self.chart.center)]
        if any(col is None for col in cols):
            return None
        return [sum((col[i] * x for col, x in zip(cols, d)), Fraction(0)) for i in range(len(self.basis))]

    def level(self, x: Sequence[Any]) -> Fraction | None:
        """With a lift u: the largest l with x - s l u >= 0 off the chart (s = x_k / d_k, x's scale in the
        chart), or None when a rate off the chart is negative or there is no lift."""
        chart, u = self.chart, self.lift
        if u is None:
            return None
        K = chart.K
        scale = Fraction(K.to_number(x[chart.k])) / chart.d[chart.k]
        values = [Fraction(K.to_number(x[i])) for i in chart.off]
        if scale <= 0 or any(v < 0 for v in values):
            return None
        return min(v / (scale * Fraction(K.to_number(u[i]))) for i, v in zip(chart.off, values) if u[i] != K.zero)

    def weights(self, x: Sequence[Any], size: Fraction) -> list[Any] | None:
        """x as a non-negative combination of the corners of the box of ``size`` (x inside), in the order of
        :meth:`corners`: the corner made of one vertex of each block gets x_k / d_k times the product of the
        vertices' weights in their blocks, which sum to 1 in each: (1 + s t) / 2 for the ends s = +-1 of an
        interval (t the coordinate over the size), the barycentric weights of the polygon's fan triangle from its
        first corner that holds the point for a polygon; None for a vector outside the box."""
        chart = self.chart
        if self.gauges(x) is None:
            return None
        y = chart.coords(x)
        u = self.coordinates(y)  # type: ignore[arg-type]
        if u is None:
            return None
        per_block = []
        for at, width, polygon in self.shapes:
            t = [v / size for v in u[at : at + width]]
            found = _interval_weights(t[0]) if polygon is None else _fan_weights(t, polygon)
            if found is None:
                return None
            per_block.append(found)
        scale = Fraction(chart.K.to_number(x[chart.k])) / chart.d[chart.k]
        out = []
        for combo in itertools.product(*per_block):
            w = scale
            for part in combo:
                w *= part
            out.append(chart.K.convert(w))
        return out

    def corners(self, sizes: Sequence[Fraction], level: Fraction = Fraction(0)) -> list[Vector]:
        """The corners of the product of the blocks, each of its size (plus ``level`` times the lift)."""
        options = []
        for (_, width, polygon), size in zip(self.shapes, sizes):
            pts = [(Fraction(1),), (Fraction(-1),)] if polygon is None else polygon
            options.append([[size * c for c in pt] for pt in pts] if width else [[]])
        out = []
        for combo in itertools.product(*options):
            t = [c for part in combo for c in part]
            out.append(self.chart.point([c + sum(tj * col[i] for tj, col in zip(t, self.basis)) for i, c in
                                         enumerate(self.chart.center)]))  # fmt: skip
        if self.lift is not None and level:
            up = self.chart.K.convert(level)
            out = [[x + up * w for x, w in zip(c, self.lift)] for c in out]
        return out


def _gauge(u: Sequence[Fraction], polygon: list[tuple[Fraction, Fraction]] | None) -> Fraction:
    """|u| for an interval; for a polygon (corners counter-clockwise around 0) the largest n_i . u / n_i . p_i over
    its edges p_i -> p_(i+1), n_i their outward normals."""
    if polygon is None:
        return abs(u[0])
    out = Fraction(0)
    for p, r in zip(polygon, polygon[1:] + polygon[:1]):
        n = (r[1] - p[1], p[0] - r[0])
        out = max(out, (n[0] * u[0] + n[1] * u[1]) / (n[0] * p[0] + n[1] * p[1]))
    return out


def _stages(
    chart: Chart, on: Sequence[int], step: Step, p: int, blocks: list[Block], *, lift: Vector | None = None
) -> list[_Stage] | None:
    """The stages 0, ..., p - 1: the direction carried by the impulses (rounded), and the eigenbasis carried by the
    Jacobians of the impulses so far, or None when an impulse finds nothing to hit or a chart fails."""
    K = chart.K
    basis = [col for cols, _ in blocks for col in cols]
    out = [_Stage(chart, basis, blocks, lift)]
    direction = chart.point(chart.center)

    def steps(x: Vector | None, n: int) -> Vector | None:
        for _ in range(n):
            x = step(x) if x is not None else None
        return x

    for n in range(1, p):
        nxt = steps(direction, n)
        if nxt is None:
            return None
        here = Chart(K, rounded_direction(K, nxt, on), on)
        if len(here.axes) != len(chart.axes):
            return None
        J = jacobian(chart, lambda x, n=n: steps(x, n), here)  # type: ignore[misc]
        if J is None:
            return None
        carried = [[sum((row[t] * col[t] for t in range(len(col))), Fraction(0)) for row in J] for col in basis]
        out.append(_Stage(here, carried, blocks, lift))
    return out


def product_cone(
    K: Backend,
    direction: Sequence[Any],
    on: Sequence[int],
    step: Step,
    *,
    p: int,
    points: Sequence[Sequence[Any]],
    lift: Lift | None = None,
) -> tuple[list[Vector], Outer, Combine] | None:
    """The generators (the corners of the product at stage 0, wide enough to hold twice every one of ``points``)
    and the enclosure of each later stage (``outer(n, vectors)``: the corners of the product at stage n that holds
    the vectors, or None; at n = p, the vectors themselves, or None when one of them lies outside the cone of the
    generators, seen without linear programming: the points, and so the generators that are not corners, lie in
    the box, and a vector without the weak generators' rates lies in the cone only inside it), and the combination
    of the corners that gives a vector inside the box (``combine(y, first, gens)``, the corners' indices from
    ``first``; each block's own weights: an interval's ends, a polygon's fan triangle), for the p impulses of
    ``step`` (one impulse of the rule, a direction to a direction) around ``direction`` over the rates ``on``.
    None when the chart has fewer than three dimensions (there :func:`verify.proofs.cones.shape.shaped_seeds`),
    when the direction is not drawn in, when the points are far from it, or when a chart fails.

    With a ``lift`` (u, L), for a run that holds positive rates off ``on`` which the period moves but never hits
    (near a face of the outgoing ones when the rates ``on`` tend to 0 against them): every corner is lifted by L u, so
    that the rates off the chart stay positive, and each stage's corners by the lowest level of u among its
    vectors (:meth:`_Stage.level`), with the weak unit vectors off the chart beside them; at n = p a vector
    lies in the cone when it lies in the box and its level is at least L, the rest of its rates off the chart
    then given to the weak unit vectors. Charts of two dimensions are taken too (``step`` must then keep the
    rates off the chart at 0: a shape of the rates ``on`` alone)."""
    chart = Chart(K, direction, on)
    if len(chart.axes) < (2 if lift is not None else 3):
        return None

    def period(x: Vector) -> Vector | None:
        y: Vector | None = x
        for _ in range(p):
            y = step(y) if y is not None else None
        return y

    L = jacobian(chart, period)
    blocks = real_blocks(L) if L is not None else None
    stages = _stages(chart, on, step, p, blocks, lift=lift[0] if lift else None) if blocks else None
    if not stages:
        return None
    sizes = [stages[0].gauges(x) for x in points]
    if any(g is None for g in sizes):
        return None
    size = 2 * max((max(g) for g in sizes if g), default=Fraction(0))
    if size == 0:
        return None
    size = round_up(size)
    scale = max(abs(x) for col in stages[0].basis for x in col)
    if size * scale > chart.top / 4:
        return None  # the points are still far from the direction
    cone = _Product(K, stages, size, lift, chart.off)
    return stages[0].corners([size] * len(stages[0].shapes), cone.base), cone.outer, cone.combine


class _Product:
    """The enclosures and combinations of :func:`product_cone`, for its stages and the generators' box size."""

    def __init__(self, K: Backend, stages: list[_Stage], size: Fraction, lift: Lift | None, off: list[int]):
        self.K, self.stages, self.size, self.lift, self.off = K, stages, size, lift, off
        self.base = lift[1] if lift is not None else Fraction(0)
        n = len(stages[0].chart.d)
        self.weak = [[K.one if i == k else K.zero for i in range(n)] for k in off] if lift is not None else []

    def outer(self, n: int, vectors: Carried) -> Carried | None:
        """The corners of the product at stage n that holds the vectors (and the weak unit vectors off the chart,
        which stay themselves); at n = p, the vectors, or None when one lies outside the generators' cone."""
        K, p, lifted = self.K, len(self.stages), self.lift is not None
        stage = self.stages[n % p]
        vectors = [(v, s) for v, s in vectors if not _along(K, v, self.weak)]
        found = [stage.gauges(v) for v, _ in vectors]
        levels = [stage.level(v) for v, _ in vectors] if lifted else []
        if n == p:  # back at the generators: a vector the chart sees outside their box is outside their cone
            if any(x is None or x < self.base for x in levels):
                return None
            return None if any(g is not None and max(g) > self.size for g in found) else vectors
        if any(g is None for g in found) or any(x is None for x in levels):
            return None
        widths = [round_up(max(g[b] for g in found) or self.size / 2**16) for b in range(len(stage.shapes))]  # type: ignore[index]
        level = round_down(min(x for x in levels if x is not None)) if levels else Fraction(0)
        return [(v, True) for v in stage.corners(widths, level)] + [(list(e), False) for e in self.weak]

    def combine(self, y: Vector, first: int, gens: Sequence[Vector]) -> dict[int, Any] | None:
        """y as a combination of the generators (the corners' indices from ``first``; the weak unit vectors found in
        ``gens``), or None outside the box or below the lift."""
        K = self.K

        def unit(k: int) -> int | None:  # the index of the weak unit vector e_k among the generators
            return next((j for j, g in enumerate(gens) if list(g) == self.weak[self.off.index(k)]), None)

        if _along(K, y, self.weak):  # a weak unit vector's multiple: itself
            k = next(i for i, x in enumerate(y) if x != K.zero)
            at = unit(k)
            return None if at is None else {at: y[k]}
        w = self.stages[0].weights(y, self.size)
        if w is None:
            return None
        out = {first + i: x for i, x in enumerate(w) if x != K.zero}
        total = sum(w, K.zero)
        for k in self.off if self.weak else ():  # what y holds off the chart beyond the lifted corners' goes to e_k
            rest = y[k] - total * K.convert(self.base) * self.lift[0][k]  # type: ignore[index]
            at = unit(k)
            if K.sign(rest) < 0 or (at is None and rest != K.zero):
                return None
            if rest != K.zero:
                out[at] = rest  # type: ignore[index]
        return out


def _interval_weights(t: Fraction) -> list[Fraction] | None:
    """The weights of the ends +1, -1 of [-1, 1] that give t, or None outside it."""
    return None if abs(t) > 1 else [(1 + t) / 2, (1 - t) / 2]


def _fan_weights(t: Sequence[Fraction], polygon: list[tuple[Fraction, Fraction]]) -> list[Fraction] | None:
    """The weights of the polygon's corners that give the point t: barycentric in the first triangle
    (corner 0, corner i, corner i + 1) that holds it; None when none does (t outside the polygon)."""
    (x0, y0), (x, y) = polygon[0], (t[0], t[1])
    for i in range(1, len(polygon) - 1):
        (x1, y1), (x2, y2) = polygon[i], polygon[i + 1]
        det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if det == 0:
            continue
        b = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / det
        c = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / det
        if b >= 0 and c >= 0 and b + c <= 1:
            out = [Fraction(0)] * len(polygon)
            out[0], out[i], out[i + 1] = 1 - b - c, b, c
            return out
    return None


def _along(K: Backend, v: Sequence[Any], units: Sequence[Vector]) -> bool:
    """Whether v is a positive multiple of one of the unit vectors ``units``."""
    nonzero = [i for i, x in enumerate(v) if x != K.zero]
    return len(nonzero) == 1 and K.sign(v[nonzero[0]]) > 0 and any(u[nonzero[0]] != K.zero for u in units)
