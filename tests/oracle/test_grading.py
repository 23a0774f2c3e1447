"""Graded verdicts of the oracle (issue 18, items 2, 3, 5): every class reached, each as expected.

The float example reaches some classes; deliberately wrong implementations (transformations of
the exact results, each breaking one thing) reach the others.
"""

from __future__ import annotations

import copy
import json
import math
import subprocess
import sys
import xml.etree.ElementTree as ET
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from tests.helpers import cradle_case
from verify.laws.rule import Budget
from verify.oracle import reference as oracle
from verify.oracle.grading import CLASSES, free_directions, ulp, ulps

ROOT = Path(__file__).resolve().parents[2]
RTOL = Fraction(1, 10**9)


def cases() -> list[dict[str, Any]]:
    return [
        cradle_case("c3", ["1", "1", "1"], ["1/2", "1/2"], ["100", "0", "0"]),  # exits after 3 impulses
        cradle_case("c3-masses", ["1", "2", "3"], ["1/3", "1/5"], ["7", "0", "-1"]),
        cradle_case("never", ["1", "1", "1"], ["1/100", "1/100"], ["100", "0", "0"]),  # proved never to exit
    ]


def exact_results(cs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return oracle.golden_results(cs)


def grade_of(cs: list[dict[str, Any]], got: list[dict[str, Any]], **kw: Any) -> dict[str, str]:
    c = oracle.compare(cs, exact_results(cs), got, rtol=RTOL, atol=Fraction(0), **kw)
    return {g.case_id: g.cls for g in c.grades}


def with_velocity(r: dict[str, Any], v: list[Fraction]) -> dict[str, Any]:
    out = copy.deepcopy(r)
    out["exit_velocity"] = [f"{x.numerator}/{x.denominator}" for x in v]
    return out


def velocity(r: dict[str, Any]) -> list[Fraction]:
    return [oracle.approx(x) for x in r["exit_velocity"]]


def energy(case: dict[str, Any], v: list[Fraction]) -> Fraction:
    m = [oracle.approx(case["mass_matrix"][i][i]) for i in range(len(v))]
    return sum((mi * x * x for mi, x in zip(m, v)), Fraction(0)) / 2


def test_the_exact_results_grade_exact() -> None:
    cs = cases()
    assert set(grade_of(cs, exact_results(cs)).values()) == {"exact"}


def test_a_tiny_error_is_within_tolerance_and_measured() -> None:
    cs = cases()[:1]
    (r,) = exact_results(cs)
    v = velocity(r)
    got = with_velocity(r, [v[0] + Fraction(1, 10**12), v[1], v[2]])
    c = oracle.compare(cs, [r], [got], rtol=RTOL, atol=Fraction(0))
    (g,) = c.grades
    assert g.cls == "within_tolerance"
    speed = max(abs(x) for x in v)
    assert g.needed_speed == Fraction(1, 10**12) / speed
    assert g.needed_ulps == ulps(v[0], v[0] + Fraction(1, 10**12))


def test_momentum_drift_energy_error_and_out_of_tolerance() -> None:
    cs = cases()[:1]
    (r,) = exact_results(cs)
    v = velocity(r)
    # a momentum change: every ball faster by the same amount (the free direction (1, 1, 1))
    drift = with_velocity(r, [x + Fraction(1, 10**3) for x in v])
    # momentum kept (delta = t (1, -2, 1)), energy raised or lowered by the sign of t
    delta = [Fraction(1), Fraction(-2), Fraction(1)]
    slope = sum(x * d for x, d in zip(v, delta))  # d/dt of the energy at t = 0 (unit masses)
    up = Fraction(1, 10**3) * (1 if slope >= 0 else -1)
    gain = with_velocity(r, [x + up * d for x, d in zip(v, delta)])
    lose = with_velocity(r, [x - up * d for x, d in zip(v, delta)])
    assert energy(cs[0], velocity(gain)) > energy(cs[0], v) > energy(cs[0], velocity(lose))
    for got, expected in ((drift, "momentum_drift"), (gain, "energy_error"), (lose, "out_of_tolerance")):
        assert grade_of(cs, [got]) == {"c3": expected}


def test_wrong_branch_names_the_first_impulse_and_the_exact_rates_there() -> None:
    cs = cases()[:1]
    (r,) = exact_results(cs)
    wrong = copy.deepcopy(r)
    wrong["impact_sets"][1] = [0, 1]
    c = oracle.compare(cs, [r], [wrong], rtol=RTOL, atol=Fraction(0))
    (g,) = c.grades
    assert g.cls == "wrong_branch"
    assert "impulse 2" in g.detail and "rates p(F) = (" in g.detail and "a single impact" in g.detail
    assert "beta = -" not in g.detail  # no placeholder


def test_a_wrong_beta_is_a_wrong_branch() -> None:
    cs = [cradle_case("both", ["1", "2", "1"], ["1/2", "1"], ["1", "0", "-1"])]
    (r,) = exact_results(cs)
    assert r["betas"][0] is not None  # a multiple impact first
    wrong = copy.deepcopy(r)
    wrong["betas"][0] = str(oracle.approx(r["betas"][0]) * 2)
    assert grade_of(cs, [wrong]) == {"both": "wrong_branch"}


def test_stops_gave_up_and_non_terminating_claims() -> None:
    cs = cases()
    exact = exact_results(cs)
    never = exact[2]
    assert never["stop"] == "non_terminating"
    claim = {"id": "never", "exit_velocity": never["exit_velocity"], "stop": "non_terminating",
             "iterations": never["iterations"], "impact_sets": never["impact_sets"]}  # fmt: skip
    gave_up = dict(claim, stop="max_iterations")
    exit_claim = dict(claim, stop="exit")
    assert grade_of(cs[2:], [claim])["never"] == "exact"
    assert grade_of(cs[2:], [gave_up])["never"] == "gave_up"
    assert grade_of(cs[2:], [exit_claim])["never"] == "wrong_stop"
    done = exact[0]
    false_claim = dict(done, stop="non_terminating")
    assert grade_of(cs[:1], [false_claim])["c3"] == "wrong_stop"


def test_bad_numbers_missing_skipped_and_limited() -> None:
    cs = cases()
    exact = exact_results(cs)
    nan = dict(exact[0], exit_velocity=["nan", "0", "inf"])
    grades = grade_of(cs, [nan, exact[2]], skipped={"c3-masses": "not built"})
    assert grades == {"c3": "bad_number", "c3-masses": "skipped", "never": "exact"}
    assert grade_of(cs[:2], [exact[0]])["c3-masses"] == "missing"
    c = oracle.compare(cs[:1], oracle.golden_results(cs[:1], budget=Budget(bits=4)), exact[:1], rtol=RTOL,
                       atol=Fraction(0))  # fmt: skip
    assert [g.cls for g in c.grades] == ["limited"]


def test_free_directions_and_ulps_are_exact() -> None:
    assert free_directions([[Fraction(1), Fraction(0)]]) == [[Fraction(0), Fraction(1)]]
    assert ulp(Fraction(2)) == 2 * ulp(Fraction(1)) and ulp(Fraction(-3, 4)) == ulp(Fraction(1)) / 2
    assert ulps(Fraction(1), Fraction(1)) == 0


def test_every_class_is_named_once() -> None:
    assert len(set(CLASSES)) == len(CLASSES)


# -- the command line: summary counts, JUnit XML -------------------------------------------------------


def run_check(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", "oracle", "check", *args], capture_output=True, text=True,
                          cwd=ROOT, check=False)  # fmt: skip


def test_the_float_example_is_graded_and_the_counts_agree(tmp_path: Path) -> None:
    junit = tmp_path / "oracle.xml"
    done = run_check("golden/cases.json", "--impl", f"{sys.executable} examples/float_impl.py", "--json",
                     "--junit", str(junit))  # fmt: skip
    assert done.returncode == 1
    out = json.loads(done.stdout)
    per_case: dict[str, int] = {}
    for g in out["grades"]:
        per_case[g["class"]] = per_case.get(g["class"], 0) + 1
    assert per_case == out["classes"] and sum(per_case.values()) == out["checked"]
    assert out["classes"]["wrong_stop"] == len(out["mismatches"])
    suite = ET.parse(junit).getroot()
    assert suite.tag == "testsuite" and int(suite.get("tests", "0")) == out["checked"]
    assert int(suite.get("failures", "0")) == out["classes"]["wrong_stop"]
    assert [c.get("name") for c in suite] == [g["id"] for g in out["grades"]]


@pytest.mark.parametrize("text", ["not a number", "nan"])
def test_one_bad_number_is_a_mismatch_of_that_case_only(tmp_path: Path, text: str) -> None:
    results = json.loads((ROOT / "golden" / "results.json").read_text(encoding="utf-8"))
    results["results"][0]["exit_velocity"][0] = text
    path = tmp_path / "r.json"
    path.write_text(json.dumps(results), encoding="utf-8")
    done = run_check("golden/cases.json", str(path), "--json")
    out = json.loads(done.stdout)
    assert done.returncode == 1 and out["classes"]["bad_number"] == 1
    assert out["classes"]["exact"] + out["classes"].get("within_tolerance", 0) == out["checked"] - 1


@pytest.mark.parametrize("way", ["file", "impl"])
@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_a_bare_json_nan_is_graded_like_the_string_nan(tmp_path: Path, way: str, bad: float) -> None:
    """Python's json.dump writes a bare NaN (or Infinity): that case is bad_number, the others are checked,
    both for a result file and for the output of --impl (issue 34, item 9)."""
    results = json.loads((ROOT / "golden" / "results.json").read_text(encoding="utf-8"))
    results["results"][1]["exit_velocity"][0] = bad
    results["results"][19]["betas"][1] = bad  # cradle-5-balls-masses-12321: beta 25/17 at impulse 2
    path = tmp_path / "r.json"
    path.write_text(json.dumps(results), encoding="utf-8")  # allow_nan: a bare NaN / Infinity
    assert ("NaN" if math.isnan(bad) else "Infinity") in path.read_text(encoding="utf-8")
    if way == "file":
        done = run_check("golden/cases.json", str(path), "--json")
    else:
        impl = tmp_path / "impl.py"
        impl.write_text(f"import sys\nsys.stdin.read()\nsys.stdout.write(open({str(path)!r}).read())\n")
        done = run_check("golden/cases.json", "--impl", f"{sys.executable} {impl}", "--json")
    assert done.returncode == 1, done.stderr
    out = json.loads(done.stdout)
    bad_ids = [m["id"] for m in out["mismatches"] if m["field"] == "bad_number"]
    assert bad_ids == [results["results"][1]["id"], results["results"][19]["id"]]
    assert all("results[" in m["detail"] for m in out["mismatches"] if m["field"] == "bad_number")
    assert out["classes"]["bad_number"] == 2
    assert out["classes"]["exact"] + out["classes"].get("within_tolerance", 0) == out["checked"] - 2


def test_a_bare_json_nan_where_no_number_belongs_names_the_file_and_field(tmp_path: Path) -> None:
    results = json.loads((ROOT / "golden" / "results.json").read_text(encoding="utf-8"))
    results["results"][1]["iterations"] = float("nan")
    path = tmp_path / "r.json"
    path.write_text(json.dumps(results), encoding="utf-8")
    done = run_check("golden/cases.json", str(path))
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.strip().splitlines() == [
        f"verify: error: {path}: results[1].iterations: expected an integer, got the bare JSON constant NaN "
        "(not a number; numbers are strings)"
    ]


# -- tolerance budgets, hard cases through the command line, error tables --------------------------------


def test_a_budget_in_ulps_lets_a_case_pass_and_only_that_case(tmp_path: Path) -> None:
    from verify.oracle.grading import Budgets, ulp

    cs = cases()[:2]
    exact = exact_results(cs)
    v = velocity(exact[0])
    off = [v[0] + 3 * ulp(v[0]), v[1], v[2]]
    got = [
        with_velocity(exact[0], off),
        with_velocity(exact[1], [x * (1 + Fraction(1, 10**6)) for x in velocity(exact[1])]),
    ]
    strict = oracle.compare(cs, exact, got, rtol=Fraction(0), atol=Fraction(0))
    assert strict.grades[0].cls == "momentum_drift"  # one component off by 3 ulps: the total momentum moved
    budgets = Budgets.parse({"default": {"rtol": "0"}, "cases": {"c3": {"ulps": 3}}})
    graded = oracle.compare(cs, exact, got, rtol=Fraction(0), atol=Fraction(0), budgets=budgets)
    assert graded.grades[0].cls == "within_tolerance"
    assert graded.grades[1].cls != "within_tolerance"  # the pattern names c3 only
    assert Budgets.parse({"cases": {"c3": {"ulps": 2}}}).for_case("c3").ulps == 2


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('{"default": {"ulps": -1}}', "ulps: expected a non-negative integer"),
        ('{"default": {"rtol": 0.1}}', "number"),
        ('{"default": {"speed": "nan"}}', "nan"),
        ('{"defaults": {}}', "expected"),
        ('{"default": {"rtol": "1e-9", "tolerance": "1"}}', "unknown field 'tolerance'"),
    ],
)
def test_a_bad_tolerance_file_is_one_line_and_exit_2(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "tol.json"
    path.write_text(text, encoding="utf-8")
    done = run_check("golden/cases.json", "golden/results.json", "--tolerances", str(path))
    assert done.returncode == 2 and message in done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr


def test_hard_cases_graded_through_the_command_line(tmp_path: Path) -> None:
    """verify oracle generate, then the float example graded on it: the per-case lines of the text
    output and the summary counts agree, and the same counts come out of --json."""
    hard = tmp_path / "hard.json"
    gen = subprocess.run([sys.executable, "-m", "verify", "oracle", "generate", "--level", "1", "--seed", "0",
                          "--out", str(hard)], capture_output=True, text=True, cwd=ROOT, check=False)  # fmt: skip
    assert gen.returncode == 0, gen.stderr
    impl = f"{sys.executable} examples/float_impl.py"
    text = run_check(str(hard), "--impl", impl).stdout
    lines = text.splitlines()
    table = lines.index("  class                count")
    counts = {}
    for line in lines[table + 1 :]:
        if not line.strip():
            break
        name, n = line.split()
        counts[name] = int(n)
    per_case = {cls: sum(line.startswith(cls.upper() + " ") for line in lines[:table]) for cls in CLASSES}
    for cls in CLASSES:
        if cls not in ("exact", "within_tolerance"):
            assert per_case[cls] == counts.get(cls, 0), cls
    out = json.loads(run_check(str(hard), "--impl", impl, "--json").stdout)
    assert out["classes"] == counts and sum(counts.values()) == out["checked"]
    assert counts.get("wrong_stop", 0) > 0 and counts.get("wrong_branch", 0) > 0  # where floats go wrong


def test_the_error_table_has_one_row_per_file(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "verify", "oracle", "table", "golden/cases.json",
                           "exact=golden/results.json", "golden/results-simultaneous.json", "--json"],
                          capture_output=True, text=True, cwd=ROOT, check=False)  # fmt: skip
    assert done.returncode == 1, done.stderr  # a row has failing cases (the other law's)
    rows = json.loads(done.stdout)["table"]
    assert [r["name"] for r in rows] == ["exact", "results-simultaneous.json"]
    assert rows[0]["classes"] == {"exact": 49} and rows[0]["worst_relative_error"]["value"] == "0"
    assert rows[1]["classes"].get("exact", 0) < 49  # the other law's results are graded against the rule


