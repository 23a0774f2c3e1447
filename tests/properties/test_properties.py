"""The property suite: its verdicts, its counterexamples, and tests of the tests.

- The verdict table at the profile of HYPOTHESIS_PROFILE (dev: 25 cases a row, ci: 100;
  thorough runs the ci table here: the 100,000-case run is ``verify properties --profile
  thorough``): every property that is a theorem of the rule is proved or holds; every
  refutation reproduces from its case record alone.
- Each property catches a deliberately broken rule (a mutant of the engine).
- The counterexamples found are kept as ``@example`` regressions of a test that compares
  the energy check with an independent recomputation from the printed formulas.

The rows of the simultaneous law (``law`` ``simultaneous``) have their own tests in
tests/properties/test_properties_simultaneous.py; here they are counted, and their refutations reproduce.
"""

from __future__ import annotations

import dataclasses
import json
from fractions import Fraction
from typing import Any

import pytest
from hypothesis import example, given

import verify.dynamics.rates as rates_module
import verify.laws.rule as rule_module
from verify import bounds
from verify.cli import main
from verify.dynamics.system import System
from verify.laws.rule import Budget, solve
from verify.proofs import termination
from verify.properties import formulas
from verify.properties.catalogue import (
    LONG_RUNS,
    PROPERTIES,
    SKIP,
    energy_does_not_increase,
    property_named,
)
from verify.properties.strategies import Drawn, cases
from verify.properties.verdicts import CENSUS_BITS, CENSUS_DIGITS, Runner, Verdict, merge_chunks, search
from verify.records.results import case_from_record
from verify.runner.tasks import decode, encode

#: Properties that are theorems of the rule (or of its implementation's contract): never refuted.
THEOREMS = {p.name for p in PROPERTIES if "rule" in p.laws} - {
    "kinetic energy does not increase",
    "the rule exits (termination)",
}


@pytest.fixture(scope="module")
def table(property_verdicts):
    return property_verdicts


@pytest.mark.slow(seconds=170)
def test_every_row_has_a_verdict(table) -> None:
    assert sum(v.law == "rule" for v in table) == 185
    # the law: 14 properties x 3 CORs x 3 families, less mirror symmetry's general family
    assert sum(v.law == "simultaneous" for v in table) == 123
    # the sequential law: 6 properties x 3 CORs x 3 families, less mirror symmetry's general family
    assert sum(v.law == "sequential" for v in table) == 51
    assert len(table) == 185 + 123 + 51
    assert {v.verdict for v in table} <= {"proved", "holds", "refuted"}
    assert all(v.cases >= 0 and v.note for v in table)


def test_theorems_are_never_refuted(table) -> None:
    refuted = [
        (v.property, v.rule, v.family, v.note)
        for v in table
        if v.verdict == "refuted" and v.law == "rule" and v.property in THEOREMS
    ]
    assert refuted == []


def test_energy_and_termination_where_proved(table) -> None:
    """Kinetic energy is proved for the ideal and symmetric rules; the ideal rule must exit."""
    for v in table:
        if v.law != "rule":
            continue
        if v.property == "kinetic energy does not increase" and v.rule in ("ideal", "symmetric"):
            assert v.verdict == "proved", v
        if v.property == "the rule exits (termination)" and v.rule == "ideal":
            assert v.verdict == "holds", v


def test_every_termination_row_has_a_census_of_its_cases(table) -> None:
    """Each termination row counts how each of its runs ended (the four stops at least) and nothing else
    has a census; the counts add up to the row's cases, with no run proved never to exit where the row
    holds (such a run is a counterexample)."""
    for v in table:
        census = v.record().get("census")
        if v.property != "the rule exits (termination)":
            assert census is None, v
            continue
        assert census is not None and set(census) >= {"exit", "non_terminating", "max_iterations", "budget"}, v
        assert sum(census.values()) == v.cases > 0, v
        if v.verdict == "holds":
            assert census["non_terminating"] == 0, v
        if v.rule == "ideal":
            assert v.verdict == "holds", v


