"""The plain loop of the rule over Fractions: the baseline of ``verify bench`` for general systems.

What a careful user would write first, with no engine: ``U = g^-1 A^T`` by Gauss-Jordan
elimination and ``G = A U`` once per geometry (:func:`plain_geometry`), then eqs. (2), (4) and (8)
on the velocity, one impulse after the other (:func:`plain_run`), in whatever numbers it is
given (``fractions.Fraction`` in the bench). It shares no code with :mod:`verify.laws`, so it is
also an independent check: the bench compares every branch sequence with the engine's.
:func:`verify.models.corner.paper_run` is the corner's own plain loop (the paper's closed forms).

>>> from fractions import Fraction as F
>>> geometry = plain_geometry([[F(1), F(0), F(0)], [F(0), F(1), F(0)], [F(0), F(0), F(1)]],
...                           [[F(-1), F(1), F(0)], [F(0), F(-1), F(1)]])
>>> sets, v = plain_run(geometry, [F(0), F(0)], [F(1, 2), F(1, 2)], [F(100), F(0), F(0)], 100)
>>> sets, [str(x) for x in v]
([(0,), (1,), (0,)], ['325/16', '375/16', '225/4'])
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

Geometry = tuple[list[list[Any]], list[list[Any]], list[list[Any]]]


def plain_geometry(g: Sequence[Sequence[Any]], A: Sequence[Sequence[Any]]) -> Geometry:
    """``(A, U, G)``: the normals, ``U_j = g^-1 A_j`` (rows) and the Gram matrix ``G = A g^-1 A^T``."""
    n, r = len(g), len(A)
    # Gauss-Jordan on [g | A^T]: g is symmetric positive definite, so no pivoting is needed
    M = [list(g[i]) + [A[j][i] for j in range(r)] for i in range(n)]
    for c in range(n):
        p = M[c][c]
        M[c] = [x / p for x in M[c]]
        for i in range(n):
            if i != c and M[i][c] != 0:
                f = M[i][c]
                M[i] = [x - f * y for x, y in zip(M[i], M[c])]
    U = [[M[i][n + j] for i in range(n)] for j in range(r)]
    G = [[sum(a * u for a, u in zip(A[i], U[j])) for j in range(r)] for i in range(r)]
    return [list(row) for row in A], U, G


def plain_run(
    geometry: Geometry, time_terms: Sequence[Any], cors: Sequence[Any], v: Sequence[Any], max_iterations: int
) -> tuple[list[tuple[int, ...]], list[Any]]:
    """The rule from velocity ``v``: (the impact sets, the velocity after the last impulse)."""
    A, U, G = geometry
    r, n = len(A), len(v)
    v = list(v)
    sets: list[tuple[int, ...]] = []
    for _ in range(max_iterations + 1):
        b = [time_terms[i] + sum(a * x for a, x in zip(A[i], v)) for i in range(r)]
        J = tuple(i for i in range(r) if b[i] < 0)
        if not J or len(sets) == max_iterations:
            break
        lam = {j: b[j] / G[j][j] for j in J}
        if len(J) == 1:
            beta = 1
        else:
            norm = sum(lam[j] * G[j][k] * lam[k] for j in J for k in J)
            beta = sum(b[j] * lam[j] for j in J) / norm
        for j in J:
            c = beta * (1 + cors[j]) * lam[j]
            v = [x - c * u for x, u in zip(v, U[j])]
        sets.append(J)
    return sets, v[:n]


def bare_rates_run(
    g: Sequence[Sequence[Any]],
    A: Sequence[Sequence[Any]],
    cors: Sequence[Any],
    v: Sequence[Any],
    max_iterations: int,
    *,
    number: Any,
) -> tuple[list[tuple[int, ...]], list[Any]]:
    """The rule in rate coordinates written out bare, for a *diagonal* mass matrix: every input
    converted by ``number`` (gmpy2's ``mpq`` in the bench), nothing validated, no object built.

    Not an engine: a bound on what Python code can reach when it computes what the general
    engine computes (``U``, ``G``, the rates, the impulses, the exit velocity) on short runs,
    where the set-up of each case is most of the work.

    >>> from fractions import Fraction as F
    >>> one, zero = F(1), F(0)
    >>> g = [[one, zero, zero], [zero, one, zero], [zero, zero, one]]
    >>> normals = [[-one, one, zero], [zero, -one, one]]
    >>> sets, v = bare_rates_run(g, normals, [F(1, 2)] * 2, [F(100), zero, zero], 9, number=F)
    >>> sets, [str(x) for x in v]
    ([(0,), (1,), (0,)], ['325/16', '375/16', '225/4'])
    """
    n, r = len(g), len(A)
    A = [[number(x) for x in row] for row in A]
    d = [number(g[i][i]) for i in range(n)]
    e = [number(x) for x in cors]
    v = [number(x) for x in v]
    U = [[a / d[k] for k, a in enumerate(row)] for row in A]
    G = [[sum(a * u for a, u in zip(A[i], U[j])) for j in range(r)] for i in range(r)]
    b = [sum(a * x for a, x in zip(row, v)) for row in A]
    mu = [0] * r
    sets: list[tuple[int, ...]] = []
    while len(sets) < max_iterations:
        J = tuple(i for i in range(r) if b[i] < 0)
        if not J:
            break
        lam = {j: b[j] / G[j][j] for j in J}
        beta = (
            1 if len(J) == 1 else sum(b[j] * lam[j] for j in J) / sum(lam[j] * G[j][k] * lam[k] for j in J for k in J)
        )
        for j in J:
            c = -beta * (1 + e[j]) * lam[j]
            b = [b[i] + G[i][j] * c for i in range(r)]
            mu[j] += c
        sets.append(J)
    return sets, [v[k] + sum(mu[j] * U[j][k] for j in range(r)) for k in range(n)]
