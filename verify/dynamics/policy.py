"""How a run of the rule stops, and what it returns: written once for every engine.

A run stops with ``"exit"`` when no constraint is hit (the engine's own test), or, before
an impulse that would exceed them, at the :class:`Limits`: ``"max_iterations"`` after
``max_iterations`` impulses, ``"budget"`` when the numbers outgrow ``bits`` or the run
outlasts ``seconds`` (the checks in this order, at the same impulse on every engine).
The traced engine (:mod:`verify.laws.rule`) and the integer engine
(:mod:`verify.laws.loops.integer`) return a :class:`Run`.

>>> limits = Limits(3, bits=8)
>>> limits.stop(2, lambda: 5), limits.stop(2, lambda: 9), limits.stop(3, lambda: 9)
(None, 'budget', 'max_iterations')
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal, Protocol, TypeAlias, get_args, runtime_checkable

from verify import bounds

#: a JSON value: what a certificate, a case record and a result record hold
JSONValue: TypeAlias = str | int | float | bool | list["JSONValue"] | dict[str, "JSONValue"] | None
JSONObject: TypeAlias = dict[str, JSONValue]

#: how a run stops (a result record's ``stop``): no constraint is hit any more; the paper's almost-equal stop
#: (paper mode); the cap on impulses; proved never to exit (with a certificate); a size or time budget ran out
Stop = Literal["exit", "aeev", "max_iterations", "non_terminating", "budget"]
STOPS: tuple[Stop, ...] = get_args(Stop)


@dataclass(frozen=True)
class Halted:
    """A stop test's answer when it stops a run: the stop and, for ``non_terminating``, its certificate."""

    stop: Stop
    certificate: JSONObject | None = None


@runtime_checkable
class Halt(Protocol):
    """A stop test: called with (system, velocity) before each impulse, once an impact is known to remain;
    returns :class:`Halted` to stop the run, or None to go on. The system it is given answers
    ``rates(velocity)`` with the rates the run holds (zeros known exactly included), so a stop test decides
    the same signs as the run. With ``after_impulse`` it is instead called right after each impulse, before
    the exit check (so it can stop a run that would exit)."""

    @property
    def after_impulse(self) -> bool: ...

    def __call__(self, system: Any, v: Sequence[Any], /) -> Halted | None: ...


@dataclass(frozen=True)
class StopTest:
    """A :class:`Halt` made of a function (``after_impulse`` False unless given).

    >>> test = StopTest(lambda system, v: Halted("aeev") if v[0] == v[1] else None)
    >>> test(None, [1, 1]), test(None, [1, 2]), test.after_impulse
    (Halted(stop='aeev', certificate=None), None, False)
    """

    test: Callable[[Any, Sequence[Any]], Halted | None]
    after_impulse: bool = False

    def __call__(self, system: Any, v: Sequence[Any], /) -> Halted | None:
        return self.test(system, v)


def as_halt(test: Halt | Callable[[Any, Sequence[Any]], Any]) -> Halt:
    """A stop test as a run calls it: a :class:`Halt` as it is, or a plain function (0.2's stop tests: it returns
    a stop's name, a pair (stop, certificate), or None) wrapped in a :class:`StopTest`. The plain form is read
    in 0.3 only.

    >>> halted = as_halt(lambda system, v: "aeev" if v[0] == v[1] else None)
    >>> halted(None, [2, 2]), halted(None, [1, 2]), halted.after_impulse
    (Halted(stop='aeev', certificate=None), None, False)
    """
    if isinstance(test, Halt):
        return test

    def halted(system: Any, v: Sequence[Any]) -> Halted | None:
        out = test(system, v)
        if out is None or isinstance(out, Halted):
            return out
        return Halted(*out) if isinstance(out, tuple) else Halted(out)

    return StopTest(halted)


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

    def stop(self, impulses: int, size: Callable[[], int]) -> Stop | None:
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
    (:class:`verify.laws.rule.Step`, when recorded) and the certificate of a stop test."""

    v: tuple[Any, ...]
    stop: Stop
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
