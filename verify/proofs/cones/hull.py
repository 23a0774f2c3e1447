"""A cone around the run's own points, with slack: for runs that switch between impact sets in no period.

Some runs never settle into one period, nor tend to one direction: a five-ball cradle under the
general rule hits (1,3) every other impulse, and (0,2) or (2) between, as the sign of one rate
decides, and that rate crosses 0 again and again without tending to it. Every impulse is linear
there (single impacts, or constraints that are mutually orthogonal), so the run is a *switched*
linear system: a map per impact set, the one taken chosen by the signs of the rates. The points
it visits (every p impulses, scaled) do not converge, so no cone grown from the carried vectors one
at a time closes: each round adds the next points of the orbit.

The orbit is bounded, though, and each map draws it in. So the cone of the orbit's points,
*pushed out* from their center by a fixed slack, is mapped into itself: the points carried from its
edges land inside the slack. Pushing out must not cross a face the orbit keeps to (a rate that is 0
at every point, or of one sign at every point: moving past it would change an impact set), so the
pushed cone is cut by those faces again. This is a rational polyhedral computation (the cone of
many points, reduced to its extreme rays; a cone intersected with half-spaces), made by the Parma
Polyhedra Library (``pplpy``) in exact integers.

The cone found here is then closed under p impulses by :func:`verify.proofs.cones.period.close`, and
its certificate is the same "invariant cone of a period" (carried with every impact set its signs
allow, cut at every x_f = 0): what makes it a proof is checked there, and again by the independent
checker. The orbit, the hull and the slack only choose the generators.

>>> from fractions import Fraction
>>> from verify.numbers.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> points = [[K.convert(Fraction(x)), K.convert(Fraction(-1))] for x in ("0", "1/2", "1/8")]
>>> [[str(x) for x in g] for g in pushed_cone(K, points, Fraction(1, 4))]  # pushed out, but x_0 >= 0 is kept
[['9', '-16'], ['0', '-1']]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from verify import bounds
from verify.numbers.backends.base import Backend
from verify.proofs.cones.shape import floor_bits

#: the periods of the orbit whose points the cone is built from
HULL_PERIODS = 400
#: the most extreme rays a pushed cone may have (each a generator of the cone closed afterwards)
MAX_HULL_RAYS = 200
#: the slacks tried, smallest first: the cone of the orbit pushed out from its center by this share
SLACKS = (Fraction(1, 64), Fraction(1, 16), Fraction(1, 4))
#: the periods over which the constraints the run hits are collected
HIT_PERIODS = 16
#: the most rounds of growing a pushed cone by the points it does not map into itself
HULL_ROUNDS = 30
#: significant bits kept of each point of the orbit (the points only choose generators)
ORBIT_BITS = 40

Vector = list[Any]


def available() -> bool:
    """Whether the Parma Polyhedra Library is installed (``pplpy``, a dependency on Linux and macOS)."""
    try:
        import ppl  # noqa: F401
    except ImportError:  # pragma: no cover - a platform without pplpy's wheels
        return False
    return True


def orbit(
    K: Backend, step: Callable[[Vector], Vector | None], b: Sequence[Any], p: int, periods: int = HULL_PERIODS
) -> list[Vector] | None:
    """The points of the run from b every p impulses of ``step`` (b first), each scaled to a largest rate of 1 and
    rounded to :data:`ORBIT_BITS` significant bits (a rate of 0 stays 0); None when the run exits.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> half = lambda x: [x[0], x[1] / 2]
    >>> [[str(v) for v in x] for x in orbit(K, half, [K.convert(Fraction(-4)), K.one], 1, periods=2)]
    [['-1', '1/4'], ['-1', '1/8'], ['-1', '1/16']]
    """
    x: Vector | None = rounded_point(K, b)
    out = []
    for _ in range(periods):
        assert x is not None
        out.append(x)
        for _ in range(p):
            x = step(x) if x is not None else None
        if x is None:
            return None
        x = rounded_point(K, x)
    assert x is not None
    return [*out, x]


def rounded_point(K: Backend, x: Sequence[Any]) -> Vector:
    """x over its largest |rate|, each rate rounded to :data:`ORBIT_BITS` significant bits (exact rationals)."""
    values = [Fraction(K.to_number(v)) for v in x]
    top = max(abs(v) for v in values)
    out = []
    for v in values:
        out.append(K.convert(floor_bits(v / top, ORBIT_BITS)[0]) if v else K.zero)
    return out


def pushed_cone(K: Backend, points: Sequence[Vector], slack: Fraction) -> list[Vector] | None:
    """The extreme rays of the cone of ``points`` pushed out from their center by ``slack`` and cut again by the faces
    the points keep to (a rate 0 at every point, or of one sign at every point), each ray as integers; None when that
    cone holds a line or has more than :data:`MAX_HULL_RAYS` rays (the bound ``hull_rays``).

    Each extreme ray g of the points' cone, scaled to a largest rate of 1, becomes ``g + slack (g - c)``, c the mean
    of those rays: the cone grows on every side by that share of its width, the points' cone inside it."""
    import ppl

    r = len(points[0])
    exact = [_fractions(K, v) for v in points]
    rays = _rays(_cone(exact, r))
    if rays is None:
        return None
    unit = [[q / max(abs(x) for x in g) for q in g] for g in rays]
    center = [sum(col) / len(unit) for col in zip(*unit)]
    pushed = _cone([[q + slack * (q - c) for q, c in zip(g, center)] for g in unit], r)
    x = [ppl.Variable(i) for i in range(r)]
    for j in range(r):
        signs = {(v[j] > 0) - (v[j] < 0) for v in exact}
        if signs == {0}:
            pushed.add_constraint(x[j] == 0)
        elif signs <= {0, 1}:
            pushed.add_constraint(x[j] >= 0)
        elif signs <= {0, -1}:
            pushed.add_constraint(x[j] <= 0)
    out = _rays(pushed)
    if out is None or len(out) > MAX_HULL_RAYS:
        if out is not None:
            bounds.reached("hull_rays")
        return None
    bounds.use("hull_rays", len(out))
    return [[K.convert(q) for q in g] for g in out]


