"""The task layer (verify/runner/tasks.py) and ``verify properties`` on it: results in task order whatever
runs them (one process, a local pool, a Dask LocalCluster, one of whose workers is killed), one retry,
failures reported while the other tasks finish, and checkpoints that resume a stopped run to the same output.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
from fractions import Fraction
from pathlib import Path

import pytest

import verify.properties.verdicts as verdicts_module
from tests.helpers import shared
from verify.cli import main
from verify.properties.verdicts import Verdict, run_verdicts
from verify.runner.tasks import Checkpoint, Task, TaskRunner, decode, encode, run_tasks

#: a small slice of the suite (a few seconds in one process) for the checkpoint tests
SMALL = ["properties", "--profile", "dev", "--property", "kinetic energy", "--family", "cradle"]
SMALL += ["--rule", "asymmetric", "--rule", "general"]
KINETIC = ["properties", "--profile", "dev", "--property", "kinetic energy", "--json", "--quiet"]


def flaky(payload: tuple[str, int, int]) -> int:
    """Fails (raises) on its first ``fails`` attempts, counted in the file ``marker``; then returns ``value``."""
    marker, value, fails = payload
    with open(marker, "a") as f:
        f.write("x")
    if os.path.getsize(marker) <= fails:
        raise ValueError(f"attempt {os.path.getsize(marker)} of {value} fails")
    return value * 10


def dies_once(payload: tuple[str, int]) -> int:
    """Kills its own process on its first attempt (a broken process pool), then returns ``value``."""
    marker, value = payload
    if not os.path.exists(marker):
        Path(marker).write_text("died")
        os._exit(1)
    return value


def run_cli(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("workers", [1, 2])
def test_one_retry_then_reported_while_the_others_finish(tmp_path: Path, workers: int) -> None:
    tasks = [
        Task(f"t{i}", flaky, (str(tmp_path / f"m{i}"), i, fails), f"row {i}") for i, fails in enumerate([0, 1, 2, 0])
    ]
    seen: list[str] = []
    run = run_tasks(tasks, workers=workers, on_result=lambda t, r: seen.append(t.id))
    assert run.results == [0, 10, None, 30]  # in task order; t1 failed once and was retried
    assert [(f.id, f.label) for f in run.failures] == [("t2", "row 2")]
    assert run.failures[0].error == "ValueError: attempt 2 of 2 fails"
    assert sorted(seen) == ["t0", "t1", "t3"]
    assert (tmp_path / "m2").read_text() == "xx"  # tried exactly twice


def test_a_dead_worker_process_is_retried(tmp_path: Path) -> None:
    tasks = [Task(f"t{i}", dies_once, (str(tmp_path / f"m{i}"), i)) for i in range(3)]
    run = run_tasks(tasks, workers=2)
    assert run.results == [0, 1, 2] and run.failures == []


def test_results_round_trip_exactly_through_a_checkpoint(tmp_path: Path) -> None:
    extra = (Fraction(1, 3), [Fraction(-2), 4], (1, 2))
    v = Verdict("p", "general", "corner", "refuted", 3, {"id": "x", "velocity": ["1/2"]}, "note", extra, law="rule")
    back = decode(json.loads(json.dumps(encode(v))))
    assert back == v and back.extra == extra and type(back.extra[2]) is tuple and type(back.extra[1]) is list
    with pytest.raises(TypeError):
        encode(0.5)
    path = str(tmp_path / "cp.jsonl")
    with Checkpoint(path, {"profile": "dev"}) as cp:
        assert cp.open() == {}
        cp.add("a", v)
    with open(path, "a") as f:
        f.write('{"id": "b", "resu')  # torn: dropped, and the next line starts clean
    with Checkpoint(path, {"profile": "dev"}) as cp:
        assert cp.open() == {"a": v}
        cp.add("c", 1)
    with Checkpoint(path, {"profile": "dev"}) as cp:
        assert cp.open() == {"a": v, "c": 1}
    assert len(Path(path).read_text().splitlines()) == 3


@pytest.mark.parametrize("command", ["properties", "sweep", "corner-claims", "all", "report"])
def test_help_lists_the_cluster_options(capsys: pytest.CaptureFixture[str], command: str) -> None:
    with pytest.raises(SystemExit):
        main([command, "--help"])
    out = capsys.readouterr().out
    for option in ("--scheduler ADDRESS", "--local-cluster N", "--checkpoint FILE", "--workers"):
        assert option in out


@pytest.mark.parametrize(
    "argv",
    [
        ["--workers", "2", "--local-cluster", "2"],
        ["--scheduler", "tcp://127.0.0.1:1", "--local-cluster", "2"],
        ["--local-cluster", "0"],
        ["--local-cluster", "two"],
    ],
)
def test_cluster_options_are_checked(capsys: pytest.CaptureFixture[str], argv: list[str]) -> None:
    code, out, err = run_cli(capsys, ["properties", *argv])
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_a_missing_dask_is_one_line(capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails as if dask were not installed
    code, out, err = run_cli(capsys, ["properties", "--local-cluster", "2"])
    assert code == 2 and out == ""
    assert err.startswith("verify: error: --local-cluster needs dask: pip install '.[cluster]' in a clone")
    assert err.count("\n") == 1 and "'verify-impacts[cluster]'" in err


@pytest.mark.slow(seconds=25)
def test_a_stopped_run_resumes_from_its_checkpoint(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch, serial_kinetic: dict
) -> None:
    whole = str(tmp_path / "whole.jsonl")
    code, expected, _ = run_cli(capsys, [*SMALL, "--workers", "1", "--checkpoint", whole])
    lines = Path(whole).read_text().splitlines(keepends=True)
    total = len(lines) - 1
    # the rule's two rules, the simultaneous and the sequential law's general CORs; kinetic energy is refuted there
    assert total == 4 and code == 1
    header = json.loads(lines[0])
    assert header["options"] == {"profile": "dev", "property": ["kinetic energy"], "family": ["cradle"],
                                 "rule": ["asymmetric", "general"], "law": None, "chunk": 2000}  # fmt: skip
    # stopped after 2 rows, while writing the third
    cut = str(tmp_path / "cut.jsonl")
    Path(cut).write_text("".join(lines[:3]) + lines[3][:25])  # header, 2 rows, a torn third
    ran: list[tuple] = []
    real = verdicts_module._run_row

    def counting(args: tuple) -> Verdict:
        ran.append(args)
        return real(args)

    monkeypatch.setattr(verdicts_module, "_run_row", counting)
    code2, resumed, err = run_cli(capsys, [*SMALL, "--workers", "1", "--checkpoint", cut])
    assert (code2, resumed) == (code, expected)  # the same table, byte for byte
    assert len(ran) == total - 2
    assert Path(cut).read_text().splitlines()[:3] == [x.rstrip("\n") for x in lines[:3]]
    assert len(Path(cut).read_text().splitlines()) == total + 1
    # JSON too: a finished checkpoint runs nothing and prints the same as a run without one
    ran.clear()
    code3, again, _ = run_cli(capsys, [*SMALL, "--json", "--quiet", "--checkpoint", cut])
    assert ran == [] and code3 == code
    alone = [
        r for r in serial_kinetic["properties"] if r["family"] == "cradle" and r["rule"] in ("asymmetric", "general")
    ]
    assert json.loads(again)["properties"] == alone
    # the same file with other options that change results is refused
    code4, out, err = run_cli(capsys, [*SMALL, "--profile", "ci", "--checkpoint", cut])
    assert code4 == 2 and out == "" and "other options (profile: 'dev', not 'ci')" in err
    assert len(err.strip().splitlines()) == 1


def test_a_row_that_fails_twice_is_reported_and_the_others_finish(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    real = verdicts_module._run_row
    tried: list[tuple] = []

    def broken(args: tuple) -> Verdict:
        if args[1:3] == ("cradle", "general") and args[4] == "rule":
            tried.append(args)
            raise RuntimeError("boom")
        return real(args)

    monkeypatch.setattr(verdicts_module, "_run_row", broken)
    cp = str(tmp_path / "cp.jsonl")
    code, out, err = run_cli(capsys, [*SMALL, "--workers", "1", "--json", "--quiet", "--checkpoint", cp])
    assert code == 3 and len(tried) == 2  # a RuntimeError: a bug (exit code 3), not bad input (2)
    assert "verify: error: row kinetic energy does not increase | rule | general | cradle failed twice: " \
           "RuntimeError: boom" in err  # fmt: skip
    shown = json.loads(out)["properties"]
    assert [(r["law"], r["rule"]) for r in shown] == [("rule", "asymmetric"), ("simultaneous", "general"),
                                                      ("sequential", "general")]  # fmt: skip
    assert len(Path(cp).read_text().splitlines()) == len(shown) + 1  # the finished rows are kept


# -- on a Dask LocalCluster ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def serial_kinetic(tmp_path_factory: pytest.TempPathFactory) -> dict:
    """``verify properties --profile dev --property 'kinetic energy' --json`` in one process, once per command
    for both test processes (:func:`tests.helpers.shared`)."""
    import contextlib
    import io

    def compute() -> dict:
        out = io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
            main([*KINETIC, "--workers", "1"])
        return json.loads(out.getvalue())

    return shared(tmp_path_factory, "serial-kinetic", compute)


@pytest.mark.slow(seconds=10)
def test_a_local_cluster_gives_the_same_verdicts(serial_kinetic: dict, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("dask.distributed")
    code, out, err = run_cli(capsys, [*KINETIC, "--local-cluster", "2"])
    assert code == 1 and json.loads(out) == serial_kinetic
    assert err.startswith("verify properties: 30 of 30 rows")


@pytest.mark.slow(seconds=11)
def test_a_killed_worker_loses_nothing(serial_kinetic: dict, capsys: pytest.CaptureFixture[str]) -> None:
    distributed = pytest.importorskip("dask.distributed")
    import logging

    cluster = distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address="127.0.0.1:0",  # a free port: other tests may run a cluster at the same time
        silence_logs=logging.CRITICAL,
    )
    killed: list[int] = []
    with cluster, distributed.Client(cluster) as client:
        pids = sorted(client.run(os.getpid).values())

        def kill_one(done: int, total: int, verdict: Verdict) -> None:
            if not killed:
                os.kill(pids[0], signal.SIGKILL)
                killed.append(pids[0])

        run = run_verdicts("dev", properties=["kinetic energy"], executor=client.get_executor(), progress=kill_one)
        assert killed and run.failures == []
        assert [v.record() for v in run.results] == serial_kinetic["properties"]
        # the same cluster through --scheduler (a few rows)
        code, out, _ = run_cli(
            capsys, [*KINETIC, "--family", "corner", "--law", "rule", "--scheduler", cluster.scheduler_address]
        )
    assert code == 0
    assert json.loads(out)["properties"] == [
        r for r in serial_kinetic["properties"] if r["family"] == "corner" and r["law"] == "rule"
    ]


# -- rows split into chunks of cases (the thorough profile) -------------------------------------------


def test_a_split_row_merges_its_chunks_the_same_whatever_runs_them(monkeypatch: pytest.MonkeyPatch) -> None:
    """A row split into seeded chunks: its verdict is the same in one process and in a pool of two, a
    holding row counts the cases of every chunk, and each chunk searches cases of its own."""
    chosen = {"properties": ["the exit velocity"], "families": ["corner"], "rules": ["ideal"], "laws": ["rule"]}
    serial = run_verdicts("dev", workers=1, chunk=10, **chosen)
    pooled = run_verdicts("dev", workers=2, chunk=10, **chosen)
    assert serial.failures == pooled.failures == []
    assert [v.record() for v in serial.results] == [v.record() for v in pooled.results]
    (row,) = serial.results
    assert row.verdict == "holds" and row.tally["drawn"] == 25  # 3 chunks of 9, 8 and 8 cases
    tasks = verdicts_module.row_tasks("dev", chunk=10, **chosen)
    assert [t.payload[3] for t in tasks] == [9, 8, 8]
    drawn: list[str] = []
    real = verdicts_module._check
    monkeypatch.setattr(
        verdicts_module, "_check", lambda p, r, item: drawn.append(json.dumps(item.record)) or real(p, r, item)
    )
    seen = []
    for payload in (tasks[1].payload, tasks[2].payload, (*tasks[2].payload[:5], None)):  # 8 cases each
        drawn.clear()
        verdicts_module._run_row(payload)
        seen.append(list(drawn))
    assert len({json.dumps(cases) for cases in seen}) == 3  # chunks 2, 3 and an unseeded run of 8: all differ


def test_a_split_refuted_row_gives_a_reproducible_counterexample_and_a_whole_census() -> None:
    """The termination row of the symmetric cradle is refuted (eps small enough never exits): split in
    chunks, the first refuting chunk gives the counterexample, which fails the property when checked
    again, and the census counts the runs of every chunk."""
    from verify.properties.verdicts import CENSUS_CASES, run_record

    chosen = {"properties": ["the rule exits"], "families": ["cradle"], "rules": ["symmetric"], "laws": ["rule"]}
    (row,) = run_verdicts("dev", workers=1, chunk=10, **chosen).results
    assert row.verdict == "refuted"
    assert row.counts[CENSUS_CASES] == row.cases == 25  # every chunk's cases, in the census
    assert sum(v for k, v in row.counts.items() if k.startswith("stop ")) == 25
    assert "a separate census of 25 cases" in row.note
    assert run_record(row.counterexample, "symmetric").stop != "exit"  # the counterexample still fails


# -- the sweeps of the corner on tasks ------------------------------------------------------------------

SWEEP = ["sweep", "--cases", "300", "--seed", "5", "--json", "--quiet"]


def _without_time(text: str) -> dict:
    found = json.loads(text)
    found.pop("seconds")
    return found


def test_a_stopped_sweep_resumes_to_the_same_output(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import verify.paper.sweep as sweep_module

    whole = str(tmp_path / "whole.jsonl")
    code, expected, _ = run_cli(capsys, [*SWEEP, "--workers", "1", "--checkpoint", whole])
    lines = Path(whole).read_text().splitlines(keepends=True)
    assert code == 0 and len(lines) == 1 + 3  # 100 cases a task
    assert json.loads(lines[0])["options"] == {"command": "sweep", "cases": 300, "seed": 5, "max_iterations": 100}
    assert _without_time(expected)["results"] == json.loads(run_cli(capsys, SWEEP)[1])["results"]  # pool, no file
    cut = str(tmp_path / "cut.jsonl")
    Path(cut).write_text("".join(lines[:2]) + lines[2][:40])  # one chunk done, the second torn
    ran: list[int] = []
    real = sweep_module._run_chunk

    def counting(args: tuple) -> list:
        ran.append(len(args[1]))
        return real(args)

    monkeypatch.setattr(sweep_module, "_run_chunk", counting)
    code2, resumed, _ = run_cli(capsys, [*SWEEP, "--workers", "1", "--checkpoint", cut])
    assert code2 == 0 and ran == [100, 100]
    assert _without_time(resumed) == _without_time(expected)
    code3, out, err = run_cli(capsys, [*SWEEP[:-4], "--seed", "6", "--checkpoint", cut])
    assert code3 == 2 and out == "" and "other options (seed: 5, not 6)" in err


def test_corner_claims_resume_from_a_checkpoint(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import verify.paper.sweep as sweep_module

    argv = ["corner-claims", "--cases", "40", "--json", "--quiet", "--workers", "1"]
    cp = str(tmp_path / "claims.jsonl")
    code, expected, _ = run_cli(capsys, [*argv, "--checkpoint", cp])
    assert len(Path(cp).read_text().splitlines()) == 1 + 3  # the claims: 160 cases in 2 tasks; floats: 40 in 1
    monkeypatch.setattr(sweep_module, "_run_chunk", lambda args: pytest.fail("a finished task ran again"))
    assert run_cli(capsys, [*argv, "--checkpoint", cp])[:2] == (code, expected)


@pytest.mark.slow
def test_a_sweep_on_a_local_cluster_equals_one_process(capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("dask.distributed")
    serial = json.loads(run_cli(capsys, [*SWEEP, "--workers", "1"])[1])
    with socket.socket() as busy:  # Dask's default port taken, as by another cluster: no clash, no warning
        with contextlib.suppress(OSError):  # (taken already, if this fails)
            busy.bind(("127.0.0.1", 8787))
            busy.listen()
        code, out, _ = run_cli(capsys, [*SWEEP, "--local-cluster", "2"])
    assert code == 0 and json.loads(out)["results"] == serial["results"]


def test_a_sweep_chunk_that_fails_twice_is_one_line_naming_its_cases(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import verify.paper.sweep as sweep_module

    real = sweep_module._run_chunk

    def second_chunk_breaks(args: tuple) -> list:
        if args[1][0]["id"] == "corner-5-100":
            raise ZeroDivisionError("boom")
        return real(args)

    monkeypatch.setattr(sweep_module, "_run_chunk", second_chunk_breaks)
    cp = str(tmp_path / "cp.jsonl")
    code, out, err = run_cli(capsys, [*SWEEP, "--workers", "1", "--checkpoint", cp])
    assert code == 3 and out == ""  # a task that fails with a bug, not with bad input: an internal error
    assert err == "verify: error: the cases corner-5-100 to corner-5-199 failed twice: ZeroDivisionError: boom\n"
    assert len(Path(cp).read_text().splitlines()) == 1 + 2  # the other two chunks are kept


# -- verify all's progress lines (issue 34, item 13) ----------------------------------------------


def test_verify_all_gives_each_step_its_own_time(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The steps of ``verify all`` take 10 s, then 300 s, then 5 s (a clock that the steps move):
    each step's line says when it started, and a line gives each step's own time."""
    import types

    from verify.cli import reports
    from verify.report import pages, summary

    now = [1000.0]
    monkeypatch.setattr(reports, "_clock", lambda: now[0])
    monkeypatch.setattr(reports, "refresh_engines", lambda out, progress: None)

    def steps(out: str, *, progress, **_: object) -> object:
        for i, seconds in enumerate((10, 300, 5), 1):
            progress(f"[report {i}/3] step {i} ...")
            now[0] += seconds
        return types.SimpleNamespace(
            table1=None, cradle_map=types.SimpleNamespace(cmap=None), corner_example=None,
            corner=types.SimpleNamespace(claims=None), profile="ci", verdicts=[],
            oracle=types.SimpleNamespace(self_check=types.SimpleNamespace(ok=True)),
        )  # fmt: skip

    monkeypatch.setattr(pages, "write_reports", steps)
    monkeypatch.setattr(summary, "all_summary", lambda *a, **k: ("summary\n", False))
    code, out, err = run_cli(capsys, ["all", "--out", str(tmp_path / "reports"), "--workers", "1"])
    assert code == 0, err
    assert out.splitlines()[1:] == [
        "[report 1/3] step 1 ... (at 0 s)",
        "[report 1/3] done in 10 s",
        "[report 2/3] step 2 ... (at 10 s)",
        "[report 2/3] done in 300 s",
        "[report 3/3] step 3 ... (at 310 s)",
        "[report 3/3] done in 5 s",
        "summary",
        f"reports written to {tmp_path / 'reports'}/ in 315 s",
    ]


def test_a_dead_worker_process_of_one_pool_is_retried_and_the_next_run_gets_a_new_pool(tmp_path: Path) -> None:
    """TaskRunner.one_pool (verify all): a process that dies breaks the shared pool; its tasks are run again, each
    alone, and the next run (here from the same thread) has a new pool."""
    with TaskRunner(workers=2) as runner, runner.one_pool():
        first = runner.run([Task(f"a{i}", dies_once, (str(tmp_path / f"a{i}"), i)) for i in range(3)])
        second = runner.run([Task(f"b{i}", abs, -i) for i in range(3)])
    assert (first.results, first.failures, second.results, second.failures) == ([0, 1, 2], [], [0, 1, 2], [])
