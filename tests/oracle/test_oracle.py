"""The reference oracle: golden dataset, checker, an implementation plugged in, safe input."""

from __future__ import annotations

import contextlib
import copy
import json
import re
import string
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from verify.cli import main
from verify.errors import InvalidInput
from verify.oracle import reference as oracle
from verify.properties import formulas
from verify.records.results import load_cases

GOLDEN = Path(__file__).resolve().parents[2] / "golden"
FLOAT_IMPL = Path(__file__).resolve().parents[2] / "examples" / "float_impl.py"


def test_golden_dataset_regenerates_byte_identically(tmp_path: Path) -> None:
    oracle.export(str(tmp_path))
    for name in ("cases.json", "results.json", "README.md"):
        assert (tmp_path / name).read_bytes() == (GOLDEN / name).read_bytes(), f"golden/{name} is stale"
    assert not list(tmp_path.glob("*.tmp"))


def test_golden_dataset_covers_what_it_promises() -> None:
    cases = json.loads((GOLDEN / "cases.json").read_text())["cases"]
    results = json.loads((GOLDEN / "results.json").read_text())["results"]
    assert [c["id"] for c in cases] == [r["id"] for r in results]
    assert len({c["id"] for c in cases}) == len(cases)
    assert any(len(c["normals"]) >= 3 and any(len(J) > 1 for J in r["impact_sets"]) for c, r in zip(cases, results))
    assert any(any(t != "0" for t in c["time_terms"]) for c in cases)  # moving constraints
    assert any("sqrt" in x for c in cases for x in c["normals"][0])  # algebraic angles
    assert {"0", "1"} <= {e for c in cases for e in c["restitution"]}
    assert sum(r["stop"] == "non_terminating" for r in results) >= 5
    assert all("certificate" in r for r in results if r["stop"] == "non_terminating")
    assert all(len(r["exit_velocity_decimal"]) == len(r["exit_velocity"]) for r in results)
    grazing = [c for c in cases for a, t in zip(c["normals"], c["time_terms"]) if _rate(a, t, c["velocity"]) == 0]
    assert grazing, "no case with p(F_i) = 0"


def _rate(a, t, v):
    """p(F) of a case's constraint, or None when an entry is irrational."""
    from fractions import Fraction

    from verify.numbers.parse import parse_number, to_number

    values = [to_number(parse_number(x)) for x in (*a, t, *v)]
    if not all(isinstance(x, Fraction) for x in values):
        return None
    n = len(a)
    return formulas.rate(values[:n], values[n], values[n + 1 :])


def test_the_golden_results_agree_with_themselves(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["oracle", "check", str(GOLDEN / "cases.json"), str(GOLDEN / "results.json")]) == 0
    assert "OK: every case agrees" in capsys.readouterr().out


def _damaged(tmp_path: Path, change) -> Path:
    data = json.loads((GOLDEN / "results.json").read_text())
    change(data["results"])
    path = tmp_path / "results.json"
    path.write_text(json.dumps(data))
    return path


def _last_digit_changed(results: list) -> None:
    """One digit of a decimal changed, far above the tolerance 1e-9 * |v0| = 1e-7."""
    r = next(r for r in results if r["id"] == "paper-table1-eps-0.5")
    text = r["exit_velocity_decimal"][2]  # 56.25 for eps = 1/2
    r["exit_velocity"][2] = text[:3] + str((int(text[3]) + 1) % 10) + text[4:]


@pytest.mark.parametrize(
    ("what", "change", "expected"),
    [
        ("a wrong digit", _last_digit_changed, [("paper-table1-eps-0.5", "exit_velocity[2]")]),
        ("a missing case", lambda rs: rs.pop(3), [("paper-table1-eps-0.8", "missing")]),
        (
            "a wrong impact set",
            lambda rs: rs[1]["impact_sets"].__setitem__(0, [1]),
            [("paper-table1-eps-0.99", "impact_sets")],
        ),
        ("a wrong stop", lambda rs: rs[0].__setitem__("stop", "budget"), [("paper-table1-eps-1", "stop")]),
        ("a wrong count", lambda rs: rs[2].__setitem__("iterations", 4), [("paper-table1-eps-0.9", "iterations")]),
        (
            "a result for no case",
            lambda rs: rs.append(dict(copy.deepcopy(rs[0]), id="nobody")),
            [("nobody", "id")],
        ),
    ],
)
def test_each_kind_of_error_is_reported_as_exactly_that(tmp_path, capsys, what, change, expected) -> None:
    path = _damaged(tmp_path, change)
    assert main(["oracle", "check", str(GOLDEN / "cases.json"), str(path), "--json"]) == 1, what
    found = json.loads(capsys.readouterr().out)["mismatches"]
    assert [(m["id"], m["field"]) for m in found] == expected, what