def test_refutations_reproduce_from_the_record_alone(table) -> None:
    for v in table:
        if v.verdict != "refuted":
            continue
        record = v.counterexample
        case_from_record(record)  # loads as verify solve would
        prop = property_named(v.property)
        try:
            why = prop.check(Runner(v.law), Drawn(v.family, v.rule, record), v.extra)
        except Exception as exc:  # the row says the engine raised: it raises again, the same way
            assert v.note.startswith(f"the engine raised {type(exc).__name__}: {' '.join(str(exc).split())}"), v
        else:
            assert why not in (None, SKIP), v
        law = "" if v.law == "rule" else f" --law {v.law}"
        assert f"; reproduce with: verify solve CASE.json --rule {v.rule}{law}" in v.note, v.note
        assert (v.law == "rule") == ("--law" not in v.note), v.note
        if v.property == "kinetic energy does not increase":
            assert "predicts" in v.note and "Where it fails" in v.note


# -- an independent recomputation of the energy property, with the counterexamples found ---------


def _independent_energy_rises(d: Drawn, impulses: int) -> tuple[bool, list]:
    """Iterate eq. (8) as printed (:mod:`verify.properties.formulas`) and watch the energy in the rest frame."""
    g, a, t, e = (d.values(k) for k in ("mass_matrix", "normals", "time_terms", "restitution"))
    if d.rule == "ideal":
        e = [Fraction(1)] * len(e)
    U = [formulas.solve_linear(g, row) for row in a]
    G = [[sum(x * y for x, y in zip(row, u)) for u in U] for row in a]
    c = formulas.solve_linear(G, [-x for x in t])
    H = [sum(ck * u[i] for ck, u in zip(c, U)) for i in range(len(g))]

    def energy(v):
        rel = [x - h for x, h in zip(v, H)]
        return formulas.phi(g, rel, rel) / 2

    v, sets, rises = d.values("velocity"), [], False
    for _ in range(impulses):
        J = tuple(j for j in range(len(a)) if formulas.rate(a[j], t[j], v) < 0)
        if not J:
            break
        w = [x + y for x, y in zip(v, formulas.printed_impulse("8", (g, a, t, e), v, J))]
        rises = rises or energy(w) > energy(v)
        v, sets = w, [*sets, J]
    return rises, sets


FOUND_ASYMMETRIC = {
    "id": "cradle-asymmetric-kinetic-energy-does-not-increase",
    "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    "normals": [["-1", "1", "0"], ["0", "-1", "1"]],
    "time_terms": ["0", "0"],
    "restitution": ["0", "1"],
    "velocity": ["1/2", "-1/2", "-2"],
    "max_iterations": 200,
}
FOUND_GENERAL = {
    "id": "cradle-general-kinetic-energy-does-not-increase",
    "mass_matrix": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]],
    "normals": [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]],
    "time_terms": ["0", "0", "0"],
    "restitution": ["0", "1", "0"],
    "velocity": ["0", "-1/3", "-4/3", "-4/3"],
    "max_iterations": 200,
}


FOUND_BY_THOROUGH = [  # verify properties --profile thorough (the first ones the search met)
    Drawn("corner", "asymmetric", {
        "id": "corner-asymmetric-kinetic-energy-does-not-increase", "max_iterations": 200,
        "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
        "normals": [["-1/2", "1", "0"], ["-1/2", "-1", "0"]], "restitution": ["0", "1"], "time_terms": ["0", "0"],
        "velocity": ["2", "0", "0"]}),
    Drawn("general", "asymmetric", {
        "id": "general-asymmetric-kinetic-energy-does-not-increase", "max_iterations": 200,
        "mass_matrix": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]],
        "normals": [["1", "0", "0", "2"], ["0", "1", "0", "-1"]], "restitution": ["0", "1"],
        "time_terms": ["0", "-1"], "velocity": ["-1/5", "0", "0", "-2/5"]}),
    Drawn("general", "general", {
        "id": "general-general-kinetic-energy-does-not-increase", "max_iterations": 200,
        "mass_matrix": [["1", "1", "0"], ["1", "2", "0"], ["0", "0", "1"]],
        "normals": [["1", "0", "0"], ["0", "1", "0"]], "restitution": ["0", "1"], "time_terms": ["0", "0"],
        "velocity": ["-1", "-1", "0"]}),
]  # fmt: skip


