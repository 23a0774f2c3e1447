"""The simultaneous law (Newton's restitution with complementarity), exactly: issue 17, item 1."""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from tests.helpers import Poison, assert_exact_vector, cradle_case, exact_value
from verify.dynamics.system import System
from verify.errors import InvalidSystem
from verify.laws.rule import solve
from verify.laws.simultaneous import complementarity, lcp_vector
from verify.models.corner import run_corner
from verify.models.cradle import cradle_system, run_cradle

ROOT = Path(__file__).resolve().parents[2]


def verify_cli(*args: str, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", *args], input=stdin, capture_output=True, text=True,
                          cwd=ROOT, check=False)  # fmt: skip


# -- what the issue requires, through `verify solve` -------------------------------------------------


@pytest.mark.parametrize(("eps", "expected"), [("1", ["-100/3", "200/3", "200/3"]), ("1/2", ["0", "50", "50"])])
def test_verify_solve_gives_the_issue_values(tmp_path: Path, eps: str, expected: list[str]) -> None:
    case = cradle_case("c", ["1", "1", "1"], [eps, eps], ["100", "0", "0"])
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [case]}), encoding="utf-8")
    done = verify_cli("solve", str(path), "--law", "simultaneous", "--json")
    assert done.returncode == 0, done.stderr
    (record,) = json.loads(done.stdout)["results"]
    assert record["exit_velocity"] == expected
    assert record["law"] == "simultaneous" and record["stop"] == "exit" and record["impact_sets"] == [[0, 1]]


def test_the_rule_is_unchanged_by_the_law_option() -> None:
    s = cradle_system("1")
    assert_exact_vector([0, 0, 100], s.backend, solve(s, ["100", "0", "0"], law="rule").exit_velocity)


def test_results_are_exact_rationals_and_no_float_is_taken() -> None:
    p = Poison
    s = System([[p(1), p(0), p(0)], [p(0), p(2), p(0)], [p(0), p(0), p(3)]], [[-1, 1, 0], [0, -1, 1]],
               [p(1, 3), p(2, 7)])  # fmt: skip
    r = solve(s, [p(5), p(-1, 2), p(0)], law="simultaneous")
    for x in (*r.exit_velocity, *(r.impulses or ())):
        exact_value(r.backend, x)


# -- the complementarity solution, against an independent brute force ---------------------------------


def brute_force(G: list[list[Fraction]], q: list[Fraction]) -> list[list[Fraction]]:
    """Every solution of LCP(q, G), by trying all 2^r active sets (SymPy; G is positive definite, so
    every G_SS is non-singular and each set gives at most one candidate)."""
    r, out = len(q), []
    for size in range(r + 1):
        for S in itertools.combinations(range(r), size):
            lam = [Fraction(0)] * r
            if S:
                sol = sp.Matrix([[G[i][k] for k in S] for i in S]).LUsolve(sp.Matrix([-q[i] for i in S]))
                for i, x in zip(S, sol):
                    lam[i] = Fraction(int(sp.fraction(x)[0]), int(sp.fraction(x)[1]))
            z = [q[i] + sum(G[i][k] * lam[k] for k in range(r)) for i in range(r)]
            complementary = all(a * b == 0 for a, b in zip(lam, z))
            if all(x >= 0 for x in lam) and all(x >= 0 for x in z) and complementary and lam not in out:
                out.append(lam)
    return out


small = st.fractions(min_value=-3, max_value=3, max_denominator=4)


@st.composite
def systems(draw: st.DrawFn) -> tuple[System, list[Fraction]]:
    """A general system: diagonal masses, 2 or 3 constraints in 3 or 4 coordinates, a velocity."""
    n = draw(st.integers(3, 4))
    r = draw(st.integers(2, 3))
    masses = [draw(st.fractions(min_value=Fraction(1, 2), max_value=3, max_denominator=4)) for _ in range(n)]
    normals = [[draw(small) for _ in range(n)] for _ in range(r)]
    cors = [draw(st.fractions(min_value=0, max_value=1, max_denominator=5)) for _ in range(r)]
    v = [draw(small) for _ in range(n)]
    g = [[masses[i] if i == j else Fraction(0) for j in range(n)] for i in range(n)]
    try:
        s = System(g, normals, cors)
    except InvalidSystem:  # dependent or zero normals: not a system of the paper
        from hypothesis import assume

        assume(False)
    return s, v


@settings(max_examples=60, deadline=None, database=None, derandomize=True)
@given(systems())
def test_the_active_set_method_finds_the_one_solution(case: tuple[System, list[Fraction]]) -> None:
    s, v = case
    K = s.backend
    q = lcp_vector(s, s.rates(s.velocity(v)))
    _, lam = complementarity(K, s.gram, q)
    G = [[K.to_number(x) for x in row] for row in s.gram]
    solutions = brute_force(G, [K.to_number(x) for x in q])
    assert solutions == [[K.to_number(x) for x in lam]]  # unique (G positive definite), and the same


@settings(max_examples=60, deadline=None, database=None, derandomize=True)
@given(systems())
def test_the_exit_obeys_the_law(case: tuple[System, list[Fraction]]) -> None:
    """Newton's law on incoming constraints, no penetration on the others, complementarity."""
    s, v = case
    K = s.backend
    r = solve(s, v, law="simultaneous")
    before = [K.to_number(x) for x in s.rates(s.velocity(v))]
    after = [K.to_number(x) for x in s.rates(r.exit_velocity)]
    lam = [K.to_number(x) for x in r.impulses or ()]
    for w, w2, e, l in zip(before, after, s.source["restitution"], lam):
        target = w2 + e * min(w, 0)
        assert l >= 0 and target >= 0 and l * target == 0
        assert w2 >= 0  # the exit is outgoing
    assert r.stop == "exit" and r.iterations == (1 if any(lam) else 0)