def test_every_mismatch_is_printed_with_a_summary(tmp_path, capsys) -> None:
    def several(rs):
        rs[0]["stop"] = "budget"
        rs[5]["impact_sets"][0] = [1]
        rs.pop(8)

    assert main(["oracle", "check", str(GOLDEN / "cases.json"), str(_damaged(tmp_path, several))]) == 1
    out = capsys.readouterr().out
    assert "3 mismatches" in out and "cases checked        49" in out
    # each named: as a MISMATCH, or under the class its grade gives (WRONG_STOP, ...); no line said twice
    said = [line for line in out.splitlines() if re.match(r"^[A-Z_]+ \S+: ", line)]
    assert len({line.split(":")[0].split(" ")[1] for line in said}) == 3 and len(set(said)) == len(said), said


def test_a_float_implementation_passes_except_where_it_takes_another_branch(capsys) -> None:
    command = f"{sys.executable} {FLOAT_IMPL}"
    code = main(["oracle", "check", str(GOLDEN / "cases.json"), "--impl", command, "--rtol", "1e-9", "--json"])
    found = json.loads(capsys.readouterr().out)["mismatches"]
    results = json.loads((GOLDEN / "results.json").read_text())["results"]
    never = {r["id"] for r in results if r["stop"] == "non_terminating"}
    assert code == 1
    assert {m["id"] for m in found} == never  # named: the runs that never exit, which it ends by tolerance
    assert {m["field"] for m in found} == {"stop"}


@pytest.mark.parametrize(
    ("command", "message"),
    [
        ("no-such-program-xyz", "command not found"),
        (f"{sys.executable} -c 'import sys; sys.exit(3)'", "exited with code 3"),
        (f"{sys.executable} -c 'print(1)'", "expected an object"),
        (f"{sys.executable} -c 'import time; time.sleep(5)'", "did not finish within 0.5 s"),
    ],
)
def test_impl_failures_are_one_line_errors(capsys, command, message) -> None:
    args = ["oracle", "check", str(GOLDEN / "cases.json"), "--impl", command, "--impl-time-limit", "0.5"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


@pytest.mark.parametrize(
    ("results", "message"),
    [
        ('{"results": [{"id": "a", "exit_velocity": [0.5], "iterations": 1, "impact_sets": [], "stop": "exit"}]}',
         "results[0].exit_velocity[0]: expected a string, got the bare number 0.5"),
        ('{"results": [{"id": "a", "exit_velocity": [], "iterations": 1, "impact_sets": [], "stop": "done"}]}',
         'results[0].stop: "done" is not one of'),
        ('{"results": [{"id": "a", "exit_velocity": [], "iterations": -1, "impact_sets": [], "stop": "exit"}]}',
         "results[0].iterations"),
        ('{"results": [{"exit_velocity": [], "iterations": 1, "impact_sets": [], "stop": "exit"}]}',
         "results[0]: missing field 'id'"),
        ("[1, 2", "not valid JSON"),
    ],
)  # fmt: skip
def test_bad_result_files_name_the_field(tmp_path, capsys, results, message) -> None:
    path = tmp_path / "r.json"
    path.write_text(results)
    assert main(["oracle", "check", str(GOLDEN / "cases.json"), str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err


def test_hostile_number_in_a_case_file_runs_nothing(tmp_path, capsys) -> None:
    marker = tmp_path / "pwned"
    case = {"id": "evil", "mass_matrix": [["1"]], "normals": [["1"]], "restitution": ["1"],
            "velocity": [f"__import__('os').system('touch {marker}')"]}  # fmt: skip
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [case]}))
    assert main(["solve", str(path)]) == 2
    err = capsys.readouterr().err
    assert "cases[0].velocity[0]: not a number" in err and "unknown name '__import__'" in err
    assert not marker.exists()


