"""Throughput figures, each beside a baseline measured in the same run (``verify bench``).

Machines here are noisy, so every figure is a ratio against a baseline timed in the same
process, alternately with it, and each time is the best of ``repeats`` runs. The batch is
:func:`verify.checks.sweep.random_corner_cases` (seed 0): rational slope k in (1/10, 10) with
numerator and denominator up to 999, both walls hit at the start, rational CORs in [0, 1]
with 0 and 1 drawn often, at most 100 impulses a case. Each contestant receives the
batch in its own number type (Fractions for the exact ones, floats for the float loop,
float arrays with radii for the float path), converted before the clock starts; the
exact engine builds and validates a :class:`~verify.core.system.System` per case inside it.

The baselines are the plain loop written for the corner alone
(:func:`verify.models.corner.paper_run`, the paper's eq. (10) with its closed forms), once
over ``fractions.Fraction`` and once over Python floats; the float one is the plain float
implementation of the corner report's float check too. Every contestant's branch sequence
(its zones) is compared with the exact engine's.

>>> figures = bench(size=20, repeats=1, impulses=(10,), table=False)
>>> [(f.name, f.unit) for f in figures[:2]]
[('corner_batch.fraction_loop', 'cases/s'), ('corner_batch.exact_engine', 'cases/s')]
"""

from __future__ import annotations

import os
import platform
import resource
import shutil
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
from fractions import Fraction
from typing import Any

from verify.checks.sweep import random_corner_cases
from verify.models.corner import corner_batch, corner_system, paper_run, zones_of

BATCH_SIZE = 10_000
BATCH_SEED = 0
MAX_IMPULSES = 100
IMPULSES = (10, 100, 1000, 10_000)
#: the short-run batch: corner cases of 1 to 3 impulses, a new slope every case (a sweep over
#: geometries, a property run), drawn with this seed and kept when the exact run is that short
SHORT_SEED = 1
SHORT_IMPULSES = 3
#: ``verify bench --quick``: a smoke run (CI runs it), not a measurement
QUICK = {"size": 500, "repeats": 1, "impulses": (10, 100), "table": False}
#: the long run of the cost-per-impulse figures: the ideal rule in a corner of slope
#: 1/10000, which reflects the disk 15,706 times before it leaves (exact), all single impacts
LONG_RUN: dict[str, Any] = {
    "slope": Fraction(1, 10_000),
    "velocity": (Fraction(1), Fraction(1, 30_000)),
    "cors": (1, 1),
}


@dataclass(frozen=True)
class Figure:
    """One line of ``verify bench --json``: ``value`` in ``unit``, ``ratio`` = value / baseline
    (for speeds, the speed-up; a baseline line names itself with ratio 1)."""

    name: str
    value: float
    unit: str
    baseline: str
    ratio: float

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


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


def _exact_engine(cases: Sequence[tuple], backend: Any) -> list:
    from verify.core.rule import solve

    out = []
    for k, xd, yd, e1, e2 in cases:
        s = corner_system(k, e1, e2, backend=backend)
        out.append(solve(s, [xd, yd, 0], max_iterations=MAX_IMPULSES, trace=False, certify=False))
    return out


def _baseline(cases: Sequence[tuple]) -> list[list[str]]:
    """The zones of the plain loop (eq. 10) on every case, in the numbers the cases are in."""
    return [paper_run(*c, max_iterations=MAX_IMPULSES)[0] for c in cases]


def _best(fns: dict[str, Callable[[], Any]], repeats: int) -> tuple[dict[str, float], dict[str, Any]]:
    """Best wall time of each function over ``repeats`` rounds, run alternately."""
    best = {name: float("inf") for name in fns}
    results: dict[str, Any] = {}
    for _ in range(repeats):
        for name, fn in fns.items():
            t = time.perf_counter()
            results[name] = fn()
            best[name] = min(best[name], time.perf_counter() - t)
    return best, results


def _speed(name: str, seconds: float, size: int, baseline: str, base_seconds: float) -> Figure:
    return Figure(name, round(size / seconds, 1), "cases/s", baseline, round(base_seconds / seconds, 2))


def _corner_figures(cases: list[tuple], repeats: int) -> list[Figure]:
    from verify.core.backends import RationalBackend
    from verify.core.engines.floats import solve_batch

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
    if exact_zones != res["fraction_loop"]:
        raise AssertionError("the exact engine and the Fraction loop disagree on the batch")
    wrong_float = sum(1 for e, z in zip(exact_zones, res["float_loop"]) if e != z)
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
        Figure("corner_batch.size", n, "cases", "corner_batch.size", 1.0),
    ]


