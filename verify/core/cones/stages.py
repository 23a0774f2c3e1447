"""A cone for four or more rates: boxes turned to the period's eigenvectors, carried stage by stage.

In three or more dimensions of the chart (:class:`verify.core.cones.shape.Chart`) the polar values of a polytope's
corners (:mod:`verify.core.cones.polar`) are many, and so are the corners of their cone: a search cannot carry them
through a period. So the cone here is a product: in the real eigenbasis of the period's linear part at the
direction d the rates tend to, an interval for each real eigenvector and a polygon for each complex pair
(:func:`verify.core.cones.shape.real_blocks`), all of one size R. A linear map sends such a product to the same
product in the basis it maps the eigenbasis to; after each impulse of the period but the last, the polar values are
therefore enclosed in the product of the same blocks in the basis carried so far (by exact central differences of
the rule's impulses, rounded: a shape), each block as wide as its largest gauge among them (:func:`product_cone`).
Only the nonlinear terms widen a stage, by O(R^2); the last impulse's polar values must lie in the cone of the
generators, which the period's contraction leaves room for. Every inclusion is checked exactly by the search
(:func:`verify.core.cones.period.close`) and, without this module, by ``tests/certificate_check.py``.

A linear map on four rates that keeps the direction (-1, 0, 0, 0) and halves, thirds and quarters the rest, one
impulse a period: the generators are the 8 corners of a box around the direction, and no stage is enclosed (the
period's last impulse goes back to the generators):

>>> from verify.core.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> q = lambda *xs: [K.convert(Fraction(x)) for x in xs]
>>> shrink = lambda x: [x[0], x[1] / 2, x[2] / 3, x[3] / 4]
>>> corners, outer, combine = product_cone(K, q(-1, 0, 0, 0), [0, 1, 2, 3], shrink, p=1,
...                                        points=[q(-1, "1/100", "1/100", 0)])
>>> len(corners), {str(v[0]) for v in corners}, sorted({str(v[1]) for v in corners})
(8, {'-1'}, ['-41/2048', '41/2048'])
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from verify.core.cones.lp import solve_columns
from verify.core.cones.shape import Block, Chart, circle, jacobian, real_blocks, round_up, rounded_direction

Vector = list[Any]
Carried = list[tuple[Vector, bool]]
Step = Callable[[Vector], "Vector | None"]
Outer = Callable[[int, Carried], "Carried | None"]
Combine = Callable[[Vector, int], "dict[int, Any] | None"]


class _Stage:
    """The chart, the carried basis and the blocks' corners and gauges at one impulse of the period."""

    def __init__(self, chart: Chart, basis: list[list[Fraction]], blocks: list[Block]):
        self.chart, self.basis, self.shapes = chart, basis, []
        at = 0
        for cols, sides in blocks:
            width = len(cols)
            self.shapes.append((at, width, circle(sides) if sides else None))
            at += width

    def gauges(self, x: Sequence[Any]) -> list[Fraction] | None:
        """Each block's gauge of x (its size in the block's own shape), or None outside the chart."""
        from verify.core.backends.rational import RationalBackend

        chart = self.chart
        if any(x[i] != chart.K.zero for i in range(len(x)) if i != chart.k and i not in chart.axes):
            return None  # a rate the chart does not see (a weak generator's): not enclosed here
        y = chart.coords(x)
        if y is None:
            return None
        u = solve_columns(RationalBackend("python"), self.basis, [a - b for a, b in zip(y, chart.center)])
        if u is None:
            return None
        return [_gauge(u[at : at + width], polygon) for at, width, polygon in self.shapes]

    def weights(self, x: Sequence[Any], size: Fraction) -> list[Any] | None:
        """x as a non-negative combination of the corners of the box of ``size`` (every block an interval, x inside):
        the corner of signs s gets x_k / d_k times prod_j (1 + s_j t_j) / 2, t the coordinates of x over the size
        (the multilinear weights, which sum to 1); None for a polygon block or a vector outside the box."""
        chart = self.chart
        if any(polygon is not None for _, _, polygon in self.shapes) or self.gauges(x) is None:
            return None
        from verify.core.backends.rational import RationalBackend

        y = chart.coords(x)
        u = solve_columns(RationalBackend("python"), self.basis, [a - b for a, b in zip(y, chart.center)])  # type: ignore[arg-type]
        t = [v / size for v in u]  # type: ignore[union-attr]
        if any(abs(v) > 1 for v in t):
            return None
        scale = Fraction(chart.K.to_number(x[chart.k])) / chart.d[chart.k]
        out = []
        for signs in itertools.product((1, -1), repeat=len(t)):
            w = scale
            for sj, tj in zip(signs, t):
                w *= (1 + sj * tj) / 2
            out.append(chart.K.convert(w))
        return out

    def corners(self, sizes: Sequence[Fraction]) -> list[Vector]:
        """The corners of the product of the blocks, each of its size."""
        options = []
        for (_, width, polygon), size in zip(self.shapes, sizes):
            pts = [(Fraction(1),), (Fraction(-1),)] if polygon is None else polygon
            options.append([[size * c for c in pt] for pt in pts] if width else [[]])
        out = []
        for combo in itertools.product(*options):
            t = [c for part in combo for c in part]
            out.append(self.chart.point([c + sum(tj * col[i] for tj, col in zip(t, self.basis)) for i, c in
                                         enumerate(self.chart.center)]))  # fmt: skip
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


