"""Sweeps of many corner cases: deterministic case generators and a parallel runner.

:func:`sweep` runs a list of case dictionaries (strings only, so they travel to other
processes or machines) with :func:`run_case`, in chunks, as tasks of :mod:`verify.runner.tasks`:
local processes by default, or a Dask cluster through ``dask.distributed.Client(...).get_executor()``,
with a checkpoint if the :class:`~verify.runner.tasks.TaskRunner` keeps one. On a terminal it draws a
progress bar on stderr. Results come back in the order of the cases.

>>> cases = random_corner_cases(3, seed=1)
>>> [r["stop"] for r in sweep(cases, workers=1, progress=False)]
['exit', 'exit', 'exit']
"""

from __future__ import annotations

import contextlib
import random
import sys
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor
from fractions import Fraction
from typing import Any

from verify.numbers.format import format_exact
from verify.runner.tasks import TaskRunner


def _q(x: Fraction) -> str:
    return format_exact(x)


def random_corner_cases(
    n: int,
    *,
    seed: int = 0,
    max_digits: int = 999,
    cors: str = "general",
    both_walls: bool = True,
    max_iterations: int = 100,
) -> list[dict[str, Any]]:
    """``n`` corner cases with rational inputs, the same for the same seed.

    Slope k in (1/10, 10) with numerator and denominator up to ``max_digits``; velocity
    (xd, yd) rational with both walls hit at the start (|yd| < k xd) when ``both_walls``;
    CORs rational in [0, 1], with 0 and 1 drawn often. ``cors`` is ``"general"`` (two
    independent CORs), ``"symmetric"`` (one COR) or ``"ideal"`` (both 1).
    """
    rng = random.Random(seed)

    def rational(lo: Fraction, hi: Fraction) -> Fraction:
        while True:
            q = Fraction(rng.randint(1, max_digits), rng.randint(1, max_digits))
            if lo < q < hi:
                return q

    def cor() -> Fraction:
        r = rng.random()
        if r < 0.1:
            return Fraction(0)
        if r < 0.2:
            return Fraction(1)
        d = rng.randint(1, 1000)
        return Fraction(rng.randint(0, d), d)

    out = []
    for i in range(n):
        k = rational(Fraction(1, 10), Fraction(10))
        xd = Fraction(rng.randint(1, 1000), rng.randint(1, 100))
        u = Fraction(rng.randint(-999, 999), 1000) if both_walls else Fraction(rng.randint(-3000, 3000), 1000)
        yd = u * k * xd
        if cors == "ideal":
            e1 = e2 = Fraction(1)
        elif cors == "symmetric":
            e1 = e2 = cor()
        else:
            e1, e2 = cor(), cor()
        out.append(
            {
                "id": f"corner-{seed}-{i}",
                "slope": _q(k),
                "velocity": [_q(xd), _q(yd)],
                "eps1": _q(e1),
                "eps2": _q(e2),
                "max_iterations": max_iterations,
            }
        )
    return out


def grid_corner_cases(
    slopes: Sequence[str],
    velocities: Sequence[Sequence[str]],
    cors: Sequence[Sequence[str]],
    *,
    max_iterations: int = 1000,
) -> list[dict[str, Any]]:
    """Every combination of the given slopes, velocities (xd, yd) and COR pairs."""
    out: list[dict[str, Any]] = []
    for k in slopes:
        for v in velocities:
            for e1, e2 in cors:
                out.append(
                    {
                        "id": f"grid-{len(out)}",
                        "slope": k,
                        "velocity": list(v),
                        "eps1": e1,
                        "eps2": e2,
                        "max_iterations": max_iterations,
                    }
                )
    return out


def run_case(case: dict[str, Any]) -> dict[str, Any]:
    """Run one corner case dictionary; returns a summary made of plain values (picklable).

    A case on intervals whose sign stays undecided (a rate that is exactly 0) is run again
    exactly when its inputs are algebraic; a case that cannot be decided either way comes
    back with stop ``"undecided"`` and the reason, and the sweep goes on.
    """
    from verify.errors import InvalidInput, Undecided
    from verify.models.corner import run_corner

    try:
        try:
            run = _run(case, run_corner)
        except Undecided:
            if case.get("backend") != "interval":
                raise
            run = _run({**case, "backend": "exact"}, run_corner)  # a rate exactly 0: decide it exactly
    except (Undecided, InvalidInput) as exc:  # not decidable here (or not algebraic): say so, go on
        return {
            "id": case.get("id"),
            "stop": "undecided",
            "iterations": None,
            "zones": [],
            "multiple_impacts": 0,
            "exit_velocity": None,
            "backend": case.get("backend", "exact"),
            "rigorous": True,
            "reason": " ".join(str(exc).split()),
        }
    r = run.result
    K = r.backend
    return {
        "id": case.get("id"),
        "stop": r.stop,
        "iterations": r.iterations,
        "zones": run.zones,
        "multiple_impacts": sum(1 for J in r.impact_sets if len(J) == 2),
        "exit_velocity": [K.to_exact(x) if K.is_exact else K.to_decimal(x, 20) for x in r.exit_velocity[:2]],
        "backend": K.describe(),
        "rigorous": K.is_rigorous,
    }


