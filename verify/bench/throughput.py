"""Throughput figures, each beside a baseline measured in the same run (``verify bench``).

Machines here are noisy, so every figure is a ratio against a baseline timed in the same
process, alternately with it, and each time is the best of ``repeats`` runs (the heap is
collected before each, off the clock). Each contestant receives its batch in its own number type
(Fractions for the exact ones, floats for the float loop, float arrays with radii for the float
path), converted before the clock starts, and keeps per case what the plain loops keep: the
branch sequence and the last velocity (:class:`Outcome`).

The batches (:data:`BATCHES`; every figure names its ``batch`` in the JSON):

- ``corner`` (figures ``corner_batch.*``): :func:`batch`, 10,000 random corner cases (rational
  slope k in (1/10, 10), both walls hit at the start, CORs in [0, 1] with 0 and 1 drawn often), at
  most 100 impulses a case. The general exact engine (a System and a solve per case) against the
  corner's plain loop on Fractions (:func:`verify.models.corner.paper_run`, eq. (10) with the
  paper's closed forms), and the certified float path against the same loop on floats, with the
  number of cases where each takes another branch sequence than the exact rule.
- ``corner_short``: :func:`short_batch`, corner cases of 1 to 3 impulses with a new slope each, where
  the set-up of a case is most of the work; beside them the bare rate loop
  (:func:`verify.bench.baselines.bare_rates_run`), a bound on what Python code reaches there.
- ``cradle``: the three-ball cradle over :func:`cradle_grid` (1,000 eps), one geometry: the batch
  entry point :func:`verify.laws.rule.solve_many` against the plain general loop
  (:mod:`verify.bench.baselines`), which also builds its geometry once.
- ``general``: :func:`general_batch`, random general systems (r = 2..4, some moving), a System and a
  solve per case against the plain general loop, which builds its geometry per case too.
- ``table1``: Table 1's runs (exact and paper mode, :func:`verify.paper.table1.table1_runs`),
  and the whole audit of Table 1 on the fastest rationals against pure-Python Fractions.
- ``impulse_cost``: one long run (the ideal rule in a corner of slope 1/10000), the cost of an impulse
  at 10 to 10,000 impulses on the exact and interval backends, with the size of the exact numbers
  and the digits the intervals needed.
- ``maps``: the exact map of four unit balls over eps in [0, 1] up to 40 impulses (``verify cradle-map
  --balls 4``), on python-flint's arithmetic of the parameter against SymPy's alone (the baseline: the
  map without the ``fast`` extra), once each; the two maps must be the same, byte for byte.

Where PARI/GP is installed (``gp``), the paper's loop in GP (:mod:`verify.bench.gp`, exact
rationals) runs the corner, short and cradle batches, and Table 1 in GP's reals (the paper's
arithmetic) and on rationals; its branch sequences must be the exact engine's.

>>> figures = bench(size=20, repeats=1, impulses=(10,), table=False, cradle=5, general=3, gp=False, map_impulses=4)
>>> [(f.name, f.unit, f.batch) for f in figures[:2]]
[('corner_batch.fraction_loop', 'cases/s', 'corner'), ('corner_batch.exact_engine', 'cases/s', 'corner')]
"""

from __future__ import annotations

import gc
import json
import os
import platform
import resource
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from fractions import Fraction
from typing import Any, NamedTuple

from verify.models.corner import corner_batch, corner_system, paper_run, zones_of
from verify.paper.sweep import random_corner_cases

BATCH_SIZE = 10_000
BATCH_SEED = 0
MAX_IMPULSES = 100
IMPULSES = (10, 100, 1000, 10_000)
#: the short-run batch: corner cases of 1 to 3 impulses, a new slope every case (a sweep over
#: geometries, a property run), drawn with this seed and kept when the exact run is that short
SHORT_SEED = 1
SHORT_IMPULSES = 3
#: the cradle batch: this many eps on a grid; the general batch: this many systems, drawn with this seed
CRADLE_SIZE = 1000
GENERAL_SIZE = 2000
GENERAL_SEED = 2
#: tables of Table 1 per clock reading (one table takes a few milliseconds)
TABLE_RUNS = 20
#: ``verify bench --quick``: a smoke run (CI runs it), not a measurement
QUICK = {"size": 500, "repeats": 1, "impulses": (10, 100), "table": False, "cradle": 100, "general": 100, "gp": False,
         "map_impulses": 8}  # fmt: skip
