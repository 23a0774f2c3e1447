"""The rule in rate coordinates, on an exact backend: a run costs O(r) an impulse, not O(n).

Every impulse of the rule is a combination ``sum_j c_j U_j`` of the Phi-normals (eq. 8), and
``dF_i . U_j = G_ij``, so it changes the rates (eq. 2) by the Gram matrix alone:
``p'(F_i) = p(F_i) + sum_j G_ij c_j`` (moving constraints too: their time terms do not
change). The iteration therefore needs only the r rates and G:

- a single impact on j (eq. 4): ``c_j = -(1 + e_j) p(F_j) / G_jj``, after which
  ``p'(F_j) = -e_j p(F_j)`` and ``p'(F_i) = p(F_i) + G_ij c_j``;
- a multiple impact on J (eq. 8): ``c_j = -beta (1 + e_j) p(F_j) / G_jj`` with beta read
  off the rates (:func:`beta_from_rates`), and ``p'(F_i) = p(F_i) + sum_j G_ij c_j``.

The coefficients are summed over the run (``mu_j``), and the velocity is formed once, at the
end: ``v = v0 + sum_j mu_j U_j``. On an exact backend these are the same numbers as the
velocity form's (:func:`verify.laws.rule._iterate`), only fewer operations: the tests check
the two against each other. The run stops like every engine's
(:mod:`verify.dynamics.policy`); the size budget is measured on the velocity, which is
formed only when a budget asks for it.

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
from typing import TYPE_CHECKING, Any, Protocol

from verify.dynamics.policy import Halt, Halted, Limits, Run

if TYPE_CHECKING:
    from verify.dynamics.system import System
    from verify.numbers.backends.base import Backend


class SearchSystem(Protocol):
    """What the rate form and the cone search read of a system: a :class:`~verify.dynamics.system.System`, or
    the same system at the sample value of its parameters (``verify.proofs.cones.period``'s ``_Sampled``)."""

    @property
    def backend(self) -> Backend: ...

    @property
    def gram(self) -> Sequence[Sequence[Any]]: ...

    @property
    def restitution(self) -> Sequence[Any]: ...

    @property
    def inverse_gram_diag(self) -> Sequence[Any]: ...

    @property
    def r(self) -> int: ...


def beta_from_rates(system: SearchSystem, b: Sequence[Any], J: Sequence[int]) -> Any:
    """beta of step c) from the rates ``b = p(F)``, computed in the basis (U_j) without solving
    the Gram system.

    With ``lambda_j = p(F_j)/G_jj``, ``sum V_j = sum lambda_j U_j``, so
    ``||sum V_j||^2 = lambda^T G_JJ lambda``; and ``Phi(V_J, U_k) = p(F_k)`` for k in J
    (``V_J = sum mu_k U_k`` with ``G_JJ mu = p(F_J)``), so ``Phi(V_J, sum V_j) = sum_j
    p(F_j) lambda_j``: the Gram solve of V_J is not needed for beta.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    >>> str(beta_from_rates(s, s.rates(s.velocity(["1", "0", "-1"])), (0, 1)))
    '2'
    """
    inv = system.inverse_gram_diag
    lam = [b[j] * inv[j] for j in J]
    numerator: Any = None
    norm: Any = None
    for a, (j, lj) in enumerate(zip(J, lam)):
        term = b[j] * lj
        numerator = term if numerator is None else numerator + term
        row = system.gram[j]
        g_lam = row[j] * lj  # the j-th entry of G_JJ lambda, times lambda_j below
        for k, lk in zip(J[a + 1 :], lam[a + 1 :]):
            g_lam = g_lam + (row[k] + row[k]) * lk  # G symmetric: off-diagonal terms twice
        norm = lj * g_lam if norm is None else norm + lj * g_lam
    return numerator / norm


def coefficients(system: System, b: Sequence[Any], J: tuple[int, ...]) -> tuple[list[tuple[int, Any]], Any]:
    """The impulse of eq. (8) on J from the rates ``b``, as ``([(j, c_j), ...], beta or None)``:
    the impulse is ``sum_j c_j U_j``.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0], [0, 1]], [[-1, 1]], ["1/2"])
    >>> [(j, str(c)) for j, c in coefficients(s, s.rates(s.velocity(["100", "0"])), (0,))[0]]
    [(0, '75')]
    """
    if len(J) == 1:
        (j,) = J
        return [(j, system.single_coefficient[j] * b[j])], None
    bt = beta_from_rates(system, b, J)
    m, inv = system.minus_one_plus_e, system.inverse_gram_diag
    return [(j, bt * m[j] * (b[j] * inv[j])) for j in J], bt


def velocity(system: System, v0: Sequence[Any], mu: Sequence[Any]) -> tuple[Any, ...]:
    """``v0 + sum_j mu_j U_j`` (``None`` in ``mu`` for a constraint that took no impulse)."""
    return moved(system, v0, [(j, c) for j, c in enumerate(mu) if c is not None])


def moved(system: System, v: Sequence[Any], pairs: Sequence[tuple[int, Any]]) -> tuple[Any, ...]:
    """``v + sum_j c_j U_j`` over the pairs ``(j, c_j)``: the velocity after an impulse."""
    out = list(v)
    for j, c in pairs:
        for k, u in system.sparse_U[j]:
            out[k] = out[k] + c * u
    return tuple(out)


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