def _run(case: dict[str, Any], run_corner: Any) -> Any:
    backend: Any = case.get("backend", "exact")
    if backend == "interval":  # sweeps give up on intervals early: an undecided sign is then decided exactly
        from verify.numbers.backends import IntervalBackend

        backend = IntervalBackend(case.get("dps") or 50, max_dps=case.get("max_dps", 200))
    return run_corner(
        alpha=case.get("alpha"),
        slope=case.get("slope"),
        phi=case.get("phi"),
        velocity=case.get("velocity"),
        eps1=case["eps1"],
        eps2=case["eps2"],
        backend=backend,
        dps=case.get("dps") if backend == "exact" else None,
        max_iterations=case.get("max_iterations", 100),
        trace=False,
        certify=case.get("certify", True),
    )


def _run_chunk(args: tuple[Callable[[dict[str, Any]], dict[str, Any]], list[dict[str, Any]]]) -> list[dict[str, Any]]:
    func, chunk = args
    return [func(case) for case in chunk]


def _bar(done: int, total: int) -> None:
    width = 30
    filled = width * done // max(total, 1)
    sys.stderr.write(f"\r[{'#' * filled}{' ' * (width - filled)}] {done}/{total}")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def sweep(
    cases: Iterable[dict[str, Any]],
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    chunk: int = 100,
    progress: bool | None = None,
    func: Callable[[dict[str, Any]], dict[str, Any]] = run_case,
    runner: TaskRunner | None = None,
) -> list[dict[str, Any]]:
    """Run every case with ``func`` (default :func:`run_case`, a module-level function), in parallel, in
    order: one task (:mod:`verify.runner.tasks`) for each ``chunk`` cases, named by the function and a
    digest of its cases.

    ``executor`` is any ``concurrent.futures.Executor`` (a Dask cluster:
    ``Client(...).get_executor()``); without one, a local process pool of ``workers``
    processes (default: every core) is used, or no pool at all for ``workers=1``. ``runner`` (a
    :class:`verify.runner.tasks.TaskRunner`, which may keep a checkpoint) replaces both. ``progress`` draws
    a bar on stderr (default: when stderr is a terminal). A chunk whose task fails twice raises
    :class:`verify.runner.tasks.TasksFailed` (naming its first and last case) once the others are done.
    """
    cases = list(cases)
    chunks = [(func, cases[i : i + chunk]) for i in range(0, len(cases), chunk)]
    show = sys.stderr.isatty() if progress is None else progress
    bar = (lambda done, total, task, result: _bar(min(done * chunk, len(cases)), len(cases))) if show else None
    with contextlib.ExitStack() as stack:
        if runner is None:
            runner = stack.enter_context(TaskRunner(workers=workers, executor=executor))
        name = f"sweep {func.__module__}.{func.__qualname__}"
        labels = [f"the cases {chunk[0].get('id')} to {chunk[-1].get('id')}" for _, chunk in chunks]
        parts = runner.map(name, _run_chunk, chunks, key=lambda payload: payload[1], progress=bar, labels=labels)
    return [r for part in parts for r in part]


def sweep_summary(results: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """How a sweep's runs ended: the count of each stop, and of runs with repeated multiple impacts.

    >>> sweep_summary([{"stop": "exit", "multiple_impacts": 2}, {"stop": "exit", "multiple_impacts": 1}])
    {'stops': {'exit': 2}, 'repeated_multiple_impacts': 1}
    """
    return {
        "stops": dict(Counter(r["stop"] for r in results)),
        "repeated_multiple_impacts": sum(1 for r in results if r["multiple_impacts"] > 1),
    }


def random_sweep(
    n: int,
    *,
    seed: int = 0,
    max_iterations: int = 100,
    workers: int | None = None,
    runner: TaskRunner | None = None,
    progress: bool | None = None,
) -> dict[str, Any]:
    """``verify sweep``: ``n`` random rational corner cases (:func:`random_corner_cases`) run exactly in
    parallel (on ``runner``, else ``workers`` local processes); their :func:`sweep_summary` with ``cases``
    (the count), ``seconds`` (wall time of the runs) and ``results`` (one summary per case, in order);
    ``progress`` as for :func:`sweep`.

    >>> s = random_sweep(2, seed=1, workers=1)
    >>> s["cases"], s["stops"], s["repeated_multiple_impacts"]
    (2, {'exit': 2}, 0)
    """
    import time

    cases = random_corner_cases(n, seed=seed, max_iterations=max_iterations)
    start = time.perf_counter()
    results = sweep(cases, workers=workers, runner=runner, progress=progress)
    seconds = time.perf_counter() - start
    return {"cases": len(cases), "seconds": seconds, **sweep_summary(results), "results": results}