# -- issue 34: the tolerance's basis (item 3), beta's own tolerance (item 2), the lines that show a class -----


def heavy_case() -> dict[str, Any]:
    """A light ball stuck to a heavy one (COR 0): the exit speed is a millionth of the entrance speed."""
    return cradle_case("heavy", ["1", "1000000"], ["0"], ["1000", "0"])


def test_the_default_tolerance_is_relative_to_the_exit_speed(tmp_path: Path) -> None:
    """An exit velocity off by 9e-5 of itself (its fifth significant digit) fails by default, although that
    error is far below 1e-9 of the entrance speed; --rtol and --atol still widen the tolerance."""
    cs = [heavy_case()]
    (r,) = exact_results(cs)
    v = velocity(r)
    speed_in, speed_out = Fraction(1000), max(abs(x) for x in v)
    assert speed_out * 10**5 < speed_in  # the exit speed is small
    off = with_velocity(r, [x * (1 + Fraction(9, 10**5)) for x in v])
    assert grade_of(cs, [off]) == {"heavy": "out_of_tolerance"}
    (case_file := tmp_path / "cases.json").write_text(json.dumps({"cases": cs}), encoding="utf-8")
    (result_file := tmp_path / "r.json").write_text(json.dumps({"results": [off]}), encoding="utf-8")
    default = run_check(str(case_file), str(result_file), "--json")
    assert default.returncode == 1 and json.loads(default.stdout)["classes"] == {"out_of_tolerance": 1}
    for option in (["--rtol", "1e-4"], ["--atol", "1e-6"]):
        wide = run_check(str(case_file), str(result_file), "--json", *option)
        assert wide.returncode == 0 and json.loads(wide.stdout)["classes"] == {"within_tolerance": 1}, option


