"""Hard cases for the oracle: inputs placed where implementations of the rule go wrong.

:func:`generate` returns case records (``docs/records.md``), each with one more field, ``why``:
a one-line reason the case is hard. The families:

- ``cradle*-eps-...``: Newton's cradle with eps just below and just above the exact breakpoints
  of its map (:func:`verify.maps.cradle.cradle_map`: where the number of impulses
  changes; 3 - 2*sqrt(2) is where three impulses become four), at distances 10^-k, and at the
  breakpoints themselves when they are rational or quadratic surds. Every eps is a rational whose
  side of the breakpoint is decided exactly (:class:`verify.numbers.algebraic.RealAlgebraic`), and
  whose distance to it is at most 10^-k;
- the termination boundary of the cradle (7 - 4*sqrt(3) for unit balls): below it and on it the
  run never exits (the exact solver proves it), just above it runs are long but finite (the count
  grows like (eps - boundary)^(-1/2));
- ``corner-*``: entrance velocities exactly along a wall (a rate exactly 0) and just beside it;
  ``wedge-*``: slopes on the wedge boundary tan(alpha) = (1 - sqrt(e))/(1 + sqrt(e))
  (:mod:`verify.models.wedge`) and just beside it, separating disks that never get out from
  those that do;
- ``grazing-*``: a ball at rest touching one at rest, CORs 0 and 1;
- ``scaled-*``, ``hilbert-*``, ``illcond-*``: masses 1e-6 and 1e6, Hilbert mass matrices and
  random ``L L^T`` with a tiny diagonal (large condition numbers), built exactly;
- ``general-*``: random systems (seeded) whose rate after the first impulse is exactly -10^-k,
  0 or +10^-k: one decision of the rule sits on its boundary.

The output depends only on ``(level, seed)``: no clock, no set order, no hash. Level 1 is small
(about 40 cases that solve exactly in a few seconds); levels 2 and 3 add distances, breakpoints,
balls and random systems, and contain every case of the levels below.

>>> cases = generate(1, 0)
>>> ids = [c["id"] for c in cases]
>>> "cradle3-eps-3-2sqrt2-minus-1e-12" in ids and "cradle3-eps-3-2sqrt2-plus-1e-12" in ids
True
>>> len(ids) == len(set(ids)) and all(c["why"] for c in cases)
True
"""

from __future__ import annotations

import math
import random
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import Budget, impulse, solve
from verify.maps.cradle import CradleMap, cradle_map, termination_boundaries
from verify.maps.line import Part
from verify.models.corner import corner_geometry, slope_of, velocity_of
from verify.models.cradle import cradle_geometry
from verify.models.rates import velocity_with_rates
from verify.models.wedge import below_boundary
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends import RationalBackend
from verify.oracle.reference import random_geometry
from verify.records.results import case_record, dumps, with_decimals

#: the iteration cap written into every case
MAX_ITERATIONS = 10_000
#: the exponents k of 10^-k used for the random near-boundary systems, in turn (any level)
NEAR_EXPONENTS = (12, 15, 9, 6, 30, 20)
NEAR_KINDS = ("minus", "zero", "plus")
#: the 2-norm condition numbers of Hilbert matrices (known values)
HILBERT_CONDITION = {6: "1.5e7", 8: "1.5e10", 10: "1.6e13"}
#: the size a random draw's exact run may reach before the draw is replaced
DRAW_BITS = 8192

_Q = RationalBackend("python")


@dataclass(frozen=True)
class CradleSpec:
    """A cradle whose map gives breakpoints: its id prefix, masses, and the map's bound on impulses."""

    tag: str
    masses: tuple[str, ...]
    max_impulses: int
    what: str
    approach: bool = False  # long finite runs above its termination boundary


@dataclass(frozen=True)
class Level:
    """What one level generates."""

    maps: tuple[CradleSpec, ...]
    distances: tuple[int, ...]  # k of 10^-k beside each breakpoint
    approach: tuple[int, ...]  # k of boundary + 10^-k: long finite runs
    wedge_cors: tuple[str, ...]
    wedge_approach: tuple[int, ...]
    balls: tuple[int, ...]  # cradles at rest for the grazing family
    hilbert: tuple[int, ...]
    illcond: int
    near: int


