"""The command line: outputs, help, and one clear line with exit code 2 for every bad input."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from tests.helpers import cradle_case
from verify.cli import build_parser, main

GOOD_CASE = cradle_case("c", ["1", "1", "1"], ["1/2", "1/2"], ["100", "0", "0"])


def case_file(tmp_path, **change):
    case = dict(GOOD_CASE, id=f"{GOOD_CASE['id']}-changed")  # each case its own id
    case.update(change)
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [GOOD_CASE, case]}))
    return str(path)


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_cradle_text(capsys):
    code, out, err = run(["cradle", "--eps", "0.5"], capsys)
    assert code == 0 and err == ""
    assert "exit velocity (exact): 325/16, 375/16, 225/4" in out
    assert "iterations: 3; stop: exit" in out


def test_cradle_json_is_a_result_record(capsys):
    code, out, _ = run(["cradle", "--eps", "0.0743", "--mode", "paper", "--json"], capsys)
    rec = json.loads(out)
    assert code == 0
    assert rec["stop"] == "aeev" and rec["iterations"] == 17
    assert set(rec) >= {
        "id",
        "exit_velocity",
        "exit_velocity_decimal",
        "iterations",
        "impact_sets",
        "betas",
        "stop",
        "kinetic_energy_in",
        "kinetic_energy_out",
    }
    assert rec["impact_sets"][:3] == [[0], [1], [0]]
    assert len(rec["exit_velocity_decimal"][0].replace(".", "").lstrip("0")) >= 30


def test_cradle_double_hit_with_masses_and_per_contact_cors(capsys):
    code, out, _ = run(["cradle", "--eps", "1/2,1", "--masses", "1,2,1", "--velocity", "1,0,-1", "--json"], capsys)
    rec = json.loads(out)
    assert code == 0 and rec["impact_sets"][0] == [0, 1] and rec["betas"][0] is not None


def test_cradle_on_other_backends(capsys):
    for backend in ("mp", "interval", "float"):
        code, out, _ = run(["cradle", "--eps", "0.9", "--backend", backend, "--json"], capsys)
        rec = json.loads(out)
        assert code == 0 and rec["iterations"] == 3 and rec["rigorous"] == (backend == "interval")


def test_table1_text_and_json(capsys):
    code, out, _ = run(["table1"], capsys)
    assert code == 0 and "AEEV / 32" in out and "Identification of the AEEV stop" in out
    code, out, _ = run(["table1", "--json"], capsys)
    data = json.loads(out)
    assert len(data["rows"]) == 17 and data["rows"][0]["exact"]["exit_velocity"] == ["0", "0", "100"]


def test_solve(tmp_path, capsys):
    code, out, _ = run(["solve", case_file(tmp_path), "--json"], capsys)
    assert code == 0
    assert json.loads(out)["results"][1]["exit_velocity"] == ["325/16", "375/16", "225/4"]


BAD = [
    ("COR above 1", ["cradle", "--eps", "1.5"], "restitution[0] = 3/2 is outside [0, 1]"),
    ("COR below 0", ["cradle", "--eps", "-0.1"], "outside [0, 1]"),
    ("malformed number", ["cradle", "--eps", "0.5.1"], 'not a number: "0.5.1"'),
    ("division by zero", ["cradle", "--eps", "1/0"], 'not a number: "1/0"'),
    ("hostile string", ["cradle", "--eps", "__import__('os').system('id')"], "unknown name '__import__'"),
    ("infinity", ["cradle", "--eps", "0.5", "--v0", "inf"], 'not a number: "inf"'),
    ("zero mass", ["cradle", "--eps", "0.5", "--masses", "1,0,1"], "masses[1] = 0 must be positive"),
    ("wrong number of masses", ["cradle", "--eps", "0.5", "--balls", "3", "--masses", "1,1"], "--masses has 2"),
    ("wrong velocity length", ["cradle", "--eps", "0.5", "--balls", "4", "--velocity", "1,2"], "--velocity has 2"),
    ("too few balls", ["cradle", "--eps", "0.5", "--balls", "1"], "balls must be an integer >= 2"),
    ("too many CORs", ["cradle", "--eps", "0.5,0.5,0.5"], "expected 1 or 2 CORs"),
    ("empty list entry", ["cradle", "--eps", "0.5,"], "empty entry"),
    ("missing option", ["cradle"], "the following arguments are required: --eps"),
    ("unknown option", ["cradle", "--eps", "0.5", "--frobnicate"], "unrecognized arguments: --frobnicate"),
    ("unknown command", ["frobnicate"], "invalid choice: 'frobnicate'"),
    ("unknown backend", ["cradle", "--eps", "0.5", "--backend", "quantum"], "invalid choice: 'quantum'"),
    ("negative cap", ["cradle", "--eps", "0.5", "--max-impulses", "-1"], "--max-impulses must be >= 0"),
    ("tiny dps", ["cradle", "--eps", "0.5", "--backend", "mp", "--dps", "2"], "dps must be an integer >= 5"),
    ("non-integer option", ["cradle", "--eps", "0.5", "--balls", "three"], "--balls must be an integer, got 'three'"),
    ("no command", [], ""),
]


@pytest.mark.parametrize(("name", "argv", "message"), BAD, ids=[b[0] for b in BAD])
def test_bad_input_gets_one_line_and_exit_code_2(name, argv, message, capsys):
    code, out, err = run(argv, capsys)
    assert code == 2
    if argv:
        assert out == ""
        assert err.count("\n") == 1 and err.startswith("verify"), err
        assert message in err
        assert "Traceback" not in err


BAD_CASES = [
    (
        "not symmetric",
        dict(mass_matrix=[["1", "1", "0"], ["0", "1", "0"], ["0", "0", "1"]]),
        "cases[1].mass_matrix is not symmetric",
    ),
    (
        "not positive definite",
        dict(mass_matrix=[["1", "2", "0"], ["2", "1", "0"], ["0", "0", "1"]]),
        "cases[1].mass_matrix is not positive definite",
    ),
    ("dependent normals", dict(normals=[["-1", "1", "0"], ["1", "-1", "0"]]), "cases[1].normals are dependent"),
    ("wrong vector length", dict(velocity=["1", "0"]), "cases[1].velocity: expected 3 numbers, got 2"),
    (
        "malformed number",
        dict(normals=[["-1", "1", "0"], ["0", "1/0", "1"]]),
        'cases[1].normals[1][1]: not a number: "1/0"',
    ),
    ("bare float", dict(restitution=[0.5, "1"]), "cases[1].restitution[0]: expected a string, got the bare number 0.5"),
    ("COR outside", dict(restitution=["2", "1"]), "cases[1].restitution[0] = 2 is outside [0, 1]"),
    ("unknown field", dict(colour="red"), "cases[1]: unknown field 'colour'"),
]


@pytest.mark.parametrize(("name", "change", "message"), BAD_CASES, ids=[b[0] for b in BAD_CASES])
def test_bad_case_files_get_one_line_and_exit_code_2(name, change, message, tmp_path, capsys):
    code, out, err = run(["solve", case_file(tmp_path, **change)], capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and message in err, err


def test_unreadable_and_invalid_files(tmp_path, capsys):
    code, _, err = run(["solve", str(tmp_path / "missing.json")], capsys)
    assert code == 2 and "cannot read" in err
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    code, _, err = run(["solve", str(bad)], capsys)
    assert code == 2 and "not valid JSON" in err


def test_every_subcommand_has_help_with_an_example():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, p in sub.choices.items():
        assert "example" in p.format_help(), name


def test_python_dash_m_verify_help():
    out = subprocess.run([sys.executable, "-m", "verify", "--help"], capture_output=True, text=True, check=True)
    assert "cradle" in out.stdout and "table1" in out.stdout


def test_the_command_line_names_its_flag_where_the_library_names_its_parameter(capsys):
    assert main(["cradle", "--eps", "1/2", "--masses", "1,tan(1),1"]) == 2
    err = capsys.readouterr().err
    assert "--backend interval" in err and 'backend="' not in err


# -- one name for the velocity where a run stops (issue 34, item 16) ------------------------------


def test_a_run_that_does_not_exit_prints_the_velocity_at_the_stop_everywhere(tmp_path, capsys):
    """``verify solve`` (proved never to exit, and at a cap), ``verify cradle`` and ``Result.summary``
    give the velocity where a run stopped one name, "exit velocity" only for an exit."""
    from verify.dynamics.system import System
    from verify.laws.rule import solve

    never = cradle_case("never", ["1", "1", "1"], ["1/100", "1/100"], ["1", "0", "0"])
    capped = {**cradle_case("capped", ["1", "1", "1"], ["1/2", "1/2"], ["1", "0", "0"]), "max_iterations": 1}
    exits = cradle_case("exits", ["1", "1", "1"], ["1/2", "1/2"], ["1", "0", "0"])
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [never, capped, exits]}))
    code, out, err = run(["solve", str(path)], capsys)
    assert code == 0, err
    blocks = out.split("\n  kinetic energy")
    assert blocks[0].startswith("never: never exits (infinitely many impulses; proved after 0 impulses)")
    assert "\n  velocity when proved never to exit: 1, 0, 0\n" in blocks[0] and "-> " not in blocks[0]
    assert "capped: max_iterations" in blocks[1] and "\n  velocity at the stop: " in blocks[1]
    assert "exits: exit" in blocks[2] and "\n  exit velocity: " in blocks[2]
    assert "exit velocity" not in blocks[0] + blocks[1]
    code, out, _ = run(["cradle", "--eps", "0.01"], capsys)
    assert "velocity when proved never to exit (exact): 100, 0, 0" in out and "exit velocity" not in out
    assert "kinetic energy: 5000 in, 5000 when proved never to exit" in out and "iterations: never end" in out
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/100", "1/100"])
    summary = solve(s, ["1", "0", "0"]).summary()
    assert "\n  velocity when proved never to exit: x1 = 1, x2 = 0, x3 = 0" in summary, summary
    assert "last velocity" not in summary and "exit velocity" not in summary
    capped_summary = solve(s, ["1", "0", "0"], max_iterations=0, certify=False).summary()
    assert "velocity at the stop" in capped_summary
