"""The float path: many cases at once in NumPy, every branch certified, exact fallback.

A batch holds N systems with the same numbers of constraints r and coordinates n. The
rule of :mod:`verify.core.rule` runs on all of them at once in *rate coordinates*: the state
of a case is its rates ``b = p(F)`` (eq. 2) and its velocity v, and an impulse
``sum_j c_j U_j`` (eq. 8) changes them by ``b += G c`` and ``v += U^T c``, with

- ``c_j = -(1 + e_j) b_j / G_jj`` for a single impact on j, whose own rate becomes
  exactly ``-e_j b_j`` (so a COR of 0 gives a rate of exactly 0, as in exact arithmetic);
- ``c_j = -beta (1 + e_j) lambda_j``, ``lambda_j = b_j / G_jj``, ``beta = sum_j b_j
  lambda_j / lambda^T G_JJ lambda`` for a multiple impact (the Gram identity of
  :func:`verify.core.rule._beta_from_rates`).

Every float carries a radius that bounds its distance to the exact value (midpoint-radius
arithmetic: each operation adds its own rounding error, ``u |z|`` with ``u = 2^-53``, and
the radii are inflated against their own rounding). A branch (is ``p(F_i) < 0``?) is taken
only when the enclosure ``b_i +- r_i`` decides it. A case with an undecided sign is taken
out of the batch and redone exactly (:func:`verify.core.rule.solve` on the rational backend),
so the branch sequence of every case is the exact one; floats take a shortcut only where
they are provably right.

>>> from fractions import Fraction as F
>>> batch = corner_batch([F(1, 2), F(1)], [[F(2), F(0)], [F(1), F(1, 2)]], [[F(0), F(1)], [F(1, 2), F(0)]])
>>> out = solve_batch(batch, max_iterations=100)
>>> out.impact_sets(0), out.stop[0], out.fallback.tolist()
([(0, 1), (0,)], 'exit', [False, True])
>>> out.impact_sets(1)  # COR 0 on S2 leaves its rate exactly 0: decided exactly
[(0, 1)]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

U = 2.0**-53  # unit roundoff of binary64
ETA = 2.0**-1074  # smallest subnormal: covers underflow
INFLATE = 1.0 + 16 * U  # covers the rounding of the radius computations themselves


def _exact_float(x: Fraction) -> tuple[float, float]:
    """``x`` rounded to the nearest float, and a bound on the rounding error (0 when exact)."""
    f = x.numerator / x.denominator  # correctly rounded (int true division)
    return f, (0.0 if Fraction(f) == x else math.ulp(f) / 2)


def _radius(*terms: np.ndarray) -> np.ndarray:
    total = terms[0]
    for t in terms[1:]:
        total = total + t
    return total * INFLATE + ETA


def _mul(a: np.ndarray, ra: np.ndarray, b: np.ndarray, rb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    z = a * b
    rz = _radius(np.abs(a) * rb, ra * np.abs(b), ra * rb, U * np.abs(z))
    exact_zero = ((a == 0) & (ra == 0)) | ((b == 0) & (rb == 0))  # a factor exactly 0: so is z
    return z, np.where(exact_zero, 0.0, rz)


def _add(a: np.ndarray, ra: np.ndarray, b: np.ndarray, rb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    z = a + b
    return z, _radius(ra, rb, U * np.abs(z))


def _div(a: np.ndarray, ra: np.ndarray, b: np.ndarray, rb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a / b`` where the enclosure of b excludes 0 (callers guarantee it)."""
    z = a / b
    low = (np.abs(b) - rb) * (1.0 - 4 * U)
    return z, _radius((ra + np.abs(z) * rb) / low, U * np.abs(z))


@dataclass
class Batch:
    """N systems in rate coordinates: float arrays with radii, and the exact cases.

    ``G`` (N, r, r) is the Gram matrix, ``Ut`` (N, r, n) the vectors U_j, ``e`` (N, r) the
    CORs, ``b`` (N, r) the rates and ``v`` (N, n) the velocity before the impact; each
    with a radius array ``r_*`` of the same shape. ``exact(i)`` returns case i as
    ``(System, velocity)`` for the exact fallback.
    """

    G: np.ndarray
    r_G: np.ndarray
    Ut: np.ndarray
    r_Ut: np.ndarray
    e: np.ndarray
    r_e: np.ndarray
    b: np.ndarray
    r_b: np.ndarray
    v: np.ndarray
    r_v: np.ndarray
    exact: Callable[[int], tuple[Any, list]]

    @property
    def size(self) -> int:
        return self.b.shape[0]