UNIT3 = "three unit balls"
LIGHT_HEAVY = ("1/1000000", "1", "1000000")


def _cradle_specs(level: int) -> tuple[CradleSpec, ...]:
    impulses = {1: (6, 3), 2: (12, 8), 3: (20, 8)}[level]
    specs = [
        CradleSpec("cradle3", ("1", "1", "1"), impulses[0], UNIT3, approach=True),
        CradleSpec("cradle3-m1e-6-1-1e6", LIGHT_HEAVY, impulses[1], "masses 1e-6, 1, 1e6"),
    ]
    if level >= 2:
        specs.append(CradleSpec("cradle4", ("1",) * 4, 12 if level == 2 else 16, "four unit balls"))
    if level >= 3:
        specs += [
            CradleSpec("cradle5", ("1",) * 5, 8, "five unit balls"),
            CradleSpec("cradle3-m1-1e6-1", ("1", "1000000", "1"), 8, "masses 1, 1e6, 1"),
            CradleSpec("cradle3-m1-2-3", ("1", "2", "3"), 12, "masses 1, 2, 3"),
        ]
    return tuple(specs)


def level_spec(level: int) -> Level:
    """The parameters of ``level`` (1, 2 or 3); each level's sets contain the level below's.

    >>> level_spec(1).distances, level_spec(2).distances
    ((12,), (6, 9, 12, 15))
    """
    if level not in (1, 2, 3):
        raise ValueError(f"level must be 1, 2 or 3, got {level!r}")

    def upto(*per_level: tuple[Any, ...]) -> tuple[Any, ...]:  # what levels 1..level add, in turn
        return tuple(x for added in per_level[:level] for x in added)

    return Level(
        maps=_cradle_specs(level),
        distances=tuple(sorted(upto((12,), (6, 9, 15), (20, 30)))),
        approach=upto((2, 3), (4, 5), (6,)),
        wedge_cors=upto(("1/4",), ("1/9", "1/2"), ("1/16",)),
        wedge_approach=upto((2, 3), (4,), (5,)),
        balls=upto((3,), (4, 5), (6,)),
        hilbert=upto((6,), (8,), (10,)),
        illcond=(1, 3, 6)[level - 1],
        near=(3, 12, 30)[level - 1],
    )


# -- exact placement beside a breakpoint ---------------------------------------------------------


def beside(b: RealAlgebraic, k: int, side: int) -> Fraction:
    """A rational eps with ``0 < side * (eps - b) <= 10^-k``, on the grid 10^-(k+4), decided exactly.

    >>> from verify.numbers.parse import to_number
    >>> b = RealAlgebraic.from_number(to_number("3 - 2*sqrt(2)"))
    >>> beside(b, 12, -1), beside(b, 12, 1)
    (Fraction(17157287525281, 100000000000000), Fraction(1715728752548099, 10000000000000000))
    """
    delta = Fraction(side, 10**k)
    scale = 10 ** (k + 4)
    rounding = math.floor if side > 0 else math.ceil
    while rounding((b.lo + delta) * scale) != rounding((b.hi + delta) * scale):
        b.refine()  # ends: b + delta is not on the grid unless b is rational (then lo == hi)
    eps = Fraction(rounding((b.lo + delta) * scale), scale)
    point = RealAlgebraic.rational(eps)
    if point.cmp(b) != side or RealAlgebraic.rational(eps - delta).cmp(b) == side:
        raise ArithmeticError(f"{eps} is not within 10^-{k} on side {side} of {b}")  # pragma: no cover
    return eps


