"""The fast paths give the rule's own results: integers for long exact runs, the float batch.

Nothing here is timed (``verify bench`` measures; CI only smoke-runs it).
"""

from __future__ import annotations

import json
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import verify.laws.rule as rule_module
from tests.helpers import bench_measured_once
from verify.bench.throughput import batch
from verify.cli import main
from verify.dynamics.policy import Limits
from verify.dynamics.system import System
from verify.laws.loops import integer as fraction_free
from verify.laws.loops.floats import solve_batch, systems_batch
from verify.laws.rule import Budget, solve
from verify.models.corner import corner_batch, paper_run, zones_of
from verify.properties.strategies import cases


def _system(record: dict) -> System:
    return System(record["mass_matrix"], record["normals"], record["restitution"], record.get("time_terms"))


@settings(max_examples=60, deadline=None)
@given(cases("general", "general"))
def test_integer_iteration_equals_the_traced_rule(drawn) -> None:
    """Fraction-free integers against the traced path (which never takes them), exactly."""
    rec = drawn.record
    s = _system(rec)
    if not s.backend.fraction_free:
        return
    budget = Budget(bits=4096)  # multiple impacts can triple the sizes: bound them
    traced = solve(s, rec["velocity"], max_iterations=60, trace=True, certify=False, budget=budget)
    fast = fraction_free.iterate(s, traced.velocity_in, budget.limits(60))
    assert fast.impact_sets == traced.impact_sets
    assert fast.betas == traced.betas
    assert fast.stop == traced.stop
    assert list(fast.v) == list(traced.exit_velocity)


def test_solve_switches_to_integers_on_long_runs_with_the_same_result(monkeypatch) -> None:
    k, xd, yd, e1, e2 = Fraction(125, 374), Fraction(334, 91), Fraction(130761, 136136), Fraction(0), Fraction(61, 228)
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-k, 1, 0], [-k, -1, 0]], [e1, e2])
    calls = []
    original = fraction_free.iterate
    monkeypatch.setattr(fraction_free, "iterate", lambda *a, **kw: calls.append(1) or original(*a, **kw))
    fast = solve(s, [xd, yd, 0], max_iterations=100, trace=False, certify=False)
    traced = solve(s, [xd, yd, 0], max_iterations=100, trace=True, certify=False)
    assert calls == [1]  # the untraced run went to integers after FRACTION_FREE_AFTER impulses
    assert fast.iterations == 100 > rule_module.FRACTION_FREE_AFTER
    assert list(fast.exit_velocity) == list(traced.exit_velocity) and fast.impact_sets == traced.impact_sets
    assert paper_run(k, xd, yd, e1, e2, max_iterations=100)[0] == zones_of(fast)  # and eq. (10) on Fractions agrees


def test_integer_budget_stops_where_the_rational_one_does() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[Fraction(-47, 190), 1, 0], [Fraction(-47, 190), -1, 0]],
               [Fraction(47, 200), Fraction(107, 491)])  # fmt: skip
    v = [Fraction(854, 15), Fraction(-742553, 57000), 0]
    fast = solve(s, v, max_iterations=500, trace=False, certify=False, budget=Budget(bits=2000))
    traced = solve(s, v, max_iterations=500, trace=True, certify=False, budget=Budget(bits=2000))
    assert fast.stop == traced.stop == "budget"
    assert fast.iterations == traced.iterations


def test_the_engines_share_one_stop_policy() -> None:
    """The cap on the impulses stops the traced, the integer and the float engines alike."""
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    velocity = ["100", "0", "0"]
    for cap in range(5):
        traced = solve(s, velocity, max_iterations=cap, certify=False)
        fast = fraction_free.iterate(s, traced.velocity_in, Limits(cap))
        floats = solve_batch(systems_batch([s], [velocity]), max_iterations=cap, exact_fallback=False)
        assert fast.stop == traced.stop == floats.stop[0] == ("exit" if cap >= 3 else "max_iterations")
        assert fast.impact_sets == traced.impact_sets == floats.impact_sets(0)
    traced = solve(s, velocity, budget=Budget(bits=10), certify=False)
    fast = fraction_free.iterate(s, traced.velocity_in, Budget(bits=10).limits(100))
    assert fast.stop == traced.stop == "budget" and fast.impact_sets == traced.impact_sets