def _arrays(values: Sequence[Any], shape: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
    pairs = [_exact_float(Fraction(x)) for x in values]
    mid = np.array([p[0] for p in pairs], dtype=float).reshape(shape)
    rad = np.array([p[1] for p in pairs], dtype=float).reshape(shape)
    return mid, rad


def systems_batch(systems: Sequence[Any], velocities: Sequence[Sequence[Any]]) -> Batch:
    """A batch from exact systems (rational backend, same r and n) and velocities.

    >>> from verify.core.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    >>> out = solve_batch(systems_batch([s], [["100", "0", "0"]]))
    >>> out.impact_sets(0), out.v[0].tolist()
    ([(0,), (1,), (0,)], [20.3125, 23.4375, 56.25])
    """
    systems = list(systems)
    if not systems:
        raise ValueError("an empty batch")
    n, r = systems[0].n, systems[0].r
    if any(s.n != n or s.r != r for s in systems):
        raise ValueError("every system of a batch needs the same numbers of coordinates and constraints")
    vel = [s.velocity(v) for s, v in zip(systems, velocities)]
    q = [s.backend.to_number for s in systems]
    N = len(systems)
    G = _arrays([q[i](x) for i, s in enumerate(systems) for row in s.gram for x in row], (N, r, r))
    Ut = _arrays([q[i](x) for i, s in enumerate(systems) for row in s.U for x in row], (N, r, n))
    e = _arrays([q[i](x) for i, s in enumerate(systems) for x in s.restitution], (N, r))
    b = _arrays([q[i](x) for i, s in enumerate(systems) for x in s.rates(vel[i])], (N, r))
    v = _arrays([q[i](x) for i, s in enumerate(systems) for x in vel[i]], (N, n))
    return Batch(*G, *Ut, *e, *b, *v, exact=lambda i: (systems[i], list(velocities[i])))


def corner_batch(
    slopes: Sequence[Fraction], velocities: Sequence[Sequence[Fraction]], cors: Sequence[Sequence[Fraction]]
) -> Batch:
    """A batch of disks in corners (:mod:`verify.models.corner`): slope k, velocity (xd, yd), CORs.

    The rates and Gram matrix are the corner's closed forms, exact in rationals:
    ``p(F_1) = yd - k xd``, ``p(F_2) = -k xd - yd``, ``G = [[1 + k^2, k^2 - 1], [k^2 - 1,
    1 + k^2]]``, ``U_1 = (-k, 1, 0)``, ``U_2 = (-k, -1, 0)``.
    """
    k = [Fraction(x) for x in slopes]
    xs = [(Fraction(v[0]), Fraction(v[1])) for v in velocities]
    N = len(k)
    G = _arrays([g for kk in k for g in (1 + kk * kk, kk * kk - 1, kk * kk - 1, 1 + kk * kk)], (N, 2, 2))
    Ut = _arrays([u for kk in k for u in (-kk, 1, 0, -kk, -1, 0)], (N, 2, 3))
    e = _arrays([Fraction(c) for pair in cors for c in pair], (N, 2))
    b = _arrays([x for kk, (xd, yd) in zip(k, xs) for x in (yd - kk * xd, -kk * xd - yd)], (N, 2))
    v = _arrays([x for xd, yd in xs for x in (xd, yd, 0)], (N, 3))

    def exact(i: int) -> tuple[Any, list]:
        from verify.models.corner import corner_system

        return corner_system(k[i], cors[i][0], cors[i][1]), [xs[i][0], xs[i][1], Fraction(0)]

    return Batch(*G, *Ut, *e, *b, *v, exact=exact)


@dataclass
class BatchResult:
    """Per case: exit velocity ``v`` with radius ``r_v`` (0 for exact fallbacks, whose ``v``
    is the exact result rounded), stop reason, impulses, impact sets (bit j of
    ``codes[i, w]`` set when constraint j is in the w-th impact set) and whether the case
    was redone exactly (``fallback``)."""

    v: np.ndarray
    r_v: np.ndarray
    b: np.ndarray
    r_b: np.ndarray
    stop: list[str]
    iterations: np.ndarray
    codes: np.ndarray
    fallback: np.ndarray
    exact_results: dict[int, Any]

    def impact_sets(self, i: int) -> list[tuple[int, ...]]:
        """The impact sets of case i, in order (the same as the exact run's)."""
        if i in self.exact_results:
            return list(self.exact_results[i].impact_sets)
        return [tuple(j for j in range(63) if int(code) >> j & 1) for code in self.codes[i, : self.iterations[i]]]


def solve_batch(
    batch: Batch, max_iterations: int = 100, *, exact_fallback: bool = True, budget: Any = None
) -> BatchResult:
    """Run the rule on every case of the batch; see the module docstring.

    Cases whose branch cannot be certified in floats are redone exactly (with
    ``exact_fallback``, under the :class:`~verify.core.rule.Budget` ``budget``; otherwise they
    end with stop ``"undecided"``).
    """
    N, r = batch.b.shape
    G, rG, Ut, rUt = batch.G, batch.r_G, batch.Ut, batch.r_Ut
    one_e = 1.0 + batch.e  # 1 + e_j: e in [0, 1], so the sum is exact up to one rounding
    r_one_e = _radius(batch.r_e, U * one_e)
    b, rb = batch.b.copy(), batch.r_b.copy()
    v, rv = batch.v.copy(), batch.r_v.copy()
    codes = np.zeros((N, max_iterations), dtype=np.int64)
    iterations = np.zeros(N, dtype=np.int64)
    stop = np.full(N, "", dtype=object)
    undecided = np.zeros(N, dtype=bool)
    active = np.arange(N)
    weights = 1 << np.arange(r)
    diag = np.arange(r)
    for w in range(max_iterations + 1):
        if active.size == 0:
            break
        bb, rr = b[active], rb[active]
        negative = bb + rr < 0  # certainly p(F_i) < 0
        decided = negative | (bb - rr >= 0)
        unsure = ~decided.all(axis=1)
        if unsure.any():
            undecided[active[unsure]] = True
            keep = ~unsure
            active, bb, rr, negative = active[keep], bb[keep], rr[keep], negative[keep]
        hit = negative.any(axis=1)
        stop[active[~hit]] = "exit"
        if w == max_iterations:
            stop[active[hit]] = "max_iterations"
            break
        active, bb, rr, negative = active[hit], bb[hit], rr[hit], negative[hit]
        if active.size == 0:
            break
        codes[active, w] = negative @ weights
        iterations[active] += 1
        g, rg = G[active], rG[active]
        gd, rgd = g[:, diag, diag], rg[:, diag, diag]
        lam, rlam = _div(bb, rr, gd, rgd)
        lam = np.where(negative, lam, 0.0)
        rlam = np.where(negative, rlam, 0.0)
        single = negative.sum(axis=1) == 1
        # beta = sum b_j lambda_j / lambda^T G lambda (1 exactly for a single impact)
        num, rnum = _mul(bb, rr, lam, rlam)
        num, rnum = num.sum(axis=1), _radius(rnum.sum(axis=1), r * U * np.abs(num).sum(axis=1))
        glam, rglam = _matvec(g, rg, lam, rlam)
        den, rden = _mul(lam, rlam, glam, rglam)
        den, rden = den.sum(axis=1), _radius(rden.sum(axis=1), r * U * np.abs(den).sum(axis=1))
        safe = single | (den - rden > 0)
        beta, rbeta = _div(num, rnum, np.where(safe, den, 1.0), np.where(safe, rden, 0.0))
        beta = np.where(single, 1.0, beta)
        rbeta = np.where(single, 0.0, rbeta)
        if not safe.all():  # cannot happen for a certified impact set; redo exactly if it does
            undecided[active[~safe]] = True
        oe, roe = one_e[active], r_one_e[active]
        c, rc = _mul(*_mul(beta[:, None], rbeta[:, None], oe, roe), lam, rlam)
        c = -c
        dv, rdv = _matvec(np.swapaxes(Ut[active], 1, 2), np.swapaxes(rUt[active], 1, 2), c, rc)
        v[active], rv[active] = _add(v[active], rv[active], dv, rdv)
        db, rdb = _matvec(g, rg, c, rc)
        nb, rnb = _add(bb, rr, db, rdb)
        # a single impact on j leaves exactly -e_j b_j on j (eq. 4): no cancellation there
        own, rown = _mul(-batch.e[active], batch.r_e[active], bb, rr)
        mine = negative & single[:, None]
        b[active] = np.where(mine, own, nb)
        rb[active] = np.where(mine, rown, rnb)
        if not safe.all():
            active = active[safe]
    exact_results: dict[int, Any] = {}
    fallback = undecided.copy()
    if exact_fallback:
        from verify.core.rule import solve

        for i in np.flatnonzero(undecided):
            system, velocity = batch.exact(int(i))
            res = solve(system, velocity, max_iterations=max_iterations, trace=False, certify=False, budget=budget)
            exact_results[int(i)] = res
            K = res.backend
            v[i], rv[i] = zip(*(_exact_float(K.to_number(x)) for x in res.exit_velocity))
            stop[i] = res.stop
            iterations[i] = res.iterations
    else:
        stop[undecided] = "undecided"
    return BatchResult(v, rv, b, rb, list(stop), iterations, codes, fallback, exact_results)


def _matvec(M: np.ndarray, rM: np.ndarray, x: np.ndarray, rx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``M x`` per case, with the radius of the products and of the summation."""
    z = np.einsum("nij,nj->ni", M, x)
    absprod = np.einsum("nij,nj->ni", np.abs(M), np.abs(x))
    rz = np.einsum("nij,nj->ni", np.abs(M), rx) + np.einsum("nij,nj->ni", rM, np.abs(x) + rx)
    k = M.shape[2]
    return z, _radius(rz, (k + 1) * U * absprod)
