"""Running another implementation (``--impl``): every failure is one clear line, the output cap
holds while the command runs, and a timeout ends every process the command started."""

from __future__ import annotations

import json
import os
import shlex
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from verify.cli.signals import GRACE
from verify.errors import InvalidInput
from verify.oracle.impl import IMPL_NOTE, run_implementation, split_command

PY = sys.executable


def py(code: str) -> str:
    """An --impl command that runs ``code`` with this Python."""
    return shlex.join([PY, "-c", code])


def failure(command: str, case_text: str = "{}", timeout: float = 10, **kw: int) -> str:
    """The one-line message of the InvalidInput that running ``command`` raises."""
    with pytest.raises(InvalidInput) as info:
        run_implementation(command, case_text, timeout, **kw)
    message = str(info.value)
    assert message.startswith("--impl: ")
    assert "\n" not in message and "Traceback" not in message and "Errno" not in message
    assert info.value.__cause__ is None and (info.value.__context__ is None or info.value.__suppress_context__)
    return message


def gone(pid: int) -> bool:
    """Whether the process ``pid`` has ended (a zombie that nobody reaped yet counts as ended)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return True
    return stat.rsplit(")", 1)[1].split()[0] in {"Z", "X"}


def wait_gone(pids: list[int], within: float = 2.0) -> bool:
    until = time.monotonic() + within
    while time.monotonic() < until:
        if all(gone(pid) for pid in pids):
            return True
        time.sleep(0.02)
    return all(gone(pid) for pid in pids)


# -- a command that works ---------------------------------------------------------------------


def test_returns_stdout_and_streams_large_input_both_ways() -> None:
    text = json.dumps({"cases": ["é" * 100] * 20_000})  # about 4 MB: more than any pipe holds
    out = run_implementation(py("import sys; sys.stdout.write(sys.stdin.read().upper())"), text, 10)
    assert out == text.upper()


def test_a_script_with_a_shebang_and_quoted_arguments(tmp_path: Path) -> None:
    script = tmp_path / "my solver.py"
    script.write_text(f"#!{PY}\nimport sys\nprint(sys.argv[1:], len(sys.stdin.read()))\n")
    script.chmod(0o755)
    assert run_implementation(f"'{script}' --json \"a b\"", "abc", 10) == "['--json', 'a b'] 3\n"


def test_a_command_that_does_not_read_its_input_is_no_error() -> None:
    big = "x" * (8 * 2**20)
    assert run_implementation(py("print('ok')"), big, 10) == "ok\n"
    closes = py("import os, time; os.close(0); time.sleep(0.2); print('ok')")
    assert run_implementation(closes, big, 10) == "ok\n"


def test_a_command_that_closes_its_output_early_is_waited_for() -> None:
    code = "import os, sys, time; print('x', flush=True); os.close(1); os.close(2); time.sleep(0.3); sys.exit(0)"
    assert run_implementation(py(code), "", 10) == "x\n"


def test_processes_left_running_are_ended_and_do_not_hold_the_run(tmp_path: Path) -> None:
    pidfile = tmp_path / "pid"
    command = shlex.join(["sh", "-c", f'sleep 100 & echo $! > "{pidfile}"; echo "{{}}"'])
    start = time.monotonic()
    assert run_implementation(command, "", 20) == "{}\n"
    assert time.monotonic() - start < 5  # not held until the timeout by the sleep that keeps stdout open
    assert wait_gone([int(pidfile.read_text())])


# -- commands that cannot be split or started -------------------------------------------------


def test_unbalanced_quote() -> None:
    message = failure("./solver 'cases.json")
    assert "no closing quotation" in message and "not run by a shell" in message and "sh -c" in message
    assert "no pipes or redirections" in message


def test_empty_command() -> None:
    assert failure("   ") == "--impl: empty command"


def test_command_not_on_path() -> None:
    message = failure("no-such-solver-xyz --json")
    assert "command not found: 'no-such-solver-xyz'" in message and "./no-such-solver-xyz" in message


def test_missing_file(tmp_path: Path) -> None:
    assert failure(str(tmp_path / "solver")) == f"--impl: no such file: {str(tmp_path / 'solver')!r}"


def test_directory(tmp_path: Path) -> None:
    assert "is a directory, not a program" in failure(str(tmp_path))


def test_file_that_is_not_executable(tmp_path: Path) -> None:
    script = tmp_path / "solver.py"
    script.write_text("#!/usr/bin/env python3\nprint('{}')\n")
    script.chmod(0o644)
    message = failure(str(script))
    assert f"{str(script)!r} is not executable" in message and f"chmod +x {script}" in message


def test_script_without_a_shebang(tmp_path: Path) -> None:
    script = tmp_path / "solver.py"
    script.write_text("print('{}')\n")
    script.chmod(0o755)
    message = failure(str(script))
    assert "script without a #! line" in message and "#!/usr/bin/env python3" in message
    assert f"'python3 {script}'" in message


def test_script_without_a_shebang_found_on_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    script = tmp_path / "my-solver"
    script.write_text("print('{}')\n")
    script.chmod(0o755)
    monkeypatch.setenv("PATH", str(tmp_path))
    assert f"cannot run {str(script)!r}: it is a script without a #! line" in failure("my-solver --json")


def test_shebang_naming_a_missing_interpreter(tmp_path: Path) -> None:
    script = tmp_path / "solver.py"
    script.write_text("#!/usr/bin/no-such-python\nprint('{}')\n")
    script.chmod(0o755)
    message = failure(str(script))
    assert "#! line names a program that does not exist ('/usr/bin/no-such-python')" in message


def test_binary_for_another_system(tmp_path: Path) -> None:
    binary = tmp_path / "solver"
    binary.write_bytes(b"\x7fELF\x01\x01\x01" + b"\0" * 64)  # a truncated, unusable ELF header
    binary.chmod(0o755)
    assert "not a program for this system" in failure(str(binary))


# -- commands that fail while running ---------------------------------------------------------


def test_killed_by_a_signal_names_it() -> None:
    message = failure(py("import os; os.abort()"))
    assert message.endswith("was killed by signal 6 (SIGABRT)")


def test_killed_by_a_signal_quotes_the_last_stderr_line() -> None:
    code = "import os, signal, sys; print('segfault near x', file=sys.stderr, flush=True); os.kill(os.getpid(), 11)"
    assert failure(py(code)).endswith("was killed by signal 11 (SIGSEGV): segfault near x")


def test_non_zero_exit_quotes_the_last_stderr_line() -> None:
    code = "import sys; print('one\\ntwo: bad case 7', file=sys.stderr); sys.exit(3)"
    assert failure(py(code)).endswith("exited with code 3: two: bad case 7")
    assert failure(py("raise SystemExit(1)")).endswith("exited with code 1: (nothing on stderr)")


def test_stderr_is_kept_to_its_end() -> None:
    code = "import sys; sys.stderr.write('noise ' * 5_000_000 + '\\nthe end\\n'); sys.exit(2)"
    assert failure(py(code)).endswith("exited with code 2: the end")


def test_output_that_is_not_utf8() -> None:
    message = failure(py('import sys; sys.stdout.buffer.write(b\'{"a": "\\xff"}\')'))
    assert "is not UTF-8 text (byte 0xff at offset 7)" in message


def test_output_cap_stops_a_flooding_writer() -> None:
    flood = py("import sys\nwhile True: sys.stdout.write('x' * 65536)")
    start = time.monotonic()
    message = failure(flood, timeout=20, max_output=100_000)
    assert "wrote more than 100000 bytes on stdout and was stopped" in message
    assert time.monotonic() - start < 5


def test_output_at_the_cap_is_accepted() -> None:
    assert len(run_implementation(py("print('x' * 999)"), "", 10, max_output=1000)) == 1000


MEMORY_PROBE = """
import resource, shlex, sys
from verify.oracle.impl import run_implementation
from verify.errors import InvalidInput
flood = shlex.join([sys.executable, "-c", "import sys\\nwhile True: sys.stdout.write('x' * 2**20)"])
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
try:
    run_implementation(flood, "", 60)
