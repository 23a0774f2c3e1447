"""Tiny dense linear algebra on tuples, written against a backend ``K``.

Only what the rule needs: dot products, matrix-vector products, and solves with
symmetric positive definite matrices by an LDL^T factorisation whose pivots are tested
with ``K.sign`` (so the test is exact on exact backends and certified on intervals).

>>> from verify.numbers.backends import get_backend
>>> K = get_backend("exact")
>>> M = [[K.convert(Fraction(2)), K.one], [K.one, K.convert(Fraction(2))]]
>>> [str(x) for x in solve_spd(K, ldl(K, M), [K.one, K.zero])]
['2/3', '-1/3']
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction  # noqa: F401  (used by the doctest)
from typing import Any

from verify.numbers.backends.base import Backend

Vector = tuple[Any, ...]
Matrix = Sequence[Sequence[Any]]


class NotPositiveDefinite(Exception):
    """Raised by :func:`ldl` with the index and value of the first non-positive pivot."""

    def __init__(self, index: int, pivot: Any):
        super().__init__(index, pivot)
        self.index = index
        self.pivot = pivot


def dot(K: Backend, a: Sequence[Any], b: Sequence[Any]) -> Any:
    """The sum of ``a[i] * b[i]``."""
    total = K.zero
    for x, y in zip(a, b):
        total = total + x * y
    return total


def matvec(K: Backend, M: Matrix, v: Sequence[Any]) -> Vector:
    """``M v``."""
    return tuple(dot(K, row, v) for row in M)


def ldl(K: Backend, M: Matrix) -> tuple[list[list[Any]], list[Any]]:
    """``M = L D L^T`` with unit lower-triangular L; raises NotPositiveDefinite.

    Every pivot must have ``K.sign(d) > 0``: this is the positive-definiteness test.
    """
    n = len(M)
    L = [[K.zero] * n for _ in range(n)]
    D: list[Any] = []
    for j in range(n):
        d = M[j][j]
        for k in range(j):
            d = d - L[j][k] * L[j][k] * D[k]
        if K.sign(d) <= 0:
            raise NotPositiveDefinite(j, d)
        D.append(d)
        L[j][j] = K.one
        for i in range(j + 1, n):
            s = M[i][j]
            for k in range(j):
                s = s - L[i][k] * L[j][k] * D[k]
            L[i][j] = s / d
    return L, D


def solve_spd(K: Backend, factors: tuple[list[list[Any]], list[Any]], b: Sequence[Any]) -> Vector:
    """Solve ``M x = b`` given ``ldl(K, M)``."""
    L, D = factors
    n = len(D)
    y = list(b)
    for i in range(n):
        for k in range(i):
            y[i] = y[i] - L[i][k] * y[k]
    for i in range(n):
        y[i] = y[i] / D[i]
    for i in reversed(range(n)):
        for k in range(i + 1, n):
            y[i] = y[i] - L[k][i] * y[k]
    return tuple(y)