#: the maps batch: the exact map of four unit balls over eps in [0, 1], explored up to this many impulses
MAP_BALLS, MAP_IMPULSES = 4, 40
#: the long run of the cost-per-impulse figures: the ideal rule in a corner of slope
#: 1/10000, which reflects the disk 15,706 times before it leaves (exact), all single impacts
LONG_RUN: dict[str, Any] = {
    "slope": Fraction(1, 10_000),
    "velocity": (Fraction(1), Fraction(1, 30_000)),
    "cors": (1, 1),
}


#: the batches of ``verify bench`` (the ``batch`` of every figure in the JSON), and what each holds
#: (its size is the figure ``<batch>.size``)
BATCHES = {
    "corner": "random corner cases (a new slope, velocity and CORs each), at most 100 impulses a case",
    "corner_short": "corner cases of 1 to 3 impulses, a new slope every case",
    "cradle": "the three-ball cradle (unit masses, v0 = 100) over a grid of eps, one geometry, at most 100 impulses",
    "general": "random general systems (r = 2..4, n = r+1..r+2, some moving), at most 100 impulses",
    "table1": "Table 1 of the paper: its 17 rows, exact and paper mode",
    "impulse_cost": "one long run (the ideal rule in a corner of slope 1/10000), cost per impulse",
    "maps": "the exact map of four unit balls over eps in [0, 1] (verify cradle-map --balls 4), once each way",
    "memory": "peak resident memory of the bench process",
}
#: the prefixes of figure names (kept stable between versions) and their batch
_BATCH_OF = {"corner_batch": "corner", "exact_bits": "impulse_cost", "interval_digits": "impulse_cost",
             "peak_memory": "memory", "memory_after_import": "memory"}  # fmt: skip


@dataclass(frozen=True)
class Figure:
    """One line of ``verify bench --json``: ``value`` in ``unit``, ``ratio`` = value / baseline
    (for speeds, the speed-up; a baseline line names itself with ratio 1)."""

    name: str
    value: float
    unit: str
    baseline: str
    ratio: float

    @property
    def batch(self) -> str:
        """The batch the figure belongs to (:data:`BATCHES`): the first part of its name."""
        return _BATCH_OF.get(self.name.split(".", 1)[0], self.name.split(".", 1)[0])

    def to_json(self) -> dict[str, Any]:
        return {**asdict(self), "batch": self.batch}


def batch(size: int = BATCH_SIZE, seed: int = BATCH_SEED) -> list[tuple[Fraction, ...]]:
    """The corner batch as exact tuples ``(k, xd, yd, e1, e2)``.

    >>> batch(1)[0]
    (Fraction(173, 79), Fraction(259, 18), Fraction(-41088019, 1422000), Fraction(497, 524), Fraction(310, 803))
    """
    out: list[tuple[Fraction, ...]] = []
    for c in random_corner_cases(size, seed=seed, max_iterations=MAX_IMPULSES):
        xd, yd = (Fraction(x) for x in c["velocity"])
        out.append((Fraction(c["slope"]), xd, yd, Fraction(c["eps1"]), Fraction(c["eps2"])))
    return out


def short_batch(size: int = BATCH_SIZE, seed: int = SHORT_SEED) -> list[tuple[Fraction, ...]]:
    """``size`` corner cases ``(k, xd, yd, e1, e2)`` whose exact run makes 1 to
    :data:`SHORT_IMPULSES` impulses (decided by the plain Fraction loop, before any clock starts).

    >>> [len(paper_run(*c)[0]) - 1 for c in short_batch(3)]
    [2, 1, 2]
    """
    out: list[tuple[Fraction, ...]] = []
    draws = 0
    while len(out) < size:
        for c in batch(max(2 * size, 100), seed=seed * 1_000_003 + draws):
            if 1 <= len(paper_run(*c, max_iterations=MAX_IMPULSES)[0]) - 1 <= SHORT_IMPULSES and len(out) < size:
                out.append(c)
        draws += 1
    return out


def cradle_grid(size: int = CRADLE_SIZE) -> list[Fraction]:
    """The eps of the cradle batch: ``i / size`` for i = 0 .. size - 1.

    >>> [str(e) for e in cradle_grid(4)]
    ['0', '1/4', '1/2', '3/4']
    """
    return [Fraction(i, size) for i in range(size)]


