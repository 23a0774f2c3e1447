"""JUnit XML of the oracle's graded verdicts: how each class is reported is the user's choice
(``--junit-as``, issue 34 item 12), read back with ElementTree."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
import xml.etree.ElementTree as ET
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from tests.helpers import cradle_case
from verify.oracle import reference as oracle

ROOT = Path(__file__).resolve().parents[2]


def graded_files(tmp_path: Path) -> tuple[Path, Path]:
    """A case file of three cases and a result file that grades them exact, within_tolerance, gave_up."""
    cases = [
        cradle_case("c3", ["1", "1", "1"], ["1/2", "1/2"], ["100", "0", "0"]),
        cradle_case("c3-masses", ["1", "2", "3"], ["1/3", "1/5"], ["7", "0", "-1"]),
        cradle_case("never", ["1", "1", "1"], ["1/100", "1/100"], ["100", "0", "0"]),  # proved never to exit
    ]
    exact = oracle.golden_results(cases)
    assert exact[2]["stop"] == "non_terminating"
    near = copy.deepcopy(exact[0])
    v0 = oracle.approx(near["exit_velocity"][0]) + Fraction(1, 10**12)
    near["exit_velocity"][0] = f"{v0.numerator}/{v0.denominator}"
    gave_up = dict(copy.deepcopy(exact[2]), stop="max_iterations")
    case_path, result_path = tmp_path / "cases.json", tmp_path / "results.json"
    case_path.write_text(json.dumps({"cases": cases}), encoding="utf-8")
    result_path.write_text(json.dumps({"results": [near, exact[1], gave_up]}), encoding="utf-8")
    return case_path, result_path


def run_check(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", "oracle", "check", *args], capture_output=True,
                          text=True, cwd=ROOT, check=False)  # fmt: skip


def reported(path: Path) -> tuple[dict[str, Any], dict[str, tuple[str, list[str]]]]:
    """The suite's counts, and each test case's class (the type of its failure, the message of its skip, else
    passed) and child tags. Every test's classname names the case file, whatever its grade."""
    suite = ET.parse(path).getroot()
    counts = {k: int(suite.get(k, "-1")) for k in ("tests", "failures", "errors", "skipped")}
    assert {c.get("classname") for c in suite} == {f"oracle.{Path(suite.get('name', '')).stem}"}

    def shown(c: ET.Element) -> str:
        child = next(iter(c), None)
        if child is None:
            return "passed"
        return child.get("type") or child.get("message", "").split(":")[0]

    return counts, {c.get("name", ""): (shown(c), [x.tag for x in c]) for c in suite}