except InvalidInput as exc:
    message = str(exc)
after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print((after - before) // 1024, message)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ru_maxrss is in KiB on Linux")
def test_memory_stays_bounded_under_a_flood() -> None:
    """The default cap (64 MiB) holds while reading: the parent's peak memory grows by about the cap,
    not by what the writer would write (it writes without end)."""
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run([PY, "-c", MEMORY_PROBE], capture_output=True, text=True, timeout=60, cwd=root, check=True)
    grown_mib, message = done.stdout.split(" ", 1)
    assert "wrote more than 67108864 bytes (64 MiB) on stdout" in message
    assert int(grown_mib) < 64 + 40


# -- timeouts end the whole process group -----------------------------------------------------


def test_timeout_kills_the_command_and_what_it_started(tmp_path: Path) -> None:
    pidfile = tmp_path / "pids"
    command = shlex.join(["sh", "-c", f'sleep 100 & echo $$ $! > "{pidfile}"; sleep 100'])
    start = time.monotonic()
    message = failure(command, timeout=0.5)
    assert time.monotonic() - start < 3
    assert "did not finish within 0.5 s; it and every process it started were killed" in message
    pids = [int(p) for p in pidfile.read_text().split()]
    assert len(pids) == 2 and wait_gone(pids)


def test_timeout_kills_a_command_that_ignores_sigterm(tmp_path: Path) -> None:
    pidfile = tmp_path / "pid"
    code = (
        "import os, signal, sys, time; signal.signal(signal.SIGTERM, signal.SIG_IGN); "
        f"open({str(pidfile)!r}, 'w').write(str(os.getpid())); time.sleep(100)"
    )
    start = time.monotonic()
    assert "did not finish within 0.3 s" in failure(py(code), timeout=0.3)
    assert time.monotonic() - start < 3
    assert wait_gone([int(pidfile.read_text())])


def test_an_interrupt_ends_the_command_and_what_it_started(tmp_path: Path) -> None:
    """The command runs in a session of its own, so a Ctrl-C at the terminal does not reach it:
    the interrupt of verify must end it."""
    pidfile = tmp_path / "pids"
    command = shlex.join(["sh", "-c", f'sleep 100 & echo $$ $! > "{pidfile}"; sleep 100'])

    def interrupt(signum: int, frame: object) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.4)
        with pytest.raises(KeyboardInterrupt):
            run_implementation(command, "", 20)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    assert wait_gone([int(p) for p in pidfile.read_text().split()])


