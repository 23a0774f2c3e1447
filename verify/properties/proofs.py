"""Symbolic proofs (checked by SymPy) of the properties that are identities.

Each proof works in the basis ``U_j = g^-1 a_j`` of the orthogonal velocities, where
``Phi(U_j, U_k) = G_jk`` (the Gram matrix), ``V_j = lambda_j U_j`` with
``lambda_j = p(F_j) / G_jj``, and ``V_J = sum mu_k U_k`` with ``G_JJ mu = (p(F_j))_j``
(:mod:`verify.laws.rule`). A proof returns the sentence it proves, or None when no identity
covers the rule (the property is then only tested). Every identity is checked with
symbols for G and the rates, for impact sets of two and three constraints.

>>> prove("beta_one", "general")
'beta = 1 when one rate is non-zero, for any Gram matrix (the other V_k = 0), |J| = 1, 2, 3 (checked by SymPy)'
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache
from typing import Any

import sympy as sp


def _gram(h: int, orthogonal: bool = False) -> sp.Matrix:
    return sp.Matrix(h, h, lambda i, j: sp.Symbol(f"G{min(i, j)}{max(i, j)}") if i == j or not orthogonal else 0)


def _parts(h: int, orthogonal: bool = False, rates: list[Any] | None = None) -> tuple[Any, ...]:
    G = _gram(h, orthogonal)
    b = sp.Matrix(rates if rates is not None else sp.symbols(f"b0:{h}"))
    lam = sp.Matrix([b[j] / G[j, j] for j in range(h)])
    mu = G.LUsolve(b)
    return G, lam, mu


def _beta(G: sp.Matrix, lam: sp.Matrix, mu: sp.Matrix) -> sp.Expr:
    return (mu.T * G * lam)[0] / (lam.T * G * lam)[0]


def _zero(expr: sp.Expr) -> bool:
    return bool(sp.cancel(sp.together(expr)) == 0)


def _energy(rule: str) -> str | None:
    """One COR e: Delta K = -(1 - e^2)/2 beta^2 ||W||^2 per impulse (W = sum V_j).

    With I = -(1 + e) beta W: Delta K = Phi(p - H, I) + ||I||^2 / 2, and
    Phi(p - H, W) = Phi(V_J, W) = beta ||W||^2 (p - H - V_J is orthogonal to every U_j).
    """
    if rule not in ("ideal", "symmetric"):
        return None
    for h in (1, 2, 3):
        G, lam, mu = _parts(h)
        beta = _beta(G, lam, mu)
        e = sp.Integer(1) if rule == "ideal" else sp.Symbol("e")
        W2 = (lam.T * G * lam)[0]
        pW = (mu.T * G * lam)[0]  # Phi(p - H, W) = Phi(V_J, W)
        delta = -(1 + e) * beta * pW + (1 + e) ** 2 * beta**2 * W2 / 2
        if not _zero(delta + (1 - e**2) / 2 * beta**2 * W2):  # pragma: no cover - the algebra would be wrong
            return None
    if rule == "ideal":
        return "Delta K = 0 per impulse: the ideal rule conserves kinetic energy, |J| = 1, 2, 3 (checked by SymPy)"
    return (
        "Delta K = -(1 - e^2)/2 beta^2 ||sum V_j||^2 <= 0 per impulse for e in [0, 1], |J| = 1, 2, 3 (checked by SymPy)"
    )


def _energy_change(rule: str) -> str | None:
    """Any CORs: Delta K = -beta sum (1 + e_j) lambda_j p(F_j) + beta^2/2 ||sum (1 + e_j) V_j||^2.

    So a multiple impulse raises the kinetic energy exactly when
    ``beta ||sum (1 + e_j) V_j||^2 > 2 sum (1 + e_j) p(F_j)^2 / G_jj``; a single impulse
    (beta = 1) and equal CORs never do (both sides then compare 1 + e with 2).
    """
    for h in (2, 3):
        G, lam, mu = _parts(h)
        beta = _beta(G, lam, mu)
        e = sp.Matrix(sp.symbols(f"e0:{h}"))
        b = sp.Matrix(sp.symbols(f"b0:{h}"))  # the rates (G mu = b)
        c = sp.Matrix([(1 + e[j]) * lam[j] for j in range(h)])  # the impulse is -beta sum c_j U_j
        pI = -beta * (mu.T * G * c)[0]  # Phi(p - H, I) = Phi(V_J, I)
        delta = pI + beta**2 * (c.T * G * c)[0] / 2
        claimed = -beta * sum((1 + e[j]) * lam[j] * b[j] for j in range(h)) + beta**2 / 2 * (c.T * G * c)[0]
        if not _zero(delta - claimed):  # pragma: no cover
            return None
    return (
        "Delta K = -beta sum (1 + e_j) p(F_j)^2/G_jj + beta^2/2 ||sum (1 + e_j) V_j||^2 (checked by SymPy): the "
        "energy rises at an impulse exactly when beta ||sum (1 + e_j) V_j||^2 > 2 sum (1 + e_j) p(F_j)^2/G_jj, "
        "which never happens at a single impact or with equal CORs"
    )


def energy_increase_criterion(inputs: Any, v: Any, J: Any) -> tuple[Any, ...]:
    """Both sides of the criterion of the energy change identity, for one impulse (Fractions).

    ``inputs`` is ``(g, normals, time_terms, restitution)``; the energy rises iff lhs > rhs.

    >>> cradle = ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0], [0, 1])
    >>> energy_increase_criterion(cradle, [0, -1, -3], (0, 1))
    (Fraction(65, 6), Fraction(9, 1))
    """
    from fractions import Fraction

    from verify.properties import formulas

    g, normals, time_terms, restitution = inputs
    beta = formulas.printed_beta(g, normals, time_terms, v, J)
    n = len(v)
    parts = {j: formulas.orthogonal_velocity(g, normals[j], time_terms[j], v) for j in J}
    c = [sum(((1 + Fraction(restitution[j])) * parts[j][i] for j in J), Fraction(0)) for i in range(n)]
    lhs = beta * formulas.phi(g, c, c)
    rhs = 2 * sum(((1 + Fraction(restitution[j])) * formulas.phi(g, parts[j], parts[j]) for j in J), Fraction(0))
    return lhs, rhs


@cache
def _simultaneous_energy_identity() -> bool:
    """Whether SymPy confirms the identity of :func:`_simultaneous_energy` (rule-independent).

    The active set's equations ``G lambda = -q`` give the rates from the impulses:
    ``w_i = -(G lambda)_i / (1 + e_i)`` incoming, ``w_i = -(G lambda)_i`` otherwise (G is
    invertible), so every identity is checked with symbols for G, lambda and the CORs.
    """
    for h in (1, 2, 3):
        G = _gram(h)
        lam, e = sp.Matrix(sp.symbols(f"l0:{h}")), sp.symbols(f"e0:{h}")
        for k in range(h + 1):  # the first k constraints are incoming
            Gl = G * lam
            w = sp.Matrix([-Gl[i] / (1 + e[i]) if i < k else -Gl[i] for i in range(h)])
            out = w + Gl
            delta = (lam.T * w)[0] + (lam.T * G * lam)[0] / 2
            half_sum = sum(lam[i] * (w[i] + out[i]) for i in range(h)) / 2
            split = sum((1 - e[i]) * lam[i] * w[i] if i < k else lam[i] * w[i] for i in range(h)) / 2
            if not (_zero(delta - half_sum) and _zero(delta - split)):  # pragma: no cover
                return False
    return True


def _simultaneous_energy(rule: str) -> str | None:
    """The simultaneous law (:mod:`verify.laws.simultaneous`), any CORs: the energy change of its impulse.

    The impulse is ``sum lambda_i U_i``, so ``Delta K = Phi(p - H, I) + ||I||^2 / 2 = lambda . w +
    lambda^T G lambda / 2`` (w the rates), and the exit rates are ``w' = w + G lambda``: hence
    ``Delta K = 1/2 sum lambda_i (w_i + w'_i)``. On its active set S the law solves
    ``w'_S = w_S - q_S`` (``q_i = (1 + e_i) w_i`` incoming, ``w_i`` otherwise), so an incoming
    constraint contributes ``(1 - e_i) lambda_i w_i / 2 <= 0`` and one that is not incoming
    ``lambda_i w_i / 2 >= 0`` (S of 1, 2, 3 constraints, every split into incoming and not).
    """
    if not _simultaneous_energy_identity():  # pragma: no cover - the algebra would be wrong
        return None
    head = (
        "Delta K = 1/2 sum lambda_i (w_i + w'_i) = 1/2 sum_incoming (1 - e_i) lambda_i w_i + "
        "1/2 sum_not incoming lambda_i w_i, on active sets of 1, 2, 3 constraints (checked by SymPy): "
    )
    if rule == "ideal":
        return head + (
            "with every COR 1 the first sum is 0, so the law never loses energy, and gains it exactly "
            "when a separating constraint (w_i > 0) takes an impulse"
        )
    return head + (
        "the incoming constraints lose energy, the energy rises only when a separating constraint "
        "(w_i > 0) takes an impulse, by more than the incoming ones dissipate"
    )


def simultaneous_energy_terms(constraints: Any, v: Any, v_out: Any, impulses: Any) -> tuple[Any, ...]:
    """The two sums of the simultaneous law's energy change (Fractions, from the raw inputs):
    ``1/2 sum lambda_i (w_i + w'_i)`` over the constraints that are not incoming (``w_i >= 0``),
    then over the incoming ones; the energy rises iff the first exceeds minus the second.

    ``constraints`` is ``(normals, time_terms)``; ``v``, ``v_out`` the velocity before and after.

    >>> cradle = ([[-1, 1, 0], [0, -1, 1]], [0, 0])
    >>> simultaneous_energy_terms(cradle, [1, 0, "1/10"], ["-3/10", "7/10", "7/10"], ["13/10", "3/5"])
    (Fraction(3, 100), Fraction(0, 1))
    """
    from fractions import Fraction

    from verify.properties import formulas

    sums = [Fraction(0), Fraction(0)]  # not incoming, incoming
    for a, t, lam in zip(*constraints, impulses):
        w, w_out = formulas.rate(a, t, v), formulas.rate(a, t, v_out)
        sums[w < 0] += Fraction(lam) * (w + w_out) / 2
    return sums[0], sums[1]


def _beta_one(rule: str) -> str | None:
    """beta = 1 when only one rate of J is non-zero: Phi(V_J, V_j) = lambda_j p(F_j)."""
    for h in (1, 2, 3):
        rates = [sp.Symbol("b0")] + [0] * (h - 1)
        G, lam, mu = _parts(h, rates=rates)
        if not _zero(_beta(G, lam, mu) - 1):  # pragma: no cover
            return None
    return (
        "beta = 1 when one rate is non-zero, for any Gram matrix (the other V_k = 0), |J| = 1, 2, 3 (checked by SymPy)"
    )


def _single(rule: str) -> str | None:
    if _beta_one(rule) is None:  # pragma: no cover
        return None
    return "for J = {j}: V_J = V_j, beta = 1, so eq. (8) is -(1 + e_j) V_j, eq. (4) (checked by SymPy)"


def _orthogonal(rule: str) -> str | None:
    """G diagonal: mu = lambda, V_J = sum V_j, beta = 1, eq. (8) = -sum (1 + e_j) V_j."""
    for h in (2, 3):
        G, lam, mu = _parts(h, orthogonal=True)
        if not (_zero(_beta(G, lam, mu) - 1) and all(_zero(m - x) for m, x in zip(mu, lam))):  # pragma: no cover
            return None
    return (
        "Phi(U_j, U_k) = 0 for j != k gives V_J = sum V_j and beta = 1: eq. (8) is -sum (1 + e_j) V_j, "
        "which is -(1 + e) V_J for equal CORs, |J| = 2, 3 (checked by SymPy)"
    )


def _reduction(equal: str) -> Callable[[str], str | None]:
    def prove_it(rule: str) -> str | None:
        e = sp.symbols("e0:3")
        V = sp.symbols("V0:3")  # the components of eq. (8) along V_j: linear, so scalars suffice
        beta = sp.Symbol("beta")
        eq8 = -beta * sum((1 + e[j]) * V[j] for j in range(2))
        printed = {
            "ideal": (-2 * beta * (V[0] + V[1]), {e[0]: 1, e[1]: 1}),
            "symmetric": (-(1 + e[0]) * beta * (V[0] + V[1]), {e[1]: e[0]}),
            "asymmetric": (-beta * ((1 + e[0]) * V[0] + (1 + e[1]) * V[1]), {}),
        }[equal]
        if not _zero(eq8.subs(printed[1]) - printed[0]):  # pragma: no cover
            return None
        return {
            "ideal": "eq. (8) with e_j = 1 is -2 beta sum V_j, eq. (5) (checked by SymPy)",
            "symmetric": "eq. (8) with e_j = e is -(1 + e) beta sum V_j, eq. (6) (checked by SymPy)",
            "asymmetric": "eq. (8) for two constraints is eq. (7) term by term (checked by SymPy)",
        }[equal]

    return prove_it


PROOFS: dict[str, Callable[[str], str | None]] = {
    "energy": _energy,
    "energy_change": _energy_change,
    "simultaneous_energy": _simultaneous_energy,
    "beta_one": _beta_one,
    "single": _single,
    "orthogonal": _orthogonal,
    "ideal": _reduction("ideal"),
    "symmetric": _reduction("symmetric"),
    "asymmetric": _reduction("asymmetric"),
}


@cache
def prove(name: str, rule: str) -> str | None:
    """The statement proved by proof ``name`` for ``rule``, or None if it does not apply."""
    return PROOFS[name](rule)