# -- backends, the other readings, errors ---------------------------------------------------------


def test_interval_backend_decides_an_exact_zero_without_chasing_it() -> None:
    """v = (2, 0, 1), COR 0 on the first contact: the impulse on it leaves the second contact's
    complementarity quantity exactly 0 (a degenerate solution); exact inputs decide it exactly."""
    s = cradle_system(["0", "1"]).convert_to("interval")
    r = solve(s, ["2", "0", "1"], law="simultaneous")
    assert not r.notes
    for x in r.exit_velocity:
        lo, hi = (Fraction(b) for b in r.backend.enclosure(x, 20))
        assert lo <= 1 <= hi and hi - lo < Fraction(1, 10**15)
    assert r.impact_sets == [(0,)]


def test_corner_on_every_backend_agrees_with_the_exact_law() -> None:
    exact = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001", law="simultaneous").result
    K = exact.backend
    for backend in ("interval", "mp", "float"):
        other = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001", law="simultaneous",
                           backend=backend).result  # fmt: skip
        for a, b in zip(exact.exit_velocity, other.exit_velocity):
            diff = Fraction(K.to_decimal(a, 30)) - Fraction(other.backend.to_decimal(b, 30))
            assert abs(diff) < Fraction(1, 10**9)


def test_rule_variants_give_the_cors() -> None:
    s = cradle_system(["1/2", "1/3"])
    ideal = solve(s, ["100", "0", "0"], law="simultaneous", rule="ideal")
    assert_exact_vector(["-100/3", "200/3", "200/3"], s.backend, ideal.exit_velocity)
    with pytest.raises(InvalidSystem, match="symmetric"):
        solve(s, ["100", "0", "0"], law="simultaneous", rule="symmetric")
    with pytest.raises(InvalidSystem, match="unknown law"):
        solve(s, ["100", "0", "0"], law="newton")


def test_no_incoming_constraint_gives_no_impulse() -> None:
    s = cradle_system("1")
    r = solve(s, ["0", "1", "2"], law="simultaneous")
    assert r.iterations == 0 and r.impact_sets == [] and r.steps == ()
    assert_exact_vector([0, 1, 2], s.backend, r.exit_velocity)


def test_cradle_and_corner_commands_take_the_law() -> None:
    done = verify_cli("cradle", "--eps", "1", "--law", "simultaneous", "--json")
    assert done.returncode == 0 and json.loads(done.stdout)["exit_velocity"] == ["-100/3", "200/3", "200/3"]
    done = verify_cli("corner", "--alpha", "pi/6", "--phi", "pi/12", "--eps1", "0.999", "--eps2", "0.001",
                      "--law", "simultaneous", "--json")  # fmt: skip
    assert done.returncode == 0 and json.loads(done.stdout)["zones"] == ["Z12", "Z0"]
    done = verify_cli("cradle", "--eps", "1", "--law", "simultaneous", "--mode", "paper")
    assert done.returncode == 2 and "Traceback" not in done.stderr and len(done.stderr.splitlines()) == 1
    plastic = run_cradle("0", law="simultaneous")  # every COR 0: the balls leave together, momentum kept
    v = [plastic.backend.to_number(x) for x in plastic.exit_velocity]
    assert len(set(v)) == 1 and sum(v) == 100


# -- the oracle with the second law ---------------------------------------------------------------


def test_golden_simultaneous_results_check_clean_and_differ_from_the_rule() -> None:
    cases = str(ROOT / "golden" / "cases.json")
    done = verify_cli("oracle", "check", cases, str(ROOT / "golden" / "results-simultaneous.json"), "--law",
                      "simultaneous", "--json")  # fmt: skip
    assert done.returncode == 0, done.stdout
    done = verify_cli("oracle", "check", cases, str(ROOT / "golden" / "results.json"), "--law", "simultaneous")
    assert done.returncode == 1 and "MISMATCH paper-table1-eps-1" in done.stdout


def test_velocity_only_results_say_what_was_not_checked(tmp_path: Path) -> None:
    case = cradle_case("c", ["1", "1", "1"], ["1", "1"], ["100", "0", "0"])
    cases = tmp_path / "cases.json"
    cases.write_text(json.dumps({"cases": [case, dict(case, id="d")]}), encoding="utf-8")
    results = tmp_path / "results.json"
    results.write_text(json.dumps({"results": [{"id": "c", "exit_velocity": ["-33.33333333333333", "66.66666666666667",
                                                                            "66.66666666666667"]}],
                                   "skipped": [{"id": "d", "reason": "not built"}]}), encoding="utf-8")  # fmt: skip
    done = verify_cli("oracle", "check", str(cases), str(results), "--law", "simultaneous", "--json")
    out = json.loads(done.stdout)
    assert done.returncode == 0, done.stdout
    assert out["unchecked"] == {"stop": 1, "iterations": 1, "impact_sets": 1}
    assert out["skipped"] == [{"id": "d", "reason": "not built"}]
    done = verify_cli("oracle", "check", str(cases), str(results), "--json")  # against the rule: (0, 0, 100)
    assert done.returncode == 1 and {m["field"] for m in json.loads(done.stdout)["mismatches"]} == {
        "exit_velocity[0]",
        "exit_velocity[1]",
        "exit_velocity[2]",
    }
