"""Running another implementation (``verify oracle check --impl COMMAND``) safely.

The command is split into words the way a shell would split it (quotes and backslashes work) but
it is *not* run by a shell (:data:`IMPL_NOTE`). It runs in a session of its own with the case file
on stdin; its stdout, the result file, is read while it runs and refused as soon as it passes
``max_output`` bytes, so that a runaway writer cannot fill the memory. On a timeout, a refused
output or an interrupt, every process it started is ended (SIGTERM, then SIGKILL after a short
grace), and so are the processes it leaves behind when it exits. Every failure is one line of
:class:`~verify.errors.InvalidInput` that says what went wrong and what to do.
"""

from __future__ import annotations

import contextlib
import errno
import os
import selectors
import shlex
import shutil
import signal
import subprocess
import time

from verify.errors import InvalidInput
from verify.records.files import MAX_FILE_BYTES

#: one line for ``--help`` and the documentation: how ``--impl`` is run
IMPL_NOTE = (
    "--impl is split into words like a shell command (quotes work) but not run by a shell: "
    "no pipes, redirections, variables or globs; use --impl \"sh -c '...'\" if you need them"
)

#: the largest stdout accepted by default (the size limit of every JSON file read)
MAX_OUTPUT = MAX_FILE_BYTES

#: how much of the end of stderr is kept (for the last line quoted in errors)
STDERR_TAIL = 64 * 1024

#: seconds between SIGTERM and SIGKILL when the process group is ended
GRACE = 0.5

#: the longest wait between two checks of whether the command has exited (seconds)
POLL = 0.05

_CHUNK = 64 * 1024


def run_implementation(command: str, case_text: str, timeout: float, *, max_output: int = MAX_OUTPUT) -> str:
    """Run ``command`` with ``case_text`` on stdin and return its stdout, decoded as UTF-8.

    ``command`` is split like a shell command but not run by a shell (:data:`IMPL_NOTE`). A
    command that cannot be started, that exits with a non-zero code or is killed by a signal,
    that takes longer than ``timeout`` seconds, that writes more than ``max_output`` bytes or
    output that is not UTF-8, raises :class:`~verify.errors.InvalidInput` with a one-line message.
    Every process the command started is ended before this returns or raises.

    >>> import shlex, sys
    >>> count = shlex.join([sys.executable, "-c", "import sys; print(len(sys.stdin.read()))"])
    >>> run_implementation(count, "abc", 10)
    '3\\n'
    >>> run_implementation(shlex.join([sys.executable, "-c", "import os; os.abort()"]), "", 10)
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: --impl: ... was killed by signal 6 (SIGABRT)
    """
    argv = split_command(command)
    proc = _start(argv)
    try:
        out, err = _exchange(proc, case_text.encode("utf-8"), command=command, timeout=timeout, max_output=max_output)
    finally:
        _end_group(proc)
    if proc.returncode != 0:
        raise InvalidInput(_status_message(command, proc.returncode, err))
    try:
        return out.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InvalidInput(
            f"--impl: the output of {command!r} is not UTF-8 text "
            f"(byte 0x{out[exc.start]:02x} at offset {exc.start}); a result file must be UTF-8 JSON"
        ) from None


def split_command(command: str) -> list[str]:
    """The words of ``command``, split like a shell would split them (:data:`IMPL_NOTE`).

    >>> split_command("./solver --json 'my cases.json'")
    ['./solver', '--json', 'my cases.json']
    >>> split_command("./solver 'oops")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: --impl: cannot split "./solver 'oops" into words (no closing quotation); ...
    """
    try:
        argv = shlex.split(command)
    except ValueError as exc:
        raise InvalidInput(
            f"--impl: cannot split {command!r} into words ({str(exc).lower()}); --impl is split like a shell "
            "command but not run by a shell (no pipes or redirections): balance the quotes, and use "
            "--impl \"sh -c '...'\" if you need a shell"
        ) from None
    if not argv:
        raise InvalidInput("--impl: empty command")
    return argv


#: the process groups of the commands running now (each ended by :func:`_end_group`)
RUNNING: set[int] = set()


