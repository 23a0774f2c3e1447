"""docs/dask.md, run: its commands are read from the page (so the page cannot drift) and run for real.

On one machine: a ``dask scheduler`` and two ``dask worker`` processes, the page's ``verify sweep
--scheduler ... --checkpoint ...``, one worker killed with the page's ``kill`` command while the run
goes on, the run interrupted (SIGINT, as Ctrl-C) and resumed with the same command; the resumed run
prints what an uninterrupted run in one process prints, and what the page shows (the time aside).
On several machines: the page's commands, every address 127.0.0.1, run to the same output.

Everything listens on 127.0.0.1 only, on free ports put in place of the page's 8786 and 8787; each
process is started in a session of its own and its whole group killed in ``finally``; every file
(checkpoints, pid files, Dask's scratch space) is written under ``tmp_path``.
"""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

pytest.importorskip("distributed")

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "dask.md"
#: the addresses of the page's machines, and the host every process of this test listens on
MACHINES = ("192.0.2.10", "192.0.2.11")
HOST = "127.0.0.1"
WAIT = 60.0  # seconds at most for any one step
_FENCE = re.compile(r"^```(\w*)\n(.*?)^```$", re.S | re.M)


def section(title: str) -> str:
    text = PAGE.read_text(encoding="utf-8")
    found = re.search(rf"^##+ {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert found, f"docs/dask.md has no section {title!r}"
    return found.group(1)


def commands(text: str) -> list[str]:
    """The command lines of the ``sh`` blocks of ``text``, in order."""
    blocks = [body for lang, body in _FENCE.findall(text) if lang == "sh"]
    return [line for block in blocks for line in block.splitlines() if line.strip()]


def shown_output(text: str) -> str:
    """The first plain code block of ``text``: what the page says a command prints."""
    blocks = [body for lang, body in _FENCE.findall(text) if not lang]
    assert blocks, "docs/dask.md shows no output"
    return blocks[0]


def without_time(output: str) -> str:
    """A sweep's output with its time (``in 4.2 s``) left out: the one part that changes between runs."""
    return re.sub(r" in [0-9.]+ s$", " in ... s", output, flags=re.M)


def free_port() -> int:
    with socket.socket() as s:
        s.bind((HOST, 0))
        return int(s.getsockname()[1])


def localise(line: str, ports: dict[str, int]) -> str:
    """A command of the page with this test's ports and every machine at 127.0.0.1."""
    for page_port, port in ports.items():
        line = re.sub(rf"(?<=[: ]){page_port}\b", str(port), line)
    for machine in MACHINES:
        line = line.replace(machine, HOST)
    return line


def option(line: str, name: str) -> str:
    """The value of the option ``name`` in a command line."""
    words = shlex.split(line)
    assert name in words, f"{name} not in {line!r}"
    return words[words.index(name) + 1]


def argv(line: str) -> list[str]:
    """``dask ...`` and ``verify ...`` with this interpreter (the programs of the venv under test)."""
    words = shlex.split(line)
    assert words[0] in ("dask", "verify"), line
    return [sys.executable, "-m", words[0], *words[1:]]


class Processes:
    """Processes started in sessions of their own, their output in files; every group killed at the end."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.started: list[subprocess.Popen[bytes]] = []
        self.names: list[str] = []
        self.env = dict(os.environ, TMPDIR=str(folder), PYTHONPATH=str(ROOT), TERM="dumb")

    def start(self, line: str, name: str, cwd: Path) -> subprocess.Popen[bytes]:
        with open(self.folder / f"{name}.out", "wb") as out, open(self.folder / f"{name}.err", "wb") as err:
            p = subprocess.Popen(argv(line), cwd=cwd, env=self.env, stdout=out, stderr=err, start_new_session=True)
        self.started.append(p)
        self.names.append(name)
        return p

    def err(self, name: str) -> str:
        return (self.folder / f"{name}.err").read_text(encoding="utf-8", errors="replace")

    def out(self, name: str) -> str:
        return (self.folder / f"{name}.out").read_text(encoding="utf-8")

    def stop_all(self) -> None:
        for p in reversed(self.started):
            if p.poll() is None:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(p.pid, signal.SIGKILL)
            with contextlib.suppress(subprocess.TimeoutExpired):
                p.wait(timeout=10)


@contextlib.contextmanager
def processes(folder: Path) -> Iterator[Processes]:
    """Processes started as from a terminal: SIGINT handled here while they start (an ignored SIGINT, which
    this test process may have inherited, is inherited by the processes it starts, and Python then never
    raises KeyboardInterrupt on Ctrl-C); every group killed at the end."""
    ps = Processes(folder)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield ps
    finally:
        signal.signal(signal.SIGINT, previous)
        ps.stop_all()


def wait_until(what: str, ready: Callable[[], bool], procs: Processes) -> None:
    deadline = time.monotonic() + WAIT
    while not ready():
        for p, name in zip(procs.started, procs.names):
            if p.poll() not in (None, 0, 130, -signal.SIGKILL):
                tail = "\n".join(procs.err(name).splitlines()[-15:])
                raise AssertionError(f"{p.args} ended with {p.returncode} while waiting for {what}:\n{tail}")
        if time.monotonic() > deadline:
            raise AssertionError(f"no {what} after {WAIT:.0f} s")
        time.sleep(0.02)


def stepped(workers: list[subprocess.Popen[bytes]], what: str, count: Callable[[], int], enough: int) -> None:
    """Let the ``workers``' process groups (a nanny and its worker, or a worker) run in steps of 20 ms,
    stopped (SIGSTOP) between them, until ``count()`` (the tasks in the checkpoint) reaches ``enough``; they
    are left stopped. After each step the count is read once it has settled: the run writes the checkpoint
    as results reach it, which may lag behind the workers on a busy machine, so the workers are never more
    than a step ahead of what the test has seen, and a run with tasks left still has some when this
    returns, whatever the machine's speed."""
    deadline = time.monotonic() + WAIT
    for worker in workers:
        os.killpg(worker.pid, signal.SIGSTOP)
    while settled(count) < enough:
        if time.monotonic() > deadline:
            for worker in workers:
                os.killpg(worker.pid, signal.SIGCONT)
            raise AssertionError(f"no {what} after {WAIT:.0f} s")
        for worker in workers:
            os.killpg(worker.pid, signal.SIGCONT)
        time.sleep(0.02)
        for worker in workers:
            os.killpg(worker.pid, signal.SIGSTOP)


def settled(count: Callable[[], int]) -> int:
    """``count()`` once it has not changed for 0.15 s (at most 10 s)."""
    last, since, deadline = count(), time.monotonic(), time.monotonic() + 10
    while time.monotonic() - since < 0.15 and time.monotonic() < deadline:
        time.sleep(0.05)
        now = count()
        if now != last:
            last, since = now, time.monotonic()
    return last


def start_cluster(procs: Processes, lines: list[str], cwd: Path) -> int:
    """Start the scheduler and workers of ``lines``; wait until every worker process has registered."""
    scheduler, *workers = lines
    assert scheduler.startswith("dask scheduler ") and all(w.startswith("dask worker ") for w in workers)
    procs.start(scheduler, "scheduler", cwd)
    count = sum(int(option(w, "--nworkers")) if "--nworkers" in w else 1 for w in workers)
    for k, worker in enumerate(workers):
        procs.start(worker, f"worker-{k}", cwd)
    wait_until(f"{count} workers", lambda: procs.err("scheduler").count("Register worker") >= count, procs)
    return count


def finished_tasks(checkpoint: Path) -> int:
    """The tasks a checkpoint holds (its lines after the header)."""
    if not checkpoint.exists():
        return 0
    return max(0, checkpoint.read_bytes().count(b"\n") - 1)


def run(line: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT), TERM="dumb")
    return subprocess.run(argv(line), cwd=cwd, env=env, capture_output=True, text=True, timeout=WAIT, check=False)


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def uninterrupted(tmp_path_factory: pytest.TempPathFactory) -> str:
    """The page's sweep run in one process, no cluster and no checkpoint."""
    line = commands(section("On one machine"))[3]
    words = shlex.split(line)
    local = [*words[: words.index("--scheduler")], "--workers", "1"]
    done = run(shlex.join(local), tmp_path_factory.mktemp("one-process"))
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_page_shows_what_an_uninterrupted_run_prints(uninterrupted: str) -> None:
    assert without_time(shown_output(section("On one machine"))) == without_time(uninterrupted)