@given(cases("cradle", "general"))
@example(Drawn("cradle", "asymmetric", FOUND_ASYMMETRIC))
@example(Drawn("cradle", "general", FOUND_GENERAL))
@example(FOUND_BY_THOROUGH[0])
@example(FOUND_BY_THOROUGH[1])
@example(FOUND_BY_THOROUGH[2])
def test_energy_check_agrees_with_the_printed_formulas(d: Drawn) -> None:
    runner = Runner()
    result = runner(d.record, d.rule)
    if result.stop == "budget":
        return
    rises, sets = _independent_energy_rises(d, result.iterations)
    assert sets == result.impact_sets
    assert (energy_does_not_increase(runner, d, None) is not None) == rises


def test_the_found_counterexamples_still_refute() -> None:
    for record, rule in ((FOUND_ASYMMETRIC, "asymmetric"), (FOUND_GENERAL, "general")):
        assert _independent_energy_rises(Drawn("cradle", rule, record), 200)[0]
    for d in FOUND_BY_THOROUGH:
        assert _independent_energy_rises(d, 200)[0], d.record["id"]


FOUND_NON_TERMINATING = {
    "id": "cradle-symmetric-the-rule-exits-termination",
    "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    "normals": [["-1", "1", "0"], ["0", "-1", "1"]],
    "time_terms": ["0", "0"],
    "restitution": ["0", "0"],
    "velocity": ["2/3", "-1/3", "-1/3"],
    "max_iterations": 200,
}


FOUND_REPEATING = {  # four balls, every COR 0: the rates repeat, scaled (found by the test below in CI)
    "id": "cradle-symmetric",
    "mass_matrix": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]],
    "normals": [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]],
    "time_terms": ["0", "0", "0"],
    "restitution": ["0", "0", "0"],
    "velocity": ["3/4", "-1/4", "-1/4", "-1/4"],
    "max_iterations": 200,
}


@given(cases("cradle", "symmetric"))
@example(Drawn("cradle", "symmetric", FOUND_NON_TERMINATING))
@example(Drawn("cradle", "symmetric", FOUND_REPEATING))
def test_non_termination_refutations_are_certified_independently(d: Drawn) -> None:
    """Whenever the termination property is refuted, tests/certificate_check.py accepts the proof."""
    from tests import certificate_check

    result = Runner()(d.record, d.rule)
    if result.stop != "non_terminating":
        return
    masses = [row[i] for i, row in enumerate(d.record["mass_matrix"])]
    kind = result.certificate["kind"]
    if kind == "alternating invariant cone":
        assert certificate_check.check(result.certificate, masses, d.record["normals"]) == []
    elif kind == "invariant cone of a period":
        cors = d.record["restitution"]
        assert certificate_check.check_period(result.certificate, masses, d.record["normals"], restitution=cors) == []
    else:
        assert kind == "repeating direction"
        assert certificate_check.check_repeating(result.certificate, masses, d.record["normals"]) == []


def test_the_found_non_terminating_case_still_refutes() -> None:
    prop = property_named("the rule exits")
    assert "proved never to exit" in prop.check(Runner(), Drawn("cradle", "symmetric", FOUND_NON_TERMINATING), None)


#: four elastic contacts under the ideal rule (found by the thorough census, chunk 2 of ideal/general):
#: the run needs more than the drawn records' 200 impulses to exit
LONG_IDEAL = {
    "id": "general-ideal",
    "mass_matrix": [
        ["1/9", "-1/3", "-1/3", "0", "1/3", "-1/3"],
        ["-1/3", "34/9", "-2/3", "5/6", "-8/3", "-2/3"],
        ["-1/3", "-2/3", "3", "-3/2", "1", "5/2"],
        ["0", "5/6", "-3/2", "21/4", "-3/2", "-1"],
        ["1/3", "-8/3", "1", "-3/2", "4", "3/2"],
        ["-1/3", "-2/3", "5/2", "-1", "3/2", "181/36"],
    ],
    "normals": [
        ["2", "1", "0", "0", "-1", "0"],
        ["1/2", "0", "1", "0", "3/2", "0"],
        ["-2", "0", "0", "-2", "1", "0"],
        ["-2", "0", "0", "0", "0", "2"],
    ],
    "time_terms": ["0", "0", "0", "0"],
    "restitution": ["1", "1", "1", "1"],
    "velocity": ["62169/94613", "-460435/94613", "1040731/283839", "-88298/94613", "-336097/94613", "-159501/189226"],
    "max_iterations": 200,
}


