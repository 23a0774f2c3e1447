"""The disk in the corner (Sect. 4.2): a case of the general engine, with the paper's zones.

A disk of unit mass in a corner of angle 2*alpha, walls S1: kx - y = 0 and S2: kx + y = 0
(k = tan alpha), coordinates (x, y, theta). The admissible side of each wall is F_i >= 0
with F_1 = y - kx and F_2 = -kx - y, so the normals are (-k, 1, 0) and (-k, -1, 0) and
``p(F_1) = -(k xd - yd)``, ``p(F_2) = -(k xd + yd)``: the paper's zones (eq. 9) are read
off the signs of the rates,

    Z0: no wall hit, Z1: only S1, Z2: only S2, Z12: both (a multiple impact).

The entrance velocity is ``v0 (cos phi, sin phi, 0)`` (the spin is irrelevant). With
``alpha = pi/6`` and ``phi = pi/12`` the inputs are algebraic (tan(pi/6) = sqrt(3)/3,
cos(pi/12) = (sqrt(6) + sqrt(2))/4) and the run is exact in their number field; an angle
whose tangent or cosine is not algebraic (alpha = 3/10 radians) runs on certified intervals
instead, and the result says so.

:func:`paper_run` is an independent implementation of eq. (10), with the paper's closed
forms for V_1, V_2 and beta, in whatever numbers it is given: the tests check the general
engine against it on Fractions, the float check (:mod:`verify.paper.float_check`)
and the benchmark (:mod:`verify.bench.throughput`) run it on floats. :func:`corner_geometry` is
the one description of the corner's mass matrix and walls.

>>> r = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001")
>>> r.zones, r.result.iterations, r.result.backend.describe()[:18]
(['Z12', 'Z12', 'Z2', 'Z0'], 3, 'exact (number fiel')
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.dynamics.system import System
from verify.errors import InvalidInput, InvalidSystem
from verify.laws.outcome import Result
from verify.laws.rule import DEFAULT_MAX_ITERATIONS, solve
from verify.laws.sequential import Law
from verify.numbers.backends import Backend, get_backend
from verify.numbers.numeric import certified_sign
from verify.numbers.parse import Number, to_number

_ONE, _ZERO, _MINUS_ONE = Fraction(1), Fraction(0), Fraction(-1)
ZONES = {(False, False): "Z0", (True, False): "Z1", (False, True): "Z2", (True, True): "Z12"}


@dataclass
class CornerRun:
    """A corner run: the engine's result, the zones visited, and how it was computed."""

    result: Result
    zones: list[str]
    slope: Number
    velocity: list[Number]
    notes: list[str] = field(default_factory=list)

    @property
    def repeated_multiple_impacts(self) -> bool:
        return sum(1 for J in self.result.impact_sets if len(J) == 2) >= 2


def _sympy() -> Any:
    import sympy

    return sympy


def slope_of(alpha: Any = None, slope: Any = None) -> Number:
    """k = tan(alpha), or the given slope; validated: 0 < alpha < pi/2, k > 0."""
    if (alpha is None) == (slope is None):
        raise InvalidInput("give exactly one of alpha and slope")
    if slope is not None:
        k = to_number(slope, where="slope")
        if certified_sign(k) <= 0:
            raise InvalidSystem(f"slope = {slope} must be positive (k = tan(alpha), 0 < alpha < pi/2)")
        return k
    a = to_number(alpha, where="alpha")
    sp = _sympy()
    a_expr = sp.Rational(a.numerator, a.denominator) if isinstance(a, Fraction) else a
    if certified_sign(a_expr) <= 0 or certified_sign(sp.pi / 2 - a_expr) <= 0:
        raise InvalidSystem(f"alpha = {alpha} must lie in (0, pi/2)")
    return to_number(sp.tan(a_expr), where="tan(alpha)")


def velocity_of(phi: Any, v0: Any = "100") -> list[Number]:
    """``v0 (cos phi, sin phi, 0)`` as exact numbers (closed forms when phi is not 0)."""
    sp = _sympy()
    p = to_number(phi, where="phi")
    speed = to_number(v0, where="v0")
    if certified_sign(speed) <= 0:
        raise InvalidSystem(f"v0 = {v0} must be positive")
    p_expr = sp.Rational(p.numerator, p.denominator) if isinstance(p, Fraction) else p
    s_expr = sp.Rational(speed.numerator, speed.denominator) if isinstance(speed, Fraction) else speed
    return [to_number(sp.expand(s_expr * sp.cos(p_expr))), to_number(sp.expand(s_expr * sp.sin(p_expr))), Fraction(0)]


