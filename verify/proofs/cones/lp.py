"""Membership in a finitely generated cone, decided exactly: is y a non-negative combination of
given vectors?

The question is a linear program: find ``d >= 0`` with ``sum_k d_k g_k = y``. :func:`feasible`
answers it by the first phase of the revised simplex method (artificial variables, Bland's rule, so it
cannot cycle), over any exact backend: every comparison is a sign the backend decides. The
coefficients it returns belong to a basis, so they are found again by one exact solve of
independent columns (:func:`solve_columns`), which is how a parameter backend uses it: the
basis is searched at one rational value of the parameter, then solved for the whole range.

>>> from fractions import Fraction
>>> from verify.numbers.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> g = [[K.one, K.zero], [K.one, K.one], [K.zero, K.one]]
>>> sorted((k, str(d)) for k, d in feasible(K, [K.convert(Fraction(3)), K.one], g).items())
[(0, '2'), (1, '1')]
>>> feasible(K, [K.convert(Fraction(-1)), K.one], g) is None
True
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from operator import mul
from typing import Any

from verify.errors import Undecided
from verify.numbers.backends.base import Backend
from verify.numbers.linalg import matvec

#: [pivots left, pivots allowed] to the search under way (:func:`pivot_budget`), or None: no bound
_LEFT: ContextVar[list[int] | None] = ContextVar("pivots_left", default=None)


class SearchTooLong(Undecided):
    """A search spent its budget of pivots (:func:`pivot_budget`): it found nothing within it."""


@contextmanager
def pivot_budget(pivots: int) -> Iterator[list[int]]:
    """Within the block, the simplex and the eliminations may pivot ``pivots`` times in all; the next pivot
    raises :class:`SearchTooLong`. A bound on the work of a search that counts steps, not seconds: the
    same on every machine. The block gets ``[pivots left, pivots allowed]``.

    >>> from fractions import Fraction
    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> with pivot_budget(0):
    ...     solve_columns(K, [[K.convert(Fraction(2)), K.zero]], [K.one, K.zero])
    Traceback (most recent call last):
    ...
    verify.proofs.cones.lp.SearchTooLong: the search spent its 0 pivots
    """
    left = [pivots, pivots]
    token = _LEFT.set(left)
    try:
        yield left
    finally:
        _LEFT.reset(token)


def solve_columns(K: Backend, columns: Sequence[Sequence[Any]], y: Sequence[Any]) -> list[Any] | None:
    """The coefficients c with ``sum c_k columns[k] = y`` (columns independent), or None when
    the columns are dependent or y is not in their span (exact elimination).

    >>> from fractions import Fraction
    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> [str(c) for c in solve_columns(K, [[K.convert(Fraction(2)), K.zero]], [K.one, K.zero])]
    ['1/2']
    """
    n, m = len(y), len(columns)
    rows = [[columns[k][i] for k in range(m)] + [y[i]] for i in range(n)]
    at = 0
    for col in range(m):
        p = next((i for i in range(at, n) if rows[i][col] != K.zero), None)
        if p is None:
            return None
        rows[at], rows[p] = rows[p], rows[at]
        _pivot(K, rows, at, col)
        at += 1
    if any(rows[i][m] != K.zero for i in range(at, n)):
        return None
    return [rows[i][m] for i in range(m)]


def feasible(
    K: Backend, y: Sequence[Any], gens: Sequence[Sequence[Any]], *, scaled: Scaled | None = None
) -> dict[int, Any] | None:
    """Non-negative coefficients ``{k: d_k}`` (the non-zero ones) with ``y = sum d_k gens[k]``, or None
    when there are none (decided exactly: phase one of the simplex method).

    The simplex is the revised one: it keeps the inverse of the basis (rows x rows) and the right-hand
    side, and computes a column only when it needs it, from the generators as given. Its reduced costs,
    ratios and so its pivots (Bland's rule) are those of the full tableau; only the numbers it does not
    need are not computed, and the ones it does keep do not grow with every pivot.

    >>> from fractions import Fraction
    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> g = [[K.one, K.zero], [K.convert(Fraction(-1)), K.one]]
    >>> sorted((k, str(d)) for k, d in feasible(K, [K.zero, K.convert(Fraction(2))], g).items())
    [(0, '2'), (1, '2')]

    ``scaled`` (over the rationals) keeps each generator's integer form by the generator's ``id``, for a caller
    that asks about the same generators many times (:func:`verify.proofs.cones.period.close`): the generators
    must then stay alive and unchanged while it keeps the dict.
    """
    if K.rationals:
        return _feasible_integers(K, y, gens, {} if scaled is None else scaled)
    n, m = len(y), len(gens)
    zero, one = K.zero, K.one
    # each row i is multiplied by -1 where y_i < 0, so that the right-hand side starts >= 0
    flip = [K.sign(x) < 0 for x in y]
    cols = [[(zero - g[i]) if flip[i] else g[i] for i in range(n)] for g in gens]
    rhs = [(zero - x) if f else x for x, f in zip(y, flip)]
    inverse = [[one if k == i else zero for k in range(n)] for i in range(n)]
    basis = [m + i for i in range(n)]  # the artificial variables start in the basis
    while True:
        entering = _entering(cols, inverse, basis, one, lambda c: K.sign(c) < 0)
        if entering is None:
            break
        a = matvec(K, inverse, cols[entering]) if entering < m else [row[entering - m] for row in inverse]
        leave, best = None, None
        for i in range(n):
            if K.sign(a[i]) > 0:
                ratio = rhs[i] / a[i]
                if leave is None or K.sign(ratio - best) < 0 or (ratio == best and basis[i] < basis[leave]):
                    leave, best = i, ratio
        if leave is None:  # unbounded: cannot happen in phase one (the objective is bounded below)
            return None
        _spend()
        piv = a[leave]
        inverse[leave] = [v / piv for v in inverse[leave]]
        rhs[leave] = rhs[leave] / piv
        for i in range(n):
            if i != leave and a[i] != zero:
                inverse[i] = [u - a[i] * w for u, w in zip(inverse[i], inverse[leave])]
                rhs[i] = rhs[i] - a[i] * rhs[leave]
        basis[leave] = entering
    if any(basis[i] >= m and rhs[i] != zero for i in range(n)):
        return None  # an artificial variable stays positive: no combination
    return {basis[i]: rhs[i] for i in range(n) if basis[i] < m and rhs[i] != zero}


#: the integer form of generators (:func:`_integers`), by ``id``: the generator itself (kept alive, so that its id
#: stays its own), its integer form and its scale
Scaled = dict[int, tuple[Sequence[Any], list[Any], Any]]


def _integers(values: Sequence[Any]) -> tuple[list[Any], int]:
    """Integers ``L * values`` and ``L``, the least common denominator (a positive factor). The integers are
    the backend's own (``int``, gmpy2's ``mpz``, flint's ``fmpz``: exact, and GMP's for long ones)."""
    denominators = [v.denominator for v in values]
    if all(d == 1 for d in denominators):
        return [v.numerator for v in values], 1
    common = math.lcm(*denominators)
    return [v.numerator * (common // d) for v, d in zip(values, denominators)], common


def _feasible_integers(
    K: Backend, y: Sequence[Any], gens: Sequence[Sequence[Any]], scaled: Scaled
) -> dict[int, Any] | None:
    """:func:`feasible` over the rationals, fraction-free: the same pivots, the same coefficients.

    Each generator and y are scaled to integers by positive factors (which changes no sign of a reduced cost
    and no order of the ratios, only the coefficients, scaled back at the end). The inverse of the basis is
    kept as its adjugate over its determinant D (> 0: each pivot is positive), with the right-hand side over
    the same D; a pivot updates them by integer steps whose division by the old D is exact (Bareiss), so no
    gcd is taken until the end."""
    n, m = len(y), len(gens)
    flip = [K.sign(x) < 0 for x in y]
    b, rhs_scale = _integers(y)
    rhs = [-v if f else v for v, f in zip(b, flip)]
    cols, scales = [], []
    for g in gens:
        found = scaled.get(id(g))
        if found is None or found[0] is not g:  # an id is a generator's only while it lives: the entry keeps it
            found = scaled[id(g)] = (g, *_integers(g))
        _, column, scale = found
        cols.append([-v if f else v for v, f in zip(column, flip)] if any(flip) else column)
        scales.append(scale)
    adjugate = [[1 if k == i else 0 for k in range(n)] for i in range(n)]
    det = 1
    basis = [m + i for i in range(n)]  # the artificial variables start in the basis
    while (entering := _entering(cols, adjugate, basis, det, lambda c: c < 0)) is not None:
        if entering < m:
            a = [sum(map(mul, row, cols[entering])) for row in adjugate]
        else:
            a = [row[entering - m] for row in adjugate]
        leave = None
        for i in range(n):  # the least ratio rhs_i / a_i over a_i > 0, ties to the least basic index (Bland)
            if a[i] > 0:
                if leave is None:
                    leave = i
                    continue
                this, best = rhs[i] * a[leave], rhs[leave] * a[i]
                if this < best or (this == best and basis[i] < basis[leave]):
                    leave = i
        if leave is None:  # unbounded: cannot happen in phase one (the objective is bounded below)
            return None
        _spend()
        piv, row, r = a[leave], adjugate[leave], rhs[leave]
        for i in range(n):
            if i != leave:
                adjugate[i] = [(u * piv - a[i] * w) // det for u, w in zip(adjugate[i], row)]
                rhs[i] = (rhs[i] * piv - a[i] * r) // det
        det = piv
        basis[leave] = entering
    if any(basis[i] >= m and rhs[i] != 0 for i in range(n)):
        return None  # an artificial variable stays positive: no combination
    return {basis[i]: K.from_integers(rhs[i] * scales[basis[i]], det * rhs_scale)
            for i in range(n) if basis[i] < m and rhs[i] != 0}  # fmt: skip


def _entering(
    cols: list[list[Any]], inverse: list[list[Any]], basis: list[int], one: Any, negative: Callable[[Any], bool]
) -> int | None:
    """The first column whose reduced cost for minimising the sum of the artificial variables is negative
    (Bland's rule), or None: the cost of column j is ``-pi . a_j``, plus ``one`` for an artificial one, where
    pi sums the rows of the inverse whose basic variable is artificial. On the fraction-free tableau of
    :func:`_feasible_integers` the inverse is the adjugate and ``one`` the determinant: every cost times it."""
    n, m = len(inverse), len(cols)
    zero = one - one
    pi = [zero] * n
    for i in range(n):
        if basis[i] >= m:
            pi = [p + r for p, r in zip(pi, inverse[i])]
    basic = set(basis)
    for j in range(m + n):
        if j in basic:
            continue
        cost = (zero - sum(map(mul, pi, cols[j]), zero)) if j < m else (one - pi[j - m])
        if negative(cost):
            return j
    return None


def _spend() -> None:
    """Count one pivot against the budget of :func:`pivot_budget` (if any); raise when it is spent."""
    left = _LEFT.get()
    if left is not None:
        left[0] -= 1
        if left[0] < 0:
            raise SearchTooLong(f"the search spent its {left[1]} pivots")


def _pivot(K: Backend, rows: list[list[Any]], r: int, c: int) -> None:
    """Scale row r so that its entry in column c is 1, and clear column c from every other row."""
    _spend()
    piv = rows[r][c]
    rows[r] = [v / piv for v in rows[r]]
    for i in range(len(rows)):
        if i != r and rows[i][c] != K.zero:
            f = rows[i][c]
            rows[i] = [a - f * b for a, b in zip(rows[i], rows[r])]