# -- the note for --help ----------------------------------------------------------------------


def test_impl_note_is_one_line_saying_how_the_command_is_run() -> None:
    assert "\n" not in IMPL_NOTE and "not run by a shell" in IMPL_NOTE and "sh -c" in IMPL_NOTE


def test_split_command_splits_like_a_shell_without_expanding() -> None:
    assert split_command("./s $HOME *.json 'a|b' > out") == ["./s", "$HOME", "*.json", "a|b", ">", "out"]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGHUP])
def test_sigterm_and_sighup_stop_oracle_check_and_every_process_of_impl(tmp_path: Path, sig: signal.Signals) -> None:
    """What CI cancellation and ``timeout`` send: verify ends as for Ctrl-C (one line, 128 + the signal's
    number), and neither the command nor what it started is left running; the JUnit file says so."""
    pidfile = tmp_path / "pids"
    impl = shlex.join(["sh", "-c", f'sleep 100 & echo $$ $! > "{pidfile}"; sleep 100'])
    cases = Path(__file__).resolve().parents[2] / "golden" / "cases.json"
    argv = [PY, "-m", "verify", "oracle", "check", str(cases), "--impl", impl, "--junit", str(tmp_path / "j.xml")]
    proc = subprocess.Popen(
        argv, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(sig, signal.SIG_DFL),  # noqa: PLW1509 (as from a terminal: not ignored)
    )  # fmt: skip
    try:
        until = time.monotonic() + 60
        while not (pidfile.exists() and len(pidfile.read_text().split()) == 2) and time.monotonic() < until:
            time.sleep(0.05)
        pids = [int(p) for p in pidfile.read_text().split()]
        proc.send_signal(sig)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 128 + sig, err
    assert err == f"verify: terminated ({sig.name})\n" and out == ""
    assert wait_gone(pids)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["j.xml", "pids"]  # no temporary file left
    assert f'message="terminated ({sig.name})"' in (tmp_path / "j.xml").read_text()


def test_sigterm_stops_a_pool_run_without_a_traceback_or_a_worker_left(tmp_path: Path) -> None:
    """The pool's processes inherit verify's handler; SIGTERM (sent to verify alone, as CI does) ends them too."""
    argv = [PY, "-m", "verify", "sweep", "--cases", "400000", "--workers", "2"]
    proc = subprocess.Popen(
        argv, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGTERM, signal.SIG_DFL),  # noqa: PLW1509 (as from a terminal)
    )  # fmt: skip
    try:
        until, workers = time.monotonic() + 60, []
        while len(workers) < 2 and time.monotonic() < until:
            time.sleep(0.1)
            children = Path(f"/proc/{proc.pid}/task/{proc.pid}/children")
            workers = [int(p) for p in children.read_text().split()] if children.exists() else []
        time.sleep(1)
        proc.send_signal(signal.SIGTERM)
        sent = time.monotonic()
        _, err = proc.communicate(timeout=60)
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert len(workers) >= 2
    assert took < GRACE, f"{took:.1f} s: the clean-up hung and the watchdog ended verify"
    assert proc.returncode == 143 and err.endswith("verify: terminated (SIGTERM)\n") and "Traceback" not in err, err
    assert wait_gone(workers, within=10)