def test_a_component_that_is_exactly_0_has_a_floor_scaled_by_the_entrance_speed() -> None:
    cs = [cradle_case("stop", ["1", "1"], ["0"], ["1", "-1"])]  # both balls stop: the exit speed is 0
    (r,) = exact_results(cs)
    assert velocity(r) == [0, 0]
    rounded = with_velocity(r, [Fraction(1, 10**17), Fraction(-1, 10**17)])
    wrong = with_velocity(r, [Fraction(1, 10**6), Fraction(-1, 10**6)])
    assert grade_of(cs, [rounded]) == {"stop": "within_tolerance"}
    assert grade_of(cs, [wrong]) == {"stop": "out_of_tolerance"}
    c = oracle.compare(cs, [r], [rounded], rtol=RTOL, atol=Fraction(0), floor=Fraction(0))
    assert [g.cls for g in c.grades] == ["out_of_tolerance"]  # --floor 0: exactly 0 means 0


def test_the_summary_prints_the_basis_of_the_tolerance() -> None:
    from verify.oracle.grading import Tolerance

    done = run_check("golden/cases.json", "golden/results.json")
    assert done.returncode == 0
    assert f"tolerance: {Tolerance().describe()}\n" in done.stdout
    assert "|v_exit| (the exact exit speed" in Tolerance().describe()
    loose = run_check("golden/cases.json", "golden/results.json", "--rtol", "1e-3", "--atol", "1/2", "--floor", "0")
    assert "tolerance: |got_i - exact_i| <= 0.5 + 0.001 |v_exit| (the exact exit speed" in loose.stdout
    assert "where exact_i = 0" not in loose.stdout
    as_json = run_check("golden/cases.json", "golden/results.json", "--json")
    assert json.loads(as_json.stdout)["tolerance"] == Tolerance().describe()