def _assert_batch_matches_exact(systems_and_velocities, result) -> None:
    for i, (s, v) in enumerate(systems_and_velocities):
        exact = solve(s, v, max_iterations=100, trace=False, certify=False, budget=Budget(bits=4096))
        if exact.stop == "budget":
            continue
        assert result.impact_sets(i) == list(exact.impact_sets), i
        assert result.stop[i] == exact.stop
        for j, x in enumerate(exact.exit_velocity):  # the radius encloses the exact value
            assert abs(Fraction(float(result.v[i][j])) - s.backend.to_number(x)) <= Fraction(float(result.r_v[i][j]))


def test_float_path_takes_the_exact_branches_on_the_bench_batch() -> None:
    F = Fraction  # and two corners of slope 1 of the bench batch (cases 4434, 4574), whose zeros need exact arithmetic
    cases_ = [
        *batch(400),
        (F(1), F(137, 18), F(-98777, 18000), F(1), F(0)),
        (F(1), F(181, 11), F(181, 2200), F(0), F(1)),
    ]
    out = solve_batch(corner_batch([c[0] for c in cases_], [c[1:3] for c in cases_], [c[3:] for c in cases_]))
    pairs = [
        (System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-c[0], 1, 0], [-c[0], -1, 0]], list(c[3:])), [c[1], c[2], 0])
        for c in cases_
    ]
    _assert_batch_matches_exact(pairs, out)
    assert out.fallback.any() and not out.fallback.all()  # both paths are exercised
    wrong = sum(
        1
        for i, c in enumerate(cases_)
        if paper_run(*(x.numerator / x.denominator for x in c), max_iterations=100)[0]
        != paper_run(*c, max_iterations=100)[0]
    )
    assert wrong > 0  # plain floats do go wrong on this batch; the float path did not


@settings(max_examples=40, deadline=None)
@given(st.lists(cases("general", "general"), min_size=1, max_size=6))
def test_float_path_on_general_systems(drawn) -> None:
    shapes = {(len(d.record["mass_matrix"]), len(d.record["normals"])) for d in drawn}
    first = [d for d in drawn if (len(d.record["mass_matrix"]), len(d.record["normals"])) == next(iter(shapes))]
    systems = [_system(d.record) for d in first]
    if not all(s.backend.fraction_free for s in systems) or any(s.moving for s in systems):
        return  # the batch holds fixed rational constraints
    velocities = [d.record["velocity"] for d in first]
    out = solve_batch(systems_batch(systems, velocities), budget=Budget(bits=4096))
    _assert_batch_matches_exact(list(zip(systems, velocities)), out)


@pytest.mark.slow(seconds=10)
def test_bench_quick_smoke(capsys, tmp_path, tmp_path_factory, monkeypatch) -> None:
    """``verify bench --quick --json --save``: the record's shape (its measurement shared with the docs'
    transcripts of the same command)."""
    bench_measured_once(monkeypatch, tmp_path_factory)
    target = tmp_path / "bench.json"
    assert main(["bench", "--quick", "--json", "--save", str(target)]) == 0
    record = json.loads(capsys.readouterr().out)
    assert json.loads(target.read_text()) == record
    assert set(record) >= {"figures", "machine", "batches"}
    for f in record["figures"]:
        assert set(f) == {"name", "value", "unit", "baseline", "ratio", "batch"}
        assert f["batch"] in record["batches"], f
    names = [f["name"] for f in record["figures"]]
    assert len(names) == len(set(names)) and "corner_batch.exact_engine" in names
    batches = {f["batch"] for f in record["figures"]}
    assert {"corner", "corner_short", "cradle", "general", "impulse_cost"} <= batches  # --quick leaves out table1
    by_name = {f["name"]: f for f in record["figures"]}
    for kind in ("cradle", "general"):  # each contestant against its own baseline, measured in the run
        assert by_name[f"{kind}.exact_engine"]["baseline"] == f"{kind}.fraction_loop"
        assert by_name[f"{kind}.fraction_loop"]["ratio"] == 1.0


def test_bench_bad_size_is_a_usage_error(capsys) -> None:
    assert main(["bench", "--size", "0"]) == 2
    assert "--size" in capsys.readouterr().err