def kill_running() -> None:
    """SIGKILL to every command still running and what it started (the last resort of a stopped verify)."""
    for pgid in list(RUNNING):
        _signal_group(pgid, signal.SIGKILL)


def _start(argv: list[str]) -> subprocess.Popen[bytes]:
    """The started process (in a new session, so that its whole group can be ended)."""
    try:
        proc = subprocess.Popen(
            argv,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            start_new_session=True,
            bufsize=0,
        )
    except OSError as exc:
        raise InvalidInput(start_error_message(argv[0], exc)) from None
    RUNNING.add(proc.pid)
    return proc


def start_error_message(program: str, exc: OSError) -> str:
    """One line that says why ``program`` could not be started (``exc``) and what to do.

    >>> start_error_message("./no-such-solver", FileNotFoundError(2, "No such file or directory"))
    "--impl: no such file: './no-such-solver'"
    """
    path = program if os.sep in program else shutil.which(program)  # a command found on PATH: its file
    if exc.errno == errno.ENOENT:
        if path is None:
            return (
                f"--impl: command not found: {program!r} (it is not on PATH; give its path, "
                f"such as ./{program}, for a program in the current directory)"
            )
        if not os.path.lexists(path):
            return f"--impl: no such file: {path!r}"
        head = _head(path)
        if head.startswith(b"#!"):
            line = head[2:].split(b"\n")[0].decode("utf-8", "replace").strip()
            return (
                f"--impl: cannot run {path!r}: its #! line names a program that does not exist ({line!r}); "
                "fix its first line, such as #!/usr/bin/env python3"
            )
        return f"--impl: cannot run {path!r}: a program it needs to start does not exist (built for another system?)"
    if exc.errno == errno.ENOEXEC:
        if path is not None and not _is_binary(_head(path)):
            return (
                f"--impl: cannot run {path!r}: it is a script without a #! line; add a first line such as "
                f"#!/usr/bin/env python3, or name its interpreter first: --impl 'python3 {path}'"
            )
        return f"--impl: cannot run {program!r}: exec format error (not a program for this system)"
    if exc.errno == errno.EACCES and path is not None:
        if os.path.isdir(path):
            return f"--impl: {path!r} is a directory, not a program; give the path of the program in it"
        if os.path.isfile(path) and not os.access(path, os.X_OK):
            return (
                f"--impl: {path!r} is not executable; make it so with chmod +x {shlex.quote(path)} "
                f"(or, for a script, name its interpreter first: --impl 'python3 {path}')"
            )
        return f"--impl: cannot run {path!r}: permission denied (is it on a file system mounted noexec?)"
    return f"--impl: cannot run {program!r}: {exc.strerror or exc}"


def _head(path: str) -> bytes:
    """The first bytes of the file ``path`` (empty if it cannot be read)."""
    try:
        with open(path, "rb") as fh:
            return fh.read(256)
    except OSError:
        return b""


def _is_binary(head: bytes) -> bool:
    """Whether ``head``, the start of a file, looks like a compiled program rather than a script."""
    magics = (b"\x7fELF", b"\xfe\xed\xfa", b"\xce\xfa\xed\xfe", b"\xcf\xfa\xed\xfe", b"\xca\xfe\xba\xbe", b"MZ")
    return head.startswith(magics) or b"\0" in head


