"""Float against exact: how often does a plain float implementation take another branch?

The plain implementation is the paper's eq. (10) in Python floats
(:func:`verify.models.corner.paper_run` on floats, the float baseline of ``verify bench`` too):
what an engineer would write first. Its zone sequence is compared with the exact one,
impulse by impulse; at the first difference the exact rates tell why: a rate that is
exactly 0 (a COR of 0 leaves the normal velocity exactly 0, or the velocity grazes a wall)
which rounding turns into a tiny number of either sign, or a rate that is not 0 but too
small for double precision.

>>> from verify.paper.sweep import random_corner_cases
>>> report = float_vs_exact(random_corner_cases(50, seed=3), workers=1)
>>> report["cases"]
50
"""

from __future__ import annotations

from concurrent.futures import Executor
from fractions import Fraction
from typing import Any, TypedDict

from verify.paper.sweep import sweep
from verify.runner.tasks import TaskRunner


def compare_case(case: dict[str, Any]) -> dict[str, Any]:
    """Exact zones and plain-float zones of one corner case, and why they differ if they do."""
    from verify.models.corner import corner_system, paper_run, run_corner, zones_of

    exact = run_corner(
        slope=case["slope"],
        velocity=case["velocity"],
        eps1=case["eps1"],
        eps2=case["eps2"],
        max_iterations=case.get("max_iterations", 100),
        trace=True,
    )
    k = Fraction(case["slope"])
    xd, yd = (Fraction(v) for v in case["velocity"])
    e1, e2 = Fraction(case["eps1"]), Fraction(case["eps2"])
    steps = max(exact.result.iterations + (1 if exact.result.stop == "exit" else 0), 1)  # zones to compare
    fz = paper_run(float(k), float(xd), float(yd), float(e1), float(e2), max_iterations=steps)[0][:steps]
    ez = zones_of(exact.result)
    common = min(len(ez), len(fz))
    first = next((w for w in range(common) if ez[w] != fz[w]), None)
    out = {
        "id": case["id"],
        "exact_zones": ez,
        "float_zones": fz[: common + 1],
        "differs": first is not None,
        "step": first,
        "reason": None,
    }
    if first is not None:
        system = corner_system(k, e1, e2)
        v = exact.result.velocity_in if first == 0 else exact.result.steps[first - 1].velocity
        rates = [system.backend.to_number(b) for b in system.rates(v)]
        out["reason"] = "exact rate 0" if any(b == 0 for b in rates) else "tiny non-zero rate"
        out["exact_rates"] = [str(b) for b in rates]
    return out


class FloatCheck(TypedDict):
    """What :func:`float_vs_exact` found: the cases compared, those where the floats take another branch,
    their count by reason and with a COR of 0, and the first five of them (case, zones, reason)."""

    cases: int
    differing: int
    reasons: dict[str, int]
    differing_with_a_cor_of_0: int
    examples: list[dict[str, Any]]


def float_vs_exact(
    cases: list[dict[str, Any]],
    *,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    runner: TaskRunner | None = None,
) -> FloatCheck:
    """Compare every case (on ``runner``, else ``executor`` or ``workers``: :func:`verify.paper.sweep.sweep`);
    counts by reason, and the first few differing cases."""
    results = sweep(cases, executor=executor, workers=workers, progress=progress, func=compare_case, runner=runner)
    differing = [(c, r) for c, r in zip(cases, results) if r["differs"]]
    reasons: dict[str, int] = {}
    for _, r in differing:
        reasons[r["reason"]] = reasons.get(r["reason"], 0) + 1
    with_zero_cor = sum(1 for c, _ in differing if "0" in (c["eps1"], c["eps2"]))
    return {
        "cases": len(cases),
        "differing": len(differing),
        "reasons": reasons,
        "differing_with_a_cor_of_0": with_zero_cor,
        "examples": [{"case": c, **r} for c, r in differing[:5]],
    }