def slug(x: Any) -> str:
    """A closed form as an id fragment: ``3 - 2*sqrt(2)`` -> ``3-2sqrt2``.

    >>> slug("3 - 2*sqrt(2)"), slug("7/5 - 2*sqrt(6)/5")
    ('3-2sqrt2', '7/5-2sqrt6/5')
    """
    return re.sub(r"sqrt\((\d+)\)", r"sqrt\1", str(x).replace(" ", "")).replace("*", "")


def _closed_form(b: RealAlgebraic) -> Any | None:
    """The breakpoint as an input the exact backends take (rational or a quadratic surd), else None."""
    if b.is_rational:
        return b.rational_value()
    return b.expr if b.poly.degree() == 2 else None


def _label(b: RealAlgebraic, below: Part, above: Part) -> str:
    form = _closed_form(b)
    if form is not None and len(slug(form)) <= 24:
        return slug(form)
    return f"break-{below.iterations}to{above.iterations}"


# -- the cradle ---------------------------------------------------------------------------------


def _cradle_case(spec: CradleSpec, case_id: str, eps: Any, why: str) -> dict[Any, Any]:
    masses = [Fraction(m) for m in spec.masses]
    g, normals = cradle_geometry(masses)
    velocity = [1] + [0] * (len(masses) - 1)
    record = case_record(case_id, g, normals, [eps] * (len(masses) - 1), velocity, max_iterations=MAX_ITERATIONS)
    record["why"] = why
    return record


def _behaviour(cmap: CradleMap, eps: Fraction | RealAlgebraic) -> str:
    part = cmap.locate(eps if isinstance(eps, RealAlgebraic) else RealAlgebraic.rational(eps))
    if part.stop == "exit":
        return f"{part.iterations} impulses"
    if part.stop == "non_terminating":
        return "never exits (proved)"
    return f"more than {part.iterations} impulses"


def _change(below: Part, above: Part) -> str:
    if below.iterations == above.iterations:
        return f"the impact sequence changes ({below.iterations} impulses on both sides)"
    return f"the count goes from {below.iterations} to {above.iterations}"


def _breakpoint_cases(spec: CradleSpec, cmap: CradleMap, level: Level) -> list[dict[Any, Any]]:
    """Beside every breakpoint between two exits: eps 10^-k below and above it when that eps lies in
    the neighbouring part of the map (no other breakpoint in between), and on it when it is rational
    or a quadratic surd."""
    out: list[dict[Any, Any]] = []
    labels: list[str] = []
    for b, below, above in cmap.thresholds():
        if below.stop != "exit" or above.stop != "exit":
            continue
        label = _label(b, below, above)
        label += f"-{labels.count(label) + 1}" if label in labels else ""
        labels.append(label)
        where = f"{spec.what}, v = (1, 0, ...): at eps = {b} {_change(below, above)}"
        for k in level.distances:
            for side, name, part in ((-1, "minus", below), (1, "plus", above)):
                eps = beside(b, k, side)
                if not 0 <= eps <= 1 or cmap.locate(RealAlgebraic.rational(eps)) is not part:
                    continue
                why = (
                    f"{where}; eps is 1e-{k} {'below' if side < 0 else 'above'} it (certified exactly): "
                    f"{_behaviour(cmap, eps)}, decided by a rate that is exactly 0 at the breakpoint"
                )
                out.append(_cradle_case(spec, f"{spec.tag}-eps-{label}-{name}-1e-{k}", eps, why))
        form = _closed_form(b)
        if form is not None:
            why = f"{where}; eps on it exactly: {_behaviour(cmap, b)}, a rate the rule tests is exactly 0 (grazing)"
            out.append(_cradle_case(spec, f"{spec.tag}-eps-{label}-exactly", form, why))
    return out


