"""`verify engines`: physics engines through the oracle (issue 17, items 2-4).

One engine runs end to end when it is installed (box2d is in the `test` extra, so CI runs it);
an engine that cannot be imported is listed as skipped; the committed record is what the
installed engines give again; every finding on the page is computed from the record.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from verify.engines import run as engines
from verify.engines.scene import scene_of
from verify.numbers.parse import parse_number, to_number

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "reports" / "engines.json"


def verify_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", *args], capture_output=True, text=True, cwd=ROOT,
                          check=False)  # fmt: skip


def is_exact_string(text: str) -> bool:
    """A number string of the contracts that the parser reads (exact references, not floats)."""
    value = to_number(parse_number(text))
    return not isinstance(value, float)


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def box2d_record() -> dict[str, Any]:
    pytest.importorskip("Box2D")
    done = verify_cli("engines", "--engine", "box2d", "--json", "--quiet")
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_box2d_runs_end_to_end(box2d_record: dict[str, Any]) -> None:
    (entry,) = box2d_record["engines"]
    assert {"name", "version", "combine_rule", "settings", "cases"} <= set(entry)
    assert entry["name"] == "box2d" and entry["version"] and entry["cases"]
    row_keys = {"id", "engine_exit_velocity", "rule_exit_velocity", "simultaneous_exit_velocity"}
    for row in entry["cases"]:
        assert row_keys <= set(row)
        assert all(is_exact_string(x) for x in row["simultaneous_exit_velocity"])
        assert row["rule_exit_velocity"] is None or all(is_exact_string(x) for x in row["rule_exit_velocity"])
    rows = {r["id"]: r for r in entry["cases"]}
    assert rows["cradle-3-eps-1"]["simultaneous_exit_velocity"] == ["-100/3", "200/3", "200/3"]
    assert [v["label"] for v in entry["variants"]][:1] == [f"{entry['alternate']['setting']} = "
                                                            f"{entry['alternate']['value']:g}"]  # fmt: skip


def rational(text: str) -> Fraction | None:
    """The exact value of a rational number string; None for a closed form (sqrt(3)/3)."""
    value = to_number(parse_number(text))
    return value if isinstance(value, Fraction) else None


def test_box2d_distances_are_those_of_its_velocities(box2d_record: dict[str, Any]) -> None:
    """The distance column, recomputed here from the printed floats and the exact strings (the cases
    with rational references: every cradle)."""
    cases = {c["id"]: c for c in box2d_record["cases"]}
    checked = 0
    for row in box2d_record["engines"][0]["cases"]:
        exact = [rational(x) for x in row["simultaneous_exit_velocity"]]
        v_in = [rational(x) for x in cases[row["id"]]["velocity"]]
        if None in exact or None in v_in:
            continue
        got = [Fraction(x) for x in row["engine_exit_velocity"]]
        d = max(abs(a - b) for a, b in zip(got, exact)) / max(abs(x) for x in v_in)  # type: ignore[operator]
        assert row["distance_to_simultaneous"] == engines.format_decimal(d, 3)
        checked += 1
    assert checked >= 20


def test_an_engine_that_is_not_installed_is_skipped(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(engines.ENGINES, "ghost", "tests.ghost_adapter")
    record = engines.engines_record(["ghost"])
    assert record["engines"] == []
    (skipped,) = record["skipped"]
    assert skipped["name"] == "ghost" and "not installed" in skipped["reason"]


def test_every_engine_case_is_a_scene() -> None:
    for case in engines.engine_cases():
        scene_of(case)  # raises Unsupported otherwise


def test_the_page_is_rendered_from_the_committed_record() -> None:
    """Every finding line of the page comes from the record (the staleness of the page itself is
    tests/report/test_reports.py's)."""
    from verify.engines.pages import engines_page_text
    from verify.views.pages import literal_products

    record = json.loads(RECORD.read_text(encoding="utf-8"))
    page = (ROOT / "reports" / "engines.md").read_text(encoding="utf-8")
    # what verify report adds to every page: the figures' numbers and captions, the provenance line
    page = re.sub(r"\n---\n\nWritten by verify [^\n]*\n$", "", page)
    page = re.sub(r"!\[Figure \d+: ([^\]]*)\]\(([^)]+)\)\n\n\*Figure \d+\.\* [^\n]*", r"![\1](\2)", page)
    assert page == literal_products(engines_page_text(record))
    assert len(record["engines"]) >= 3
    for entry in record["engines"]:
        assert f"**{entry['name']} {entry['version']}**" in page
        assert f"| {entry['name']} | {entry['explained']['precision']} |" in page


def test_every_case_of_the_record_is_printed_from_it(capsys) -> None:
    """``verify engines --from RECORD --cases``: the record's answers on every case, no engine run; a file that
    is not a record is refused (exit code 2) before anything is printed."""
    from verify.cli import main

    record = json.loads(RECORD.read_text(encoding="utf-8"))
    box2d = next(e for e in record["engines"] if e["name"] == "box2d")
    assert main(["engines", "--from", str(RECORD), "--cases", "--engine", "box2d"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"box2d {box2d['version']}: {len(box2d['cases'])} cases")
    assert all(f"| `{c['id']}` |" in out for c in box2d["cases"]) and "pymunk" not in out
    assert main(["engines", "--from", "README.md"]) == 2
    captured = capsys.readouterr()
    assert "--from README.md: not an engines record" in captured.err and not captured.out
    out_dir = RECORD.parent / "never-written"
    assert main(["engines", "--from", str(RECORD), "--engine", "box2d", "--report", "--out", str(out_dir)]) == 2
    captured = capsys.readouterr()
    assert "--report cannot go with it" in captured.err and not captured.out and not out_dir.exists()


@pytest.mark.slow(seconds=11)
def test_the_record_is_what_the_installed_engines_give() -> None:
    """Every installed engine of the recorded version gives the recorded velocities again (to
    1e-9 of the speed: engines compute in binary floating point, and a CPU may round otherwise)."""
    record = json.loads(RECORD.read_text(encoding="utf-8"))
    present = set(engines.installed())
    names = [e["name"] for e in record["engines"] if e["name"] in present]
    if not names:
        pytest.skip("none of the recorded engines is installed")
    fresh = {e["name"]: e for e in engines.engines_record(names)["engines"]}
    cases = {c["id"]: c for c in record["cases"]}
    for entry in record["engines"]:
        if entry["name"] not in fresh or fresh[entry["name"]]["version"] != entry["version"]:
            continue
        new = {r["id"]: r for r in fresh[entry["name"]]["cases"]}
        assert set(new) == {r["id"] for r in entry["cases"]}
        for row in entry["cases"]:
            scale = max(abs(Fraction(engines.short_decimal(x, 30))) for x in cases[row["id"]]["velocity"])
            for a, b in zip(row["engine_exit_velocity"], new[row["id"]]["engine_exit_velocity"]):
                assert abs(Fraction(a) - Fraction(b)) <= scale / 10**9, (entry["name"], row["id"])


def test_box2d_is_the_exact_sequential_law_of_its_own_settings(box2d_record: dict[str, Any]) -> None:
    """Box2D 2.3 at its defaults (8 velocity iterations, restitution above 1 m/s) leaves the 3-ball cradles at
    eps > 0 as the exact sequential law with those settings does, to float32 precision (1e-5 of the speed),
    recomputed here; the record's explanation says so, and its summary counts its rows."""
    from verify.laws.rule import solve
    from verify.laws.sequential import Sequential
    from verify.records.results import case_from_record

    (entry,) = box2d_record["engines"]
    rows = {r["id"]: r for r in entry["cases"]}
    cases = {c["id"]: c for c in box2d_record["cases"]}
    for eps in engines.GRID[1:]:
        cid = f"cradle-3-eps-{eps}"
        c = case_from_record(cases[cid])
        r = solve(c.system, c.velocity_source, law=Sequential(8, threshold=1))
        exact = [r.backend.to_number(x) for x in r.exit_velocity]
        got = [Fraction(x) for x in rows[cid]["engine_exit_velocity"]]
        assert max(abs(a - b) for a, b in zip(got, exact)) <= Fraction(100, 10**5), cid
        assert rows[cid]["model"] is not None and "8 sweeps" in rows[cid]["model"]
    summary = entry["explained"]
    assert summary["cases"] == len(entry["cases"])
    assert summary["explained"] == sum(1 for row in entry["cases"] if row["model"]) == sum(summary["models"].values())


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def sapien_record() -> dict[str, Any]:
    pytest.importorskip("sapien")
    done = verify_cli("engines", "--engine", "sapien", "--json", "--quiet")
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def test_sapien_runs_end_to_end_and_drops_restitution_under_its_threshold(sapien_record: dict[str, Any]) -> None:
    """SAPIEN (PhysX 5, in the `test` extra) end to end: it ran on the CPU, every row is explained or says
    why not, and PhysX's bounce threshold (2 m/s) shows: the 3-ball cradle with CORs 1 approached at 9/5
    leaves as the simultaneous law with CORs 0 does (recomputed here, to float32 precision), at 11/5 it
    bounces (far from that plastic answer)."""
    from verify.laws.rule import solve
    from verify.records.results import case_from_record

    (entry,) = sapien_record["engines"]
    assert entry["name"] == "sapien" and entry["solver"]["threshold"] == 2.0
    rows = {r["id"]: r for r in entry["cases"]}
    for row in entry["cases"]:
        assert row["model"] or row["why"]
    cases = {c["id"]: c for c in sapien_record["cases"]}

    def to_plastic(cid: str) -> Fraction:
        c = case_from_record(dict(cases[cid], restitution=["0", "0"]))
        r = solve(c.system, c.velocity_source, law="simultaneous")
        exact = [r.backend.to_number(x) for x in r.exit_velocity]
        got = [Fraction(x) for x in rows[cid]["engine_exit_velocity"]]
        return max(abs(a - b) for a, b in zip(got, exact)) / Fraction(cases[cid]["velocity"][0])

    assert to_plastic("slow-cradle-3-eps-1-v0-9/5") <= Fraction(1, 10**5)
    assert to_plastic("slow-cradle-3-eps-1-v0-11/5") > Fraction(1, 10)
    assert "threshold 2" in rows["slow-cradle-3-eps-1-v0-9/5"]["model"]  # a model with PhysX's threshold
