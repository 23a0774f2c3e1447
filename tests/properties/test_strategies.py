"""The strategies build valid inputs directly, cover what they promise, and shrink readably."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import HealthCheck, Phase, find, given, settings

from verify.numbers.backends import RationalBackend
from verify.numbers.linalg import ldl
from verify.properties import formulas
from verify.properties.strategies import FAMILIES, RULES, cases, rates
from verify.records.results import case_from_record

Q = RationalBackend("python")


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("rule", RULES)
def test_drawn_cases_are_valid(family: str, rule: str) -> None:
    @settings(suppress_health_check=[HealthCheck.too_slow])
    @given(cases(family, rule))
    def check(d):
        g, a = d.values("mass_matrix"), d.values("normals")
        e, v = d.values("restitution"), d.values("velocity")
        n, r = len(g), len(a)
        assert all(g[i][j] == g[j][i] for i in range(n) for j in range(n))
        ldl(Q, g)  # raises unless positive definite
        assert len(formulas.kernel(a)) == n - r  # independent normals
        assert r < n or family != "general"
        assert all(0 <= x <= 1 for x in e)
        if rule == "ideal":
            assert e == [1] * r
        if rule == "symmetric":
            assert len(set(e)) == 1
        if rule == "asymmetric":
            assert r == 2
        assert min(rates(d)) < 0, "the velocity must hit a constraint"
        assert len(v) == n
        case_from_record(d.record)  # the loader of verify solve accepts it

    check()


def _orthogonal_pair(d) -> bool:
    g, a = d.values("mass_matrix"), d.values("normals")
    if len(a) < 2:
        return False
    u = [formulas.solve_linear(g, row) for row in a]
    return sum(x * y for x, y in zip(a[0], u[1])) == 0


FEATURES = {
    "a multiple impact": ("general", lambda d: sum(x < 0 for x in rates(d)) >= 2),
    "a grazing constraint": ("general", lambda d: 0 in rates(d)),
    "moving constraints": ("general", lambda d: any(Fraction(t) != 0 for t in d.record["time_terms"])),
    "orthogonal constraints": ("general", _orthogonal_pair),
    "a right-angle corner": ("corner", _orthogonal_pair),
    "four constraints": ("general", lambda d: len(d.record["normals"]) == 4),
    "five balls": ("cradle", lambda d: len(d.record["velocity"]) == 5),
}


@pytest.mark.parametrize("feature", FEATURES)
def test_the_strategies_reach_what_the_properties_need(feature: str) -> None:
    """Multiple impacts, grazing rates, orthogonal and moving constraints all occur in 300 draws."""
    family, condition = FEATURES[feature]
    seen = []

    @settings(
        max_examples=300,
        database=None,
        derandomize=True,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(cases(family, "general"))
    def draw(d):
        seen.append(condition(d))

    draw()
    assert any(seen), f"no case with {feature} in {len(seen)} draws"


def test_failing_cases_shrink_to_something_readable() -> None:
    """A search shrinks to the simplest case with three constraints, whatever ran before it.

    No example database (an earlier run's failures would be replayed first) and derandomised,
    so the result is the same in every run and in any test order.
    """
    quiet = settings(database=None, derandomize=True, suppress_health_check=list(HealthCheck))
    d = find(cases("general", "general"), lambda d: len(d.record["normals"]) >= 3, settings=quiet)
    assert d.record["mass_matrix"] == [["1" if i == j else "0" for j in range(4)] for i in range(4)]
    assert all(len(x) <= 4 for row in d.record["normals"] for x in row)
    assert d.record["time_terms"] == ["0", "0", "0"]
