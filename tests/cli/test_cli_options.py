"""Every numeric and output-path option of the command line, found by walking the parser itself.

A new option with one of the checked types (verify.cli.common.BoundedInt, Seconds, NonNegativeRational,
ExactNumber, OutputDir, OutputFile) is covered here without editing this file; an option typed
with a bare ``int`` or ``float`` (whose range nothing checks) fails the walk. Then: the budget
options of ``verify solve`` and ``verify oracle check`` (--max-impulses, --max-bits,
--case-time-limit), the status line on a terminal, and a failing case named in the error.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import sys
from pathlib import Path

import pytest

from tests.helpers import cradle_case
from verify.cli import build_parser, checks, main, maps, paper, reports, run
from verify.cli.common import (
    BoundedInt,
    ExactNumber,
    IntList,
    NonNegativeRational,
    OutputDir,
    OutputFile,
    RationalList,
    Seconds,
    UsageError,
    write_output,
)

ROOT = Path(__file__).resolve().parents[2]

#: arguments that make each (sub)command otherwise valid at parse time
REQUIRED = {
    ("cradle",): {"--eps": "0.5"},
    ("solve",): {"CASES.json": "cases.json"},
    ("map",): {"CASE.json": "case.json"},
    ("corner",): {"--alpha": "pi/6", "--phi": "0", "--eps1": "0.5", "--eps2": "0.5"},
    ("oracle", "check"): {"CASES.json": "cases.json", "RESULTS.json": "results.json"},
    ("oracle", "explain"): {"CASES.json": "cases.json", "RESULTS.json": "results.json"},
    ("oracle", "export"): {"DIR": "golden-out"},
    ("oracle", "table"): {"CASES.json": "cases.json", "RESULTS.json": "results.json"},
}
NUMERIC = (BoundedInt, Seconds, NonNegativeRational, ExactNumber, IntList, RationalList)
PATHS = (OutputDir, OutputFile)


def commands(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()):
    """Every leaf (sub)command as (its words, its parser)."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield prefix, parser
    for sub in subs:
        for name, p in sub.choices.items():
            yield from commands(p, (*prefix, name))


def options(kinds: tuple[type, ...]):
    """(command words, parser, action, the option's name) for every action whose type is one of ``kinds``."""
    out = []
    for words, p in commands(build_parser()):
        for action in p._actions:
            if isinstance(action.type, kinds):
                out.append((words, p, action, key(action)))
    return out


def key(action: argparse.Action) -> str:
    return action.option_strings[0] if action.option_strings else action.metavar


def argv_for(words, parser, action, value) -> list[str]:
    """A command line that is valid but for ``value`` given to ``action``."""
    given = dict(REQUIRED.get(words, {}))
    for group in parser._mutually_exclusive_groups:  # --slope replaces --alpha
        if action in group._group_actions:
            for other in group._group_actions:
                given.pop(key(other), None)
    given[key(action)] = value
    argv = list(words)
    for a in parser._actions:  # positionals in their order
        if key(a) in given:
            # the = form: a value such as -inf is not taken for an option
            argv.append(f"{key(a)}={given[key(a)]}" if a.option_strings else given[key(a)])
    return argv


NUMERIC_OPTIONS = [(w, n) for w, _, _, n in options(NUMERIC)]
PATH_OPTIONS = [(w, n) for w, _, _, n in options(PATHS)]


def bad_values(kind) -> list[str]:
    if isinstance(kind, BoundedInt):
        values = ["abc", "nan", "inf", "1e400", "1.5", "0x10", "", str(kind.lo - 1), str(kind.hi + 1), "9" * 100,
                  "-" + "9" * 100, "-1"]  # fmt: skip
        return values + (["0"] if kind.lo > 0 else [])
    if isinstance(kind, Seconds):
        return ["abc", "nan", "inf", "-inf", "1e400", "0", "-1", str(kind.hi + 1), "pi", "1/0", ""]
    if isinstance(kind, NonNegativeRational):
        return ["abc", "nan", "inf", "-1", "-1e-9", "pi", "1/0", ""]
    if isinstance(kind, IntList):
        return ["abc", "1,,2", "0", str(kind.hi + 1), "3-1", "1.5", "1-" + "9" * 100, "nan", ""]
    if isinstance(kind, RationalList):
        return ["abc", "1,,2", "-1", "nan", "inf", "1/0", "pi", ""]
    assert isinstance(kind, ExactNumber)
    return ["abc", "nan", "inf", "1/0", "", "__import__('os')", "2**100000"]