def grown_cone(
    K: Backend,
    points: Sequence[Vector],
    slack: Fraction,
    carried: Callable[[list[Vector]], list[Vector] | None],
    rounds: int = HULL_ROUNDS,
) -> list[Vector] | None:
    """A pushed cone (:func:`pushed_cone`) of the points that ``carried`` (the vectors its generators become after a
    period, or None when a period cannot carry them) maps into itself: each round adds the carried vectors that lie
    outside to the points and pushes their cone out again. None when the rounds run out (the bound ``hull_rounds``),
    or a cone cannot be pushed or carried. Whether the cone is closed is decided again, with every sign exact, by
    :func:`verify.proofs.cones.period.close`: here the points only grow.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> shear = lambda gens: [[x[0] + x[1] / 4, x[1]] for x in gens]  # draws every ray towards (1, 0)
    >>> gens = grown_cone(K, [[K.one, K.one]], Fraction(1, 16), shear)
    >>> len(gens), [K.one, K.zero] in gens  # from (1, 1) a little beyond, down to (1, 0)
    (2, True)
    >>> quarter = lambda gens: [[-x[1], x[0]] for x in gens]  # a quarter turn: no cone is mapped into itself
    >>> grown_cone(K, [[K.one, K.one]], Fraction(1, 16), quarter) is None
    True
    """
    points = list(points)
    for done in range(1, rounds + 1):
        gens = pushed_cone(K, points, slack)
        moved = None if gens is None else carried(gens)
        if gens is None or moved is None:
            return None
        cone = _cone([_fractions(K, g) for g in gens], len(gens[0]))
        outside = [y for y in moved if not _holds(cone, _fractions(K, y))]
        if not outside:
            bounds.use("hull_rounds", done)
            return gens
        points += [rounded_point(K, y) for y in outside]
    bounds.reached("hull_rounds")
    return None


def extreme_rays(K: Backend, vectors: Sequence[tuple[Vector, bool]]) -> list[tuple[Vector, bool]] | None:
    """The extreme rays of the cone of the vectors, as integers, each strict, when every vector is strict and not 0
    (each point of their cone then has weight on a strict one); None when one is not, or their cone holds a line:
    the carried vectors of :func:`verify.proofs.cones.period.carry` reduced without linear programming. (A strict
    vector 0 is a point the period sends to rates 0, which exit: it must stay, for the linear programming to refuse.)

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> v = [[K.one, K.zero], [K.one, K.one], [K.zero, K.convert(Fraction(1, 2))]]
    >>> sorted([str(x) for x in g] for g, _ in extreme_rays(K, [(x, True) for x in v]))
    [['0', '1'], ['1', '0']]
    """
    exact = [_fractions(K, v) for v, _ in vectors]
    if not vectors or not all(s for _, s in vectors) or not all(any(v) for v in exact):
        return None
    rays = _rays(_cone(exact, len(exact[0])))
    if not rays:
        return None
    return [([K.convert(q) for q in g], True) for g in rays]


def _holds(cone: Any, v: Sequence[Fraction]) -> bool:
    """Whether the cone (a PPL polyhedron) holds the ray of v (exactly)."""
    import ppl

    if not any(v):
        return True
    scale = math.lcm(*(q.denominator for q in v))
    ray = ppl.ray(sum((int(q * scale) * ppl.Variable(i) for i, q in enumerate(v)), ppl.Linear_Expression()))
    return bool(cone.relation_with(ray).implies(ppl.Poly_Gen_Relation.subsumes()))


def _fractions(K: Backend, v: Sequence[Any]) -> list[Fraction]:
    return [Fraction(K.to_number(x)) for x in v]


def _cone(points: Sequence[Sequence[Fraction]], r: int) -> Any:
    """The closed cone of the points as a PPL polyhedron."""
    import ppl

    x = [ppl.Variable(i) for i in range(r)]
    gs = ppl.Generator_System()
    gs.insert(ppl.point())
    for v in points:
        qs = list(v)
        scale = math.lcm(*(q.denominator for q in qs))
        if any(qs):
            gs.insert(ppl.ray(sum((int(q * scale) * x[i] for i, q in enumerate(qs)), ppl.Linear_Expression())))
    return ppl.C_Polyhedron(gs)


def _rays(cone: Any) -> list[list[Fraction]] | None:
    """The extreme rays of a pointed cone (integers, as Fractions); None when it holds a line."""
    out = []
    for g in cone.minimized_generators():
        if g.is_line():
            return None
        if g.is_ray():
            out.append([Fraction(int(c)) for c in g.coefficients()])
    return out