def _stages(chart: Chart, on: Sequence[int], step: Step, p: int, blocks: list[Block]) -> list[_Stage] | None:
    """The stages 0, ..., p - 1: the direction carried by the impulses (rounded), and the eigenbasis carried by the
    Jacobians of the impulses so far, or None when an impulse finds nothing to hit or a chart fails."""
    K = chart.K
    basis = [col for cols, _ in blocks for col in cols]
    out = [_Stage(chart, basis, blocks)]
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
        out.append(_Stage(here, carried, blocks))
    return out


def product_cone(
    K: Any, direction: Sequence[Any], on: Sequence[int], step: Step, *, p: int, points: Sequence[Sequence[Any]]
) -> tuple[list[Vector], Outer, Combine] | None:
    """The generators (the corners of the product at stage 0, wide enough to hold twice every one of ``points``)
    and the enclosure of each later stage (``outer(n, vectors)``: the corners of the product at stage n that holds
    the vectors, or None; at n = p, the vectors themselves, or None when one of them lies outside the cone of the
    generators, seen without linear programming: the points, and so the generators that are not corners, lie in
    the box, and a vector without the weak generators' rates lies in the cone only inside it), and the combination
    of the corners that gives a vector inside the box (``combine(y, first)``, the corners' indices from
    ``first``; None where a block is a polygon), for the p impulses of ``step`` (one impulse of the rule, a
    direction to a direction) around ``direction`` over the rates ``on``. None when the chart has fewer than
    three dimensions (there :func:`verify.core.cones.shape.shaped_seeds`), when the direction is not drawn in,
    when the points are far from it, or when a chart fails."""
    chart = Chart(K, direction, on)
    if len(chart.axes) < 3:
        return None

    def period(x: Vector) -> Vector | None:
        y: Vector | None = x
        for _ in range(p):
            y = step(y) if y is not None else None
        return y

    L = jacobian(chart, period)
    blocks = real_blocks(L) if L is not None else None
    stages = _stages(chart, on, step, p, blocks) if blocks else None
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

    def outer(n: int, vectors: Carried) -> Carried | None:
        stage = stages[n % p]
        found = [stage.gauges(v) for v, _ in vectors]
        if n == p:  # back at the generators: a vector the chart sees outside their box is outside their cone
            return None if any(g is not None and max(g) > size for g in found) else vectors
        if any(g is None for g in found):
            return None
        widths = [round_up(max(g[b] for g in found) or size / 2**16) for b in range(len(stage.shapes))]  # type: ignore[index]
        return [(v, True) for v in stage.corners(widths)]

    def combine(y: Vector, first: int) -> dict[int, Any] | None:
        w = stages[0].weights(y, size)
        return None if w is None else {first + i: x for i, x in enumerate(w) if x != K.zero}

    return stages[0].corners([size] * len(stages[0].shapes)), outer, combine
