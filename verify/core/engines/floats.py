"""The float path: many cases at once in NumPy, every branch certified, exact fallback.

A batch (:func:`systems_batch`) holds N systems with the same numbers of constraints r and coordinates n. The
rule of :mod:`verify.core.rule` runs on all of them at once in *rate coordinates*: the state
of a case is its rates ``b = p(F)`` (eq. 2) and its velocity v, and an impulse
``sum_j c_j U_j`` (eq. 8) changes them by ``b += G c`` and ``v += U^T c``, with

- ``c_j = -(1 + e_j) b_j / G_jj`` for a single impact on j, whose own rate becomes
  exactly ``-e_j b_j`` (so a COR of 0 gives a rate of exactly 0, as in exact arithmetic);
- ``c_j = -beta (1 + e_j) lambda_j``, ``lambda_j = b_j / G_jj``, ``beta = sum_j b_j
  lambda_j / lambda^T G_JJ lambda`` for a multiple impact (the Gram identity of
  :func:`verify.core.rule.beta_from_rates`).

Every float carries a radius that bounds its distance to the exact value (midpoint-radius
arithmetic: each operation adds its own rounding error, ``u |z|`` with ``u = 2^-53``, and
the radii are inflated against their own rounding). A branch (is ``p(F_i) < 0``?) is taken
only when the enclosure ``b_i +- r_i`` decides it. A case with an undecided sign is taken
out of the batch and redone exactly (:func:`verify.core.rule.solve` on the rational backend),
so the branch sequence of every case is the exact one; floats take a shortcut only where
they are provably right.

>>> from verify.core.system import System
>>> corners = [System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[f"-{k}", 1, 0], [f"-{k}", -1, 0]], e)
...            for k, e in (("1/2", ["0", "1"]), ("1", ["1/2", "0"]))]
>>> batch = systems_batch(corners, [["2", "0", "0"], ["1", "1/2", "0"]])
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

from verify.core.engines.policy import Limits

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
        return int(self.b.shape[0])


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


@dataclass
class _State:
    """The cases of a batch while the rule runs: rates and velocities with their radii, and per
    case the impact sets so far (as bit codes), impulses, stop reason and undecided flag."""

    b: np.ndarray
    r_b: np.ndarray
    v: np.ndarray
    r_v: np.ndarray
    codes: np.ndarray
    iterations: np.ndarray
    stop: np.ndarray
    undecided: np.ndarray

    @classmethod
    def of(cls, batch: Batch, max_iterations: int) -> _State:
        N = batch.size
        return cls(
            batch.b.copy(),
            batch.r_b.copy(),
            batch.v.copy(),
            batch.r_v.copy(),
            np.zeros((N, max_iterations), dtype=np.int64),
            np.zeros(N, dtype=np.int64),
            np.full(N, "", dtype=object),
            np.zeros(N, dtype=bool),
        )


def _branches(state: _State, active: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step b) on the active cases, where the enclosures decide it: the cases with an undecided
    sign are marked and dropped, those with no impact end with ``"exit"``; returns the cases
    still hit and their impact sets (a boolean row per case)."""
    bb, rr = state.b[active], state.r_b[active]
    negative = bb + rr < 0  # certainly p(F_i) < 0
    decided = negative | (bb - rr >= 0)
    unsure = ~decided.all(axis=1)
    if unsure.any():
        state.undecided[active[unsure]] = True
        active, negative = active[~unsure], negative[~unsure]
    hit = negative.any(axis=1)
    state.stop[active[~hit]] = "exit"
    return active[hit], negative[hit]