def general_batch(size: int = GENERAL_SIZE, seed: int = GENERAL_SEED) -> list[tuple[Any, ...]]:
    """``size`` random general systems with a velocity each, as exact tuples
    ``(mass_matrix, normals, time_terms, cors, velocity)``, drawn as the oracle's random cases
    (:func:`verify.oracle.reference.random_case`). A draw whose exact run passes
    :data:`~verify.oracle.reference.GENERATION_BITS` bits within :data:`MAX_IMPULSES` impulses is
    replaced by the next (decided before any clock starts): both contestants then do the same,
    bounded work.

    >>> g, normals, time_terms, cors, v = general_batch(1)[0]
    >>> len(normals), len(v)
    (2, 3)
    """
    from verify.dynamics.system import System
    from verify.laws.rule import Budget, solve
    from verify.numbers.parse import to_number
    from verify.oracle.reference import GENERATION_BITS, random_cases

    def exact(rec: dict[Any, Any]) -> tuple[Any, ...]:
        g, a = ([[to_number(x) for x in row] for row in rec[f]] for f in ("mass_matrix", "normals"))
        c, e, v = ([to_number(x) for x in rec[f]] for f in ("time_terms", "restitution", "velocity"))
        return g, a, c, e, v

    def bounded(rec: dict[Any, Any]) -> bool:
        g, a, c, e, v = exact(rec)
        run = solve(System(g, a, e, c), v, max_iterations=MAX_IMPULSES, trace=False, certify=False,
                    budget=Budget(bits=GENERATION_BITS))  # fmt: skip
        return run.stop != "budget"

    return [exact(rec) for rec in random_cases(size, seed=seed, keep=bounded)[0]]


class Outcome(NamedTuple):
    """What every contestant keeps of a case: its branch sequence and its last velocity (the
    exact engine's :class:`~verify.laws.outcome.Result`, with its System, is not kept: the plain
    loops keep no more than this either)."""

    impact_sets: list[Any]
    stop: str
    velocity: tuple[Any, ...]


def _kept(result: Any) -> Outcome:
    return Outcome(result.impact_sets, result.stop, result.exit_velocity)


def _exact_engine(cases: Sequence[tuple[Any, ...]], backend: Any) -> list[Outcome]:
    """The general engine on corner cases: one System and one solve a case."""
    from verify.laws.rule import solve

    out = []
    for k, xd, yd, e1, e2 in cases:
        s = corner_system(k, e1, e2, backend=backend)
        out.append(_kept(solve(s, [xd, yd, 0], max_iterations=MAX_IMPULSES, trace=False, certify=False)))
    return out


def _baseline(cases: Sequence[tuple[Any, ...]]) -> list[tuple[Any, ...]]:
    """The plain loop (eq. 10) on every case, in the numbers the cases are in: (zones, xd, yd)."""
    return [paper_run(*c, max_iterations=MAX_IMPULSES) for c in cases]


def _best(fns: dict[str, Callable[[], Any]], repeats: int) -> tuple[dict[str, float], dict[str, Any]]:
    """Best wall time of each function over ``repeats`` rounds, run alternately."""
    best = {name: float("inf") for name in fns}
    results: dict[str, Any] = {}
    for _ in range(repeats):
        for name, fn in fns.items():
            results[name] = None  # this contestant's last output: not alive while it runs again
            gc.collect()  # each run starts from the same heap (not timed)
            t = time.perf_counter()
            results[name] = fn()
            best[name] = min(best[name], time.perf_counter() - t)
    return best, results


def _speed(name: str, seconds: float, size: int, baseline: str, base_seconds: float) -> Figure:
    return Figure(name, round(size / seconds, 1), "cases/s", baseline, round(base_seconds / seconds, 2))


def _against_loop(batch: str, times: dict[str, float], n: int, *contestants: str) -> list[Figure]:
    """The batch's plain Fraction loop (its baseline), each contestant against it, and the size."""
    base = f"{batch}.fraction_loop"
    loop = times["fraction_loop"]
    return [
        _speed(base, loop, n, base, loop),
        *(_speed(f"{batch}.{name}", times[name], n, base, loop) for name in contestants),
        Figure(f"{batch}.size", n, "cases", f"{batch}.size", 1.0),
    ]