def test_a_long_ideal_run_exits_within_the_termination_cap() -> None:
    """The termination property runs with its own cap (LONG_RUNS), so that this run, past the size budget and
    decided on certified intervals, exits instead of stopping at 200 impulses undecided."""
    prop = property_named("the rule exits")
    assert prop.max_iterations == LONG_RUNS > LONG_IDEAL["max_iterations"]
    record = dict(LONG_IDEAL, max_iterations=prop.max_iterations)
    runner = Runner()
    assert prop.check(runner, Drawn("general", "ideal", record), None) is None
    result = runner(record, "ideal", decide=True)
    assert result.stop == "exit" and result.iterations > LONG_IDEAL["max_iterations"], result.iterations
    assert result.backend.name == "interval" and runner.counts["stop exit"] == 1


#: five plastic balls under the symmetric rule: a period of two multiple impulses on four contacts, whose exact
#: numbers pass the size budget within a few impulses; left at the census' cap until the cones of a face proved it
#: (tests/proofs/test_periodic.py, PLASTIC); a case record here
STUCK_CRADLE = {
    "id": "cradle-symmetric",
    "mass_matrix": [
        ["8/3", "0", "0", "0", "0"],
        ["0", "1", "0", "0", "0"],
        ["0", "0", "3", "0", "0"],
        ["0", "0", "0", "3", "0"],
        ["0", "0", "0", "0", "7/3"],
    ],
    "normals": [
        ["-1", "1", "0", "0", "0"],
        ["0", "-1", "1", "0", "0"],
        ["0", "0", "-1", "1", "0"],
        ["0", "0", "0", "-1", "1"],
    ],
    "time_terms": ["0"] * 4,
    "restitution": ["0"] * 4,
    "velocity": ["127/60", "127/60", "7/60", "-11/16", "-11/16"],
    "max_iterations": 200,
}


#: four contacts under the general rule (CORs 0, 1, 1, 0), found by the thorough census: its exact numbers pass
#: 4096 bits after 7 impulses, and a rate that tends to 0 stays undecided on intervals at the census' digits
PAST_BOTH = {
    "id": "general-general",
    "mass_matrix": [
        ["1", "-1", "1", "0", "1", "-1"],
        ["-1", "5/4", "-1/2", "-1/2", "-3/4", "3/2"],
        ["1", "-1/2", "22/9", "-5/3", "13/6", "-2/3"],
        ["0", "-1/2", "-5/3", "6", "1/2", "-1"],
        ["1", "-3/4", "13/6", "1/2", "133/36", "-7/3"],
        ["-1", "3/2", "-2/3", "-1", "-7/3", "65/18"],
    ],
    "normals": [["2", "-2", "1/2", "0", "0", "0"], ["0", "2", "-1", "-1", "0", "0"], ["0", "2", "2", "0", "-2", "0"],
                ["0", "-1", "2", "0", "0", "-1"]],
    "time_terms": ["0", "0", "0", "0"],
    "restitution": ["0", "1", "1", "0"],
    "velocity": ["-217289/1160780", "-151813/1160780", "65476/290195", "-56553/116078", "245169/290195",
                 "675621/1160780"],
    "max_iterations": 200,
}  # fmt: skip