def _impulses(batch: Batch, state: _State, active: np.ndarray, negative: np.ndarray, w: int) -> np.ndarray:
    """The w-th impulse (eq. 8) on the active cases, in rate coordinates; returns the cases that
    go on (a case whose beta cannot be certified is marked undecided)."""
    r = batch.b.shape[1]
    diag = np.arange(r)
    bb, rr = state.b[active], state.r_b[active]
    state.codes[active, w] = negative @ (1 << np.arange(r))
    state.iterations[active] += 1
    g, rg = batch.G[active], batch.r_G[active]
    lam, rlam = _div(bb, rr, g[:, diag, diag], rg[:, diag, diag])
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
        state.undecided[active[~safe]] = True
    one_e = 1.0 + batch.e[active]  # 1 + e_j: e in [0, 1], so the sum is exact up to one rounding
    c, rc = _mul(*_mul(beta[:, None], rbeta[:, None], one_e, _radius(batch.r_e[active], U * one_e)), lam, rlam)
    c = -c
    dv, rdv = _matvec(np.swapaxes(batch.Ut[active], 1, 2), np.swapaxes(batch.r_Ut[active], 1, 2), c, rc)
    state.v[active], state.r_v[active] = _add(state.v[active], state.r_v[active], dv, rdv)
    db, rdb = _matvec(g, rg, c, rc)
    nb, rnb = _add(bb, rr, db, rdb)
    # a single impact on j leaves exactly -e_j b_j on j (eq. 4): no cancellation there
    own, rown = _mul(-batch.e[active], batch.r_e[active], bb, rr)
    mine = negative & single[:, None]
    state.b[active] = np.where(mine, own, nb)
    state.r_b[active] = np.where(mine, rown, rnb)
    return active if safe.all() else active[safe]


def _redo_exactly(batch: Batch, state: _State, max_iterations: int, budget: Any) -> dict[int, Any]:
    """The undecided cases run exactly (:func:`verify.core.rule.solve`, rational backend): their
    results, by case, with the exit velocity rounded once into ``state``."""
    from verify.core.rule import solve

    out: dict[int, Any] = {}
    for i in np.flatnonzero(state.undecided):
        system, velocity = batch.exact(int(i))
        res = solve(system, velocity, max_iterations=max_iterations, trace=False, certify=False, budget=budget)
        out[int(i)] = res
        K = res.backend
        state.v[i], state.r_v[i] = zip(*(_exact_float(K.to_number(x)) for x in res.exit_velocity))
        state.stop[i] = res.stop
        state.iterations[i] = res.iterations
    return out


def solve_batch(
    batch: Batch, max_iterations: int = 100, *, exact_fallback: bool = True, budget: Any = None
) -> BatchResult:
    """Run the rule on every case of the batch; see the module docstring.

    Cases whose branch cannot be certified in floats are redone exactly (with
    ``exact_fallback``, under the :class:`~verify.core.rule.Budget` ``budget``; otherwise they
    end with stop ``"undecided"``). The cap on the impulses is the engines' (:class:`Limits`).
    """
    limits = Limits(max_iterations)
    state = _State.of(batch, max_iterations)
    active = np.arange(batch.size)
    for w in range(max_iterations + 1):
        if active.size == 0:
            break
        active, negative = _branches(state, active)
        if limits.exhausted(w):
            state.stop[active] = "max_iterations"
            break
        if active.size == 0:
            break
        active = _impulses(batch, state, active, negative, w)
    fallback = state.undecided.copy()
    exact_results: dict[int, Any] = {}
    if exact_fallback:
        exact_results = _redo_exactly(batch, state, max_iterations, budget)
    else:
        state.stop[state.undecided] = "undecided"
    return BatchResult(
        state.v, state.r_v, state.b, state.r_b, list(state.stop), state.iterations, state.codes, fallback, exact_results
    )


def _matvec(M: np.ndarray, rM: np.ndarray, x: np.ndarray, rx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``M x`` per case, with the radius of the products and of the summation."""
    z = np.einsum("nij,nj->ni", M, x)
    absprod = np.einsum("nij,nj->ni", np.abs(M), np.abs(x))
    rz = np.einsum("nij,nj->ni", np.abs(M), rx) + np.einsum("nij,nj->ni", rM, np.abs(x) + rx)
    k = M.shape[2]
    return z, _radius(rz, (k + 1) * U * absprod)
