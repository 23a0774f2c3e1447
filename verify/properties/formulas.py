"""The paper's impulse formulas as printed, in plain Fractions, for cross-checks.

This module is deliberately independent of the engine (:mod:`verify.laws.rule`,
:mod:`verify.dynamics.system`, :mod:`verify.numbers.linalg`, the backends): it recomputes one impulse
from the raw inputs (mass matrix g, normals a_i, time terms, CORs) with its own Gaussian
elimination, so that the property suite can compare the engine with eqs. (4)-(8)
written the way the paper writes them:

- ``V_i = (p(F_i) / (a_i g^-1 a_i^T)) g^-1 a_i^T`` (the orthogonal velocity w.r.t. S_i);
- ``V_J``: the Phi-orthogonal projection of p - H onto span{g^-1 a_j : j in J};
- ``beta = Phi(V_J, sum V_j) / ||sum V_j||^2``;
- eq. (4) ``-(1 + e) V_j``; eq. (5) ``-2 beta (V_1 + V_2)``; eq. (6)
  ``-(1 + e) beta (V_1 + V_2)``; eq. (7) ``-beta ((1 + e_1) V_1 + (1 + e_2) V_2)``; eq. (8)
  ``-beta sum (1 + e_j) V_j``.

>>> g = [[1, 0], [0, 1]]
>>> [str(x) for x in printed_impulse("4", (g, [[-1, 1]], [0], ["1/2"]), [100, 0], [0])]
['-75', '75']
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

EQUATIONS = ("4", "5", "6", "7", "8")


def _q(x: Any) -> Fraction:
    return x if isinstance(x, Fraction) else Fraction(x)


def solve_linear(A: Sequence[Sequence[Any]], b: Sequence[Any]) -> list[Fraction]:
    """Solve ``A x = b`` exactly by Gaussian elimination with pivoting on non-zero entries.

    >>> solve_linear([[0, 1], [2, 0]], [3, 4])
    [Fraction(2, 1), Fraction(3, 1)]
    """
    n = len(A)
    M = [[_q(x) for x in row] + [_q(b[i])] for i, row in enumerate(A)]
    for c in range(n):
        p = next(i for i in range(c, n) if M[i][c] != 0)
        M[c], M[p] = M[p], M[c]
        for i in range(n):
            if i != c and M[i][c] != 0:
                f = M[i][c] / M[c][c]
                M[i] = [x - f * y for x, y in zip(M[i], M[c])]
    return [M[i][n] / M[i][i] for i in range(n)]


def phi(g: Sequence[Sequence[Any]], x: Sequence[Any], y: Sequence[Any]) -> Fraction:
    """The metric ``Phi(x, y) = x^T g y``."""
    return sum((_q(g[i][j]) * _q(x[i]) * _q(y[j]) for i in range(len(x)) for j in range(len(y))), Fraction(0))


def rate(normal: Sequence[Any], time_term: Any, v: Sequence[Any]) -> Fraction:
    """``p(F) = dF/dt + dF . v``."""
    return _q(time_term) + sum((_q(a) * _q(x) for a, x in zip(normal, v)), Fraction(0))


def orthogonal_velocity(g: Any, normal: Sequence[Any], time_term: Any, v: Sequence[Any]) -> list[Fraction]:
    """``V_i(p) = (p(F_i) / (a_i g^-1 a_i^T)) g^-1 a_i^T``."""
    u = solve_linear(g, normal)
    c = rate(normal, time_term, v) / sum((_q(a) * x for a, x in zip(normal, u)), Fraction(0))
    return [c * x for x in u]


def global_orthogonal_velocity(
    g: Any, normals: Sequence[Sequence[Any]], time_terms: Sequence[Any], v: Sequence[Any], J: Sequence[int]
) -> list[Fraction]:
    """``V_J(p) = sum_k mu_k g^-1 a_k`` with ``a_j . V_J = p(F_j)`` for every j in J."""
    U = [solve_linear(g, normals[k]) for k in J]
    G = [[sum((_q(a) * x for a, x in zip(normals[j], u)), Fraction(0)) for u in U] for j in J]
    mu = solve_linear(G, [rate(normals[j], time_terms[j], v) for j in J])
    n = len(v)
    return [sum((m * u[i] for m, u in zip(mu, U)), Fraction(0)) for i in range(n)]


def printed_beta(g: Any, normals: Any, time_terms: Any, v: Sequence[Any], J: Sequence[int]) -> Fraction:
    """``beta = Phi(V_J, sum V_j) / ||sum V_j||^2`` (Sect. 3.2 and 3.5 c)."""
    W = _sum([orthogonal_velocity(g, normals[j], time_terms[j], v) for j in J], len(v))
    return phi(g, global_orthogonal_velocity(g, normals, time_terms, v, J), W) / phi(g, W, W)


def _sum(vectors: Sequence[Sequence[Fraction]], n: int) -> list[Fraction]:
    return [sum((w[i] for w in vectors), Fraction(0)) for i in range(n)]


def printed_impulse(equation: str, inputs: Sequence[Any], v: Sequence[Any], J: Sequence[int]) -> list[Fraction]:
    """The impulse of eq. ``equation`` ("4" ... "8") for the impact set J, as printed.

    ``inputs`` is ``(g, normals, time_terms, restitution)``.

    Eq. (4) needs |J| = 1, eqs. (5)-(7) |J| = 2 (they are printed for two constraints; (5)
    and (6) use ``restitution[J[0]]``, which must equal the other COR for (6) and be 1 for
    (5)), eq. (8) any non-empty J.
    """
    g, normals, time_terms, restitution = inputs
    n = len(v)
    V = {j: orthogonal_velocity(g, normals[j], time_terms[j], v) for j in J}
    e = {j: _q(restitution[j]) for j in J}
    if equation == "4":
        (j,) = J
        return [-(1 + e[j]) * x for x in V[j]]
    if equation in ("5", "6", "7") and len(J) != 2:
        raise ValueError(f"eq. ({equation}) is printed for two constraints, got J = {list(J)}")
    b = printed_beta(g, normals, time_terms, v, J) if len(J) >= 2 else Fraction(1)
    if equation == "5":
        return [-2 * b * x for x in _sum(list(V.values()), n)]
    if equation == "6":
        return [-(1 + e[J[0]]) * b * x for x in _sum(list(V.values()), n)]
    if equation in ("7", "8"):
        return [-b * x for x in _sum([[(1 + e[j]) * x for x in V[j]] for j in J], n)]
    raise ValueError(f"unknown equation {equation!r} (one of {', '.join(EQUATIONS)})")


def kernel(rows: Sequence[Sequence[Any]]) -> list[list[Fraction]]:
    """A basis of the vectors c with ``row . c = 0`` for every row (reduced row echelon form).

    >>> kernel([[-1, 1, 0], [0, -1, 1]])
    [[Fraction(1, 1), Fraction(1, 1), Fraction(1, 1)]]
    """
    M = [[_q(x) for x in row] for row in rows]
    n = len(M[0]) if M else 0
    pivots: list[int] = []
    r = 0
    for c in range(n):
        p = next((i for i in range(r, len(M)) if M[i][c] != 0), None)
        if p is None:
            continue
        M[r], M[p] = M[p], M[r]
        M[r] = [x / M[r][c] for x in M[r]]
        for i in range(len(M)):
            if i != r and M[i][c] != 0:
                M[i] = [x - M[i][c] * y for x, y in zip(M[i], M[r])]
        pivots.append(c)
        r += 1
    basis = []
    for free in (c for c in range(n) if c not in pivots):
        vec = [Fraction(0)] * n
        vec[free] = Fraction(1)
        for i, c in enumerate(pivots):
            vec[c] = -M[i][free]
        basis.append(vec)
    return basis
