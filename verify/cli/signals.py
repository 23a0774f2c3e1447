"""SIGTERM and SIGHUP stop ``verify`` as Ctrl-C does.

CI cancellation, ``timeout`` and a closed terminal send SIGTERM or SIGHUP, not SIGINT. While a
command runs, each raises :class:`Terminated` (a ``KeyboardInterrupt``) in the main thread, so the
same clean-up runs as for Ctrl-C: the processes ``--impl`` started are ended, a local pool's
processes are stopped, an output file being written is not left half-written; the command line
then prints one line and exits with the shell's code for the signal (128 + its number: 143 for
SIGTERM, 129 for SIGHUP). A signal that was ignored when ``verify`` started (``nohup``) stays
ignored.
"""

from __future__ import annotations

import contextlib
import os
import signal
import threading
from collections.abc import Iterator

#: the signals that stop a command as Ctrl-C does
STOPPING = (signal.SIGTERM, signal.SIGHUP)
#: seconds the clean-up may take after the signal; then every process started is killed and verify exits (an
#: exception raised by a signal handler can land inside a lock's acquisition and leave a wait that never ends)
GRACE = 10.0


class Terminated(KeyboardInterrupt):
    """A command stopped by SIGTERM or SIGHUP (``signum``)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum
        self.watchdog: threading.Timer | None = None  # set when a signal raised it in this process

    @property
    def exit_code(self) -> int:
        """The shell's code for the signal: 128 + its number."""
        return 128 + self.signum

    @property
    def name(self) -> str:
        """The signal's name (``SIGTERM``)."""
        return signal.Signals(self.signum).name


def finish(stop: Terminated) -> None:
    """The clean-up of a signal is done (the exception reached the command line): exit now, with the signal's
    code, when a signal raised ``stop`` in this process; the interpreter's own shutdown, which joins the threads
    of a pool that was not waited for, is skipped. (A ``Terminated`` raised otherwise, as by a test, returns.)"""
    import sys

    if stop.watchdog is None:
        return
    stop.watchdog.cancel()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    os._exit(stop.exit_code)


def _hard_exit(stop: Terminated) -> None:
    """The clean-up did not end within :data:`GRACE` seconds: kill what was started, and exit now."""
    import multiprocessing
    import sys

    from verify.oracle.impl import kill_running

    kill_running()
    for child in multiprocessing.active_children():
        with contextlib.suppress(OSError, ValueError, AttributeError):
            child.kill()
    with contextlib.suppress(OSError, ValueError):
        sys.stderr.write(f"verify: terminated ({stop.name})\n")
        sys.stderr.flush()
    os._exit(stop.exit_code)


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP raise :class:`Terminated` (once: a second signal while the
    first one's clean-up runs is ignored). Outside the main thread, nothing changes.

    >>> stop = Terminated(signal.SIGHUP)
    >>> isinstance(stop, KeyboardInterrupt), stop.name, stop.exit_code
    (True, 'SIGHUP', 129)

    (``tests/oracle/test_impl_runner.py`` sends each signal to a ``verify`` process.)
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in STOPPING}
    ours = [s for s, handler in previous.items() if handler is signal.SIG_DFL]  # an ignored one stays ignored
    owner = os.getpid()

    def stop(signum: int, _frame: object) -> None:
        if os.getpid() != owner:  # a process forked from this one (a pool's): it ends as by default
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        for s in ours:
            signal.signal(s, signal.SIG_IGN)
        stop = Terminated(signum)
        stop.watchdog = threading.Timer(GRACE, _hard_exit, (stop,))
        stop.watchdog.daemon = True
        stop.watchdog.start()
        raise stop

    for s in ours:
        signal.signal(s, stop)
    try:
        yield
    finally:
        for s in ours:
            signal.signal(s, previous[s])