def test_beta_has_its_own_tolerance_not_the_velocity_s(tmp_path: Path) -> None:
    """{"default": {"rtol": "0", "ulps": 4096}} leaves beta's tolerance at its own default: a beta rounded
    as a float rounds it is not a wrong branch (and not exact); beta's own field still grades it."""
    from verify.oracle import grading

    cs = [cradle_case("both", ["1", "2", "1"], ["1/2", "1"], ["1", "0", "-1"])]
    (r,) = exact_results(cs)
    rounded = copy.deepcopy(r)
    rounded["betas"][0] = str(oracle.approx(r["betas"][0]) * (1 + Fraction(1, 10**15)))
    budgets = grading.Budgets.parse({"default": {"rtol": "0", "ulps": 4096}})
    c = oracle.compare(cs, [r], [rounded], rtol=Fraction(0), atol=Fraction(0), budgets=budgets)
    assert [g.cls for g in c.grades] == ["within_tolerance"] and c.ok
    assert budgets.default.beta == grading.DEFAULT_BETA == grading.Tolerance().beta
    strict = grading.Budgets.parse({"default": {"rtol": "0", "ulps": 4096, "beta": "1e-16"}})
    c = oracle.compare(cs, [r], [rounded], rtol=Fraction(0), atol=Fraction(0), budgets=strict)
    assert [g.cls for g in c.grades] == ["wrong_branch"] and "expected beta" in c.grades[0].detail