def direction_of(phi: Any) -> list[Number]:
    """``(1, tan phi, 0)``, the velocity of speed 1/cos(phi) in the direction phi (|phi| < pi/2), as exact numbers.
    The rule is positively homogeneous in the velocity (its signs and its beta do not change when the velocity is
    scaled by a positive number), so every speed in that direction has these impact sets and stops, and exit
    velocities scaled by the same factor; these numbers often lie in a smaller field than ``velocity_of``'s
    (the paper's phi = pi/12: Q(sqrt(3)) instead of Q(sqrt(2), sqrt(3))).

    >>> [str(v) for v in direction_of("pi/12")]
    ['1', '2 - sqrt(3)', '0']
    """
    sp = _sympy()
    p = to_number(phi, where="phi")
    p_expr = sp.Rational(p.numerator, p.denominator) if isinstance(p, Fraction) else p
    if certified_sign(sp.pi / 2 - sp.Abs(p_expr)) <= 0:
        raise InvalidSystem(f"phi = {phi} must lie strictly between -pi/2 and pi/2")
    return [Fraction(1), to_number(sp.expand(sp.tan(p_expr))), Fraction(0)]


def corner_geometry(k: Any) -> tuple[list[list[Fraction]], list[list[Any]]]:
    """The corner of slope ``k`` in coordinates (x, y, theta): the unit mass matrix and the
    normals (-k, 1, 0) of S1 and (-k, -1, 0) of S2, as exact numbers (``k`` as given).

    >>> g, normals = corner_geometry(Fraction(1, 2))
    >>> [[str(a) for a in row] for row in normals], [str(x) for x in g[2]]
    ([['-1/2', '1', '0'], ['-1/2', '-1', '0']], ['0', '0', '1'])
    """
    minus_k = -k
    g = [[_ONE if i == j else _ZERO for j in range(3)] for i in range(3)]
    return g, [[minus_k, _ONE, _ZERO], [minus_k, _MINUS_ONE, _ZERO]]


def corner_system(
    slope: Any, eps1: Any, eps2: Any, *, backend: str | Backend = "exact", dps: int | None = None
) -> System:
    """The corner with walls of slope k = tan(alpha) and CORs eps1 (S1) and eps2 (S2).

    >>> s = corner_system("1/2", "1", "1/2")
    >>> [[str(a) for a in row] for row in s.normals]
    [['-1/2', '1', '0'], ['-1/2', '-1', '0']]
    """
    mass_matrix, normals = corner_geometry(to_number(slope, where="slope"))
    return System(
        mass_matrix,
        normals,
        [eps1, eps2],
        backend=backend,
        dps=dps,
        names=["S1", "S2"],
        coordinates=["x", "y", "theta"],
    )


def zone(system: System, v: Any) -> str:
    """The zone of eq. (9) of a velocity: Z0, Z1, Z2 or Z12."""
    K = system.backend
    b = system.rates(v)
    return ZONES[(K.sign(b[0]) < 0, K.sign(b[1]) < 0)]


def zones_of(result: Any) -> list[str]:
    """The zones visited: one per impulse, then the zone of the exit velocity (of a
    :class:`~verify.laws.outcome.Result`, or anything with its ``impact_sets`` and ``stop``)."""
    out = [ZONES[(0 in J, 1 in J)] for J in result.impact_sets]
    if result.stop == "exit":
        out.append("Z0")
    return out


def _backend_for(inputs: list[Number], backend: str | Backend, dps: int | None, notes: list[str]) -> Backend | str:
    """Exact when every input is algebraic; certified intervals otherwise (and say so)."""
    if backend != "exact":
        return backend
    from verify.numbers.backends import algebraic_generators

    if algebraic_generators(inputs) is None:
        bad = next(v for v in inputs if not isinstance(v, Fraction) and v.is_algebraic is not True)
        notes.append(f"{bad} is not algebraic: run on certified intervals instead of exact numbers")
        return get_backend("interval", dps=dps)
    return "exact"


