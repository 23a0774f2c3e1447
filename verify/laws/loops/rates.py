"""The rule's loop in rate coordinates, on an exact backend: a run costs O(r) an impulse, not O(n).

The impulses act on the r rates through the Gram matrix alone, with the closed forms of
:mod:`verify.dynamics.rates`, and the velocity is formed once, at the end. On an exact backend these are the same
numbers as the velocity form's (:func:`verify.laws.rule._iterate`), only fewer operations: the tests check the
two against each other. The run stops like every loop's (:mod:`verify.dynamics.policy`); the size budget is
measured on the velocity, which is formed only when a budget asks for it.

>>> from verify.dynamics.policy import Limits
>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
>>> out = iterate(s, s.velocity(["100", "0", "0"]), Limits(10))
>>> [s.backend.to_exact(x) for x in out.v], out.impact_sets, out.stop
(['325/16', '375/16', '225/4'], [(0,), (1,), (0,)], 'exit')
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

from verify.dynamics.policy import Halt, Halted, Limits, Run
from verify.dynamics.rates import coefficients, moved, velocity
from verify.dynamics.system import System


class KnownRates:
    """The system as a stop test sees it during a run: ``rates(v)`` of the current velocity
    returns the rates the run holds (so a stop test asks the signs the run decided, zeros known
    exactly included); everything else is the system's own."""

    __slots__ = ("_b", "_system", "_v")

    def __init__(self, system: System, v: Sequence[Any], b: Sequence[Any]):
        self._system, self._v, self._b = system, v, b

    def rates(self, v: Sequence[Any]) -> tuple[Any, ...]:
        return tuple(self._b) if v is self._v else self._system.rates(v)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._system, name)


def _size(system: System, v0: Sequence[Any], mu: Sequence[Any], now: Sequence[Any] | None) -> int:
    """The size of the largest component of the velocity (``now``, or formed from ``v0`` and ``mu``)."""
    return max(system.backend.size(x) for x in (now if now is not None else velocity(system, v0, mu)))


def _stop_reason(halts: Sequence[Halt], system: Any, v: tuple[Any, ...]) -> Halted | None:
    """The first stop test that fires."""
    for h in halts:
        halted = h(system, v)
        if halted is not None:
            return halted
    return None


def iterate(
    system: System,
    v: Sequence[Any],
    limits: Limits,
    *,
    cap: int | None = None,
    halts: Sequence[Halt] = (),
    progress: Callable[[int], None] | None = None,
) -> Run:
    """Run the rule from ``v`` (backend elements of an exact backend) as
    :func:`verify.laws.rule.solve` does without a trace, within ``limits``, or ``cap`` impulses
    when it is smaller (the run then stops with ``"max_iterations"``).

    ``halts`` are stop tests (:data:`verify.laws.rule.Halt`), called as the traced loop calls
    them: before each impulse once an impact remains, or, with a true ``after_impulse``, right
    after each impulse. They need the velocity, which is then kept up to date (O(n) an impulse).
    ``progress`` is called with the number of impulses after each one.
    """
    K = system.backend
    sign, restitution = K.sign, system.restitution
    most = limits.max_iterations if cap is None else min(cap, limits.max_iterations)
    b = list(system.rates(v))
    r = len(b)
    mu: list[Any] = [None] * r
    columns = system.gram_columns
    impact_sets: list[tuple[int, ...]] = []
    betas: list[Any] = []
    watch = limits.bits is not None or limits.deadline is not None
    after = [h for h in halts if h.after_impulse]
    before = [h for h in halts if not h.after_impulse]
    now = tuple(v)  # the velocity, kept up to date only when a stop test needs it
    certificate = None
    while True:
        if after and impact_sets:
            halted = _stop_reason(after, system, now)
            if halted is not None:
                stop, certificate = halted.stop, halted.certificate
                break
        J = tuple([i for i in range(r) if sign(b[i]) < 0])
        if not J:
            stop = "exit"
            break
        if before:
            halted = _stop_reason(before, KnownRates(system, now, b), now)
            if halted is not None:
                stop, certificate = halted.stop, halted.certificate
                break
        if len(impact_sets) >= most:
            stop = "max_iterations"
            break
        if watch and limits.over_budget(partial(_size, system, v, mu, now if halts else None)):
            stop = "budget"
            break
        if len(J) == 1:
            (j,) = J
            c = system.single_coefficient[j] * b[j]
            for i, gij in columns[j]:
                b[i] = b[i] + gij * c
            b[j] = K.zero - restitution[j] * b[j]  # b_j + G_jj c_j, exactly
            mu[j] = c if mu[j] is None else mu[j] + c
            pairs: list[tuple[int, Any]] = [(j, c)]
            betas.append(None)
        else:
            pairs, bt = coefficients(system, b, J)
            for j, c in pairs:  # every c_j is computed from the rates before the impulse
                b[j] = b[j] + system.gram[j][j] * c
                for i, gij in columns[j]:
                    b[i] = b[i] + gij * c
                mu[j] = c if mu[j] is None else mu[j] + c
            betas.append(bt)
        impact_sets.append(J)
        if halts:
            now = moved(system, now, pairs)
        if progress is not None:
            progress(len(impact_sets))
    return Run(now if halts else velocity(system, v, mu), stop, impact_sets, betas, (), certificate)