def _exchange(
    proc: subprocess.Popen[bytes], data: bytes, *, command: str, timeout: float, max_output: int
) -> tuple[bytearray, bytes]:
    """Write ``data`` to the process's stdin while reading its stdout (at most ``max_output`` bytes)
    and the end of its stderr, until it exits; returns (stdout, stderr tail)."""
    assert proc.stdin is not None and proc.stdout is not None and proc.stderr is not None
    deadline = time.monotonic() + timeout
    out = bytearray()  # grown in place: its peak is the cap, and it is decoded without a copy
    err = bytearray()
    view = memoryview(data)
    with selectors.DefaultSelector() as sel:
        sel.register(proc.stdout, selectors.EVENT_READ)
        sel.register(proc.stderr, selectors.EVENT_READ)
        if view:
            os.set_blocking(proc.stdin.fileno(), False)
            sel.register(proc.stdin, selectors.EVENT_WRITE)
        else:
            proc.stdin.close()
        exited = False
        while True:
            exited = exited or _has_exited(proc)
            left = deadline - time.monotonic()
            if left <= 0 and not exited:
                raise InvalidInput(
                    f"--impl: {command!r} did not finish within {timeout:g} s; it and every process it "
                    "started were killed (--impl-time-limit sets the limit)"
                )
            if exited and (left <= 0 or not sel.get_map()):
                break
            if not sel.get_map():  # it closed its stdout and stderr but runs on
                time.sleep(min(left, POLL))
                continue
            ready = sel.select(0 if exited else min(left, POLL))
            if not ready and exited:
                break  # it has exited and everything it wrote has been read (what it left running is ended)
            for key, _ in ready:
                if key.fileobj is proc.stdin:
                    view = _write_some(sel, proc, view)
                    continue
                chunk = os.read(key.fd, _CHUNK)
                if not chunk:
                    sel.unregister(key.fileobj)
                elif key.fileobj is proc.stdout:
                    out += chunk
                    if len(out) > max_output:
                        raise InvalidInput(
                            f"--impl: {command!r} wrote more than {_size(max_output)} on stdout and was stopped; "
                            "a result file must be smaller"
                        )
                else:
                    err += chunk
                    del err[:-STDERR_TAIL]
    return out, bytes(err)


def _write_some(sel: selectors.BaseSelector, proc: subprocess.Popen[bytes], view: memoryview) -> memoryview:
    """Write what the stdin pipe takes of ``view``; close stdin when all is written or when the
    process closed its end (a command that does not read its input is not an error)."""
    assert proc.stdin is not None
    try:
        view = view[os.write(proc.stdin.fileno(), view[:_CHUNK]) :]
    except BlockingIOError:
        return view
    except BrokenPipeError:
        view = view[:0]
    if not view:
        sel.unregister(proc.stdin)
        proc.stdin.close()
    return view


def _has_exited(proc: subprocess.Popen[bytes]) -> bool:
    """Whether the process has exited, without reaping it where the system allows (so that its
    process group id cannot be reused before the group is ended)."""
    if proc.returncode is not None:
        return True
    waitid = getattr(os, "waitid", None)
    if waitid is None:  # macOS before Python 3.13
        return proc.poll() is not None
    try:
        return waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None
    except ChildProcessError:
        return proc.poll() is not None


def _end_group(proc: subprocess.Popen[bytes]) -> None:
    """End every process of the command's group (SIGTERM, then SIGKILL after :data:`GRACE` seconds
    if the command itself is still running), reap the command and close its pipes."""
    if not _has_exited(proc):
        _signal_group(proc.pid, signal.SIGTERM)
        until = time.monotonic() + GRACE
        while not _has_exited(proc) and time.monotonic() < until:
            time.sleep(0.01)
    _signal_group(proc.pid, signal.SIGKILL)  # also the processes it left behind
    RUNNING.discard(proc.pid)
    for pipe in (proc.stdin, proc.stdout, proc.stderr):
        if pipe is not None:
            pipe.close()
    proc.wait()


def _signal_group(pgid: int, sig: signal.Signals) -> None:
    """Send ``sig`` to the process group ``pgid`` (nothing if it is already gone)."""
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pgid, sig)


def _status_message(command: str, code: int, err: bytes) -> str:
    """The one-line error for a command that ended with the status ``code`` (negative: a signal)."""
    lines = err.decode("utf-8", "replace").strip().splitlines()
    last = "".join(c if c.isprintable() else "?" for c in lines[-1].strip())[:300] if lines else ""
    if code < 0:
        try:
            name = f"signal {-code} ({signal.Signals(-code).name})"
        except ValueError:
            name = f"signal {-code}"
        return f"--impl: {command!r} was killed by {name}" + (f": {last}" if last else "")
    return f"--impl: {command!r} exited with code {code}: " + (last or "(nothing on stderr)")


def _size(n: int) -> str:
    """``n`` bytes for a message: ``67108864 bytes (64 MiB)``."""
    return f"{n} bytes ({n / 2**20:g} MiB)" if n >= 2**20 else f"{n} bytes"
