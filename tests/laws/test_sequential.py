"""The sequential-impulse law (projected Gauss-Seidel, exactly): issue 38, item 1."""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from tests.helpers import Poison, cradle_case, exact_value
from verify.dynamics.system import System
from verify.errors import InvalidSystem
from verify.laws.rule import solve
from verify.laws.sequential import Sequential

ROOT = Path(__file__).resolve().parents[2]
small = st.fractions(min_value=-3, max_value=3, max_denominator=3)


def verify_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", *args], capture_output=True, text=True, cwd=ROOT,
                          check=False)  # fmt: skip


# -- the must-holds, through the command line --------------------------------------------------


def test_one_sweep_of_the_cradle_prints_exactly_0_50_50() -> None:
    done = verify_cli("cradle", "--eps", "1", "--law", "sequential", "--iterations", "1")
    assert done.returncode == 0, done.stderr
    assert "exit velocity (exact): 0, 50, 50\n" in done.stdout


def test_a_thousand_sweeps_are_within_1e_12_of_the_simultaneous_law() -> None:
    done = verify_cli("cradle", "--eps", "1", "--law", "sequential", "--iterations", "1000", "--json")
    assert done.returncode == 0, done.stderr
    record = json.loads(done.stdout)
    got = [Fraction(x) for x in record["exit_velocity"]]
    expected = [Fraction(-100, 3), Fraction(200, 3), Fraction(200, 3)]
    assert max(abs(a - b) for a, b in zip(got, expected)) < Fraction(1, 10**12)
    assert got != expected  # exact rationals, not rounded: the sweeps never reach it in finitely many steps
    assert record["law"] == "sequential" and record["law_settings"]["iterations"] == 1000


# -- an independent reference: the sweeps written out on Fractions from the raw inputs -----------------


def reference(g: list[list[Fraction]], a: list[list[Fraction]], e: list[Fraction], v: list[Fraction], *, sweeps: int,
              order: list[int], threshold: Fraction) -> list[Fraction]:  # fmt: skip
    """Projected Gauss-Seidel as an engine's solver writes it (Catto's accumulated impulses), from g, the
    normals a, the CORs e: U_i = g^-1 a_i, G_ii = a_i . U_i, one contact at a time."""
    import sympy as sp

    ginv = sp.Matrix(g).inv()
    U = [[Fraction(str(x)) for x in ginv * sp.Matrix(row)] for row in a]

    def rate(i: int, u: list[Fraction]) -> Fraction:
        return sum((x * y for x, y in zip(a[i], u)), Fraction(0))

    G = [rate(i, U[i]) for i in range(len(a))]
    w0 = [rate(i, v) for i in range(len(a))]
    target = [-e[i] * w0[i] if -w0[i] > threshold else Fraction(0) for i in range(len(a))]
    lam = [Fraction(0)] * len(a)
    u = list(v)
    for _ in range(sweeps):
        for i in order:
            new = max(lam[i] + (target[i] - rate(i, u)) / G[i], Fraction(0))
            u = [x + (new - lam[i]) * y for x, y in zip(u, U[i])]
            lam[i] = new
    return u


@st.composite
def systems(draw: st.DrawFn) -> tuple[list[list[Fraction]], list[list[Fraction]], list[Fraction], list[Fraction]]:
    """A system of 2 or 3 constraints in 3 or 4 coordinates (diagonal masses), and a velocity."""
    n, r = draw(st.integers(3, 4)), draw(st.integers(2, 3))
    masses = [draw(st.fractions(min_value=Fraction(1, 2), max_value=3, max_denominator=4)) for _ in range(n)]
    g = [[masses[i] if i == j else Fraction(0) for j in range(n)] for i in range(n)]
    a = [[draw(small) for _ in range(n)] for _ in range(r)]
    e = [draw(st.fractions(min_value=0, max_value=1, max_denominator=5)) for _ in range(r)]
    v = [draw(small) for _ in range(n)]
    try:
        System(g, a, e)
    except InvalidSystem:  # dependent or zero normals: not a system of the paper
        assume(False)
    return g, a, e, v