@pytest.mark.slow(seconds=10)
def test_a_run_past_both_budgets_ends_with_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    """At the intervals' precision limit an undecided sign is checked by replaying the run exactly; that
    replay gives up past the same 4096 bits as the exact run, so the run ends with ``budget`` instead of
    replaying numbers that grow at every impulse for hundreds of impulses."""
    exact_impulses = 0

    def counted(system: System, b: Any, J: Any) -> Any:
        nonlocal exact_impulses
        if system.backend.is_exact:
            exact_impulses += 1
            assert exact_impulses <= 16, "the exact check replays past the size budget"  # 7 + 7 (the run, the check)
        return _original_impulse(system, b, J)

    monkeypatch.setattr(rule_module, "_impulse_from_rates", counted)
    record = dict(PAST_BOTH, max_iterations=LONG_RUNS)
    runner = Runner()
    with bounds.recording() as seen:
        assert property_named("the rule exits").check(runner, Drawn("general", "general", record), None) is None
    result = runner(record, "general", decide=True)
    assert (result.stop, result.backend.name, result.iterations) == ("budget", "exact", 7), result.notes
    assert seen["run_digits:reached"] == 1 and "run_digits" not in seen
    # the census lists the case it left undecided, once however often it is drawn, as a case record of its row
    assert property_named("the rule exits").check(runner, Drawn("general", "general", record), None) is None
    assert runner.undecided == {"budget": [record]} and runner.counts["stop budget"] == 2
    v = Verdict("the rule exits (termination)", "general", "general", "holds", 2, counts=dict(runner.counts),
                undecided=runner.undecided)  # fmt: skip
    listed = v.record()["undecided"]
    assert listed == {"max_iterations": [], "budget": [dict(record, id="general-general-budget-1")]}
    case = case_from_record(listed["budget"][0])  # a valid case record, as verify solve reads it
    assert case.velocity_source == PAST_BOTH["velocity"]
    merged = merge_chunks([v, dataclasses.replace(v, undecided={"budget": [record], "max_iterations": [STUCK_CRADLE]})])
    assert merged.undecided == {"budget": [record], "max_iterations": [STUCK_CRADLE]}
    assert merged.census() == {"exit": 0, "non_terminating": 0, "max_iterations": 0, "budget": 4}
    assert decode(json.loads(json.dumps(encode(merged)))) == merged  # a checkpoint keeps them


def _at_400_digits(record: dict[str, Any], max_iterations: int) -> Any:
    """The record's general-rule run under the census' size budget, decided on intervals of the library's default
    400 digits instead of the census' CENSUS_DIGITS."""
    system = System(record["mass_matrix"], record["normals"], record["restitution"], record["time_terms"])
    budget = Budget(bits=CENSUS_BITS, intervals=True, interval_dps=400)
    return solve(system, record["velocity"], max_iterations=max_iterations, budget=budget)


#: five balls under the general rule (CORs 1, 1/10, 0, 0), found by the thorough census: (1,3) every other impulse
#: and (0,2) or (2) between, in no period; no cone of a period closed around it, and it stayed at the census' cap of
#: 4000 impulses (its intervals need more than 400 digits for that) until a cone around its own points proved it
#: (tests/proofs/test_switched.py)
AT_CAP = {
    "id": "cradle-general",
    "mass_matrix": [["1/3", "0", "0", "0", "0"], ["0", "3", "0", "0", "0"], ["0", "0", "1/2", "0", "0"],
                    ["0", "0", "0", "1", "0"], ["0", "0", "0", "0", "2"]],
    "normals": [["-1", "1", "0", "0", "0"], ["0", "-1", "1", "0", "0"], ["0", "0", "-1", "1", "0"],
                ["0", "0", "0", "-1", "1"]],
    "time_terms": ["0", "0", "0", "0"],
    "restitution": ["1", "1/10", "0", "0"],
    "velocity": ["-18/29", "-18/29", "-83/87", "-83/87", "-5/3"],
    "max_iterations": 200,
}  # fmt: skip


