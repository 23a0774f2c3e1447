"""Each engine's answers explained by an exact model of its own algorithm (issue 38, item 4).

The models are computed exactly; here engine answers are made from exact values (their nearest
floats, as an engine would print them), then moved, so that each outcome of the explanation is shown
to happen, and the thresholds of the corner are checked against their closed form."""

from __future__ import annotations

from fractions import Fraction
from typing import Any

import sympy as sp

from verify.engines.explain import Explainer, explain_case, explained_summary, models
from verify.engines.run import engine_cases
from verify.laws.rule import solve
from verify.laws.sequential import Sequential
from verify.records.results import case_from_record

CASES = {c["id"]: c for c in engine_cases()}
SEQUENTIAL = {"settings": {"k": 8}, "solver": {"kind": "sequential", "iterations": "k", "threshold": 1.0,
                                                "precision": "float32"}}  # fmt: skip


def floats_of(case: dict[str, Any], law: Any, cors: list[str] | None = None) -> list[str]:
    """An engine's answer that is the model's exit velocity, rounded to doubles and printed."""
    c = case_from_record(dict(case, restitution=cors or case["restitution"]))
    r = solve(c.system, c.velocity_source, law=law, trace=False)
    return [repr(float(Fraction(r.backend.to_decimal(x, 30)))) for x in r.exit_velocity]


def test_an_answer_that_is_a_model_is_explained_by_it() -> None:
    case = CASES["cradle-3-eps-1/2"]
    answer = floats_of(case, Sequential(8, threshold=1))
    row = explain_case(Explainer(), SEQUENTIAL, case, answer)
    assert row["model"] == "the sequential law, 8 sweeps, order as given, threshold 1"
    assert Fraction(row["model_distance"]) <= Fraction(1, 10**5)


def test_an_answer_moved_past_the_precision_is_not() -> None:
    case = CASES["cradle-3-eps-1/2"]
    answer = [repr(float(x) + 0.01) for x in floats_of(case, Sequential(8, threshold=1))]
    row = explain_case(Explainer(), SEQUENTIAL, case, answer)
    assert row["model"] is None and row["why"].startswith("no model within the engine's precision")


def test_an_energy_gain_no_model_has_is_named() -> None:
    case = CASES["cradle-3-eps-1"]  # in: 5000; out: 15000
    row = explain_case(Explainer(), SEQUENTIAL, case, ["-100.0", "100.0", "100.0"])
    assert row["model"] is None and row["why"].startswith("an energy gain no model has")


def test_a_dropped_cor_is_named() -> None:
    case = CASES["paper-corner-pi6-pi12"]  # S2's COR is 0.001
    answer = floats_of(case, "simultaneous", [case["restitution"][0], "0"])
    row = explain_case(Explainer(), SEQUENTIAL, case, answer)
    assert row["model"] is None and row["why"].startswith("a dropped COR (COR 0.001 acts as 0")


def test_soft_contact_is_named_for_a_soft_engine() -> None:
    case = CASES["cradle-3-eps-1/2"]
    soft = {"settings": {}, "solver": {"kind": "soft", "precision": "float64"}}
    row = explain_case(Explainer(), soft, case, ["1.0", "2.0", "3.0"])
    assert row["why"].startswith("soft contact")


def test_a_corner_threshold_is_on_the_rate_of_the_walls() -> None:
    """A wall (-k, 1, 0) has rate sqrt(1 + k^2) times the disk's normal speed: the engine's threshold T
    becomes T sqrt(1 + k^2) on the rate (k = sqrt(3)/3: 2/sqrt(3) = 2 sqrt(3)/3)."""
    case = CASES["paper-corner-pi6-pi12"]
    law = next(m.law for m in models(SEQUENTIAL, case) if isinstance(m.law, Sequential))
    k = sp.sqrt(3) / 3
    assert [sp.simplify(sp.sympify(t) - sp.sqrt(1 + k**2)) for t in law.threshold] == [0, 0]


def test_a_threshold_on_the_cor_times_the_speed_and_a_floor() -> None:
    """DART's kind: no bounce when e * approach <= 0.1 (a speed threshold 0.1 / e) or e <= 1e-3."""
    case = dict(CASES["cradle-3-eps-1/2"], restitution=["1/2", "1/1000"])
    dart = {"settings": {"k": 30}, "solver": {"kind": "simultaneous", "iterations": "k", "threshold": 0.1,
                                              "threshold_of": "cor_times_speed", "cor_floor": 0.001}}  # fmt: skip
    by_label = {m.label: m for m in models(dart, case)}
    with_threshold = by_label["the simultaneous law with the engine's threshold"]
    assert with_threshold.cors == ("1/2", "0") and with_threshold.thresholds == ("1/5", "0")


def test_the_summary_counts_every_case_once() -> None:
    explainer = Explainer()
    rows = []
    for cid in ("cradle-3-eps-1/2", "cradle-3-eps-1", "cradle-4-eps-1"):
        answer = floats_of(CASES[cid], Sequential(8, threshold=1))
        rows.append(explain_case(explainer, SEQUENTIAL, CASES[cid], answer))
    rows.append(explain_case(explainer, SEQUENTIAL, CASES["cradle-3-eps-1"], ["-100.0", "100.0", "100.0"]))
    s = explained_summary(SEQUENTIAL, rows)
    assert s["cases"] == 4 and s["explained"] == 3 == sum(s["models"].values())
    assert sum(s["unexplained"].values()) == 1