def _corner_figures(cases: list[tuple[Any, ...]], repeats: int, with_gp: bool = True) -> list[Figure]:
    from verify.laws.loops.floats import solve_batch
    from verify.numbers.backends import RationalBackend

    n = len(cases)
    fast, plain = RationalBackend(), RationalBackend("python")
    floats = [tuple(x.numerator / x.denominator for x in c) for c in cases]  # correctly rounded
    arrays = corner_batch([c[0] for c in cases], [c[1:3] for c in cases], [c[3:] for c in cases])
    times, res = _best(
        {
            "fraction_loop": lambda: _baseline(cases),
            "exact_engine": lambda: _exact_engine(cases, fast),
            "exact_engine_pure_python": lambda: _exact_engine(cases, plain),
            "float_loop": lambda: _baseline(floats),
            "float_path": lambda: solve_batch(arrays, MAX_IMPULSES),
        },
        repeats,
    )
    exact_zones = [zones_of(r) for r in res["exact_engine"]]
    if exact_zones != [z for z, _, _ in res["fraction_loop"]]:
        raise AssertionError("the exact engine and the Fraction loop disagree on the batch")
    wrong_float = sum(1 for e, (z, _, _) in zip(exact_zones, res["float_loop"]) if e != z)
    path = res["float_path"]
    exact_sets = [list(r.impact_sets) for r in res["exact_engine"]]
    wrong_path = sum(1 for i, e in enumerate(exact_sets) if e != path.impact_sets(i))
    base, fbase = "corner_batch.fraction_loop", "corner_batch.float_loop"
    t = times
    return [
        _speed(base, t["fraction_loop"], n, base, t["fraction_loop"]),
        _speed("corner_batch.exact_engine", t["exact_engine"], n, base, t["fraction_loop"]),
        _speed("corner_batch.exact_engine_pure_python", t["exact_engine_pure_python"], n, base, t["fraction_loop"]),
        _speed(fbase, t["float_loop"], n, fbase, t["float_loop"]),
        _speed("corner_batch.float_path", t["float_path"], n, fbase, t["float_loop"]),
        Figure(
            "corner_batch.float_loop_wrong_branches",
            wrong_float,
            "cases",
            "corner_batch.size",
            round(wrong_float / n, 4),
        ),
        Figure(
            "corner_batch.float_path_wrong_branches", wrong_path, "cases", "corner_batch.size", round(wrong_path / n, 4)
        ),
        Figure(
            "corner_batch.float_path_exact_fallbacks",
            int(path.fallback.sum()),
            "cases",
            "corner_batch.size",
            round(float(path.fallback.sum()) / n, 4),
        ),
        *(
            Figure(f"corner_batch.float_path_rung_{name}", count, "cases", "corner_batch.size", round(count / n, 4))
            for name, count in path.rung_counts().items()
        ),
        Figure("corner_batch.size", n, "cases", "corner_batch.size", 1.0),
        *(_gp_corner("corner_batch", cases, res["exact_engine"], repeats, t["fraction_loop"]) if with_gp else []),
    ]


def _gp_corner(
    batch: str, cases: list[tuple[Any, ...]], engine: Sequence[Outcome], repeats: int, base: float
) -> list[Figure]:
    gp = _gp()
    if gp is None:
        return []
    runs = gp.run_corners(cases, max_impulses=MAX_IMPULSES, repeats=repeats)
    return [_gp_figure(batch, runs, engine, (f"{batch}.fraction_loop", base))]


def _short_figures(cases: list[tuple[Any, ...]], repeats: int, with_gp: bool = True) -> list[Figure]:
    """The short runs with a new geometry per case: the general exact engine (one System and one
    solve a case) against the plain Fraction loop; their branch sequences must agree. Beside
    them, the bare rate loop (:func:`verify.bench.baselines.bare_rates_run`, nothing validated,
    no object built): not a contestant, a bound on what Python code reaches on this batch."""
    from verify.bench.baselines import bare_rates_run
    from verify.models.corner import corner_geometry
    from verify.numbers.backends import RationalBackend

    n, fast, still = len(cases), RationalBackend(), Fraction(0)

    def bare() -> list[tuple[Any, ...]]:
        out = []
        for k, xd, yd, e1, e2 in cases:
            g, normals = corner_geometry(k)
            out.append(bare_rates_run(g, normals, [e1, e2], [xd, yd, still], MAX_IMPULSES, number=fast.convert))
        return out

    times, res = _best({"fraction_loop": lambda: _baseline(cases), "exact_engine": lambda: _exact_engine(cases, fast),
                        "bare_rates": bare}, repeats)  # fmt: skip
    if [zones_of(r) for r in res["exact_engine"]] != [z for z, _, _ in res["fraction_loop"]]:
        raise AssertionError("the exact engine and the Fraction loop disagree on the short batch")
    if [sets for sets, _ in res["bare_rates"]] != [o.impact_sets for o in res["exact_engine"]]:
        raise AssertionError("the bare rate loop and the exact engine disagree on the short batch")
    return [
        *_against_loop("corner_short", times, n, "exact_engine", "bare_rates"),
        *(_gp_corner("corner_short", cases, res["exact_engine"], repeats, times["fraction_loop"]) if with_gp else []),
    ]


