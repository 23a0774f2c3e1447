"""The paper's claims about the disk in the corner (Sect. 4.2), each checked and reported.

Each claim is checked exactly on deterministic samples of rational corner cases
(:func:`verify.paper.sweep.random_corner_cases`), run in parallel, and reported as ``holds``
(with the number of cases), ``refuted`` (with an exact counterexample case that
``verify corner --slope ... --phi ...`` or the library reproduces), or, for the asymmetric
case, ``found`` with where repeated multiple impacts occur.

>>> claims = check_claims(20, workers=1)
>>> {c.verdict for c in claims} <= {"found", "not found", "holds", "refuted"}
True
"""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Literal

from verify.dynamics.policy import JSONObject
from verify.paper.sweep import random_corner_cases, run_case, sweep
from verify.runner.tasks import TaskRunner

if TYPE_CHECKING:
    import sympy as sp

    from verify.paper.float_check import FloatCheck

#: a claim's verdict on the sample: it holds, a case refutes it, or (the asymmetric corner) where repeated
#: multiple impacts occur was found, or not
ClaimVerdict = Literal["holds", "refuted", "found", "not found"]


@dataclass
class Claim:
    """A claim of the paper with its verdict on the sample."""

    name: str
    verdict: ClaimVerdict
    cases: int
    note: str
    counterexample: dict[str, Any] | None = None
    examples: list[dict[str, Any]] = field(default_factory=list)


def run_with_paper(case: dict[str, Any]) -> dict[str, Any]:
    """:func:`run_case` plus the paper's own eq. (10) (closed forms, Fractions) on the same case."""
    from verify.models.corner import paper_run

    out = run_case(case)
    k = Fraction(case["slope"])
    xd, yd = (Fraction(v) for v in case["velocity"])
    e1, e2 = Fraction(case["eps1"]), Fraction(case["eps2"])
    steps = out["iterations"]
    zones, px, py = paper_run(k, xd, yd, e1, e2, max_iterations=steps)
    engine_zones = out["zones"][:steps]
    same = zones[:steps] == engine_zones
    if out["stop"] == "exit":
        same = same and zones == out["zones"] and [str(px), str(py)] == [str(Fraction(v)) for v in out["exit_velocity"]]
    out["agrees_with_paper_formulas"] = same
    return out


def _mirror(case: dict[str, Any]) -> dict[str, Any]:
    xd, yd = case["velocity"]
    return {
        **case,
        "id": case["id"] + "-mirror",
        "velocity": [xd, str(-Fraction(yd))],
        "eps1": case["eps2"],
        "eps2": case["eps1"],
    }


def _first(cases: list[dict[str, Any]], results: list[dict[str, Any]], bad: Any) -> dict[str, Any] | None:
    return next((c for c, r in zip(cases, results) if bad(c, r)), None)


def check_claims(
    n: int = 2000,
    *,
    seed: int = 0,
    executor: Executor | None = None,
    workers: int | None = None,
    progress: bool | None = None,
    runner: TaskRunner | None = None,
) -> list[Claim]:
    """Check the claims of Sect. 4.2 on ``n`` cases of each kind (general, symmetric, ideal); the runs are
    tasks of ``runner`` (:class:`verify.runner.tasks.TaskRunner`), else of ``executor`` or ``workers``."""
    general = random_corner_cases(n, seed=seed, max_iterations=1000)
    symmetric = random_corner_cases(n, seed=seed + 1, cors="symmetric", max_iterations=1000)
    ideal = random_corner_cases(n, seed=seed + 2, cors="ideal", max_iterations=1000)
    mirrored = [_mirror(c) for c in general]
    every = general + symmetric + ideal + mirrored
    results = sweep(every, executor=executor, workers=workers, progress=progress, func=run_with_paper, runner=runner)
    rg, rs, ri, rm = (results[i * n : (i + 1) * n] for i in range(4))
    bad = _first(general + symmetric + ideal, rg + rs + ri, lambda c, r: not r["agrees_with_paper_formulas"])
    ideal_claim, symmetric_claim = _at_most_once_claims(ideal, ri, symmetric, rs)
    return [
        Claim(
            "the general engine (Gram solve) agrees with the paper's closed forms (eq. 10) for V_1, V_2 and beta",
            "refuted" if bad else "holds",
            3 * n,
            "zones and exit velocities compared exactly (the betas enter both)",
            bad,
        ),
        _mirror_claim(general, rg, rm),
        ideal_claim,
        symmetric_claim,
        _repeated_claim(general, rg),
    ]