def test_export_refuses_a_file_as_folder(tmp_path, capsys) -> None:
    target = tmp_path / "file"
    target.write_text("keep me")
    assert main(["oracle", "export", str(target)]) == 2
    assert target.read_text() == "keep me"


# -- fuzzing the loaders: never a traceback, never a hang ----------------------------------------


def _load_bytes(tmp_path: Path, data: bytes) -> None:
    path = tmp_path / "fuzz.json"
    path.write_bytes(data)
    with contextlib.suppress(InvalidInput):
        load_cases(str(path))


@settings(deadline=2000, max_examples=200)
@given(st.binary(max_size=400))
def test_loader_fuzz_random_bytes(tmp_path_factory, data: bytes) -> None:
    _load_bytes(tmp_path_factory.mktemp("fuzz"), data)


_JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(string.printable, max_size=12),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
    max_leaves=20,
)
_FIELDS = ["id", "mass_matrix", "normals", "time_terms", "restitution", "velocity", "max_iterations"]
_HOSTILE = st.sampled_from(
    ["__import__('os')", "1/0", "9**9**9**9", "(" * 500 + "1" + ")" * 500, "sqrt(-1)", "x", "CRootOf(x, 9)", "1e999999",
     "lambda: 1", "[1]", "'a'", "1" * 5000, "tan(pi/2)", "0.1", "-", "", " ", "nan", "inf"]
)  # fmt: skip


@settings(deadline=5000, max_examples=200)
@given(st.dictionaries(st.sampled_from(_FIELDS), _JSON | st.lists(st.lists(_HOSTILE, max_size=3), max_size=3)))
def test_loader_fuzz_random_case_records(tmp_path_factory, record) -> None:
    data = json.dumps({"cases": [record]}).encode()
    _load_bytes(tmp_path_factory.mktemp("fuzz"), data)


@settings(deadline=5000, max_examples=100)
@given(_HOSTILE, st.integers(0, 3))
def test_hostile_strings_in_every_field(tmp_path_factory, text, where) -> None:
    case = {"id": "h", "mass_matrix": [["1", "0"], ["0", "1"]], "normals": [["1", "0"]], "restitution": ["1"],
            "velocity": ["-1", "0"]}  # fmt: skip
    spot = [("mass_matrix", 0, 0), ("normals", 0, 1), ("restitution", 0, None), ("velocity", 1, None)][where]
    if spot[2] is None:
        case[spot[0]][spot[1]] = text
    else:
        case[spot[0]][spot[1]][spot[2]] = text
    _load_bytes(tmp_path_factory.mktemp("fuzz"), json.dumps({"cases": [case]}).encode())


def test_deep_nesting_is_refused_quickly(tmp_path) -> None:
    path = tmp_path / "deep.json"
    path.write_text('{"cases": ' + "[" * 100_000 + "]" * 100_000 + "}")
    with pytest.raises(InvalidInput):
        load_cases(str(path))


def test_the_docs_show_what_the_worked_example_prints(capsys) -> None:
    page = (GOLDEN.parent / "docs" / "oracle.md").read_text()
    worked = page[page.index("### Worked example: a float implementation") :]
    worked = worked[: worked.index("\n### ", 1)]
    shown = [line for line in worked.splitlines() if line.startswith("WRONG_STOP ")]
    assert len(shown) == 7, "the guard: the worked example shows its mismatches"
    main(["oracle", "check", str(GOLDEN / "cases.json"), "--impl", f"{sys.executable} {FLOAT_IMPL}"])
    printed = [line for line in capsys.readouterr().out.splitlines() if line.startswith("WRONG_STOP ")]
    assert shown == printed


def test_oversized_result_files_are_refused(monkeypatch) -> None:
    import verify.records.files

    monkeypatch.setattr(verify.records.files, "MAX_FILE_BYTES", 100)
    with pytest.raises(InvalidInput, match="larger than 100 bytes"):
        oracle.load_results(" " * 101, "big.json")