@pytest.fixture
def no_command_runs(monkeypatch, tmp_path):
    """Parse only: a command that would run fails the test (a bad value slipped through)."""
    for group in (checks, maps, paper, reports, run):
        for name in dir(group):
            if name.startswith("cmd_"):
                monkeypatch.setattr(group, name, lambda args, name=name: pytest.fail(f"{name} ran: {args}"))
    monkeypatch.chdir(tmp_path)  # default output folders (reports) are checked here


def test_no_option_is_a_bare_int_or_float():
    for words, p in commands(build_parser()):
        for action in p._actions:
            assert action.type not in (int, float), f"verify {' '.join(words)} {action.option_strings}: use BoundedInt"


def test_the_walk_finds_the_options():
    names = {(" ".join(w), n) for w, _, _, n in options(NUMERIC + PATHS)}
    expected = [
        ("cradle", "--dps"), ("solve", "--max-impulses"), ("solve", "--max-bits"), ("solve", "--case-time-limit"),
        ("oracle check", "--impl-time-limit"), ("oracle check", "--case-time-limit"), ("cradle-map", "--approach"),
        ("sweep", "--seed"), ("bench", "--size"), ("table1", "--max-impulses"), ("properties", "--workers"),
        ("cradle", "--v0"), ("oracle check", "--rtol"), ("report", "--out"), ("oracle export", "DIR"),
        ("bench", "--save"), ("cradle-map", "--figure"), ("corner-claims", "--figures"),
        ("properties", "--counterexamples"), ("all", "--out"),
    ]  # fmt: skip
    assert set(expected) <= names, set(expected) - names


@pytest.mark.parametrize(("words", "name"), NUMERIC_OPTIONS, ids=[f"{' '.join(w)} {n}" for w, n in NUMERIC_OPTIONS])
def test_every_numeric_option_rejects_bad_values(words, name, no_command_runs, capsys):
    (found,) = [(p, a) for w, p, a, n in options(NUMERIC) if w == words and n == name]
    parser, action = found
    for value in bad_values(action.type):
        code = main(argv_for(words, parser, action, value))
        out, err = capsys.readouterr()
        assert code == 2, (name, value)
        assert out == "" and err.count("\n") == 1 and err.startswith("verify: error: "), (name, value, err)
        assert name in err and value in err, (name, value, err)
        assert "Traceback" not in err