def _mirrored_ok(r: dict[str, Any], m: dict[str, Any]) -> bool:
    """Whether the run ``m`` of the mirrored case is the mirror image of the run ``r``."""
    swap = {"Z1": "Z2", "Z2": "Z1"}
    mirrored = [swap.get(z, z) for z in r["zones"]]
    if r["stop"] != m["stop"]:
        return False
    if r["stop"] != "exit":  # a proof may fire a step earlier on one side: compare what both ran
        common = min(len(mirrored), len(m["zones"]))
        return bool(mirrored[:common] == m["zones"][:common])
    if mirrored != m["zones"]:
        return False
    (x, y), (mx, my) = (map(Fraction, r["exit_velocity"]), map(Fraction, m["exit_velocity"]))
    return x == mx and y == -my


def _mirror_claim(general: list[dict[str, Any]], rg: list[dict[str, Any]], rm: list[dict[str, Any]]) -> Claim:
    bad = next((c for c, r, m in zip(general, rg, rm) if not _mirrored_ok(r, m)), None)
    return Claim(
        "mirror symmetry: phi -> -phi with eps1 <-> eps2 gives y -> -y",
        "refuted" if bad else "holds",
        len(general),
        "exit velocities compared exactly; zones Z1 and Z2 swapped",
        bad,
    )


def _at_most_once_claims(
    ideal: list[dict[str, Any]], ri: list[dict[str, Any]], symmetric: list[dict[str, Any]], rs: list[dict[str, Any]]
) -> tuple[Claim, Claim]:
    bad_ideal = _first(ideal, ri, lambda c, r: r["stop"] != "exit" or r["multiple_impacts"] > 1)
    bad_symmetric = _first(symmetric, rs, lambda c, r: r["multiple_impacts"] > 1)
    return (
        Claim(
            "ideal corner (eps1 = eps2 = 1): at most one multiple impact, and the disk always leaves",
            "refuted" if bad_ideal else "holds",
            len(ideal),
            "proved by Fassino and Pasquero (2019); checked here exactly",
            bad_ideal,
        ),
        Claim(
            "symmetric non-ideal corner (eps1 = eps2 < 1): multiple impacts happen at most once",
            "refuted" if bad_symmetric else "holds",
            len(symmetric),
            "the paper's numerical claim, checked exactly",
            bad_symmetric,
        ),
    )


def _repeated_claim(general: list[dict[str, Any]], rg: list[dict[str, Any]]) -> Claim:
    repeated = [(c, r) for c, r in zip(general, rg) if r["multiple_impacts"] > 1]
    gaps = sorted(abs(Fraction(c["eps1"]) - Fraction(c["eps2"])) for c, _ in repeated)
    note = f"{len(repeated)} of {len(general)} asymmetric cases have repeated multiple impacts" + (
        f"; |eps1 - eps2| among them ranges from {gaps[0]} to {gaps[-1]}" if gaps else ""
    )
    return Claim(
        "asymmetric corner: repeated multiple impacts occur when the CORs differ",
        "found" if repeated else "not found",
        len(general),
        note,
        None,
        [c for c, _ in repeated[:5]],
    )


@dataclass(frozen=True)
class CornerFindings:
    """Everything ``verify corner-claims`` reports: the claims, the symmetric corner's termination boundary
    (tan(alpha*) and alpha*, SymPy expressions), the rebounds as the corner narrows at one COR ``eps`` (a row
    per slope), and float against exact (:func:`verify.paper.float_check.float_vs_exact`)."""

    claims: list[Claim]
    boundary: tuple[sp.Expr, sp.Expr]
    eps: str
    rebounds: list[JSONObject]
    floats: FloatCheck


def corner_findings(
    cases: int = 2000,
    *,
    seed: int = 0,
    workers: int | None = None,
    runner: TaskRunner | None = None,
    progress: bool | None = False,
) -> CornerFindings:
    """Everything ``verify corner-claims`` reports (:class:`CornerFindings`), for the text and JSON views. The
    sweeps run on ``runner`` (local processes, a Dask cluster, with a checkpoint or not), else on ``workers`` processes;
    ``progress`` draws their bars on stderr (None: on a terminal)."""
    from verify.models.wedge import approach_slopes, rebounds_by_slope, symmetric_boundary
    from verify.paper.float_check import float_vs_exact

    claims = check_claims(cases, seed=seed, workers=workers, runner=runner, progress=progress)
    eps = "1/4"
    slopes = ["1/2", "2/5", *approach_slopes(Fraction(1, 4), 4), "3/10", "1/5"]
    rebounds = rebounds_by_slope(eps, ["1", "3/10"], slopes)
    floats = float_vs_exact(random_corner_cases(cases, seed=seed), workers=workers, runner=runner, progress=progress)
    return CornerFindings(claims, symmetric_boundary(), eps, rebounds, floats)