@pytest.mark.slow(seconds=16)
def test_on_one_machine_a_killed_worker_and_an_interrupted_run_lose_nothing(tmp_path: Path, uninterrupted: str) -> None:
    text = section("On one machine")
    lines = commands(text)
    assert len(lines) == 6, lines  # scheduler, two workers, the run, the kill, the resumed run
    ports = {"8786": free_port(), "8787": free_port()}
    scheduler, w1, w2, command, kill, resume = (localise(line, ports) for line in lines)
    assert resume == command, "docs/dask.md: the run is resumed with the same command"
    assert kill.startswith("kill ") and "--pid-file" in w2
    work = tmp_path / "work"
    work.mkdir()
    checkpoint = work / option(command, "--checkpoint")
    total = int(option(command, "--cases")) // 100  # tasks of 100 cases
    with processes(tmp_path) as procs:
        start_cluster(procs, [scheduler, w1, w2], work)
        running = procs.start(command, "run", work)

        def done() -> int:
            return finished_tasks(checkpoint)

        # w1 and w2 run in steps from the start (left stopped): the run is never far ahead of what is seen
        stepped(procs.started[1:3], "finished tasks before the kill", done, 5)
        subprocess.run(["sh", "-c", kill], cwd=work, check=True, timeout=WAIT)  # the page's kill
        killed = procs.started[2]
        killed.wait(timeout=WAIT)
        assert killed.returncode == -signal.SIGKILL
        # the run goes on, on w1; w1 is let run in short steps (its process group stopped between them), so
        # that the interrupt lands midway however fast this machine finishes the remaining tasks
        worker = procs.started[1]
        seen = settled(done)
        stepped([worker], "tasks finished after the kill", done, seen + 5)
        running.send_signal(signal.SIGINT)  # Ctrl-C, while w1 is stopped: the run cannot end otherwise
        with contextlib.suppress(subprocess.TimeoutExpired):
            running.wait(timeout=1)
        os.killpg(worker.pid, signal.SIGCONT)  # a stopped worker would hold the client's shutdown
        running.wait(timeout=WAIT)
        assert running.returncode == 130, f"SIGINT here: {signal.getsignal(signal.SIGINT)}\n" + procs.err("run")
        assert procs.err("run").splitlines()[-1] == "verify: interrupted"
        assert procs.out("run") == ""
        kept = finished_tasks(checkpoint)
        assert 10 <= kept < total, f"{kept} of {total} tasks in the checkpoint: the run was not interrupted midway"
        resumed = run(resume, work)  # on the worker that is left
    assert resumed.returncode == 0, resumed.stderr
    assert finished_tasks(checkpoint) == total
    assert without_time(resumed.stdout) == without_time(uninterrupted)


def test_on_several_machines_the_commands_give_the_same_output(tmp_path: Path, uninterrupted: str) -> None:
    lines = commands(section("On several machines"))
    assert len(lines) == 3, lines  # the scheduler, a worker machine, the run
    assert all(machine in " ".join(lines) for machine in MACHINES)
    ports = {"8786": free_port(), "8787": free_port()}
    scheduler, worker, command = (localise(line, ports) for line in lines)
    assert HOST in worker and "192.0.2" not in " ".join([scheduler, worker, command])
    with processes(tmp_path) as procs:
        assert start_cluster(procs, [scheduler, worker], tmp_path) == 2
        done = run(command, tmp_path)
    assert done.returncode == 0, done.stderr
    assert without_time(done.stdout) == without_time(uninterrupted)