@pytest.mark.parametrize(("words", "name"), NUMERIC_OPTIONS, ids=[f"{' '.join(w)} {n}" for w, n in NUMERIC_OPTIONS])
def test_every_numeric_option_accepts_its_range(words, name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (found,) = [(p, a) for w, p, a, n in options(NUMERIC) if w == words and n == name]
    parser, action = found
    kind = action.type
    good = {BoundedInt: [str(kind.lo), str(kind.hi)] if isinstance(kind, BoundedInt) else [],
            Seconds: ["1", "0.5", "1/4", str(getattr(kind, "hi", 1))], NonNegativeRational: ["0", "1e-9"],
            ExactNumber: ["1/2", "pi/6"], IntList: ["1", "1-20,25"],
            RationalList: ["0", "0,1/2,1e-3"]}[type(kind)]  # fmt: skip
    for value in good:
        args = build_parser().parse_args(argv_for(words, parser, action, value))
        assert getattr(args, action.dest) == kind(value)


def test_dps_zero_is_an_error_not_50(capsys):
    assert main(["cradle", "--eps", "0.5", "--backend", "mp", "--dps", "0"]) == 2
    err = capsys.readouterr().err
    assert err == "verify: error: verify cradle: --dps must be an integer >= 5, got '0'\n"


# -- output paths ---------------------------------------------------------------------------------


def impossible_paths(tmp_path: Path, kind) -> list[str]:
    a_file = tmp_path / "a-file"
    a_file.write_text("x")
    name = "x.png" if isinstance(kind, OutputFile) and kind.suffixes else "x"
    paths = [str(a_file / "sub" / name)]  # under a file
    if sys.platform.startswith("linux") and os.path.isdir("/proc/self"):
        paths.append(f"/proc/verify-no-such-{os.getpid()}/{name}")  # a folder nobody can create, root included
    folder = tmp_path / ("a-folder" + (kind.suffixes[0] if isinstance(kind, OutputFile) and kind.suffixes else ""))
    folder.mkdir(exist_ok=True)
    paths.append(str(folder) if isinstance(kind, OutputFile) else str(a_file))  # the wrong kind
    return paths


def tree(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


@pytest.mark.parametrize(("words", "name"), PATH_OPTIONS, ids=[f"{' '.join(w)} {n}" for w, n in PATH_OPTIONS])
def test_every_output_path_option_rejects_an_impossible_path(words, name, tmp_path, no_command_runs, capsys):
    (found,) = [(p, a) for w, p, a, n in options(PATHS) if w == words and n == name]
    parser, action = found
    work = tmp_path / "work"
    work.mkdir()
    for value in impossible_paths(work, action.type):
        before = tree(tmp_path)
        code = main(argv_for(words, parser, action, value))
        out, err = capsys.readouterr()
        assert code == 2, (name, value)
        assert out == "" and err.count("\n") == 1 and name in err and value in err, err
        assert "Traceback" not in err
        assert tree(tmp_path) == before  # nothing written, not even a probe file
    assert not os.path.exists(f"/proc/verify-no-such-{os.getpid()}")


def test_output_paths_are_checked_without_creating_anything(tmp_path):
    """A folder option may name a folder to create (it is made when written); a file option needs its folder:
    no folder is created that the user did not ask for (issue 60)."""
    target = tmp_path / "new" / "deeper"
    assert OutputDir()(str(target)) == str(target)
    with pytest.raises(argparse.ArgumentTypeError, match="must be a file in a folder that exists"):
        OutputFile((".png",))(str(target / "map.png"))
    assert OutputFile((".png",))(str(tmp_path / "map.png")) == str(tmp_path / "map.png")
    assert tree(tmp_path) == []


def test_a_failed_export_leaves_no_temporary_file(tmp_path, monkeypatch, capsys):
    from verify.oracle import reference as oracle

    case = {"id": "c", "mass_matrix": [["1", "0"], ["0", "1"]], "normals": [["-1", "1"]], "time_terms": ["0"],
            "restitution": ["1/2"], "velocity": ["1", "0"], "max_iterations": 10}  # fmt: skip
    monkeypatch.setattr(oracle, "golden_dataset", lambda: ([case], 0))
    folder = tmp_path / "golden"
    (folder / "results.json.tmp").mkdir(parents=True)  # the second file cannot be written
    assert main(["oracle", "export", str(folder)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "results.json.tmp" in err and "DIR" in err
    assert sorted(os.listdir(folder)) == ["results.json.tmp"]  # cases.json.tmp was removed, nothing renamed


def test_a_failed_report_leaves_no_temporary_file(tmp_path, monkeypatch, capsys):
    from verify.report import pages as report

    monkeypatch.setattr(report, "PAGES", [("table1.md", lambda out, ctx: "# page\n")])
    monkeypatch.setattr(report, "index_page", lambda found: "# index\n")  # not the findings of the real pages
    out_dir = tmp_path / "reports"
    (out_dir / "README.md.tmp").mkdir(parents=True)
    assert main(["report", "--out", str(out_dir)]) == 2
    out, err = capsys.readouterr()
    *progress, last = err.splitlines()
    assert out == "" and progress == ["[report 1/1] Table 1: printed, exact and paper mode, every entry checked ..."]
    assert last.startswith("verify: error: --out ") and "README.md.tmp" in last
    assert sorted(os.listdir(out_dir)) == ["README.md.tmp"]  # table1.md.tmp was removed, nothing renamed


def test_write_file_leaves_nothing_on_failure(tmp_path):
    (tmp_path / "bench.json.tmp").mkdir()
    with pytest.raises(UsageError, match=r"--save .*bench\.json\.tmp"):
        write_output(str(tmp_path / "bench.json"), "{}\n", "--save")
    assert tree(tmp_path) == ["bench.json.tmp"]


# -- budgets, progress, failing cases ---------------------------------------------------------------

#: the newcomer's case: a 4-ball cradle, masses 1..4, small CORs; exact numbers grow ~17 bits per impulse
# a long run that no certificate ends: three unit balls just above the termination boundary 7 - 4*sqrt(3)
# (four balls of masses 1, 2, 3, 4 are now proved never to exit by a cone of a period)
CRADLE_4 = cradle_case("cradle-near-boundary", ["1", "1", "1"], ["0.0718", "0.0718"], ["1", "0", "0"])
SMALL = cradle_case("small", ["1", "1", "1"], ["1/3", "1/7"], ["100", "0", "0"])


def case_file(tmp_path: Path, *cases: dict, name: str = "cases.json") -> str:
    path = tmp_path / name
    path.write_text(json.dumps({"cases": list(cases)}))
    return str(path)


def solve_json(argv, capsys) -> list[dict]:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)["results"]


def test_solve_progress_hook_counts_every_impulse():
    from verify.laws.rule import solve
    from verify.records.results import case_from_record

    c = case_from_record(SMALL)
    calls: list[int] = []
    r = solve(c.system, c.velocity_source, trace=False, certify=False, progress=calls.append)
    assert calls == list(range(1, r.iterations + 1)) and r.iterations > 2


def test_solve_max_iterations_overrides_the_cases_cap(tmp_path, capsys):
    path = case_file(tmp_path, dict(SMALL, max_iterations=50), dict(SMALL, id="small-2"))
    (a, b) = solve_json(["solve", path, "--json", "--max-impulses", "1"], capsys)
    assert (a["stop"], a["iterations"]) == (b["stop"], b["iterations"]) == ("max_iterations", 1)
    (a, b) = solve_json(["solve", path, "--json"], capsys)
    assert a["stop"] == b["stop"] == "exit"


def test_solve_max_bits_ends_a_long_run_with_stop_budget(tmp_path, capsys):
    (r,) = solve_json(["solve", case_file(tmp_path, CRADLE_4), "--json", "--max-bits", "3000"], capsys)
    assert r["stop"] == "budget" and 100 < r["iterations"] < 400  # the default cap would take minutes
    (r,) = solve_json(["solve", case_file(tmp_path, SMALL), "--json", "--max-bits", "10"], capsys)
    assert (r["stop"], r["iterations"]) == ("budget", 2)  # as verify.laws.rule.Budget's doctest


def test_solve_case_timeout_ends_a_long_run_with_stop_budget(tmp_path, capsys):
    (r,) = solve_json(["solve", case_file(tmp_path, CRADLE_4), "--json", "--case-time-limit", "1/100"], capsys)
    assert r["stop"] == "budget" and r["iterations"] < 10_000


class FakeTerminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_status_line_on_a_terminal_only(tmp_path, monkeypatch, capsys):
    path = case_file(tmp_path, SMALL, dict(SMALL, id="second"))
    assert main(["solve", path]) == 0
    assert capsys.readouterr().err == ""  # not a terminal: nothing
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.delenv("TERM", raising=False)
    assert main(["solve", path]) == 0
    shown = terminal.getvalue()
    assert "\r\x1b[Kverify solve: case 1/2 small: starting" in shown
    assert "\r\x1b[Kverify solve: case 2/2 second: starting" in shown
    assert shown.endswith("\r\x1b[K")  # cleared at the end
    assert "small: exit after" in capsys.readouterr().out  # the results are unchanged
    terminal.seek(0)
    terminal.truncate()
    assert main(["solve", path, "--quiet"]) == 0
    assert terminal.getvalue() == ""


def test_status_line_counts_impulses(tmp_path, monkeypatch):
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.delenv("TERM", raising=False)
    clock = iter(range(0, 10**6))  # each reading of the clock one second later: every update is shown
    monkeypatch.setattr("time.monotonic", lambda: float(next(clock)))
    assert main(["solve", case_file(tmp_path, SMALL), "--max-impulses", "2"]) == 0
    assert "case 1/1 small: 1 impulse" in terminal.getvalue()
    assert "case 1/1 small: 2 impulses" in terminal.getvalue()


def test_a_failing_case_is_named(tmp_path, monkeypatch, capsys):
    from verify.errors import NoConvergence
    from verify.laws import rule

    real = rule.solve

    def solve(system, velocity, **kw):
        if system.n == 4:
            raise NoConvergence("interval, 3200 digits: a sign stayed undecided at the precision limit")
        return real(system, velocity, **kw)

    monkeypatch.setattr(rule, "solve", solve)
    four = cradle_case("cradle-4-masses-1234", ["1", "2", "3", "4"], ["0.01", "0.02", "0.03"], ["1", "0", "0", "0"])
    path = case_file(tmp_path, SMALL, four)
    assert main(["solve", path, "--backend", "interval"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert "case 'cradle-4-masses-1234' (cases[1]): interval, 3200 digits: a sign stayed undecided" in err


def test_a_rule_that_does_not_apply_names_the_case(tmp_path, capsys):
    path = case_file(tmp_path, SMALL, dict(SMALL, id="unequal"))
    assert main(["solve", path, "--rule", "symmetric"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "case 'small' (cases[0]): the symmetric rule (6)" in err


def test_ctrl_c_is_one_line(monkeypatch, capsys):
    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(paper, "cmd_table1", interrupted)
    assert main(["table1"]) == 130
    assert capsys.readouterr().err == "verify: interrupted\n"


def test_an_internal_error_is_one_line_with_its_own_exit_code(monkeypatch, capsys):
    """A bug in verify is neither a mismatch (1) nor bad input (2): exit code 3, one line, the traceback only
    with --debug or VERIFY_DEBUG."""

    def broken(args):
        raise ZeroDivisionError("a bug\nover two lines")

    monkeypatch.setattr(paper, "cmd_table1", broken)
    monkeypatch.delenv("VERIFY_DEBUG", raising=False)
    assert main(["table1"]) == 3
    err = capsys.readouterr().err
    assert err.startswith("verify: internal error (ZeroDivisionError: a bug over two lines): a bug in verify")
    assert err.count("\n") == 1 and "Traceback" not in err and "--debug" in err
    for argv, env in ((["--debug", "table1"], None), (["table1"], "1")):
        if env:
            monkeypatch.setenv("VERIFY_DEBUG", env)
        assert main(argv) == 3
        err = capsys.readouterr().err
        assert "Traceback" in err and "in broken" in err and err.endswith("please report it\n")


# -- oracle check with a budget -----------------------------------------------------------------------


def their_results(tmp_path: Path, records: list[dict], edit) -> str:
    from verify.oracle.reference import golden_results

    results = golden_results(records)
    for r in results:
        edit(r)
    path = tmp_path / "theirs.json"
    path.write_text(json.dumps({"results": results}))
    return str(path)


def test_oracle_check_with_a_budget_checks_the_impulses_it_made(tmp_path, capsys):
    from verify.laws.rule import Budget
    from verify.oracle.reference import golden_results

    records = [dict(CRADLE_4, max_iterations=400)]
    cases = case_file(tmp_path, dict(CRADLE_4))
    made = golden_results(records, budget=Budget(bits=3000))[0]["iterations"]
    assert 100 < made < 400

    def exits_after(n):
        def edit(r):
            r.update(stop="exit", iterations=n, impact_sets=r["impact_sets"][:n], betas=r["betas"][:n])

        return edit

    agrees = their_results(tmp_path, records, exits_after(400))  # goes on past the budget: not refuted
    assert main(["oracle", "check", cases, agrees, "--max-bits", "3000"]) == 0
    out = capsys.readouterr().out
    assert "OK: every case agrees" in out and "note: 1 case checked only on the impulses" in out
    assert main(["oracle", "check", cases, agrees, "--max-bits", "3000", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["limited_by_budget"] == ["cradle-near-boundary"]

    early = their_results(tmp_path, records, exits_after(100))  # exits while the exact run still impacts
    assert main(["oracle", "check", cases, early, "--max-bits", "3000"]) == 1
    assert f"expected more than {made} impulses" in capsys.readouterr().out

    def wrong_set(r):
        exits_after(400)(r)
        r["impact_sets"][4] = [3] if r["impact_sets"][4] != [3] else [0]

    wrong = their_results(tmp_path, records, wrong_set)
    assert main(["oracle", "check", cases, wrong, "--max-bits", "3000"]) == 1
    assert "impact_sets: from impulse 5" in capsys.readouterr().out


def test_oracle_check_status_line_on_a_terminal(tmp_path, monkeypatch, capsys):
    cases = case_file(tmp_path, SMALL)
    theirs = their_results(tmp_path, [SMALL], lambda r: None)
    terminal = FakeTerminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    monkeypatch.delenv("TERM", raising=False)
    assert main(["oracle", "check", cases, theirs]) == 0
    assert "\r\x1b[Kverify oracle check: exact results, case 1/1 small: 0 impulses" in terminal.getvalue()
    assert terminal.getvalue().endswith("\r\x1b[K")
    assert "OK: every case agrees" in capsys.readouterr().out
    terminal.seek(0)
    terminal.truncate()
    assert main(["oracle", "check", cases, theirs, "--quiet"]) == 0
    assert terminal.getvalue() == ""


def test_oracle_check_max_iterations_reaches_the_implementation(tmp_path, capsys):
    cases = case_file(tmp_path, SMALL)
    command = f"{sys.executable} {ROOT / 'examples' / 'float_impl.py'}"
    assert main(["oracle", "check", cases, "--impl", command]) == 0  # exits after 3 impulses, both
    capsys.readouterr()
    assert main(["oracle", "check", cases, "--impl", command, "--max-impulses", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["mismatches"] == []  # both stop at the cap of 1


# -- help --------------------------------------------------------------------------------------------


def test_help_of_every_command_works_and_names_the_docs(capsys):
    for words in [(), ("oracle",), *(w for w, _ in commands(build_parser()))]:
        with pytest.raises(SystemExit) as done:
            main([*words, "--help"])
        assert done.value.code == 0, words
        text = capsys.readouterr().out
        assert "usage: verify" in text and "example" in text and "shared/" not in text, words
    top = build_parser().format_help()
    assert "Formats and commands: docs/ in the source repository (docs/README.md)." in top
    solve_help = " ".join(dict(commands(build_parser()))[("solve",)].format_help().split())
    assert "docs/records.md in the source repository" in solve_help and "--case-time-limit" in solve_help


# -- the number of balls (issue 34, item 17) ------------------------------------------------------


def _help_of(parser: argparse.ArgumentParser, option: str) -> str:
    (action,) = [a for a in parser._actions if option in a.option_strings]
    return " ".join((action.help or "").split())


@pytest.mark.parametrize("command", ["cradle", "cradle-map"])
def test_the_help_of_balls_says_that_the_lists_set_the_number_of_balls(command):
    parser = dict(commands(build_parser()))[(command,)]
    balls = _help_of(parser, "--balls")
    assert "(default 3)" not in balls and "--masses or --velocity" in balls and "else 3" in balls, balls


@pytest.mark.parametrize(
    ("argv", "balls"),
    [
        ([], 3),
        (["--velocity", "1,0"], 2),  # the run: two balls, as the help now says
        (["--masses", "1,2,1,2"], 4),
        (["--balls", "2", "--velocity", "1,0"], 2),
    ],
)
def test_the_cradle_runs_the_number_of_balls_the_help_says(argv, balls, capsys):
    assert main(["cradle", "--eps", "0.5", *argv]) == 0
    assert capsys.readouterr().out.startswith(f"Newton's cradle: {balls} balls (")


def test_a_list_of_another_length_than_balls_is_refused_in_one_line(capsys):
    assert main(["cradle", "--eps", "0.5", "--balls", "3", "--velocity", "1,0"]) == 2
    err = capsys.readouterr().err
    assert err == "verify: error: verify cradle: --velocity has 2 entries but there are 3 balls\n", err


# -- one vocabulary (issue 61, item 7) ---------------------------------------------------------------------

#: the 0.2 names of renamed options: each still parses, hidden from --help, with a note on stderr
OLD_NAMES = {"--max-iterations": "--max-impulses", "--exact-cap": "--max-impulses",
             "--case-timeout": "--case-time-limit", "--timeout": "--impl-time-limit"}  # fmt: skip
#: ``oracle generate --out FILE`` is ``--save FILE`` (as ``bench --save``): --out is a folder everywhere else
OLD_FILE_OUT = ("--out", "--save")
#: words of options that mean one thing each: the cap on impulses, the time limits, an output folder
CAP, FOLDER = "--max-impulses", "--out"


def test_every_subcommand_takes_quiet():
    missing = [" ".join(w) for w, p in commands(build_parser()) if "--quiet" not in p._option_string_actions]
    assert not missing, f"without --quiet: {missing}"


def test_no_subcommand_shows_an_old_name_and_each_cap_is_max_impulses():
    from verify.cli.common import Renamed

    for words, p in commands(build_parser()):
        shown = p.format_help()
        assert not [old for old in OLD_NAMES if f"{old} " in shown or f"{old}\n" in shown], words
        for action in p._actions:
            if isinstance(action, Renamed):
                pairs = {(old, action.option_strings[0]) for old in action.old}
                assert pairs <= {*OLD_NAMES.items(), OLD_FILE_OUT}, (words, pairs)
            if action.dest in ("max_iterations", "exact_cap"):
                pytest.fail(f"verify {' '.join(words)}: a cap on impulses not named {CAP}")


def test_out_is_a_folder_wherever_it_is_an_option():
    from verify.cli.common import OutputDir, Renamed

    found = [
        (w, a)
        for w, p in commands(build_parser())
        for a in p._actions
        if FOLDER in a.option_strings and not (isinstance(a, Renamed) and FOLDER in a.old)  # oracle generate's 0.2 name
    ]
    assert {" ".join(w) for w, _ in found} >= {"report", "all", "engines", "oracle export"}
    assert all(isinstance(a.type, OutputDir) for _, a in found), [(w, a.option_strings) for w, a in found]


@pytest.mark.parametrize(("argv", "old", "new"), [
    (["cradle", "--eps", "1/2", "--max-iterations", "2", "--json"], "--max-iterations", "--max-impulses"),
    (["table1", "--exact-cap", "5", "--json"], "--exact-cap", "--max-impulses"),
])  # fmt: skip
def test_an_old_name_still_works_with_a_note(argv, old, new, capsys, monkeypatch):
    assert main(argv) == 0
    with_old = capsys.readouterr()
    assert with_old.err.strip() == f"verify: note: {old} is now {new} (the old name works in 0.3 only)"
    assert main([new if a == old else a for a in argv]) == 0
    with_new = capsys.readouterr()
    assert with_new.err == "" and with_new.out == with_old.out


def test_oracle_export_takes_its_folder_once(tmp_path, capsys):
    assert main(["oracle", "export", "--out", str(tmp_path / "a")]) == 0
    assert main(["oracle", "export", str(tmp_path / "b")]) == 0
    assert (tmp_path / "a" / "cases.json").read_bytes() == (tmp_path / "b" / "cases.json").read_bytes()
    capsys.readouterr()
    assert main(["oracle", "export", str(tmp_path / "c"), "--out", str(tmp_path / "d")]) == 2
    assert "give the folder once" in capsys.readouterr().err and not (tmp_path / "c").exists()