def _termination_cases(spec: CradleSpec, cmap: CradleMap, level: Level) -> list[dict[Any, Any]]:
    out: list[dict[Any, Any]] = []
    for b in termination_boundaries(cmap):
        form = _closed_form(b)
        label = slug(form) if form is not None and len(slug(form)) <= 24 else "boundary"
        where = f"{spec.what}, v = (1, 0, ...): the termination boundary is eps = {b}"
        for k in level.distances:
            eps = beside(b, k, -1)
            if eps >= 0:
                why = f"{where}; eps is 1e-{k} below it: never exits (proved), floats stop when the velocities fade"
                out.append(_cradle_case(spec, f"{spec.tag}-eps-{label}-minus-1e-{k}", eps, why))
        if form is not None:
            why = f"{where}; eps on it exactly: never exits (proved: a double eigenvalue, the cones just exist)"
            out.append(_cradle_case(spec, f"{spec.tag}-eps-{label}-exactly", form, why))
        for k in level.approach if spec.approach else ():
            eps = beside(b, k, 1)
            why = (
                f"{where}; eps is 1e-{k} above it: exits, after a long but finite run "
                f"(the count grows like (eps - boundary)^(-1/2))"
            )
            out.append(_cradle_case(spec, f"{spec.tag}-eps-{label}-plus-1e-{k}", eps, why))
    return out


def cradle_cases(level: Level) -> list[dict[Any, Any]]:
    """The cradle's breakpoint and termination-boundary cases of a level (one map per cradle)."""
    out: list[dict[Any, Any]] = []
    for spec in level.maps:
        cmap = cradle_map(masses=list(spec.masses), max_impulses=spec.max_impulses)
        out += _breakpoint_cases(spec, cmap, level)
        out += _termination_cases(spec, cmap, level)
    return out


# -- the corner and the wedge --------------------------------------------------------------------


def _corner_case(case_id: str, slope: Any, eps: Sequence[Any], velocity: Sequence[Any], why: str) -> dict[Any, Any]:
    g, normals = corner_geometry(slope)
    record = case_record(case_id, g, normals, eps, [*velocity, 0], max_iterations=MAX_ITERATIONS)
    record["why"] = why
    return record


def corner_cases(level: Level) -> list[dict[Any, Any]]:
    """Entrance velocities along a wall of the corner (a rate exactly 0) and 10^-k beside it."""
    k2, eps = Fraction(1, 2), [Fraction(1, 2), Fraction(1, 5)]
    base = "corner of slope 1/2, CORs 1/2 and 1/5"
    out = [
        _corner_case("corner-slope-1/2-along-wall-1", k2, eps, [1, k2],
                     f"{base}: v along wall 1 (its rate exactly 0): zone Z2, a single impact, not Z12"),
        _corner_case("corner-slope-1/2-leaving-along-wall-1", k2, eps, [-1, -k2],
                     f"{base}: v leaves along wall 1 (rate exactly 0, the other positive): zone Z0, no impulse"),
    ]  # fmt: skip
    for k in level.distances:
        d = Fraction(1, 10**k)
        out += [
            _corner_case(f"corner-slope-1/2-beside-wall-1-in-1e-{k}", k2, eps, [1, k2 - d],
                         f"{base}: v 1e-{k} inside wall 1 (rate exactly -1e-{k}): zone Z12, a double impact"),
            _corner_case(f"corner-slope-1/2-beside-wall-1-out-1e-{k}", k2, eps, [1, k2 + d],
                         f"{base}: v 1e-{k} off wall 1 (rate exactly +1e-{k}): zone Z2, a single impact"),
            _corner_case(f"corner-slope-1/2-leaving-beside-wall-1-1e-{k}", k2, eps, [-1, -k2 - d],
                         f"{base}: v leaves 1e-{k} into wall 1 (rate exactly -1e-{k}): one tiny impact, not Z0"),
        ]  # fmt: skip
    k6 = slope_of(alpha="pi/6")
    out.append(
        _corner_case("corner-pi6-along-wall-1", k6, eps, velocity_of("pi/6", "1")[:2],
                     "corner of half-angle pi/6: v = (cos pi/6, sin pi/6) runs along wall 1, its rate is exactly 0 "
                     "in Q(sqrt(3)) (floats get a rounding residue): zone Z2"),
    )  # fmt: skip
    return out


