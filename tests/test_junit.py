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
from verify.checks import oracle

ROOT = Path(__file__).resolve().parents[1]


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
    """The suite's counts, and each test case's classname and child tags."""
    suite = ET.parse(path).getroot()
    counts = {k: int(suite.get(k, "-1")) for k in ("tests", "failures", "errors", "skipped")}
    return counts, {c.get("name", ""): (c.get("classname", ""), [x.tag for x in c]) for c in suite}


def test_by_default_gave_up_is_a_failure(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "oracle.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit))
    assert done.returncode == 1, done.stderr  # the stop differs: a mismatch, whatever the report
    counts, tests = reported(junit)
    assert tests == {"c3": ("oracle.within_tolerance", []), "c3-masses": ("oracle.exact", []),
                     "never": ("oracle.gave_up", ["failure"])}  # fmt: skip
    assert counts == {"tests": 3, "failures": 1, "errors": 0, "skipped": 0}


def test_junit_as_reports_each_class_as_the_user_says(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    junit = tmp_path / "oracle.xml"
    done = run_check(str(cases), str(results), "--junit", str(junit),
                     "--junit-as", "gave_up=skipped,within_tolerance=failure")  # fmt: skip
    assert done.returncode == 1, done.stderr
    counts, tests = reported(junit)
    assert tests == {"c3": ("oracle.within_tolerance", ["failure"]), "c3-masses": ("oracle.exact", []),
                     "never": ("oracle.gave_up", ["skipped"])}  # fmt: skip
    assert counts == {"tests": 3, "failures": 1, "errors": 0, "skipped": 1}
    skipped = ET.parse(junit).getroot().find("testcase[@name='never']/skipped")
    assert skipped is not None and skipped.get("message", "").startswith("gave_up")
    done = run_check(str(cases), str(results), "--junit", str(junit), "--junit-as", "gave_up=passed")
    counts, tests = reported(junit)
    assert tests["never"] == ("oracle.gave_up", []) and counts["failures"] == counts["skipped"] == 0


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
    assert not junit.exists()


def test_junit_as_without_junit_is_refused(tmp_path: Path) -> None:
    cases, results = graded_files(tmp_path)
    done = run_check(str(cases), str(results), "--junit-as", "gave_up=skipped")
    assert done.returncode == 2 and done.stderr == "verify: error: verify oracle check: --junit-as needs --junit FILE\n"
