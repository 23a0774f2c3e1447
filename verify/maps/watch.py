"""The budgets and the progress of a map (:class:`Watch`), shared by its lines and its cells."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.maps import DEFAULT_HALVINGS
from verify.numbers.format import format_decimal


@dataclass
class Watch:
    """The budgets and the progress of one map, shared by its lines: a wall-clock budget (``seconds``), a
    size budget (``max_parts``: parts decided, over all lines), the depth of the search for turning cones
    (``halvings``), a ``progress`` callback (a line of text:
    parts done, the measure decided so far, the deepest impulse) and, on Ctrl-C, the map decided so far.
    When the map stops early, ``stopped`` says why and every part not yet run is unexplored, with that
    reason; ``interrupted`` is True after Ctrl-C.

    >>> w = Watch(max_parts=0)
    >>> w.check(), w.stopped
    (True, 'the size budget of 0 parts was reached')
    """

    seconds: float | None = None
    max_parts: int | None = None
    progress: Callable[[str], None] | None = None
    #: how many times the search for turning cones below a boundary halves a piece (:mod:`verify.maps.turning`)
    halvings: int = DEFAULT_HALVINGS
    started: float = field(default_factory=time.monotonic)
    parts: int = 0
    decided: Fraction = Fraction(0)
    deepest: int = 0
    stopped: str = ""
    interrupted: bool = False

    def check(self) -> bool:
        """Whether the map must stop now (and ``stopped`` says why)."""
        if not self.stopped and self.max_parts is not None and self.parts >= self.max_parts:
            self.stopped = f"the size budget of {self.max_parts} parts was reached"
        if not self.stopped and self.seconds is not None and time.monotonic() - self.started >= self.seconds:
            shown = format_decimal(Fraction(self.seconds).limit_denominator(1000), 12)
            self.stopped = f"the wall-clock budget of {shown} s ran out"
        return bool(self.stopped)

    def done(self, part: Any) -> None:
        """Count a decided part (a :class:`~verify.maps.line.Part`: its length, a lower bound within 2e-9 of it)."""
        self.parts += 1
        self.deepest = max(self.deepest, part.iterations)
        if part.stop != "max_iterations":
            width = Fraction(1, 10**9)
            lower, upper = part.piece.lower.narrowed(width), part.piece.upper.narrowed(width)
            self.decided += max(Fraction(0), upper[0] - lower[1])
        if self.progress is not None:
            elapsed = round(time.monotonic() - self.started)  # the clock: a float, shown to the second
            self.progress(f"map: {self.parts} parts, decided a length of {format_decimal(self.decided, 6)}, "
                          f"deepest impulse {self.deepest}, {elapsed} s")  # fmt: skip