def run_corner(
    *,
    alpha: Any = None,
    slope: Any = None,
    phi: Any = None,
    velocity: Any = None,
    eps1: Any,
    eps2: Any,
    v0: Any = "100",
    backend: str | Backend = "exact",
    dps: int | None = None,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    rule: str = "general",
    law: Law = "rule",
    trace: bool = True,
    certify: bool = True,
) -> CornerRun:
    """Run the disk in the corner. Give ``alpha`` or ``slope``, and ``phi`` or ``velocity``;
    ``law`` is ``"rule"`` (the paper's) or ``"simultaneous"`` (:mod:`verify.laws.simultaneous`).

    >>> r = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001", law="simultaneous")
    >>> r.zones, [r.result.backend.to_decimal(x, 6) for x in r.result.exit_velocity[:2]]
    (['Z12', 'Z0'], ['-25.9267', '14.8872'])
    """
    notes: list[str] = []
    k = slope_of(alpha, slope)
    if (phi is None) == (velocity is None):
        raise InvalidInput("give exactly one of phi and velocity")
    if velocity is not None:
        if len(velocity) != 2:
            raise InvalidSystem(f"velocity: expected 2 components (xd, yd), got {len(velocity)}")
        v = [to_number(x, where=f"velocity[{i}]") for i, x in enumerate(velocity)] + [Fraction(0)]
    else:
        v = velocity_of(phi, v0)
    cors = [to_number(e, where=f"eps{i + 1}") for i, e in enumerate((eps1, eps2))]
    for i, e in enumerate(cors):
        if certified_sign(e) < 0 or certified_sign(1 - e) < 0:
            raise InvalidSystem(f"eps{i + 1} = {(eps1, eps2)[i]} is outside [0, 1]")
    chosen = _backend_for([k, *v, *cors], backend, dps, notes)
    system = corner_system(k, cors[0], cors[1], backend=chosen, dps=dps if chosen != "exact" else None)
    result = solve(system, v, rule=rule, law=law, max_iterations=max_iterations, trace=trace, certify=certify)
    return CornerRun(result, zones_of(result), k, v, notes + list(result.notes))


# -- the paper's own formulas (eq. 10), written independently of the engine -----------------


def paper_run(k: Any, xd: Any, yd: Any, e1: Any, e2: Any, *, max_iterations: int = 1000) -> tuple[list[str], Any, Any]:
    """Eq. (10) with the paper's closed forms, iterated: (zones, xd, yd).

    One zone per impulse, then ``"Z0"`` when the velocity leaves within ``max_iterations``
    impulses (the zones of :func:`zones_of`); ``(xd, yd)`` is the velocity after the last
    impulse. Works on any numbers with + - * / and comparisons (Fractions, floats, SymPy
    numbers), with the same operations in the same order on each: the benchmark times it
    on Fractions and on floats as the plain baseline, so it stays a plain loop.

    >>> paper_run(Fraction(1, 2), Fraction(2), Fraction(0), Fraction(0), Fraction(1))
    (['Z12', 'Z1', 'Z0'], Fraction(-8, 5), Fraction(-4, 5))
    >>> paper_run(0.5, 2.0, 0.0, 0.0, 1.0, max_iterations=1)[0]
    ['Z12']
    """
    one = k * 0 + 1
    d = one + k * k  # 1 + k^2
    k2, k4, half_d = k * k, k**4, d / 2
    kd, minus_one_d, one_d = k / d, -one / d, one / d  # V_1 = (k, -1) s1 / d, V_2 = (k, 1) s2 / d
    f1, f2 = 1 + e1, 1 + e2
    zones: list[str] = []
    for impulses in range(max_iterations + 1):
        s1 = k * xd - yd  # -p(F_1): S1 is hit when s1 > 0
        s2 = k * xd + yd  # -p(F_2)
        h1, h2 = s1 > 0, s2 > 0
        if not (h1 or h2):
            zones.append("Z0")
            break
        if impulses == max_iterations:
            break
        if h1 and h2:
            y2 = yd * yd
            beta = half_d * (k2 * xd * xd + y2) / (k4 * xd * xd + y2)
            xd, yd = (
                xd - beta * (f1 * (kd * s1) + f2 * (kd * s2)),
                yd - beta * (f1 * (minus_one_d * s1) + f2 * (one_d * s2)),
            )
            zones.append("Z12")
        elif h1:
            xd, yd = xd - f1 * (kd * s1), yd - f1 * (minus_one_d * s1)
            zones.append("Z1")
        else:
            xd, yd = xd - f2 * (kd * s2), yd - f2 * (one_d * s2)
            zones.append("Z2")
    return zones, xd, yd


def corner_batch(slopes: list[Any], velocities: list[Any], cors: list[Any]) -> Any:
    """A float batch (:func:`verify.laws.loops.floats.systems_batch`) of disks in corners: per
    case the slope k, the velocity (xd, yd) and the CORs (eps1, eps2), exact rationals.

    >>> from verify.laws.loops.floats import solve_batch
    >>> F = Fraction
    >>> out = solve_batch(corner_batch([F(1, 2), F(1)], [[2, 0], [1, F(1, 2)]], [[0, 1], [F(1, 2), 0]]))
    >>> out.impact_sets(0), out.stop[0], out.fallback.tolist()
    ([(0, 1), (0,)], 'exit', [False, True])
    """
    from verify.errors import require

    require("numpy", "the float path")
    from verify.laws.loops.floats import systems_batch

    systems = [corner_system(k, e[0], e[1]) for k, e in zip(slopes, cors)]
    return systems_batch(systems, [[v[0], v[1], 0] for v in velocities])