def _wedge_boundary(e: Fraction) -> Any:
    s = sp.sqrt(sp.Rational(e.numerator, e.denominator))
    k = sp.expand(sp.radsimp((1 - s) / (1 + s)))
    return Fraction(int(k.p), int(k.q)) if k.is_Rational else k


def wedge_cases(level: Level) -> list[dict[Any, Any]]:
    """The symmetric wedge on its boundary slope, 10^-k narrower (never exits), and wider (exits late)."""
    out: list[dict[Any, Any]] = []
    for text in level.wedge_cors:
        e = Fraction(text)
        form = _wedge_boundary(e)
        b = RealAlgebraic.from_number(form)
        head = f"wedge-e-{text}-slope"
        where = f"symmetric corner, CORs {text}, boundary slope tan(alpha) = {form} (double eigenvalue)"
        why = f"{where}: v along wall 1 (rate exactly 0) on the boundary slope: never exits (proved)"
        out.append(_corner_case(f"{head}-{slug(form)}-along-wall", form, [e, e], [1, form], why))
        for k in level.distances:
            slope = beside(b, k, -1)
            if not below_boundary(slope, e):
                raise ArithmeticError(f"slope {slope} is not below the wedge boundary")  # pragma: no cover
            why = f"{where}: slope 1e-{k} below it, v along wall 1: never exits (proved), floats report an exit"
            out.append(_corner_case(f"{head}-{slug(form)}-minus-1e-{k}", slope, [e, e], [1, slope], why))
        for k in level.wedge_approach:
            slope = beside(b, k, 1)
            if below_boundary(slope, e):
                raise ArithmeticError(f"slope {slope} is not above the wedge boundary")  # pragma: no cover
            why = f"{where}: slope 1e-{k} above it, v along wall 1: exits after a long alternation"
            out.append(_corner_case(f"{head}-{slug(form)}-plus-1e-{k}", slope, [e, e], [1, slope], why))
    return out


# -- grazing contacts, CORs 0 and 1 ----------------------------------------------------------------


def grazing_cases(level: Level) -> list[dict[Any, Any]]:
    """Cradles whose first ball hits balls at rest that touch (a rate exactly 0), CORs 0 and 1."""
    out: list[dict[Any, Any]] = []
    for balls in level.balls:
        g, normals = cradle_geometry([Fraction(1)] * balls)
        v = [1] + [0] * (balls - 1)
        alternating = [i % 2 for i in range(balls - 1)]
        choices = [("1", [1] * (balls - 1)), ("0", [0] * (balls - 1))] if balls <= 4 else [("1", [1] * (balls - 1))]
        choices += [("0-1", alternating), ("1-0", [1 - x for x in alternating])]
        for name, eps in choices:
            why = (
                f"{balls} unit balls, balls 2..{balls} at rest and touching (rates exactly 0: grazing), CORs "
                f"{', '.join(map(str, eps))}: a COR of 0 leaves a rate exactly 0 after its impact, 1 keeps the energy"
            )
            record = case_record(
                f"grazing-cradle{balls}-cors-{name}", g, normals, eps, v, max_iterations=MAX_ITERATIONS
            )
            record["why"] = why
            out.append(record)
    return out


# -- badly scaled mass matrices -----------------------------------------------------------------


def scaled_cases(level: Level) -> list[dict[Any, Any]]:
    """Cradles with masses 1e-6 and 1e6, and Hilbert mass matrices (condition numbers up to 1e13)."""
    out: list[dict[Any, Any]] = []
    for masses, v, what in (
        (LIGHT_HEAVY, [1, 0, 0], "a ball of mass 1e-6 hits masses 1 and 1e6"),
        (LIGHT_HEAVY[::-1], [1, 0, 0], "a ball of mass 1e6 hits masses 1 and 1e-6"),
    ):
        g, normals = cradle_geometry([Fraction(m) for m in masses])
        record = case_record(f"scaled-cradle3-m{'-'.join(masses)}", g, normals, ["1/2", "1/2"], v,
                             max_iterations=MAX_ITERATIONS)  # fmt: skip
        record["why"] = f"{what}, CORs 1/2: velocities of sizes 1e-6 to 1e6 in one run"
        out.append(record)
    for n in level.hilbert:
        g = [[Fraction(1, i + j + 1) for j in range(n)] for i in range(n)]
        normals = [[Fraction(int(c == i)) for c in range(n)] for i in range(2)]
        w = velocity_with_rates((g, normals, [0, 0]), [Fraction(0)] * n, {0: Fraction(-1), 1: Fraction(-1, 2)})
        record = case_record(f"hilbert-{n}", g, normals, ["1/2", "1/3"], w, max_iterations=MAX_ITERATIONS)
        record["why"] = (
            f"mass matrix the Hilbert matrix of order {n} (exact rationals, condition number "
            f"{HILBERT_CONDITION.get(n, 'large')}): a double impact whose Gram matrix comes from its inverse"
        )
        out.append(record)
    return out