@settings(max_examples=50, deadline=None, database=None, derandomize=True)
@given(systems(), st.integers(1, 6), st.randoms(use_true_random=False), st.sampled_from([0, Fraction(1, 2)]))
def test_the_law_is_the_engines_loop_exactly(case: tuple, sweeps: int, rnd, threshold: Fraction) -> None:
    g, a, e, v = case
    order = list(range(len(a)))
    rnd.shuffle(order)
    r = solve(System(g, a, e), v, law=Sequential(sweeps, tuple(order), threshold))
    expected = reference(g, a, e, v, sweeps=sweeps, order=order, threshold=threshold)
    assert [exact_value(r.backend, x) for x in r.exit_velocity] == expected
    rates = [sum((x * y for x, y in zip(row, [r.backend.to_number(c) for c in r.exit_velocity])), Fraction(0))
             for row in a]  # fmt: skip
    assert r.stop == ("exit" if min(rates) >= 0 else "max_iterations")


def objective(s: System, v: list[Fraction], lam: list[Fraction]) -> Fraction:
    """The quadratic 1/2 lam^T G lam + q^T lam that projected Gauss-Seidel descends (q of the LCP)."""
    K = s.backend
    G = [[K.to_number(x) for x in row] for row in s.gram]
    w = [K.to_number(x) for x in s.rates(s.velocity(v))]
    e = [K.to_number(x) for x in s.restitution]
    q = [(1 + ei) * wi if wi < 0 else wi for wi, ei in zip(w, e)]
    quad = sum(lam[i] * G[i][j] * lam[j] for i in range(len(q)) for j in range(len(q)))
    return quad / 2 + sum(qi * li for qi, li in zip(q, lam))


@settings(max_examples=30, deadline=None, database=None, derandomize=True)
@given(systems())
def test_more_sweeps_come_closer_to_the_simultaneous_law(case: tuple) -> None:
    """The distance to the simultaneous law, in the kinetic metric, is bounded by the objective's gap, which
    the sweeps never raise; it shrinks to 0; and where the sweeps stop changing the two laws are equal."""
    g, a, e, v = case
    s = System(g, a, e)
    K = s.backend
    exact = solve(s, v, law="simultaneous")
    best = objective(s, v, [K.to_number(x) for x in exact.impulses or ()])
    target = [K.to_number(x) for x in exact.exit_velocity]
    gaps = []
    for sweeps in (1, 2, 4, 8, 16, 32):
        r = solve(s, v, law=Sequential(sweeps))
        got = [K.to_number(x) for x in r.exit_velocity]
        gap = objective(s, v, [K.to_number(x) for x in r.impulses or ()]) - best
        diff = [x - y for x, y in zip(got, target)]
        metric = sum(diff[i] * g[i][j] * diff[j] for i in range(len(v)) for j in range(len(v)))
        assert 0 <= metric <= 2 * gap
        gaps.append(gap)
        if r.iterations < sweeps:  # the sweeps stopped changing: the simultaneous law exactly
            assert got == target and gap == 0
    assert gaps == sorted(gaps, reverse=True)
    assert gaps[-1] < gaps[0] or gaps[0] == 0


def test_no_float_is_taken_and_every_backend_follows_the_exact_branches() -> None:
    p = Poison
    s = System([[p(1), p(0), p(0)], [p(0), p(2), p(0)], [p(0), p(0), p(3)]], [[-1, 1, 0], [0, -1, 1]],
               [p(1, 3), p(2, 7)])  # fmt: skip
    law = Sequential(4, (1, 0), p(1, 10))
    r = solve(s, [p(5), p(-1, 2), p(0)], law=law)
    exact = [exact_value(r.backend, x) for x in (*r.exit_velocity, *(r.impulses or ()))]
    for backend in ("interval", "mp", "float"):
        other = solve(s.convert_to(backend), ["5", "-1/2", "0"], law=law)
        assert other.impact_sets == r.impact_sets and other.stop == r.stop
        values = [Fraction(other.backend.to_decimal(x, 12)) for x in (*other.exit_velocity, *(other.impulses or ()))]
        assert max(abs(x - y) for x, y in zip(values, exact)) < Fraction(1, 10**9)


