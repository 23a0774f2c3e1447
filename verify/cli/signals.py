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
import signal
import threading
from collections.abc import Iterator

#: the signals that stop a command as Ctrl-C does
STOPPING = (signal.SIGTERM, signal.SIGHUP)


class Terminated(KeyboardInterrupt):
    """A command stopped by SIGTERM or SIGHUP (``signum``)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum

    @property
    def exit_code(self) -> int:
        """The shell's code for the signal: 128 + its number."""
        return 128 + self.signum

    @property
    def name(self) -> str:
        """The signal's name (``SIGTERM``)."""
        return signal.Signals(self.signum).name


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Within the block, SIGTERM and SIGHUP raise :class:`Terminated` (once: a second signal while the
    first one's clean-up runs is ignored). Outside the main thread, nothing changes.

    >>> import os
    >>> try:
    ...     with stop_on_signals():
    ...         os.kill(os.getpid(), signal.SIGTERM)
    ... except Terminated as stop:
    ...     print(stop.name, stop.exit_code)
    SIGTERM 143
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in STOPPING}
    ours = [s for s, handler in previous.items() if handler is signal.SIG_DFL]  # an ignored one stays ignored

    def stop(signum: int, _frame: object) -> None:
        for s in ours:
            signal.signal(s, signal.SIG_IGN)
        raise Terminated(signum)

    for s in ours:
        signal.signal(s, stop)
    try:
        yield
    finally:
        for s in ours:
            signal.signal(s, previous[s])
