"""The rule in rate coordinates (:mod:`verify.laws.loops.rates`), shared geometry and
:func:`verify.laws.rule.solve_many` give the traced rule's own numbers, exactly.

Nothing here is timed (``verify bench`` measures).
"""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given, settings

import verify.laws.rule as rule_module
from verify.dynamics.policy import Limits
from verify.dynamics.system import System
from verify.errors import BadNumber, InvalidSystem
from verify.laws.loops import rates
from verify.laws.rule import Budget, solve, solve_many
from verify.properties.strategies import cases


def _system(record: dict, backend: object = "exact") -> System:
    return System(record["mass_matrix"], record["normals"], record["restitution"], record.get("time_terms"),
                  backend=backend)  # fmt: skip


@settings(max_examples=80, deadline=None)
@given(cases("general", "general"))
def test_rate_form_equals_the_traced_rule(drawn) -> None:
    """Every impact set, beta, stop and exit component equal to the traced (velocity-form) run,
    moving constraints and algebraic number fields included."""
    rec = drawn.record
    s = _system(rec)
    budget = Budget(bits=4096)
    traced = solve(s, rec["velocity"], max_iterations=40, trace=True, certify=False, budget=budget)
    s = traced.system  # the field of the velocity too
    fast = rates.iterate(s, traced.velocity_in, budget.limits(40))
    assert fast.impact_sets == traced.impact_sets
    assert fast.betas == traced.betas
    assert fast.stop == traced.stop
    assert list(fast.v) == list(traced.exit_velocity)


def test_rate_form_runs_in_a_number_field() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [["-sqrt(3)/3", 1, 0], ["-sqrt(3)/3", -1, 0]], ["0.999", "0.001"])
    v = ["(sqrt(6) + sqrt(2))/4", "(sqrt(6) - sqrt(2))/4", "0"]
    traced = solve(s, v, trace=True, certify=False)
    assert traced.backend.is_exact and not traced.backend.rationals  # a number field
    fast = solve(s, v, trace=False, certify=False)  # the rate form on the field backend
    assert fast.impact_sets == traced.impact_sets == [(0, 1), (0, 1), (1,)]
    assert list(fast.exit_velocity) == list(traced.exit_velocity)


def test_rate_form_budget_and_cap_stop_where_the_traced_rule_does() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[Fraction(-47, 190), 1, 0], [Fraction(-47, 190), -1, 0]],
               [Fraction(47, 200), Fraction(107, 491)])  # fmt: skip
    v = s.velocity([Fraction(854, 15), Fraction(-742553, 57000), 0])
    for limits in (Limits(7), Budget(bits=300).limits(500)):
        fast = rates.iterate(s, v, limits)
        traced = solve(s, v, max_iterations=limits.max_iterations, certify=False,
                       budget=Budget(bits=limits.bits) if limits.bits else None)  # fmt: skip
        assert fast.stop == traced.stop != "exit"
        assert fast.impact_sets == traced.impact_sets and list(fast.v) == list(traced.exit_velocity)
    capped = rates.iterate(s, v, Limits(500), cap=2)
    assert capped.stop == "max_iterations" and len(capped.impact_sets) == 2


def test_short_untraced_runs_take_the_rate_form(monkeypatch) -> None:
    calls = []
    original = rates.iterate
    monkeypatch.setattr(rates, "iterate", lambda *a, **kw: calls.append(1) or original(*a, **kw))
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    fast = solve(s, ["100", "0", "0"], trace=False, certify=False)
    assert calls == [1] and fast.iterations == 3 <= rule_module.FRACTION_FREE_AFTER
    assert [s.backend.to_exact(x) for x in fast.exit_velocity] == ["325/16", "375/16", "225/4"]


def test_with_restitution_shares_the_geometry_and_checks_the_cors() -> None:
    s = System([[2, 1], [1, 3]], [[1, 0], [0, 1]], ["1/2", "1/3"])
    t = s.with_restitution(["1/5", 1])
    assert t.U is s.U and t.gram is s.gram  # shared, not rebuilt
    fresh = System([[2, 1], [1, 3]], [[1, 0], [0, 1]], ["1/5", 1])
    for name in ("restitution", "minus_one_plus_e", "single_coefficient", "inverse_gram_diag", "gram"):
        assert getattr(t, name) == getattr(fresh, name), name
    assert [str(x) for x in s.restitution] == ["1/2", "1/3"]  # the original is unchanged
    with pytest.raises(InvalidSystem, match=r"restitution\[0\] = 3/2 is outside \[0, 1\]"):
        s.with_restitution(["3/2", 0])
    with pytest.raises(InvalidSystem, match="expected 2 numbers"):
        s.with_restitution([1])
    with pytest.raises(BadNumber):
        s.with_restitution([0.5, 1])


def test_solve_many_equals_one_solve_per_case() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    eps = ["1", "0.5", "0.1716", "0.1715", "0.1", "0", "0.5"]
    velocities = [["100", "0", "0"]] * len(eps)
    many = solve_many(s, velocities, restitutions=[[e, e] for e in eps], trace=False)
    for e, r in zip(eps, many):
        one = solve(System(s.source["mass_matrix"], s.source["normals"], [e, e]), ["100", "0", "0"], trace=False)
        assert (r.stop, r.impact_sets, list(r.exit_velocity)) == (one.stop, one.impact_sets, list(one.exit_velocity))
    assert many[1].system is many[-1].system  # a repeated COR vector is converted once
    plain = solve_many(s, [["1", "0", "0"], ["0", "0", "-1"]])
    assert [r.system for r in plain] == [s, s]
    with pytest.raises(InvalidSystem, match="one per case"):
        solve_many(s, velocities, restitutions=[[1, 1]])


def test_run_cradle_many_widens_the_field_for_an_algebraic_cor() -> None:
    """A COR outside the field of the system built first (rationals here) gets a system over the
    larger field; every run equals its own run_cradle."""
    from verify.models.cradle import run_cradle, run_cradle_many

    eps = ["1", "3 - 2*sqrt(2)", "0.1"]
    many = run_cradle_many(eps, trace=False)
    assert not many[1].backend.rationals and many[0].backend.rationals
    for e, r in zip(eps, many):
        one = run_cradle(e, trace=False)
        assert (r.stop, r.impact_sets) == (one.stop, one.impact_sets)
        assert [r.backend.to_exact(x) for x in r.exit_velocity] == [one.backend.to_exact(x) for x in one.exit_velocity]