# -- random systems with a decision on its boundary ------------------------------------------------


def _draw_system(rng: random.Random, tiny: int) -> tuple[list[Any], list[Any], list[Any], list[Any]]:
    """A random SPD ``L L^T`` (the diagonal of L from 1 down to 10^-tiny), independent normals, time
    terms (moving one time in four) and CORs with 0 and 1."""

    def q(lo: int, hi: int, den: int = 4) -> Fraction:
        return Fraction(rng.randint(lo * den, hi * den), rng.randint(1, den))

    n = rng.randint(3, 5)
    r = rng.randint(2, n - 1)
    diagonal = [Fraction(1, 10 ** (tiny * i // (n - 1))) * q(1, 2) for i in range(n)]
    g, normals = random_geometry(rng, n, r, lambda i: diagonal[i], q)
    moving = rng.random() < 0.25
    time_terms = [q(-2, 2, 2) if moving else Fraction(0) for _ in range(r)]
    eps = [rng.choice([Fraction(0), Fraction(1), Fraction(rng.randint(1, 9), 10)]) for _ in range(r)]
    return g, normals, time_terms, eps


def near_boundary_case(rng: random.Random, case_id: str, kind: str, k: int, tiny: int = 0) -> dict[Any, Any] | None:
    """A random system whose rate of its last constraint, after the first impulse, is exactly -10^-k
    (``kind`` "minus"), 0 ("zero") or +10^-k ("plus"); None when the draw does not fit (the caller
    draws again). The first impact set is {0} or {0, 1}; the other rates stay positive.

    >>> rec = near_boundary_case(random.Random(1), "x", "minus", 12)
    >>> s = System(rec["mass_matrix"], rec["normals"], rec["restitution"], rec["time_terms"], backend=_Q)
    >>> v = s.velocity(rec["velocity"])
    >>> s.rates([x + y for x, y in zip(v, impulse(s, v))])[-1]
    Fraction(-1, 1000000000000)
    """
    g, normals, time_terms, eps = _draw_system(rng, tiny)
    n, r = len(g), len(normals)
    J = (0, 1) if r >= 3 and rng.random() < 0.5 else (0,)
    watched = r - 1
    targets = {j: -Fraction(rng.randint(4, 12), 4) for j in J}
    w = [Fraction(rng.randint(-8, 8), 4) for _ in range(n)]
    v = velocity_with_rates((g, normals, time_terms), w, targets)
    system = System(g, normals, eps, time_terms, backend=_Q)
    dv = impulse(system, system.velocity(v), J)
    change = [sum((a * x for a, x in zip(row, dv)), Fraction(0)) for row in normals]
    if change[watched] == 0:
        return None
    if change[watched] > 0:  # the impulse must lower the watched rate: turn that constraint round
        normals[watched] = [-a for a in normals[watched]]
        change[watched] = -change[watched]
    after = {"minus": Fraction(-1, 10**k), "zero": Fraction(0), "plus": Fraction(1, 10**k)}[kind]
    targets[watched] = after - change[watched]
    for m in range(r):
        if m not in targets:
            targets[m] = Fraction(rng.randint(2, 8), 4) + max(Fraction(0), -change[m])
    v = velocity_with_rates((g, normals, time_terms), w, targets)
    record = case_record(case_id, g, normals, eps, v, time_terms=time_terms, max_iterations=MAX_ITERATIONS)
    what = {"minus": f"exactly -1e-{k}: an impact, however small", "zero": "exactly 0: grazing, no impact",
            "plus": f"exactly +1e-{k}: no impact"}[kind]  # fmt: skip
    scale = f", L L^T with diagonal of L down to 1e-{tiny}" if tiny else ""
    record["why"] = (
        f"random system (n = {n}, r = {r}, {'moving' if any(time_terms) else 'fixed'}{scale}): after the first "
        f"impulse (impact set {list(J)}) the rate of constraint {watched} is {what}"
    )
    return record


def _ends(record: dict[Any, Any]) -> bool:
    """Whether the exact run of a draw ends (exit or proved never to exit) while its numbers stay small."""
    system = System(record["mass_matrix"], record["normals"], record["restitution"], record["time_terms"])
    r = solve(system, record["velocity"], max_iterations=1000, trace=False, budget=Budget(bits=DRAW_BITS))
    return r.stop in ("exit", "non_terminating")


def random_cases(seed: int, count: int, prefix: str, tiny: int = 0) -> list[dict[Any, Any]]:
    """``count`` near-boundary random systems from ``random.Random`` seeded by (prefix, seed); the
    first ``m`` cases of a larger count are the ``m`` cases of a smaller one."""
    rng = random.Random(f"verify-hardcases-{prefix}-{seed}")
    out: list[dict[Any, Any]] = []
    while len(out) < count:
        i = len(out)
        kind, k = NEAR_KINDS[i % len(NEAR_KINDS)], NEAR_EXPONENTS[i % len(NEAR_EXPONENTS)]
        label = f"-1e-{k}" if kind != "zero" else ""
        record = near_boundary_case(rng, f"{prefix}-{i:02d}-rate-after-{kind}{label}", kind, k, tiny)
        if record is not None and _ends(record):
            out.append(record)
    return out


# -- the whole set ------------------------------------------------------------------------------------


def generate(level: int, seed: int, law: str = "rule") -> list[dict[Any, Any]]:
    """The hard cases of ``level`` (1, 2 or 3) and ``seed``: case records with a ``why`` field; with
    ``law`` ``"simultaneous"`` or ``"sequential"`` also the cases where that law branches
    (:mod:`verify.oracle.lawcases`).

    The seed drives the random families only (``general-*``, ``illcond-*``); the same
    ``(level, seed, law)`` always gives the same list.

    >>> cases = generate(1, 7)
    >>> len(cases), sum(c["id"].startswith("general-") for c in cases)
    (40, 3)
    """
    spec = level_spec(level)
    families: list[Callable[[Level], list[dict[Any, Any]]]] = [cradle_cases, corner_cases, wedge_cases, grazing_cases,
                                                      scaled_cases]  # fmt: skip
    out = [record for family in families for record in family(spec)]
    out += random_cases(seed, spec.illcond, "illcond", tiny=8)
    out += random_cases(seed, spec.near, "general")
    from verify.oracle.lawcases import law_cases

    out += law_cases(level, law)
    ids = [c["id"] for c in out]
    if len(ids) != len(set(ids)):
        raise AssertionError("hard case ids are not unique")  # pragma: no cover
    return out


def generate_file_text(level: int, seed: int, law: str = "rule") -> str:
    """The case file of :func:`generate` as text (sorted keys, two-space indentation), each case with its
    ``decimal`` object (:func:`verify.records.results.with_decimals`): the same bytes for the same
    ``(level, seed)``.

    >>> generate_file_text(1, 0).splitlines()[:3]
    ['{', '  "cases": [', '    {']
    """
    from verify.records.versions import generated_dataset, stamped

    return dumps(
        stamped({"cases": [with_decimals(c) for c in generate(level, seed, law)]}, generated_dataset(level, seed, law))
    )
