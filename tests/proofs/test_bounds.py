"""The bounds inside the algorithms (verify.bounds): each is a constant of the module it names, each is
recorded where the code compares with it, and ``verify bounds`` adds up what the processes of a command used."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from fractions import Fraction as F
from pathlib import Path

import pytest

from tests.proofs.test_periodic import CASES, _system
from verify import bounds
from verify.laws.rule import solve
from verify.proofs.cones import period
from verify.report import bounds as catalogue

ROOT = Path(__file__).resolve().parents[2]


def test_every_bound_is_an_integer_constant_of_the_module_it_names() -> None:
    for name, b in catalogue.BOUNDS.items():
        assert isinstance(b.value, int) and b.value > 0, name


def test_every_bound_is_recorded_where_the_code_compares_with_it() -> None:
    code = "\n".join(p.read_text() for p in (ROOT / "verify").rglob("*.py") if p.name != "bounds.py")
    used = set(re.findall(r'bounds\.use\("(\w+)"', code)) | set(re.findall(r'bounds\.use\(\s*"(\w+)" if', code))
    used |= set(re.findall(r'else "(\w+)", MAX_PIVOTS', code))
    reached = set(re.findall(r'bounds\.reached\("(\w+)"\)', code))
    assert set(catalogue.BOUNDS) == used
    assert set(catalogue.BOUNDS) - {"pivots_failed", "period"} <= reached


def test_a_search_that_finds_its_cone_records_its_pivots_within_the_bound() -> None:
    masses, cors, velocity = CASES["5 balls, plastic, period (0,2)(1,3)"]
    system, _, _ = _system(masses, cors)
    with bounds.recording() as seen:
        r = solve(system, velocity, max_iterations=200)
    assert r.stop == "non_terminating"
    assert 0 < seen["pivots"] <= period.MAX_PIVOTS
    assert 1 <= seen["period"] <= 6
    assert seen["carried"] <= period.MAX_CARRIED


def test_a_smaller_pivot_budget_is_reached_and_the_run_goes_on(monkeypatch: pytest.MonkeyPatch) -> None:
    masses, cors, velocity = CASES["5 balls, plastic, period (0,2)(1,3)"]
    system, _, _ = _system(masses, cors)
    with bounds.recording() as seen:
        needed = solve(system, velocity, max_iterations=200)
    monkeypatch.setattr(period, "MAX_PIVOTS", seen["pivots"] - 1)
    with bounds.recording() as seen:
        r = solve(system, velocity, max_iterations=needed.iterations + 30)
    assert seen["pivots:reached"] >= 1
    assert r.stop != "non_terminating" or r.iterations > needed.iterations


def test_nothing_is_recorded_outside_a_recording() -> None:
    with bounds.recording() as seen:
        pass
    bounds.use("pivots", 3)
    assert seen == {}


def test_the_summary_takes_the_largest_use_and_counts_what_was_reached() -> None:
    records = [{"bound": "carried", "peak": 7}, {"bound": "carried", "peak": 3}]
    records += [{"bound": "crossings", "reached": 1}] * 2
    s = catalogue.summary([*map(json.dumps, records), ""])
    assert s["carried"] == (7, 0) and s["crossings"] == (None, 2) and s["pivots"] == (None, 0)
    for bad in (
        '{"bound": "nope", "peak": 1}',
        '{"bound": "carried"}',
        "[1]",
        '{"bound": "carried", "peak": 1, "x": 2}',
    ):
        with pytest.raises(ValueError, match="line 1"):
            catalogue.summary([bad])


def test_processes_of_a_command_append_to_one_file_and_verify_bounds_adds_them_up(tmp_path: Path) -> None:
    masses, cors, velocity = CASES["5 balls, plastic, period (0,2)(1,3)"]
    system, g, normals = _system(masses, cors)
    case = {"id": "plastic", "mass_matrix": g, "normals": normals, "restitution": cors, "velocity": velocity}
    (tmp_path / "cases.json").write_text(json.dumps({"cases": [case]}))
    log = tmp_path / "bounds.log"
    env = {**os.environ, "VERIFY_BOUNDS": str(log)}
    for _ in range(2):  # two processes, one file
        subprocess.run([sys.executable, "-m", "verify", "solve", str(tmp_path / "cases.json"), "--quiet"],
                       env=env, check=True, capture_output=True)  # fmt: skip
    lines = log.read_text().splitlines()
    with bounds.recording() as seen:
        solve(system, [F(v) for v in velocity], max_iterations=1000)
    assert catalogue.summary(lines)["pivots"] == (seen["pivots"], 0)
    out = subprocess.run(
        [sys.executable, "-m", "verify", "bounds", str(log)], capture_output=True, text=True, check=False
    )
    assert out.returncode == 0
    row = next(line for line in out.stdout.splitlines() if line.startswith("pivots "))
    assert row.split()[1:3] == [str(period.MAX_PIVOTS), f"{seen['pivots']:,}"]


@pytest.mark.parametrize("content", ["not json\n", '{"bound": "pivots", "peak": "many"}\n'])
def test_verify_bounds_refuses_a_file_that_is_not_a_log(tmp_path: Path, content: str) -> None:
    (tmp_path / "x.log").write_text(content)
    out = subprocess.run([sys.executable, "-m", "verify", "bounds", str(tmp_path / "x.log")],
                         capture_output=True, text=True, check=False)  # fmt: skip
    assert out.returncode == 2 and "line 1" in out.stderr and "Traceback" not in out.stderr and out.stdout == ""
