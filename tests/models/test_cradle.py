"""Newton's cradle (Sect. 4.1): the paper's formulas, the two models, N balls."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from verify.errors import InvalidSystem
from verify.laws.rule import solve
from verify.models.cradle import cradle_geometry, cradle_system, cradle_system_full, run_cradle

eps_open = st.fractions(min_value=F(1, 60), max_value=F(59, 60), max_denominator=60)


def velocities(result):
    K = result.backend
    return [[K.to_number(x) for x in s.velocity] for s in result.steps]


@given(eps_open, st.fractions(min_value=F(1, 7), max_value=1000, max_denominator=7))
def test_first_three_steps_are_the_papers_formulas(e, v0):
    r = run_cradle(e, v0=v0, max_iterations=3, certify=False)
    p1, p2, p3 = velocities(r)[:3]
    assert p1 == [(1 - e) / 2 * v0, (1 + e) / 2 * v0, 0]
    assert p2 == [(1 - e) / 2 * v0, (1 - e * e) / 4 * v0, (1 + e) ** 2 / 4 * v0]
    assert p3 == [(1 - e) * (3 + e * e) / 8 * v0, (1 - e * e) * (3 - e) / 8 * v0, (1 + e) ** 2 / 4 * v0]
    assert r.impact_sets == [(0,), (1,), (0,)]


@given(eps_open)
def test_three_impulses_iff_eps_at_least_3_minus_2_sqrt2(e):
    # the paper: p_L^3 exits iff eps >= 3 - 2 sqrt(2); for rational eps < 3, that is (3 - eps)^2 <= 8
    r = run_cradle(e, max_iterations=4)
    assert (r.iterations == 3 and r.stop == "exit") == ((3 - e) ** 2 <= 8)


def test_ideal_cradle_passes_the_velocity_down_the_line():
    for n in (2, 3, 5, 8):
        r = run_cradle(1, balls=n)
        K = r.backend
        assert [K.to_number(x) for x in r.exit_velocity] == [0] * (n - 1) + [100]
        assert r.iterations == n - 1


@given(
    st.lists(st.fractions(min_value=0, max_value=1, max_denominator=10), min_size=2, max_size=2),
    st.lists(st.fractions(min_value=F(1, 4), max_value=4, max_denominator=4), min_size=3, max_size=3),
    st.lists(st.fractions(min_value=-3, max_value=3, max_denominator=5), min_size=3, max_size=3),
    st.fractions(min_value=-2, max_value=2, max_denominator=3),
)
@settings(max_examples=25)
def test_reduced_and_full_models_agree(eps, masses, v, spin):
    """The paper's S_(i,j) in (x, y, theta) give the reduced result; y stays 0, spins unchanged."""
    reduced = cradle_system(eps, 3, masses)
    full = cradle_system_full(eps, 3, masses, radius="3/2")
    assert full.names == ("S(1,2)", "S(2,3)")  # S_(1,3) is not in contact
    r = solve(reduced, v, max_iterations=80)
    v_full = []
    for i in range(3):
        v_full += [v[i], 0, spin * (i + 1)]
    f = solve(full, v_full, max_iterations=80)
    K = r.backend
    assert r.impact_sets == f.impact_sets
    assert r.stop == f.stop
    out = [K.to_number(x) for x in f.exit_velocity]
    assert out[0::3] == [K.to_number(x) for x in r.exit_velocity]
    assert out[1::3] == [0, 0, 0]
    assert out[2::3] == [spin * (i + 1) for i in range(3)]


def test_velocity_that_hits_both_contacts_at_once():
    r = run_cradle("1/2", velocity=["2", "0", "-1"])
    assert r.impact_sets[0] == (0, 1)
    assert r.betas[0] is not None
    assert r.stop == "exit"


def test_one_cor_per_contact_and_unequal_masses():
    r = run_cradle(["1", "0"], masses=["1", "2", "1"])
    K = r.backend
    # momentum is conserved by every impulse (the constraints are internal)
    momentum = [1, 2, 1]
    assert sum(m * K.to_number(x) for m, x in zip(momentum, r.exit_velocity, strict=True)) == 100
    assert r.stop == "exit"


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(balls=1), "balls must be an integer >= 2"),
        (dict(masses=["1", "0", "1"]), r"masses\[1\] = 0 must be positive"),
        (dict(masses=["1", "-2", "1"]), "must be positive"),
        (dict(masses=["1", "1"]), "masses: expected 3"),
        (dict(velocity=["1", "1"]), "velocity: expected 3"),
        (dict(mode="fast"), "unknown mode"),
    ],
)
def test_cradle_rejects_bad_input(kwargs, message):
    with pytest.raises(InvalidSystem, match=message):
        run_cradle("1/2", **kwargs)


def test_cor_count_must_match_the_contacts():
    with pytest.raises(InvalidSystem, match="expected 1 or 2 CORs"):
        run_cradle(["1", "1", "1"])


def test_the_cradle_system_is_the_cradle_geometry():
    g, normals = cradle_geometry([F(1), F(2), F(3), F(1, 2)])
    s = cradle_system("1/2", 4, ["1", "2", "3", "1/2"])
    assert s.source["mass_matrix"] == tuple(tuple(row) for row in g)
    assert s.source["normals"] == tuple(tuple(row) for row in normals)
    assert [[str(a) for a in row] for row in normals][2] == ["0", "0", "-1", "1"]


def test_a_two_ball_cradle_asks_for_one_cor(capsys):
    """One contact: the message asks for 1 COR, not for "1 or 1 CORs"."""
    from verify.cli import main

    assert main(["cradle", "--eps", "1/2,1/2", "--velocity", "1,0"]) == 2
    err = capsys.readouterr().err
    assert "expected 1 COR (one contact), got 2" in err and "1 or 1" not in err