def _gp_figure(batch: str, runs: Any, engine: Sequence[Outcome], base: tuple[str, float]) -> Figure:
    """The figure of the repository's GP script (:mod:`verify.bench.gp`, exact rationals) on a
    batch against ``base`` (its name and time); its branch sequences must be the exact engine's
    (an independent check)."""
    if [list(sets) for sets in runs.impact_sets] != [list(o.impact_sets) for o in engine]:
        raise AssertionError(f"PARI/GP and the exact engine disagree on the {batch} batch")
    return _speed(f"{batch}.gp", runs.seconds, len(engine), *base)


def _gp() -> Any:
    """:mod:`verify.bench.gp` when ``gp`` is installed, else None."""
    from verify.bench import gp

    return gp if gp.available() else None


def _same_branches(batch: str, engine: Sequence[Outcome], loop: Sequence[tuple[Any, ...]]) -> None:
    if [list(o.impact_sets) for o in engine] != [list(sets) for sets, _ in loop]:
        raise AssertionError(f"the exact engine and the plain Fraction loop disagree on the {batch} batch")


def _cradle_figures(eps: list[Fraction], repeats: int, with_gp: bool = True) -> list[Figure]:
    """The three-ball cradle over a grid of eps, one geometry: the engine's batch entry point
    (:func:`verify.laws.rule.solve_many`) against the plain loop, which also builds its geometry
    once (:mod:`verify.bench.baselines`)."""
    from verify.bench.baselines import plain_geometry, plain_run
    from verify.dynamics.system import System
    from verify.laws.rule import solve_many
    from verify.models.cradle import cradle_geometry
    from verify.numbers.backends import RationalBackend

    fast, n = RationalBackend(), len(eps)
    g, normals = cradle_geometry([Fraction(1)] * 3)
    v, still = [Fraction(100), Fraction(0), Fraction(0)], [Fraction(0), Fraction(0)]

    def loop() -> list[tuple[Any, ...]]:
        geometry = plain_geometry(g, normals)
        return [plain_run(geometry, still, [e, e], v, MAX_IMPULSES) for e in eps]

    def engine() -> list[Outcome]:
        s = System(g, normals, [1, 1], backend=fast)
        out = solve_many(s, [v] * n, restitutions=[[e, e] for e in eps], max_iterations=MAX_IMPULSES, trace=False,
                         certify=False)  # fmt: skip
        return [_kept(r) for r in out]

    times, res = _best({"fraction_loop": loop, "exact_engine": engine}, repeats)
    _same_branches("cradle", res["exact_engine"], res["fraction_loop"])
    return [
        *_against_loop("cradle", times, n, "exact_engine"),
        *(
            _gp_systems("cradle", [(g, normals, [e, e], v) for e in eps], res["exact_engine"], repeats, times)
            if with_gp
            else []
        ),
    ]


def _general_figures(cases: list[tuple[Any, ...]], repeats: int) -> list[Figure]:
    """Random general systems, a new geometry each: one System and one solve a case against the
    plain loop (:mod:`verify.bench.baselines`), which builds its geometry per case too."""
    from verify.bench.baselines import plain_geometry, plain_run
    from verify.dynamics.system import System
    from verify.laws.rule import solve
    from verify.numbers.backends import RationalBackend

    fast, n = RationalBackend(), len(cases)

    def loop() -> list[tuple[Any, ...]]:
        return [plain_run(plain_geometry(g, a), c, e, v, MAX_IMPULSES) for g, a, c, e, v in cases]

    def engine() -> list[Outcome]:
        return [_kept(solve(System(g, a, e, c, backend=fast), v, max_iterations=MAX_IMPULSES, trace=False,
                            certify=False)) for g, a, c, e, v in cases]  # fmt: skip

    times, res = _best({"fraction_loop": loop, "exact_engine": engine}, repeats)
    _same_branches("general", res["exact_engine"], res["fraction_loop"])
    return _against_loop("general", times, n, "exact_engine")