def test_a_threshold_drops_the_restitution_of_slow_contacts() -> None:
    s = System([[1, 0], [0, 1]], [[-1, 1]], [1])
    fast = solve(s, ["2", "0"], law=Sequential(1, threshold=1))
    slow = solve(s, ["1", "0"], law=Sequential(1, threshold=1))  # approaching at exactly 1: no restitution
    assert [fast.backend.to_exact(x) for x in fast.exit_velocity] == ["0", "2"]
    assert [slow.backend.to_exact(x) for x in slow.exit_velocity] == ["1/2", "1/2"]


def test_the_settings_are_checked() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    for bad in ({"iterations": 0}, {"order": (0, 0)}, {"order": (0,)}, {"threshold": "-1"}, {"threshold": (0,)}):
        with pytest.raises(InvalidSystem):
            solve(s, ["1", "0", "0"], law=Sequential(**bad))


@pytest.mark.parametrize(
    "args",
    [
        ("--iterations", "3"),  # without --law sequential
        ("--law", "sequential", "--iterations", "0"),
        ("--law", "sequential", "--iterations", "x"),
        ("--law", "sequential", "--order", "1,a"),
        ("--law", "sequential", "--order", "0,0"),
        ("--law", "sequential", "--threshold", "-1"),
        ("--law", "sequential", "--threshold", "__import__('os')"),
    ],
)
def test_bad_settings_exit_2_without_a_traceback(args: tuple[str, ...]) -> None:
    done = verify_cli("cradle", "--eps", "1", *args)
    assert done.returncode == 2 and "Traceback" not in done.stderr and done.stdout == ""


def test_solve_and_the_oracle_take_the_settings(tmp_path: Path) -> None:
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [cradle_case("c", ["1", "1", "1"], ["1", "1"], ["100", "0", "0"])]}))
    done = verify_cli("solve", str(path), "--law", "sequential", "--iterations", "2", "--order", "1,0", "--json")
    assert done.returncode == 0, done.stderr
    (record,) = json.loads(done.stdout)["results"]
    # contact 1 first: nothing approaches there (target 0, no impulse); then contact 0 (target rate 100):
    # (0, 100, 0); sweep 2: contact 1 (target 0) takes 50: (0, 50, 50); contact 0, at rate 50, takes 25 more
    # towards its target 100: (-25, 75, 50), where contact 1 approaches again: not an exit
    assert record["exit_velocity"] == ["-25", "75", "50"] and record["law_settings"]["order"] == [1, 0]
    assert record["stop"] == "max_iterations"
    results = tmp_path / "results.json"
    mine = {"id": "c", "exit_velocity": ["-25", "75", "50"], "stop": "max_iterations"}
    results.write_text(json.dumps({"results": [mine]}))
    check = verify_cli("oracle", "check", str(path), str(results), "--law", "sequential", "--iterations", "2",
                       "--order", "1,0", "--quiet")  # fmt: skip
    assert check.returncode == 0, check.stdout + check.stderr
    other = verify_cli("oracle", "check", str(path), str(results), "--law", "sequential", "--quiet")
    assert other.returncode == 1  # 10 sweeps in the order given: another exit velocity


def test_the_corner_takes_the_law_over_its_number_field() -> None:
    done = verify_cli("corner", "--alpha", "pi/6", "--phi", "pi/12", "--eps1", "0.999", "--eps2", "0.001",
                      "--law", "sequential", "--iterations", "3", "--order", "1,0", "--json")  # fmt: skip
    assert done.returncode == 0, done.stderr
    record = json.loads(done.stdout)
    assert record["law"] == "sequential" and record["law_settings"]["order"] == [1, 0]
    assert "sqrt" in "".join(record["exit_velocity"])  # exact in Q(sqrt(2), sqrt(3)), not rounded


def test_the_property_suite_runs_the_settings_and_says_how_to_reproduce() -> None:
    done = verify_cli("properties", "--profile", "dev", "--property", "relabelling", "--family", "cradle",
                      "--rule", "general", "--law", "sequential", "--iterations", "2", "--json", "--quiet",
                      "--workers", "1")  # fmt: skip
    assert done.returncode == 1, done.stderr  # refuted: the sweeps visit the contacts in the order given
    (row,) = json.loads(done.stdout)["properties"]
    assert row["law"] == "sequential" and row["verdict"] == "refuted"
    assert "verify solve CASE.json --rule general --law sequential --iterations 2" in row["note"]
