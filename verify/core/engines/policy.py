"""How a run of the rule stops, and what it returns: written once for every engine.

A run stops with ``"exit"`` when no constraint is hit (the engine's own test), or, before
an impulse that would exceed them, at the :class:`Limits`: ``"max_iterations"`` after
``max_iterations`` impulses, ``"budget"`` when the numbers outgrow ``bits`` or the run
outlasts ``seconds`` (the checks in this order, at the same impulse on every engine).
The traced engine (:mod:`verify.core.rule`) and the integer engine
(:mod:`verify.core.engines.integer`) return a :class:`Run`.

>>> limits = Limits(3, bits=8)
>>> limits.stop(2, lambda: 5), limits.stop(2, lambda: 9), limits.stop(3, lambda: 9)
(None, 'budget', 'max_iterations')
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

from verify.core import bounds


@dataclass(frozen=True)
class Limits:
    """The stop policy of one run: at most ``max_iterations`` impulses, numbers of at most
    ``bits`` bits, at most ``seconds`` of wall time (from :meth:`start`)."""

    max_iterations: int
    bits: int | None = None
    seconds: float | None = None
    deadline: float | None = None  #: set by :meth:`start` when ``seconds`` is given

    def start(self) -> Limits:
        """These limits with the clock started now (kept if it already runs: phases of one
        run share one deadline)."""
        if self.seconds is None or self.deadline is not None:
            return self
        return replace(self, deadline=time.monotonic() + self.seconds)

    def capped(self, max_iterations: int) -> Limits:
        """The same limits (and deadline) with another cap on the impulses."""
        return replace(self, max_iterations=max_iterations)

    def exhausted(self, impulses: int) -> bool:
        """Whether ``impulses`` impulses reach the cap (stop ``"max_iterations"``)."""
        return impulses >= self.max_iterations

    def over_budget(self, size: Callable[[], int]) -> bool:
        """Whether the run is over budget; ``size()`` (asked only when ``bits`` is set) is the
        largest numerator-plus-denominator size of the velocity, in bits."""
        if self.bits is not None:
            used = size()
            if used > self.bits:
                bounds.reached("run_bits")
                return True
            bounds.use("run_bits", used)
        return self.deadline is not None and time.monotonic() > self.deadline

    def stop(self, impulses: int, size: Callable[[], int]) -> str | None:
        """The stop reason before the next impulse, after ``impulses`` of them while some
        constraint is still hit, or None to go on (see :meth:`over_budget` for ``size``)."""
        if self.exhausted(impulses):
            return "max_iterations"
        if self.over_budget(size):
            return "budget"
        return None


@dataclass(frozen=True)
class Run:
    """What an engine returns: the last velocity ``v`` (backend elements), the stop reason,
    the impact sets and betas (None for a single impact) of the impulses, the trace
    (:class:`verify.core.rule.Step`, when recorded) and the certificate of a stop test."""

    v: tuple[Any, ...]
    stop: str
    impact_sets: list[tuple[int, ...]]
    betas: list[Any]
    steps: tuple[Any, ...] = ()
    certificate: dict[str, Any] | None = field(default=None)
    #: on a backend that is not rigorous: (the first impulse decided on a rate below the working precision,
    #: that rate's size, the rates' size so far), or None
    doubt: tuple[int, Any, Any] | None = None

    def then(self, later: Run) -> Run:
        """This run continued by ``later`` (which started from this run's velocity)."""
        return Run(
            later.v,
            later.stop,
            self.impact_sets + later.impact_sets,
            self.betas + later.betas,
            self.steps + later.steps,
            later.certificate,
        )