def _gp_systems(
    batch: str, systems: list[tuple[Any, ...]], engine: Sequence[Outcome], repeats: int, times: dict[Any, Any]
) -> list[Figure]:
    gp = _gp()
    if gp is None:
        return []
    runs = gp.run_systems(systems, max_impulses=MAX_IMPULSES, repeats=repeats)
    return [_gp_figure(batch, runs, engine, (f"{batch}.fraction_loop", times["fraction_loop"]))]


def _table_figures(repeats: int, with_gp: bool = True) -> list[Figure]:
    """Table 1: its runs alone (exact and paper mode, :func:`verify.paper.table1.table1_runs`)
    against the paper's loop in PARI/GP where installed (in the paper's arithmetic, GP reals, and
    on exact rationals), and the whole audit (:func:`verify.paper.table1.table1`) on the
    fastest rationals against pure-Python Fractions."""
    from verify.paper.table1 import table1, table1_runs

    def pure_python() -> Any:
        old = os.environ.get("VERIFY_RATIONALS")
        os.environ["VERIFY_RATIONALS"] = "python"
        try:
            return table1()
        finally:
            if old is None:
                del os.environ["VERIFY_RATIONALS"]
            else:
                os.environ["VERIFY_RATIONALS"] = old

    def runs() -> Any:  # the tables of one clock reading: a table takes milliseconds
        return [table1_runs() for _ in range(TABLE_RUNS)]

    times, res = _best({"runs": runs, "fast": table1, "python": pure_python}, repeats)
    base = "table1.pure_python"
    per_table = times["runs"] / TABLE_RUNS
    out = [
        Figure(base, round(1 / times["python"], 3), "tables/s", base, 1.0),
        Figure(
            "table1.per_second",
            round(1 / times["fast"], 3),
            "tables/s",
            base,
            round(times["python"] / times["fast"], 2),
        ),
    ]
    gp = _gp() if with_gp else None
    if gp is None:
        return [*out, Figure("table1.runs", round(1 / per_table, 1), "tables/s", "table1.runs", 1.0)]
    reals, rationals = gp.run_table1(real=True, repeats=repeats), gp.run_table1(real=False, repeats=repeats)
    found = [[(r.stop, list(r.impact_sets)) for _, r in res["runs"][0]]]
    for name, g in (("reals", reals), ("rationals", rationals)):
        if [list(zip(g.stops, (list(s) for s in g.impact_sets)))] != found:
            raise AssertionError(f"PARI/GP ({name}) and the paper mode of the exact engine disagree on Table 1")
    gbase = "table1.gp"
    return [
        *out,
        Figure("table1.runs", round(1 / per_table, 1), "tables/s", gbase, round(reals.seconds / per_table, 3)),
        Figure(gbase, round(1 / reals.seconds, 1), "tables/s", gbase, 1.0),
        Figure(
            "table1.gp_rationals",
            round(1 / rationals.seconds, 1),
            "tables/s",
            gbase,
            round(reals.seconds / rationals.seconds, 3),
        ),
    ]