def _short_figures(cases: list[tuple], repeats: int) -> list[Figure]:
    """The short runs with a new geometry per case: the general exact engine (one System and one
    solve a case) against the plain Fraction loop; their branch sequences must agree."""
    from verify.core.backends import RationalBackend

    n, fast = len(cases), RationalBackend()
    times, res = _best({"fraction_loop": lambda: _baseline(cases), "exact_engine": lambda: _exact_engine(cases, fast)},
                       repeats)  # fmt: skip
    if [zones_of(r) for r in res["exact_engine"]] != res["fraction_loop"]:
        raise AssertionError("the exact engine and the Fraction loop disagree on the short batch")
    base = "corner_short.fraction_loop"
    return [
        _speed(base, times["fraction_loop"], n, base, times["fraction_loop"]),
        _speed("corner_short.exact_engine", times["exact_engine"], n, base, times["fraction_loop"]),
        Figure("corner_short.size", n, "cases", "corner_short.size", 1.0),
    ]


def _table_figures(repeats: int) -> list[Figure]:
    from verify.checks.paper.table1 import table1

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

    times, _ = _best({"fast": table1, "python": pure_python}, repeats)
    base = "table1.pure_python"
    return [
        Figure(base, round(1 / times["python"], 3), "tables/s", base, 1.0),
        Figure(
            "table1.per_second",
            round(1 / times["fast"], 3),
            "tables/s",
            base,
            round(times["python"] / times["fast"], 2),
        ),
    ]


def _impulse_figures(impulses: Sequence[int]) -> list[Figure]:
    from verify.core.backends import IntervalBackend, RationalBackend
    from verify.core.rule import solve

    k, (xd, yd), (e1, e2) = LONG_RUN["slope"], LONG_RUN["velocity"], LONG_RUN["cors"]
    out: list[Figure] = []
    first: dict[str, float] = {}
    for name, backend in (("exact", RationalBackend()), ("interval", IntervalBackend(50, max_dps=51_200))):
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


def bench(
    *,
    size: int = BATCH_SIZE,
    repeats: int = 3,
    impulses: Sequence[int] = IMPULSES,
    table: bool = True,
    progress: Callable[[str], None] | None = None,
) -> list[Figure]:
    """Every figure of ``verify bench`` (see the module docstring)."""
    say = progress or (lambda _msg: None)
    start_rss = _rss_mib()
    say(f"corner batch: {size} cases, best of {repeats}")
    figures = _corner_figures(batch(size), repeats)
    say(f"short corner runs, a new geometry per case: {size} cases, best of {repeats}")
    figures += _short_figures(short_batch(size), repeats)
    if table:
        say("Table 1, exact and paper mode")
        figures += _table_figures(repeats)
    say(f"cost per impulse at {', '.join(map(str, impulses))} impulses")
    figures += _impulse_figures(impulses)
    peak = _rss_mib()
    figures.append(Figure("peak_memory", round(peak, 1), "MiB", "memory_after_import", round(peak / start_rss, 2)))
    figures.append(Figure("memory_after_import", round(start_rss, 1), "MiB", "memory_after_import", 1.0))
    return figures


def machine() -> str:
    """A short description of this machine (for the JSON record)."""
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, {platform.system()}"


def bench_json(figures: Sequence[Figure], *, quick: bool = False) -> dict[str, Any]:
    """The ``verify bench --json`` record (contracts): figures and the machine."""
    return {"figures": [f.to_json() for f in figures], "machine": machine(), "quick": quick}


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
    """Each ratio that the project requires, read off a bench record, met or not."""
    f = {x["name"]: x for x in record["figures"]}
    out = []

    def line(text: str, ok: bool) -> None:
        out.append(f"{text}: {'met' if ok else 'NOT met'}")

    if "corner_batch.exact_engine" in f:
        r = f["corner_batch.exact_engine"]["ratio"]
        line(f"exact engine / plain Fraction loop on the corner batch = {r:.2f} (at least 2.0)", r >= 2.0)
    if "corner_short.exact_engine" in f:
        r = f["corner_short.exact_engine"]["ratio"]
        line(f"exact engine / plain Fraction loop on short runs, a new geometry per case = {r:.2f} (at least 2.2)",
             r >= 2.2)  # fmt: skip
    if shutil.which("gp") is None:
        out.append("PARI/GP (gp) is not installed here: no ratio against the paper's own tool")
    if "corner_batch.float_path" in f:
        r = f["corner_batch.float_path"]["ratio"]
        line(f"float path with exact fallback / plain float loop = {r:.2f} (at least 10)", r >= 10)
        wrong = f["corner_batch.float_path_wrong_branches"]["value"]
        plain = f["corner_batch.float_loop_wrong_branches"]["value"]
        line(f"float path wrong branch sequences = {wrong} (none; the plain float loop: {plain})", wrong == 0)
    costs = sorted(
        (int(x["name"].rsplit(".", 1)[1]), x["value"])
        for x in record["figures"]
        if x["name"].startswith("impulse_cost.interval.")
    )
    if len(costs) >= 2:
        spread = max(c for _, c in costs) / min(c for _, c in costs)
        first, last = costs[0][0], costs[-1][0]
        line(
            f"interval cost per impulse from {first:,} to {last:,} impulses varies {spread:.2f}x (within 2x)",
            spread <= 2,
        )
    return out