def test_every_wrong_branch_line_shows_the_exact_rates_where_the_runs_part() -> None:
    """Also where the exact run ends and the other goes on: the rates of the exact exit velocity."""
    from verify.numbers.format import format_exact

    cs = cases()[:1]
    (r,) = exact_results(cs)
    longer = copy.deepcopy(r)
    longer["impact_sets"].append([0])
    longer["iterations"] += 1
    (g,) = oracle.compare(cs, [r], [longer], rtol=RTOL, atol=Fraction(0)).grades
    normals = [[oracle.approx(x) for x in row] for row in cs[0]["normals"]]
    rates = [sum((a * x for a, x in zip(row, velocity(r))), Fraction(0)) for row in normals]
    assert all(x >= 0 for x in rates)
    assert g.cls == "wrong_branch" and g.detail.startswith("from impulse 4: expected none (the run ends), got [0]")
    assert f"rates p(F) = ({', '.join(format_exact(x) for x in rates)})" in g.detail
    shorter = copy.deepcopy(r)
    shorter["impact_sets"].pop()
    shorter["iterations"] -= 1
    (g,) = oracle.compare(cs, [r], [shorter], rtol=RTOL, atol=Fraction(0)).grades
    assert g.cls == "wrong_branch" and "from impulse 3: expected [0], got none" in g.detail
    assert "rates p(F) = (" in g.detail


