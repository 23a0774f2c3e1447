"""How much of each bound inside the algorithms the runs use: recorded here, below every layer, by the algorithms.

A bound here is chosen for users: large enough for every search the tests and the ci census make, small
enough that a search which cannot succeed gives up in seconds. Each is a constant of the module that uses it,
named in the catalogue :data:`verify.report.bounds.BOUNDS` (read it there; a bound a user may want to move is
also an option of the command line: ``--max-bits``, ``--max-impulses``, ``--lines``).

A use is recorded when it stays within the bound (the largest use is what the bound must allow), and
the times the bound was reached apart. How much of each bound a command uses is measured, not guessed:
with the environment variable ``VERIFY_BOUNDS`` naming a file, every process of the command appends a
line there each time one of its peaks grows, and each time a bound is reached (a line of JSON, one
``write`` each, so that the test processes and the census workers may share the file).
``verify bounds FILE`` prints the table: the value of each bound, the largest amount a run used, and
how often it was reached. Without the variable nothing is recorded (one test of a global per use).

>>> with recording() as seen:
...     use("pivots", 12)
...     use("pivots", 5)
>>> seen["pivots"]
12
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from contextlib import contextmanager

_PATH = os.environ.get("VERIFY_BOUNDS") or None
_PEAKS: dict[str, int] | None = {} if _PATH else None
_LISTENERS: list[dict[str, int]] = []


def use(name: str, amount: int) -> None:
    """Record that a run used ``amount`` of the bound ``name`` (a key of :data:`BOUNDS`). Free
    unless recording (``VERIFY_BOUNDS`` or :func:`recording`)."""
    if _PEAKS is None and not _LISTENERS:
        return
    for seen in _LISTENERS:
        seen[name] = max(seen.get(name, amount), amount)
    if _PEAKS is not None and not _LISTENERS and amount > _PEAKS.get(name, -1):
        _PEAKS[name] = amount
        _write({"bound": name, "peak": amount})


def reached(name: str) -> None:
    """Record that a run reached the bound ``name`` (and gave up, or changed its way, as
    :data:`BOUNDS` says)."""
    if _PEAKS is None and not _LISTENERS:
        return
    for seen in _LISTENERS:
        seen[f"{name}:reached"] = seen.get(f"{name}:reached", 0) + 1
    if _PEAKS is not None and not _LISTENERS:
        _write({"bound": name, "reached": 1})


def _write(line: dict[str, object]) -> None:
    """Append one line to the file of ``VERIFY_BOUNDS`` (one ``write``: whole lines from many processes)."""
    assert _PATH is not None
    fd = os.open(_PATH, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
    try:
        os.write(fd, (json.dumps(line, sort_keys=True) + "\n").encode())
    finally:
        os.close(fd)


@contextmanager
def recording() -> Iterator[dict[str, int]]:
    """Within the block, the peaks of this process (``name``) and the bounds reached (``name:reached``,
    a count), in the dict yielded; nothing is written to the file of ``VERIFY_BOUNDS`` meanwhile (a
    test that moves a bound on purpose does not count as a use).

    >>> from verify.proofs.termination import MAX_PERIOD
    >>> with recording() as seen:
    ...     reached("period")
    >>> seen
    {'period:reached': 1}
    """
    seen: dict[str, int] = {}
    _LISTENERS.append(seen)
    try:
        yield seen
    finally:
        _LISTENERS.remove(seen)
