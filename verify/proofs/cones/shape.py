"""Seeds of a cone shaped by the period map: a polytope around the direction the rates tend to.

Near the direction d the rates tend to (a fixed point of the period map on directions), the map is close to its
linear part. Seen in the chart ``x_k = d_k`` (k the largest entry of d), that is a matrix L whose eigenvalues are
the ratios of the other eigenvalues of the period's derivative to its growth along d: the direction is drawn in
when each has modulus below 1. In the real eigenbasis of L (a column for each real eigenvalue, the real and
imaginary parts of the eigenvector for each complex pair), L maps the polytope

    { sum_b gauge_b(u_b) <= R }   (|u_b| for a real column, a regular polygon's gauge for a complex pair)

into itself when every modulus is below the polygons' inner radius, ``cos(pi / sides)``: the seeds are its
corners, ``d + R c`` and ``d - R c`` for each real column c, the polygon's corners for each complex pair, R twice
the rates' own gauge so that they lie inside. The period map is not linear, nor is the cone closed here: the
seeds are a shape, found with rounded numbers (central differences in exact rationals; mpmath's eigenvectors, but
for a spiral in a plane), and :func:`verify.proofs.cones.period.close` checks every inclusion in
exact arithmetic, carrying multiple impulses by their polar values (:mod:`verify.proofs.cones.polar`).

A map that turns the directions around (-1, 0, 0) by 45 degrees and shrinks them by 1/sqrt(2) (a spiral: one
complex pair):

>>> from verify.numbers.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> q = lambda *xs: [K.convert(Fraction(x)) for x in xs]
>>> turn = lambda x: [x[0], (x[1] - x[2]) / 2, (x[1] + x[2]) / 2]
>>> corners = shaped_seeds(K, q(-1, 0, 0), [0, 1, 2], turn, [q(-1, "1/100", 0)])
>>> len(corners), {str(v[0]) for v in corners}, max(abs(v[1]) for v in corners) < Fraction(1, 10)
(16, {'-1'}, True)

Two real eigenvalues: the corners of a square turned to the eigenvectors (a cross-polytope):

>>> [[str(x) for x in v] for v in shaped_seeds(K, q(-1, 0, 0), [0, 1, 2], lambda x: [x[0], x[1] / 2, x[2] / 3],
...                                             [q(-1, "1/100", 0)])]
[['-1', '41/2048', '0'], ['-1', '-41/2048', '0'], ['-1', '0', '41/2048'], ['-1', '0', '-41/2048']]

A direction that is not drawn in (a modulus of 1) gets none:

>>> shaped_seeds(K, q(-1, 0, 0), [0, 1, 2], lambda x: [x[0], x[1], x[2] / 3], [q(-1, "1/100", 0)])
[]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import mpmath

from verify.numbers.backends.base import Backend
from verify.proofs.cones.lp import solve_columns

Vector = list[Any]
#: the largest modulus of a complex pair of the chart's eigenvalues for which seeds are made: a direction turned
#: and drawn in more slowly than this needs a polygon of more sides than :data:`SIDES`
MAX_MODULUS = Fraction(63, 64)
#: the bound of a real eigenvalue's modulus (not reached): its interval is scaled by it exactly, so any contraction
#: will do, and whether the nonlinear terms leave it room is decided by the search
REAL_MODULUS = Fraction(1)
#: the polygon of a complex pair: the fewest sides whose inner radius cos(pi / sides) exceeds the modulus by 1/16
SIDES = (4, 8, 16, 32)


def shaped_seeds(
    K: Backend,
    direction: Sequence[Any],
    on: Sequence[int],
    period_map: Callable[[Vector], Vector | None],
    points: Sequence[Sequence[Any]],
) -> list[Vector]:
    """The corners of a polytope around ``direction`` (rationals) shaped by the linear part of ``period_map``
    there (a direction to a direction), wide enough to hold every one of ``points`` (module docstring). The
    chart runs over the entries ``on`` (the rates hit in a period; the others are 0 in the corners, for the weak
    generators of the cone to add). Empty when the direction is not drawn in (a modulus of 1, or a turning pair's
    of at least :data:`MAX_MODULUS`), when the points are still far from it, or when the chart fails."""
    chart = Chart(K, direction, on)
    if not chart.axes:
        return []
    L = jacobian(chart, period_map)
    blocks = real_blocks(L) if L is not None else None
    if not blocks:
        return []
    starts = [chart.coords(x) for x in points]
    if any(s is None for s in starts):
        return []
    return _corners(K, chart.point, chart.center, blocks, starts, top=chart.top)  # type: ignore[arg-type]


class Chart:
    """The chart ``x_k = d_k`` through a direction d (rationals) over the entries ``on``, k the largest of them:
    a rate vector x (x_k of d_k's sign) is seen as ``x_i d_k / x_k`` for the other entries of ``on``
    (:attr:`axes`); :attr:`center` is d's own, :attr:`off` the entries the chart does not see."""

    def __init__(self, K: Backend, direction: Sequence[Any], on: Sequence[int]):
        self.K = K
        self.d = d = [Fraction(K.to_number(x)) for x in direction]
        live = [i for i in on if d[i] != 0]
        self.k = max(live, key=lambda i: abs(d[i])) if live else -1
        self.axes = [i for i in on if i != self.k] if live and len(on) >= 2 else []
        self.center = [d[i] for i in self.axes]
        self.top = abs(d[self.k]) if live else Fraction(0)
        self.off = [i for i in range(len(d)) if i != self.k and i not in self.axes]

    def coords(self, x: Sequence[Any]) -> list[Fraction] | None:
        """x in the chart, or None when x_k is 0 or of the other sign."""
        y = [Fraction(self.K.to_number(v)) for v in x]
        k = self.k
        if y[k] == 0 or (y[k] > 0) != (self.d[k] > 0):
            return None
        return [y[i] * self.d[k] / y[k] for i in self.axes]

    def point(self, c: Sequence[Fraction]) -> Vector:
        """The rate vector at chart coordinates c (0 off ``on``)."""
        out = [Fraction(0)] * len(self.d)
        out[self.k] = self.d[self.k]
        for i, x in zip(self.axes, c):
            out[i] = x
        return [self.K.convert(x) for x in out]


def jacobian(
    chart: Chart, period_map: Callable[[Vector], Vector | None], into: Chart | None = None
) -> list[list[Fraction]] | None:
    """The Jacobian of ``period_map`` at the chart's center, from ``chart`` to ``into`` (default: the same chart),
    rows by the entries of ``into``: exact central differences of step 2^-20 of the direction's size, each entry
    rounded to a denominator of at most 2^24 (a shape), or None when a chart fails."""
    out = into if into is not None else chart
    h = chart.top / 2**20
    cols = []
    for t in range(len(chart.axes)):
        ends = []
        for sign in (1, -1):
            c = list(chart.center)
            c[t] += sign * h
            y = period_map(chart.point(c))
            ends.append(out.coords(y) if y is not None else None)
        if ends[0] is None or ends[1] is None:
            return None
        cols.append([((u - w) / (2 * h)).limit_denominator(2**24) for u, w in zip(*ends)])
    return [[cols[j][i] for j in range(len(cols))] for i in range(len(out.axes))]


Block = tuple[list[list[Fraction]], int]  #: (one real column, or the real and imaginary parts of a complex pair; sides)


def real_blocks(L: list[list[Fraction]]) -> list[Block] | None:
    """The real eigenbasis of L in blocks, each with the sides of its polygon (0 for a real column), or None when
    a real eigenvalue has a modulus of at least :data:`REAL_MODULUS`, or a complex pair one of :data:`MAX_MODULUS`.
    A 2 x 2 matrix with complex eigenvalues alpha +- i beta (a spiral) takes the exact eigenvector (b, lambda - a)
    (beta rounded to 24 bits) and a polygon of 16 sides; otherwise mpmath's eigenvectors at 30 digits, rounded to 24
    bits, and polygons of the fewest sides each modulus allows (every corner adds polar values to carry)."""
    m = len(L)
    if m == 2:
        (a, bb), (c, dd) = L
        disc = (a - dd) ** 2 + 4 * bb * c
        if disc < 0 and bb != 0:
            alpha, beta = (a + dd) / 2, _root(-disc, 24) / 2
            modulus2 = alpha * alpha + beta * beta
            if modulus2 >= MAX_MODULUS**2:
                return None
            return [([[bb, alpha - a], [Fraction(0), beta]], 16)]  # a spiral in a plane: 16 sides, a polygon alone
    with mpmath.workdps(30):
        A = mpmath.matrix([[mpmath.mpf(x.numerator) / x.denominator for x in row] for row in L])
        values, vectors = mpmath.eig(A)
        bound = mpmath.mpf(MAX_MODULUS.numerator) / MAX_MODULUS.denominator
        blocks: list[Block] = []
        for n, lam in enumerate(values):
            real = abs(mpmath.im(lam)) <= abs(lam) * mpmath.mpf(10) ** -20
            if abs(lam) >= (mpmath.mpf(REAL_MODULUS.numerator) / REAL_MODULUS.denominator if real else bound):
                return None
            vec = [vectors[i, n] for i in range(m)]
            top = max(vec, key=abs)
            vec = [x / top for x in vec]  # the largest entry 1: a real eigenvector has real entries
            if real:
                blocks.append(([_short([mpmath.re(x) for x in vec])], 0))
            elif mpmath.im(lam) > 0:
                modulus2 = Fraction(int(mpmath.nint(abs(lam) ** 2 * 2**24)) + 1, 2**24)  # rounded up
                parts = [_short([mpmath.re(x) for x in vec]), _short([mpmath.im(x) for x in vec])]
                blocks.append((parts, _sides(modulus2)))
    return blocks if sum(len(cols) for cols, _ in blocks) == m else None


def _short(xs: Sequence[Any], bits: int = 24) -> list[Fraction]:
    """mpmath numbers as rationals of ``bits`` bits after the point, scaled to a largest entry of 1."""
    top = max(abs(x) for x in xs) or mpmath.mpf(1)
    return [Fraction(int(mpmath.nint(x / top * 2**bits)), 2**bits) for x in xs]


def _sides(modulus2: Fraction) -> int:
    """The fewest sides of :data:`SIDES` whose polygon's inner radius exceeds the modulus (given squared) by 1/16."""
    for n in SIDES:
        if (modulus2.numerator * 256) < _inner2(n) * modulus2.denominator * 225:
            return n
    return SIDES[-1]


def _inner2(n: int) -> Fraction:
    """cos(pi / n)^2 from below (exact for 4, bounds from below otherwise), for :func:`_sides`."""
    return {4: Fraction(1, 2), 8: Fraction(853, 1000), 16: Fraction(961, 1000), 32: Fraction(990, 1000)}[n]


def _corners(
    K: Backend,
    point: Callable[[Sequence[Fraction]], Vector],
    c0: list[Fraction],
    blocks: list[Block],
    starts: list[list[Fraction]],
    *,
    top: Fraction,
) -> list[Vector]:
    """The corners of the polytope (module docstring) with R twice the largest 1-norm of the starts' coordinates
    in the basis (rounded up to 8 significant bits; a block's gauge is at most sqrt(2) times its 1-norm), each
    rounded to short numbers; none when R times the basis reaches top / 4."""
    from verify.numbers.backends.rational import RationalBackend

    Q = RationalBackend("python")
    basis = [col for cols, _ in blocks for col in cols]
    size = Fraction(0)
    for s in starts:
        u = solve_columns(Q, basis, [x - y for x, y in zip(s, c0)])
        if u is None:
            return []
        size = max(size, 2 * sum(abs(x) for x in u))
    if size == 0:
        return []
    radius = round_up(size)
    scale = max(abs(x) for col in basis for x in col)
    if radius * scale > top / 4:
        return []  # the rates are still far from the direction: a polytope that wide does not close
    unit = radius * scale / 2**16  # the corners rounded to short numbers
    shifts: list[list[Fraction]] = []
    for cols, sides in blocks:
        if not sides:
            shifts += [[radius * x for x in cols[0]], [-radius * x for x in cols[0]]]
            continue
        for cs, sn in circle(sides):
            shifts.append([radius * (cs * x + sn * y) for x, y in zip(*cols)])
    return [point([x + round(s / unit) * unit for x, s in zip(c0, shift)]) for shift in shifts]


def exponent(q: Fraction) -> int:
    """The e with 2^(e-1) <= q < 2^e (q > 0), from the exact integers of q.

    >>> exponent(Fraction(1, 3)), exponent(Fraction(4))
    (-1, 3)
    """
    e = q.numerator.bit_length() - q.denominator.bit_length()
    while Fraction(2) ** e <= q:
        e += 1
    while Fraction(2) ** (e - 1) > q:
        e -= 1
    return e


def floor_bits(q: Fraction, bits: int) -> tuple[Fraction, Fraction]:
    """(q rounded down to ``bits`` significant bits, a unit of that last bit) for q != 0: a short rational at most q,
    within one unit of it.

    >>> floor_bits(Fraction(1, 3), 4), floor_bits(Fraction(-1, 3), 4)
    ((Fraction(5, 16), Fraction(1, 32)), (Fraction(-11, 32), Fraction(1, 32)))
    """
    unit = Fraction(2) ** (exponent(abs(q)) - bits)
    return Fraction(math.floor(q / unit)) * unit, unit


def round_up(x: Fraction) -> Fraction:
    """x rounded up to 8 significant bits (x > 0): a short size that is at least x.

    >>> round_up(Fraction(1, 3))
    Fraction(171, 512)
    """
    return math.ceil(x / _unit(x)) * _unit(x)


def round_down(x: Fraction) -> Fraction:
    """x rounded down to 8 significant bits (0 for x <= 0): a short level that is at most x.

    >>> round_down(Fraction(1, 3))
    Fraction(85, 256)
    """
    return math.floor(x / _unit(x)) * _unit(x) if x > 0 else Fraction(0)


def _unit(x: Fraction) -> Fraction:
    """A power of 2 near 2^-8 x (x > 0): the 8th significant bit, or the 9th."""
    return Fraction(2) ** (x.numerator.bit_length() - x.denominator.bit_length() - 8)


def rounded_direction(K: Backend, v: Sequence[Any], on: Sequence[int], bits: int = 64) -> Vector:
    """v / max |v_i| over i in ``on``, each entry rounded down to a multiple of 2^-bits (exact integers): a
    direction in short numbers.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> [str(x) for x in rounded_direction(K, [K.convert(Fraction(-3)), K.one], [0], bits=4)]
    ['-1', '5/16']
    """
    values = [Fraction(K.to_number(x)) for x in v]
    top = max(abs(values[i]) for i in on)
    out = []
    for x in values:
        q = x * 2**bits / top
        out.append(K.convert(Fraction(q.numerator // q.denominator, 2**bits)))
    return out


def _root(q: Fraction, bits: int = 64) -> Fraction:
    """A rational within 2^-bits relative of sqrt(q) (q > 0), from integer square roots."""
    scale = 4**bits
    return Fraction(math.isqrt(q.numerator * scale * q.denominator), 2**bits * q.denominator)


def circle(sides: int) -> list[tuple[Fraction, Fraction]]:
    """``sides`` points near the unit circle, nearly evenly spaced: (1, 0) turned again and again by the
    rational rotation ``((1 - t^2, -2t), (2t, 1 - t^2)) / (1 + t^2)`` with t near tan(pi / sides) (a few terms of
    its series at pi ~ 355/113), each rounded to 20 bits. Exact rationals throughout; the polygon need not be
    regular.

    >>> [(round(float(x), 3), round(float(y), 3)) for x, y in circle(4)]
    [(1.0, 0.0), (0.003, 1.0), (-1.0, 0.007), (-0.01, -1.0)]
    """
    x = Fraction(355, 113) / sides
    t = x + x**3 / 3 + 2 * x**5 / 15 + 17 * x**7 / 315
    c, s = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
    out, point = [], (Fraction(1), Fraction(0))
    for _ in range(sides):
        out.append(tuple(Fraction(round(v * 2**20), 2**20) for v in point))
        point = (c * point[0] - s * point[1], s * point[0] + c * point[1])
    return out  # type: ignore[return-value]