def _impulse_figures(impulses: Sequence[int]) -> list[Figure]:
    from verify.laws.rule import solve
    from verify.numbers.backends import IntervalBackend, RationalBackend

    k, (xd, yd), (e1, e2) = LONG_RUN["slope"], LONG_RUN["velocity"], LONG_RUN["cors"]
    out: list[Figure] = []
    first: dict[str, float] = {}
    for name, backend in (("exact", RationalBackend()), ("interval", IntervalBackend(50, max_dps=51_200))):
        warm = corner_system(k, e1, e2, backend=backend)  # imports and caches first, off the clock
        solve(warm, [xd, yd, 0], max_iterations=impulses[0], trace=False, certify=False)
        for count in impulses:
            system = corner_system(k, e1, e2, backend=backend)
            t = time.perf_counter()
            r = solve(system, [xd, yd, 0], max_iterations=count, trace=False, certify=False)
            cost = (time.perf_counter() - t) / max(r.iterations, 1) * 1e6
            first.setdefault(name, cost)
            label = f"impulse_cost.{name}.{count}"
            base = f"impulse_cost.{name}.{impulses[0]}"
            out.append(Figure(label, round(cost, 2), "us/impulse", base, round(cost / first[name], 2)))
            K = r.backend
            if name == "exact":
                bits = max(K.size(x) for x in r.exit_velocity)
                out.append(Figure(f"exact_bits.{count}", bits, "bits", f"exact_bits.{impulses[0]}", 0.0))
            else:
                out.append(Figure(f"interval_digits.{count}", K.dps, "digits", "interval_digits.start", K.dps / 50))
    # bits ratios against the first count
    bits0 = next(f.value for f in out if f.name == f"exact_bits.{impulses[0]}")
    return [
        Figure(f.name, f.value, f.unit, f.baseline, round(f.value / bits0, 2)) if f.unit == "bits" else f for f in out
    ]


def _rss_mib() -> float:
    # ru_maxrss is in KiB on Linux, bytes on macOS
    scale = 1 if platform.system() == "Darwin" else 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale / 2**20


def _map_figures(impulses: int) -> list[Figure]:
    """The map of four unit balls, on python-flint's arithmetic of the parameter against SymPy's alone (the
    baseline: the map as it runs without the fast extra), once each (the same map: checked), and its size."""
    from verify.maps.cradle import cradle_map, map_json
    from verify.numbers.backends.ratfunc import FLINT, using

    def run() -> str:
        return json.dumps(map_json(cradle_map(MAP_BALLS, max_impulses=impulses)))

    def on_sympy() -> str:
        with using("sympy"):
            return run()

    fns = {"sympy": on_sympy, **({"flint": run} if FLINT else {})}
    times, results = _best(fns, 1)
    if len(set(results.values())) != 1:
        raise AssertionError("the map on flint's arithmetic differs from the map on SymPy's")
    base = "maps.sympy"
    speed = {name: Figure(f"maps.{name}", round(1 / t, 4), "maps/s", base, round(times["sympy"] / t, 2))
             for name, t in times.items()}  # fmt: skip
    return [*speed.values(), Figure("maps.max_impulses", impulses, "impulses", "maps.max_impulses", 1.0)]


def bench(
    *,
    size: int = BATCH_SIZE,
    repeats: int = 3,
    impulses: Sequence[int] = IMPULSES,
    table: bool = True,
    cradle: int = CRADLE_SIZE,
    general: int = GENERAL_SIZE,
    gp: bool = True,
    map_impulses: int = MAP_IMPULSES,
    progress: Callable[[str], None] | None = None,
) -> list[Figure]:
    """Every figure of ``verify bench`` (see the module docstring): ``size`` cases in each corner
    batch, ``cradle`` eps in the cradle batch, ``general`` systems in the general one, the maps batch
    explored up to ``map_impulses``."""
    from verify.errors import require

    require("numpy", "verify bench (its float path)")  # before the first timing
    say = progress or (lambda _msg: None)
    start_rss = _rss_mib()
    say(f"corner batch: {size} cases, best of {repeats}")
    figures = _corner_figures(batch(size), repeats, gp)
    say(f"short corner runs, a new geometry per case: {size} cases, best of {repeats}")
    figures += _short_figures(short_batch(size), repeats, gp)
    say(f"three-ball cradle over {cradle} eps, one geometry: best of {repeats}")
    figures += _cradle_figures(cradle_grid(cradle), repeats, gp)
    say(f"general systems: {general} cases, best of {repeats}")
    figures += _general_figures(general_batch(general), repeats)
    if table:
        say("Table 1, exact and paper mode")
        figures += _table_figures(repeats, gp)
    say(f"cost per impulse at {', '.join(map(str, impulses))} impulses")
    figures += _impulse_figures(impulses)
    say(f"the map of {MAP_BALLS} unit balls up to {map_impulses} impulses, on flint's arithmetic and on SymPy's")
    figures += _map_figures(map_impulses)
    peak = _rss_mib()
    figures.append(Figure("peak_memory", round(peak, 1), "MiB", "memory_after_import", round(peak / start_rss, 2)))
    figures.append(Figure("memory_after_import", round(start_rss, 1), "MiB", "memory_after_import", 1.0))
    return figures