def test_momentum_drift_and_energy_error_lines_give_the_drift_and_the_energy() -> None:
    from verify.numbers.format import format_decimal

    cs = cases()[:1]
    (r,) = exact_results(cs)
    v = velocity(r)
    drift = with_velocity(r, [x + Fraction(1, 10**3) for x in v])  # unit masses: the momentum gains 3/1000
    c = oracle.compare(cs, [r], [drift], rtol=RTOL, atol=Fraction(0))
    (g,) = c.grades
    assert g.cls == "momentum_drift" and "drift 0.003 > tolerance" in g.detail and "(1, 1, 1)" in g.detail
    delta = [Fraction(1), Fraction(-2), Fraction(1)]
    slope = sum(x * d for x, d in zip(v, delta))
    up = Fraction(1, 10**3) * (1 if slope >= 0 else -1)
    gain = with_velocity(r, [x + up * d for x, d in zip(v, delta)])
    (g,) = oracle.compare(cs, [r], [gain], rtol=RTOL, atol=Fraction(0)).grades
    excess = energy(cs[0], velocity(gain)) - energy(cs[0], v)
    assert g.cls == "energy_error"
    assert g.detail.startswith(
        "the kinetic energy of the exit velocity is " + format_decimal(energy(cs[0], velocity(gain)), 12)
    )
    assert f": {format_decimal(excess, 3)} too much > tolerance" in g.detail


def test_results_of_another_law_are_said_to_be(tmp_path: Path) -> None:
    """A result file whose records name another law than --law is graded as asked, and the report says so
    (a simultaneous-law file checked under the rule fails case by case: the line tells why)."""
    argv = [sys.executable, "-m", "verify", "oracle", "check", "golden/cases.json", "golden/results-simultaneous.json"]
    done = subprocess.run([*argv, "--quiet"], capture_output=True, text=True, cwd=ROOT, check=False)
    assert done.returncode == 1
    assert "note: the results name the simultaneous law and were graded under the rule" in done.stdout
    done = subprocess.run([*argv, "--law", "simultaneous", "--quiet"], capture_output=True, text=True, cwd=ROOT,
                          check=False)  # fmt: skip
    assert done.returncode == 0 and "note: the results name" not in done.stdout