def test_by_default_gave_up_is_a_failure(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "oracle.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit))
    assert done.returncode == 1, done.stderr  # the stop differs: a mismatch, whatever the report
    counts, tests = reported(junit)
    assert tests == {"c3": ("passed", []), "c3-masses": ("passed", []), "never": ("gave_up", ["failure"])}
    assert counts == {"tests": 3, "failures": 1, "errors": 0, "skipped": 0}


def test_junit_as_reports_each_class_as_the_user_says(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "oracle.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit),
                     "--junit-as", "gave_up=skipped,within_tolerance=failure")  # fmt: skip
    assert done.returncode == 1, done.stderr
    counts, tests = reported(junit)
    assert tests == {"c3": ("within_tolerance", ["failure"]), "c3-masses": ("passed", []),
                     "never": ("gave_up", ["skipped"])}  # fmt: skip
    assert counts == {"tests": 3, "failures": 1, "errors": 0, "skipped": 1}
    skipped = ET.parse(junit).getroot().find("testcase[@name='never']/skipped")
    assert skipped is not None and skipped.get("message", "").startswith("gave_up")
    done = run_check(str(cases), str(results), "--junit", str(junit), "--junit-as", "gave_up=passed")
    counts, tests = reported(junit)
    assert tests["never"] == ("passed", []) and counts["failures"] == counts["skipped"] == 0


@pytest.mark.parametrize(
    ("value", "message"),
    [
        ("gave_up=ignored", "--junit-as: gave_up=ignored: 'ignored' is not one of failure, skipped, passed"),
        ("gaveup=skipped", "--junit-as: gaveup=skipped: 'gaveup' is not a class (exact, within_tolerance,"),
        ("gave_up", "--junit-as: 'gave_up': expected CLASS=KIND, e.g. gave_up=skipped"),
        ("gave_up=skipped,gave_up=passed", "--junit-as: gave_up=passed: gave_up is given twice"),
    ],
)
def test_a_bad_junit_as_is_refused_in_one_line(tmp_path: Path, value: str, message: str) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "oracle.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit), "--junit-as", value)
    assert done.returncode == 2 and done.stdout == ""
    (line,) = done.stderr.splitlines()
    assert line.startswith(f"verify: error: verify oracle check: {message}")
    suite = ET.parse(junit).getroot()  # the JUnit file says what went wrong (a CI dashboard shows it)
    assert suite.get("errors") == "1" and suite[0][0].get("message", "").startswith(f"verify oracle check: {message}")


def test_junit_as_without_junit_is_refused(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    done = run_check(str(cases), str(results), "--junit-as", "gave_up=skipped")
    assert done.returncode == 2 and done.stderr == "verify: error: verify oracle check: --junit-as needs --junit FILE\n"


# -- issue 60, item 5: JUnit as CI dashboards read it --------------------------------------------------------


def test_a_case_keeps_its_classname_whatever_its_grade_and_every_test_has_a_time(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    names = []
    for report_as in ("gave_up=passed", "within_tolerance=failure"):
        junit = tmp_path / f"{report_as.split('=')[0]}.xml"
        run_check(str(cases), str(results), "--junit", str(junit), "--junit-as", report_as)
        suite = ET.parse(junit).getroot()
        names.append({c.get("name"): c.get("classname") for c in suite})
        assert float(suite.get("time", "x")) >= 0 and all(float(c.get("time", "x")) >= 0 for c in suite)
    assert names[0] == names[1] == dict.fromkeys(("c3", "c3-masses", "never"), "oracle.cases")


def test_a_failure_names_every_failed_check_with_both_numbers_the_velocity_first(tmp_path: Path) -> None:
    """A velocity off by 0.1 % breaks the momentum too: the class says so, and the text shows the velocity."""
    cases, _ = graded_files(tmp_path)
    exact = oracle.golden_results(json.loads(cases.read_text())["cases"])
    off = copy.deepcopy(exact[0])
    v = oracle.approx(off["exit_velocity"][2]) * Fraction(1001, 1000)
    off["exit_velocity"][2] = f"{v.numerator}/{v.denominator}"
    junit = tmp_path / "j.xml"
    for extra in ({}, {"iterations": off["iterations"] + 1}):  # the velocity alone, then with a wrong count too
        results = tmp_path / "off.json"
        results.write_text(json.dumps({"results": [dict(off, **extra), *exact[1:]]}), encoding="utf-8")
        assert run_check(str(cases), str(results), "--junit", str(junit)).returncode == 1
        failure = ET.parse(junit).getroot().find("testcase[@name='c3']/failure")
        assert failure is not None
        lines = (failure.text or "").splitlines()
        assert lines[0].startswith("exit_velocity[2]: expected ") and ", got " in lines[0], lines
        if extra:
            n = off["iterations"]
            assert failure.get("type") == "wrong_stop" and lines[1:] == [
                f"wrong_stop: iterations: expected {n}, got {n + 1}"
            ]
        else:
            assert failure.get("type") == "momentum_drift" and lines[1].startswith("momentum_drift: the momentum")


def test_a_run_that_cannot_grade_writes_a_junit_file_saying_why(tmp_path: Path) -> None:
    cases, _ = graded_files(tmp_path)
    junit = tmp_path / "j.xml"
    junit.write_text("<testsuite name='stale' />")
    done = run_check(str(cases), str(tmp_path / "missing.json"), "--junit", str(junit))
    assert done.returncode == 2 and "missing.json: cannot read" in done.stderr
    suite = ET.parse(junit).getroot()
    assert suite.get("errors") == "1" and "missing.json: cannot read" in suite[0][0].get("message", "")


def test_junit_creates_no_folder(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    done = run_check(str(cases), str(results), "--junit", str(tmp_path / "no" / "dir" / "x.xml"))
    assert done.returncode == 2 and "folder that exists" in done.stderr and not (tmp_path / "no").exists()


def test_dash_reads_stdin_and_writes_stdout(tmp_path: Path) -> None:
    """``-`` is stdin for the case file and stdout for --junit (the report then goes to stderr)."""
    cases, results = graded_files(tmp_path)
    argv = [sys.executable, "-m", "verify", "oracle", "check", "-", str(results), "--junit", "-"]
    done = subprocess.run(argv, input=cases.read_text(), capture_output=True, text=True, cwd=tmp_path, check=False)
    assert done.returncode == 1 and "as tests (--junit)" in done.stderr
    suite = ET.fromstring(done.stdout)
    assert suite.get("tests") == "3" and {c.get("classname") for c in suite} == {"oracle.stdin"}
    done = run_check(str(cases), str(results), "--junit", "-", "--json")
    assert done.returncode == 2 and "both write to stdout" in done.stderr and done.stdout == ""


def test_options_refused_while_read_also_replace_a_stale_junit_file(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "j.xml"
    junit.write_text("<testsuite name='stale' />")
    done = run_check(str(cases), str(results), "--junit", str(junit), "--rtol", "abc")
    assert done.returncode == 2 and "--rtol" in done.stderr
    suite = ET.parse(junit).getroot()
    assert suite.get("errors") == "1" and "--rtol" in suite[0][0].get("message", "")


def test_results_of_no_case_fail_a_test_of_their_own(tmp_path: Path) -> None:
    """A result for an id the case file does not have is a mismatch (exit code 1): the JUnit file is not green."""
    cases, _ = graded_files(tmp_path)
    exact = oracle.golden_results(json.loads(cases.read_text())["cases"])
    results = tmp_path / "extra.json"
    results.write_text(json.dumps({"results": [*exact, dict(exact[0], id="nosuch")]}), encoding="utf-8")
    junit = tmp_path / "j.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit))
    assert done.returncode == 1 and "1 failed, 0 skipped of 4" in done.stdout, done.stdout
    counts, tests = reported(junit)
    assert counts["failures"] == 1 and tests["the result file"] == ("result_file", ["failure"])