def machine() -> str:
    """A short description of this machine (for the JSON record)."""
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, {platform.system()}"


def bench_json(figures: Sequence[Figure], *, quick: bool = False) -> dict[str, Any]:
    """The ``verify bench --json`` record (contracts): figures and the machine."""
    return {"figures": [f.to_json() for f in figures], "machine": machine(), "quick": quick,
            "batches": {b: BATCHES[b] for b in dict.fromkeys(f.batch for f in figures) if b in BATCHES}}  # fmt: skip


def bench_text(record: dict[str, Any]) -> str:
    """The figures as an aligned table, with what each ratio compares."""
    rows = [("figure", "value", "unit", "ratio", "against")]
    for f in record["figures"]:
        value = f"{f['value']:,}" if isinstance(f["value"], int) else f"{f['value']:,.2f}"
        rows.append((f["name"], value, f["unit"], f"{f['ratio']:.2f}", f["baseline"]))
    widths = [max(len(r[i]) for r in rows) for i in range(5)]
    lines = [f"machine: {record['machine']}" + (" (quick smoke run: not a measurement)" if record.get("quick") else "")]
    for r in rows:
        lines.append(
            "  ".join(c.rjust(w) if i in (1, 3) else c.ljust(w) for i, (c, w) in enumerate(zip(r, widths))).rstrip()
        )
    return "\n".join(lines) + "\n"


def requirements(record: dict[str, Any]) -> list[str]:
    """Each ratio that the project requires of its speed, read off a bench record, met or not."""
    f = {x["name"]: x for x in record["figures"]}
    out = []

    def line(text: str, ok: bool) -> None:
        out.append(f"{text}: {'met' if ok else 'NOT met'}")

    def ratio(name: str) -> float:
        return float(f[name]["ratio"])

    if "corner_short.exact_engine" in f:
        r = ratio("corner_short.exact_engine")
        line(f"exact engine / plain Fraction loop on short runs, a new geometry per case = {r:.2f} (at least 2.2)",
             r >= 2.2)  # fmt: skip
        if "corner_short.gp" in f:
            g = ratio("corner_short.gp")
            line(f"exact engine / PARI/GP on the same short runs = {r / g:.2f} (at least 1)", r >= g)
    if "corner_batch.exact_engine" in f:
        r = ratio("corner_batch.exact_engine")
        line(f"exact engine / plain Fraction loop on the long-run corner batch = {r:.2f} (at least 2.0)", r >= 2.0)
    if "table1.runs" in f and "table1.gp" in f:
        ours, theirs = float(f["table1.runs"]["value"]), float(f["table1.gp"]["value"])
        line(f"Table 1 (exact and paper mode) / the paper's loop in PARI/GP (its reals) = {ours / theirs:.2f} "
             "(at least 0.5)", ours >= theirs / 2)  # fmt: skip
        exact = float(f["table1.gp_rationals"]["value"])
        line(f"Table 1 (exact and paper mode) / the same GP loop on exact rationals = {ours / exact:.2f} "
             "(at least 0.5)", ours >= exact / 2)  # fmt: skip
    if not any(name.endswith(".gp") for name in f):
        out.append(
            "a --quick run times no PARI/GP loop"
            if record.get("quick")
            else "PARI/GP (gp) was not installed where this record was made: no ratio against the paper's own tool"
        )
    if "corner_batch.float_path" in f:
        r = ratio("corner_batch.float_path")
        line(f"certified float path / plain float loop = {r:.2f} (at least 0.5)", r >= 0.5)
        wrong = f["corner_batch.float_path_wrong_branches"]["value"]
        plain = f["corner_batch.float_loop_wrong_branches"]["value"]
        line(f"float path wrong branch sequences = {wrong} (none; the plain float loop: {plain})", wrong == 0)
    costs = {
        (x["name"].split(".")[1], int(x["name"].rsplit(".", 1)[1])): float(x["value"])
        for x in record["figures"]
        if x["name"].startswith("impulse_cost.")
    }
    last = max((count for _, count in costs), default=None)
    if last is not None and ("interval", last) in costs and ("exact", last) in costs:
        r = costs["interval", last] / costs["exact", last]
        line(f"interval / exact cost per impulse at {last:,} impulses = {r:.3f} (at most 0.2)", r <= 0.2)
    return out
