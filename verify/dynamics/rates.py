"""The rule in rate coordinates: the closed forms a run in rates uses, and the cone search too.

Every impulse of the rule is a combination ``sum_j c_j U_j`` of the Phi-normals (eq. 8), and
``dF_i . U_j = G_ij``, so it changes the rates (eq. 2) by the Gram matrix alone:
``p'(F_i) = p(F_i) + sum_j G_ij c_j`` (moving constraints too: their time terms do not
change). The iteration therefore needs only the r rates and G:

- a single impact on j (eq. 4): ``c_j = -(1 + e_j) p(F_j) / G_jj``, after which
  ``p'(F_j) = -e_j p(F_j)`` and ``p'(F_i) = p(F_i) + G_ij c_j``;
- a multiple impact on J (eq. 8): ``c_j = -beta (1 + e_j) p(F_j) / G_jj`` with beta read
  off the rates (:func:`beta_from_rates`), and ``p'(F_i) = p(F_i) + sum_j G_ij c_j``.

The coefficients are summed over the run (``mu_j``), and the velocity is formed once, at the
end: ``v = v0 + sum_j mu_j U_j`` (:func:`velocity`). The loop itself is
:func:`verify.laws.loops.rates.iterate`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

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