def test_the_census_digits_carry_a_long_run_to_its_cap_with_every_sign_certified(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """AT_CAP's intervals lose a sign within its first 1000 impulses at 400 digits (stop budget); at the census'
    digits (CENSUS_DIGITS) every sign of its LONG_RUNS impulses is certified. It is still impacting there. (The
    census proves it never exits with a cone around its own points, tests/proofs/test_switched.py: that search
    is held back here, so that the run goes on to its cap.)"""
    monkeypatch.setattr(termination, "SWITCHED_AFTER", 10**9)
    record = dict(AT_CAP, max_iterations=LONG_RUNS)
    fewer = _at_400_digits(record, 1000)
    assert (fewer.stop, fewer.backend.name) == ("budget", "exact"), fewer.notes
    with bounds.recording() as seen:
        result = Runner()(record, "general", decide=True)
    assert (result.stop, result.backend.name, result.iterations) == ("max_iterations", "interval", LONG_RUNS)
    assert 400 < result.backend.dps <= CENSUS_DIGITS and seen["run_digits"] == result.backend.dps


#: four contacts under the general rule (CORs 1, 1, 1, 5/6), found by the thorough census: it exits after 391
#: impulses, decided at 800 digits; at 400 the intervals lose a sign first, and it stayed at the size budget
LONG_EXIT = {
    "id": "general-general",
    "mass_matrix": [
        ["4/9", "-2/3", "2/3", "0", "0", "1/3"],
        ["-2/3", "5/4", "-1/2", "-1/2", "-1/2", "0"],
        ["2/3", "-1/2", "22/9", "-1/3", "-5/3", "11/6"],
        ["0", "-1/2", "-1/3", "22/9", "2/3", "1/6"],
        ["0", "-1/2", "-5/3", "2/3", "4", "1/2"],
        ["1/3", "0", "11/6", "1/6", "1/2", "15/2"],
    ],
    "normals": [["1/2", "-1", "0", "0", "2", "0"], ["2", "0", "2", "0", "-1/2", "0"], ["1", "0", "0", "1", "-3/2", "0"],
                ["-2", "0", "0", "0", "-1", "2"]],
    "time_terms": ["0", "0", "0", "0"],
    "restitution": ["1", "1", "1", "5/6"],
    "velocity": ["150877/133062", "96209/22177", "-1117/44354", "-184393/66531", "181277/199593", "400174/199593"],
    "max_iterations": 200,
}  # fmt: skip


def test_the_census_digits_decide_a_long_exit_that_400_digits_left_at_the_budget() -> None:
    record = dict(LONG_EXIT, max_iterations=LONG_RUNS)
    fewer = _at_400_digits(record, LONG_RUNS)
    assert fewer.stop == "budget", fewer.notes
    prop = property_named("the rule exits")
    runner = Runner()
    assert prop.check(runner, Drawn("general", "general", record), None) is None
    result = runner(record, "general", decide=True)
    assert (result.stop, result.backend.name, result.iterations) == ("exit", "interval", 391), result.notes
    assert result.backend.dps == 800  # past the library's default of 400 digits
    assert runner.counts["decided on certified intervals past the size budget"] == 1
    rates = result.system.rates(result.exit_velocity)
    assert all(result.backend.sign(x) >= 0 for x in rates)  # outgoing, every sign certified


# -- tests of the tests: each property catches a broken rule --------------------------------------

_original_impulse = rule_module._impulse_from_rates
_original_beta = rates_module.beta_from_rates  # the engine's beta, where it is defined
_original_for_rule = rule_module._system_for_rule
_original_rates = System.rates


def _wrong_beta_sign(system, b, J):
    impulse, beta = _original_impulse(system, b, J)
    if beta is None:
        return impulse, beta
    K = system.backend
    return tuple(K.zero - x for x in impulse), K.zero - beta


def _reversed_cors(system, b, J):
    return _original_impulse(system.with_restitution(list(system.source["restitution"])[::-1]), b, J)


def _first_cor_for_all(system, b, J):
    return _original_impulse(system.with_restitution([system.source["restitution"][0]] * system.r), b, J)


def _coefficients(system, b, J, divide=True):
    K = system.backend
    beta = _original_beta(system, b, J) if len(J) > 1 else K.one
    e = system.restitution
    coef = [K.zero - beta * (K.one + e[j]) * (b[j] / system.gram_diag[j] if divide else b[j]) for j in J]
    return coef, (beta if len(J) > 1 else None)


def _euclidean_direction(system, b, J):  # impulse along dF_j^T instead of U_j = g^-1 dF_j^T
    K = system.backend
    coef, beta = _coefficients(system, b, J)
    return tuple(sum((c * system.normals[j][i] for c, j in zip(coef, J)), K.zero) for i in range(system.n)), beta


def _no_gram_division(system, b, J):
    coef, beta = _coefficients(system, b, J, divide=False)
    return system.combine_normals(list(zip(J, coef))), beta


def _ignores_time_terms(system, b, J):
    return _original_impulse(system, [x - t for x, t in zip(b, system.time_terms)], J)


def _quadratic_in_rates(system, b, J):
    K = system.backend
    return _original_impulse(system, [x * (K.zero - x) for x in b], J)


def _over_restitution(system, b, J):
    impulse, beta = _original_impulse(system, b, J)
    K = system.backend
    return tuple(x * K.convert(Fraction(3, 2)) for x in impulse), beta


def _inexact_off_by_a_little(system, b, J):
    impulse, beta = _original_impulse(system, b, J)
    K = system.backend
    if K.is_exact:
        return impulse, beta
    return tuple(x * K.convert(Fraction(10**12 + 1, 10**12)) for x in impulse), beta


def _beta_times_mass(system, b, J):
    return _original_beta(system, b, J) * system.gram_diag[J[0]]


def _ideal_with_cor_zero(system, rule):
    if rule == "ideal":
        return system.with_restitution([0] * system.r)
    return _original_for_rule(system, rule)


def _negated_rates(self, v):
    return tuple(self.backend.zero - x for x in _original_rates(self, v))


MUTANTS = {
    "kinetic energy does not increase": ("_impulse_from_rates", _over_restitution, "corner", "ideal"),
    "the exit velocity is outgoing": ("rates", _negated_rates, "corner", "general"),
    "each impulse is eq. (8) as printed": ("_impulse_from_rates", _wrong_beta_sign, "corner", "general"),
    "a single impact gives eq. (4)": ("_impulse_from_rates", _reversed_cors, "general", "general"),
    "beta = 1 for one constraint": ("beta_from_rates", _beta_times_mass, "general", "general"),
    "all CORs 1 give the ideal rule (5)": ("_impulse_from_rates", _wrong_beta_sign, "corner", "ideal"),
    "equal CORs give the symmetric rule (6)": ("_impulse_from_rates", _wrong_beta_sign, "corner", "symmetric"),
    "two constraints: eq. (8) is the asymmetric rule (7)": (
        "_impulse_from_rates",
        _reversed_cors,
        "corner",
        "asymmetric",
    ),
    "orthogonal constraints give the codimension > 1 rule (Prop. 1)": (
        "_impulse_from_rates",
        _reversed_cors,
        "corner",
        "general",
    ),
    "relabelling the constraints changes nothing": ("_impulse_from_rates", _first_cor_for_all, "corner", "general"),
    "mirror symmetry (corner y -> -y; cradle read backwards)": (
        "_impulse_from_rates",
        _first_cor_for_all,
        "corner",
        "general",
    ),
    "homogeneity: scaling the velocity by lambda > 0 scales the result": (
        "_impulse_from_rates",
        _quadratic_in_rates,
        "corner",
        "general",
    ),
    "scaling all masses changes nothing": ("_impulse_from_rates", _no_gram_division, "cradle", "general"),
    "covariance under a linear change of coordinates": (
        "_impulse_from_rates",
        _euclidean_direction,
        "corner",
        "general",
    ),
    "frame independence (constraints in uniform motion)": (
        "_impulse_from_rates",
        _ignores_time_terms,
        "corner",
        "general",
    ),
    "the rule exits (termination)": ("_system_for_rule", _ideal_with_cor_zero, "cradle", "ideal"),
    "momentum along directions free of constraints is conserved": (
        "_impulse_from_rates",
        _euclidean_direction,
        "cradle",
        "general",
    ),
    "backends agree (exact, interval, mp, float)": (
        "_impulse_from_rates",
        _inexact_off_by_a_little,
        "corner",
        "general",
    ),
}


def test_every_property_has_a_mutant() -> None:
    assert set(MUTANTS) == {p.name for p in PROPERTIES if "rule" in p.laws}


@pytest.mark.parametrize("name", list(MUTANTS))
def test_each_property_catches_a_broken_rule(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    attribute, mutant, family, rule = MUTANTS[name]
    target = {"rates": System, "beta_from_rates": rates_module}.get(attribute, rule_module)
    monkeypatch.setattr(target, attribute, mutant)
    verdict = search(property_named(name), family, rule, 100)
    assert verdict.verdict == "refuted", f"{name}: the mutant {mutant.__name__} was not caught ({verdict.note})"
    assert "the engine raised" not in verdict.note, verdict.note  # caught by the property, not by a crash


# -- the command line ---------------------------------------------------------------------------------


def test_cli_json_follows_the_contract(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["properties", "--profile", "dev", "--property", "the exit velocity", "--family", "corner",
                 "--workers", "1", "--quiet", "--json"])  # fmt: skip
    out = json.loads(capsys.readouterr().out)
    # the rule's 4 rules, the simultaneous and the sequential law's 3 CORs each
    assert out["profile"] == "dev" and len(out["properties"]) == 4 + 3 + 3
    for row in out["properties"]:
        assert set(row) == {"property", "law", "rule", "family", "verdict", "cases", "counterexample", "note"}
        if row["law"] != "sequential":  # the sweeps can end with a contact incoming again
            assert row["verdict"] == "holds" and row["counterexample"] is None
        assert (row["verdict"] == "refuted") == (row["counterexample"] is not None)
    assert code == (1 if any(row["verdict"] == "refuted" for row in out["properties"]) else 0)
    assert [(r["law"], r["rule"]) for r in out["properties"]] == [
        ("rule", "ideal"), ("simultaneous", "ideal"), ("sequential", "ideal"), ("rule", "symmetric"),
        ("simultaneous", "symmetric"), ("sequential", "symmetric"), ("rule", "asymmetric"), ("rule", "general"),
        ("simultaneous", "general"), ("sequential", "general"),
    ]  # fmt: skip


def test_cli_refutation_is_reproduced_by_verify_solve(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "found"
    code = main(["properties", "--profile", "dev", "--property", "kinetic energy", "--rule", "asymmetric",
                 "--family", "cradle", "--law", "rule", "--workers", "1", "--quiet",
                 "--counterexamples", str(folder)])  # fmt: skip
    text = capsys.readouterr().out
    assert code == 1 and "REFUTED: kinetic energy does not increase (asymmetric rule, cradle)" in text
    (path,) = folder.iterdir()
    assert main(["solve", str(path), "--rule", "asymmetric", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)["results"][0]
    assert result["stop"] == "exit" and result["impact_sets"][0] == [0, 1]


def test_cli_rejects_an_unknown_property(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["properties", "--property", "no such thing", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "unknown property 'no such thing'" in err


def test_cli_profile_names_are_the_verdict_profiles() -> None:
    """One table of profiles, offered by the command line without loading Hypothesis and SymPy."""
    import subprocess
    import sys

    from verify.cli import build_parser
    from verify.properties import profiles, verdicts

    assert verdicts.PROFILES is profiles.PROFILES
    for command in ("properties", "report"):
        assert [build_parser().parse_args([command, "--profile", p]).profile for p in profiles.PROFILES] == list(
            profiles.PROFILES
        )
    loaded = "sorted({'hypothesis', 'sympy'} & set(sys.modules))"
    code = f"import sys, verify.cli; verify.cli.build_parser(); print({loaded})"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout == "[]\n"


def test_rows_sharing_runs_and_drawn_cases_give_the_verdicts_of_rows_searched_alone() -> None:
    """TableShare: rows of one table (here two properties on both families under the rule, rows that hold and
    rows refuted, several on one strategy) share their runs and the cases drawn for rows that held; each verdict,
    its counterexample and its census, is the one of the row searched alone, without a share."""
    from verify.properties.catalogue import property_named
    from verify.properties.verdicts import _run_row, row_tasks, share_for

    names = ["the exit velocity is outgoing", "kinetic energy does not increase"]
    tasks = row_tasks("dev", properties=names, families=["cradle", "general"], laws=["rule"])
    together = [_run_row(t.payload) for t in tasks]
    share = share_for(tasks[0].payload[-1])
    assert share is not None and share.runs and share.drawn  # the rows did share
    alone = [search(property_named(name), f, r, n, law=law, seed=seed) for name, f, r, n, law, seed, _ in
             (t.payload for t in tasks)]  # fmt: skip
    assert {v.record()["verdict"] for v in alone} >= {"refuted", "holds"}
    assert [v.record() for v in together] == [v.record() for v in alone]
