"""The float path: many cases at once in NumPy, every branch certified, exact arithmetic where floats cannot decide.

A batch (:func:`systems_batch`) holds N systems with the same numbers of constraints r and coordinates n. The
rule of :mod:`verify.laws.rule` runs on all of them at once in *rate coordinates*: the state
of a case is its rates ``b = p(F)`` (eq. 2), and an impulse ``sum_j c_j U_j`` (eq. 8) changes
them by ``b += G c``; the velocity is ``v0 + U^T C`` with C the sum of the impulses so far,
formed once at the end. With ``lambda_j = b_j / G_jj``:

- a single impact on j has ``c_j = -(1 + e_j) lambda_j``: rate i becomes ``b_i + S_ji b_j``
  with ``S_ji = -(1 + e_j) G_ij / G_jj``, and rate j exactly ``-e_j b_j`` (eq. 4), which is
  not negative, so j is not hit again at the next step (for a COR of 0 that rate is exactly 0);
- a multiple impact has ``c_j = -beta (1 + e_j) lambda_j``, ``beta = sum_j b_j lambda_j /
  lambda^T G_JJ lambda`` (the Gram identity of :func:`verify.laws.rule.beta_from_rates`).

The constants (``S``, ``-(1 + e_j) / G_jj``, G, the CORs, U) are computed exactly when the batch
is built and rounded once. Every float carries a bound on its distance to the exact value (each
operation adds its own rounding error, ``u |z|`` with ``u = 2^-53``, and the bounds are inflated
against their own rounding); a branch (is ``p(F_i) < 0``?) is taken only when the bound decides it.

The bound is where the cost is. Boxes (a radius per rate) pay the *wrapping effect*: an impulse
maps a box through ``|M|`` instead of M, and in a long chain of single impacts, where each rate is
a difference of two terms, the radii grow geometrically while the rates shrink: on the corner
batch of ``verify bench`` 5% of the cases lost their sign after 20 to 100 impulses although the
floats were still correct to 15 digits. So with two constraints the error of the rates is bounded
in the frame of the rates themselves: ``b = b~ + alpha b~ + beta n~`` with ``n~ = (-b~_1, b~_0)``,
``|alpha| <= a``, ``|beta| <= t``. The frame is orthogonal with ``|n~| = |b~|``, so its inverse is
exact (its transpose over ``|b~|^2``), and a single impact maps the error in it through the exact
map: ``a`` is a relative error that only accumulates, and ``t`` is multiplied by about
``e_j |b|^2 / |b'|^2`` (the determinant of the impact), which is what the rates really do. A
multiple impact is taken on boxes and its result put back into the frame, and the first decision
(on the rates as given, each rounded once) on boxes. Other numbers of constraints run on boxes
throughout.

A case with a sign that its bound does not decide goes up a rung:

1. *catch-up*: the impulses the floats took since the case's last exact state are replayed over
   integers (:func:`verify.laws.loops.integer.iterate`, the exact engine's own iteration, which
   checks that they are the same impact sets), the exact rates decide the sign, and the floats go
   on from that exact state rounded (an exact 0 is the point 0). Cheap when it happens early (a
   zero that the structure does not explain), and all the catch-ups of a case together replay
   each of its impulses at most once;
2. *exact*: when the floats cannot hold the exact state either (outside the float range), a
   multiple impact's beta cannot be certified, or the system is not on the rational backend,
   the case is redone from the start by :func:`verify.laws.rule.solve`.

So the branch sequence of every case is the exact one; floats take a shortcut only where they are
provably right. ``BatchResult.rung`` says which rung each case needed.

>>> from verify.dynamics.system import System
>>> corners = [System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[f"-{k}", 1, 0], [f"-{k}", -1, 0]], e)
...            for k, e in (("1/2", ["0", "1"]), ("1", ["1/2", "0"]))]
>>> batch = systems_batch(corners, [["2", "0", "0"], ["1", "1/2", "0"]])
>>> out = solve_batch(batch, max_iterations=100)
>>> out.impact_sets(0), out.stop[0], out.fallback.tolist(), out.rung.tolist()
([(0, 1), (0,)], 'exit', [False, True], [0, 1])
>>> out.impact_sets(1)  # S2 at rate exactly 0 after a multiple impact: the catch-up decided it
[(0, 1)]
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from verify.dynamics.policy import Limits

U = 2.0**-53  # unit roundoff of binary64
ETA = 2.0**-1074  # smallest subnormal: covers underflow
INFLATE = 1.0 + 16 * U  # covers the rounding of the radius computations themselves
#: squared norms of the rates below this leave the frame untrusted (the case is caught up exactly)
TINY = 2.0**-900

#: the rungs of :attr:`BatchResult.rung`: floats alone, floats with exact catch-ups, redone exactly
RUNG_FLOATS, RUNG_CATCH_UP, RUNG_EXACT = 0, 1, 2
RUNGS = ("floats", "catch_up", "exact")


def _exact_float(x: Fraction) -> tuple[float, float]:
    """``x`` rounded to the nearest float, and a bound on the rounding error (0 when exact; an
    infinite bound when ``x`` is outside the float range).

    >>> _exact_float(Fraction(1, 2)), _exact_float(Fraction(1, 3))[1] > 0, _exact_float(Fraction(1, 10**400))
    ((0.5, 0.0), True, (0.0, 5e-324))
    """
    try:
        f = x.numerator / x.denominator  # correctly rounded (int true division)
    except OverflowError:
        return (math.inf if x > 0 else -math.inf), math.inf
    if Fraction(f) == x:
        return f, 0.0
    # half an ulp bounds the error of a correct rounding; below the normal range half the
    # smallest subnormal is not a float, so a whole ulp
    return f, (math.ulp(f) / 2 if abs(f) >= sys.float_info.min else math.ulp(f))


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


def _matvec(M: np.ndarray, rM: np.ndarray, x: np.ndarray, rx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``M x`` per case, with the radius of the products and of the summation."""
    z = np.einsum("nij,nj->ni", M, x)
    absprod = np.einsum("nij,nj->ni", np.abs(M), np.abs(x))
    rz = np.einsum("nij,nj->ni", np.abs(M), rx) + np.einsum("nij,nj->ni", rM, np.abs(x) + rx)
    k = M.shape[2]
    return z, _radius(rz, (k + 1) * U * absprod)


@dataclass
class Batch:
    """N systems in rate coordinates: float arrays with radii, and the exact cases.

    ``G`` (N, r, r) is the Gram matrix, ``Ut`` (N, r, n) the vectors U_j, ``e`` (N, r) the
    CORs, ``b`` (N, r) the rates and ``v`` (N, n) the velocity before the impact; ``S`` (N, r, r)
    the single impacts (``S[:, j, i] = -(1 + e_j) G_ij / G_jj``: rate i gains ``S_ji b_j`` at a
    single impact on j) and ``kappa`` (N, r) their impulses (``c_j = kappa_j b_j``,
    ``kappa_j = -(1 + e_j) / G_jj``); each with a radius array ``r_*`` of the same shape, each
    entry the exact value rounded once. ``exact(i)`` returns case i as ``(System, velocity)``
    for the exact rungs.
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
    exact: Callable[[int], tuple[Any, list[Any]]]
    S: np.ndarray
    r_S: np.ndarray
    kappa: np.ndarray
    r_kappa: np.ndarray

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

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    >>> out = solve_batch(systems_batch([s], [["100", "0", "0"]]))
    >>> out.impact_sets(0), out.v[0].tolist(), out.rung.tolist()
    ([(0,), (1,), (0,)], [20.3125, 23.4375, 56.25], [0])
    """
    systems = list(systems)
    if not systems:
        raise ValueError("an empty batch")
    n, r = systems[0].n, systems[0].r
    if any(s.n != n or s.r != r for s in systems):
        raise ValueError("every system of a batch needs the same numbers of coordinates and constraints")
    vel = [s.velocity(v) for s, v in zip(systems, velocities)]
    N = len(systems)
    gram, cors, single, kappa = [], [], [], []
    for s in systems:
        number = s.backend.to_number
        g = [[Fraction(number(x)) for x in row] for row in s.gram]
        cor = [Fraction(number(x)) for x in s.restitution]
        gram += [x for row in g for x in row]
        cors += cor
        single += [-(1 + cor[j]) * g[j][i] / g[j][j] for j in range(r) for i in range(r)]
        kappa += [-(1 + cor[j]) / g[j][j] for j in range(r)]
    q = [s.backend.to_number for s in systems]
    G = _arrays(gram, (N, r, r))
    Ut = _arrays([q[i](x) for i, s in enumerate(systems) for row in s.U for x in row], (N, r, n))
    e = _arrays(cors, (N, r))
    b = _arrays([q[i](x) for i, s in enumerate(systems) for x in s.rates(vel[i])], (N, r))
    v = _arrays([q[i](x) for i, s in enumerate(systems) for x in vel[i]], (N, n))
    S = _arrays(single, (N, r, r))
    k = _arrays(kappa, (N, r))
    return Batch(*G, *Ut, *e, *b, *v, exact=lambda i: (systems[i], list(velocities[i])),
                 S=S[0], r_S=S[1], kappa=k[0], r_kappa=k[1])  # fmt: skip


@dataclass
class BatchResult:
    """Per case: exit velocity ``v`` with radius ``r_v`` (0 for the exact redos, whose ``v`` is
    the exact result rounded), the rates ``b`` before the last decision with radius ``r_b``, stop
    reason, impulses, impact sets (bit j of ``codes[i, w]`` set when constraint j is in the w-th
    impact set), the rung that decided the case (``rung``: :data:`RUNG_FLOATS`,
    :data:`RUNG_CATCH_UP` or :data:`RUNG_EXACT`, names in :data:`RUNGS`) and whether exact
    arithmetic decided any of its branches (``fallback``, the same as ``rung > 0``; the results of
    the exact redos are in ``exact_results``)."""

    v: np.ndarray
    r_v: np.ndarray
    b: np.ndarray
    r_b: np.ndarray
    stop: list[str]
    iterations: np.ndarray
    codes: np.ndarray
    fallback: np.ndarray
    exact_results: dict[int, Any]
    rung: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8))

    def impact_sets(self, i: int) -> list[tuple[int, ...]]:
        """The impact sets of case i, in order (the same as the exact run's)."""
        if i in self.exact_results:
            return list(self.exact_results[i].impact_sets)
        return _code_sets(self.codes[i, : self.iterations[i]])

    def rung_counts(self) -> dict[str, int]:
        """How many cases each rung decided.

        >>> from verify.dynamics.system import System
        >>> s = System([[1, 0], [0, 1]], [[-1, 1]], [1])
        >>> solve_batch(systems_batch([s], [["1", "0"]])).rung_counts()
        {'floats': 1, 'catch_up': 0, 'exact': 0}
        """
        counts = np.bincount(self.rung, minlength=len(RUNGS))
        return {name: int(c) for name, c in zip(RUNGS, counts)}


def _code_sets(codes: Any) -> list[tuple[int, ...]]:
    """The impact sets of bit codes (bit j set when constraint j is in the set)."""
    return [tuple(j for j in range(63) if int(c) >> j & 1) for c in codes]


class _Run:
    """One :func:`solve_batch`: the per-case results, the exact rungs, and the float loops.

    The float loops hold the active cases in arrays (``idx`` their case numbers); a case that
    ends is marked dead and its arrays are compacted away once a quarter of them are dead.
    """

    def __init__(self, batch: Batch, max_iterations: int, exact_fallback: bool, budget: Any):
        self.batch = batch
        N, r = batch.b.shape
        self.r = r
        self.limits = budget.limits(max_iterations) if budget is not None else Limits(max_iterations)
        self.max_iterations = max_iterations
        self.exact_fallback = exact_fallback
        self.budget = budget
        self.codes = np.zeros((N, max_iterations), dtype=np.int64)
        self.iterations = np.zeros(N, dtype=np.int64)
        self.stop = np.full(N, "", dtype=object)
        self.rung = np.zeros(N, dtype=np.int8)
        self.redo = np.zeros(N, dtype=bool)
        self.out_b = batch.b.copy()
        self.out_rb = batch.r_b.copy()
        # the velocity is v0 + U^T C, C = kappa * acc + Cm: acc sums the rates b_j of the single
        # impacts on j, Cm the impulses of the multiple impacts (since the last exact state)
        self.acc = np.zeros((N, r))
        self.racc = np.zeros((N, r))
        self.Cm = np.zeros((N, r))
        self.rCm = np.zeros((N, r))
        self.v0 = batch.v.copy()
        self.rv0 = batch.r_v.copy()
        self.anchors: dict[int, tuple[int, tuple[Any, ...]]] = {}  # case -> (impulses, exact velocity there)
        self.exact_results: dict[int, Any] = {}

    # -- the exact rungs ------------------------------------------------------------------

    def catch_up(self, i: int, w: int) -> tuple[list[float], list[float]] | None:
        """The exact rates of case i after its w impulses (rounded, with radii), its floats
        re-anchored there; None when the case is finished instead (ends exactly, or goes to the
        exact redo: then :attr:`redo` is set)."""
        self.rung[i] = max(self.rung[i], RUNG_CATCH_UP)
        if not self.exact_fallback:
            self.stop[i] = "undecided"
            self.iterations[i] = w
            self.rung[i] = RUNG_EXACT
            return None
        system, velocity = self.batch.exact(i)
        if not system.backend.fraction_free:
            self.redo[i] = True
            return None
        start, v = self.anchors.get(i) or (0, system.velocity(velocity))
        K = system.backend
        if w > start:
            from verify.laws.loops import integer

            run = integer.iterate(system, v, self.limits.capped(w - start))
            done = _code_sets(self.codes[i, start : start + len(run.impact_sets)])
            ended = run.stop == "exit" and start + len(run.impact_sets) == w  # exits exactly where unsure
            if run.impact_sets != done or not (ended or run.stop in ("max_iterations", "budget")):
                raise AssertionError(f"case {i}: the exact catch-up disagrees with the certified floats")
            v = run.v
            if run.stop == "budget":
                self.finish_exactly(i, start + len(run.impact_sets), v, "budget")
                return None
        rates = [K.to_number(x) for x in system.rates(v)]
        if not any(x < 0 for x in rates):
            self.finish_exactly(i, w, v, "exit")
            return None
        if w < self.max_iterations and self.limits.over_budget(lambda: max(K.size(x) for x in v)):
            self.finish_exactly(i, w, v, "budget")
            return None
        self.anchors[i] = (w, v)
        pairs = [_exact_float(K.to_number(x)) for x in v]
        self.v0[i] = [p[0] for p in pairs]
        self.rv0[i] = [p[1] for p in pairs]
        self.acc[i] = self.racc[i] = self.Cm[i] = self.rCm[i] = 0.0
        rounded = [_exact_float(x) for x in rates]
        if not all(math.isfinite(p[1]) and (p[1] < abs(p[0]) or p[1] == 0) for p in rounded):
            self.redo[i] = True  # the floats cannot hold the exact state
            return None
        return [p[0] for p in rounded], [p[1] for p in rounded]

    def finish_exactly(self, i: int, w: int, v: tuple[Any, ...], stop: str) -> None:
        """Case i ends at the exact velocity v after w impulses (from a catch-up)."""
        system = self.batch.exact(i)[0]
        K = system.backend
        pairs = [_exact_float(K.to_number(x)) for x in v]
        self.v0[i] = [p[0] for p in pairs]
        self.rv0[i] = [p[1] for p in pairs]
        self.acc[i] = self.racc[i] = self.Cm[i] = self.rCm[i] = 0.0
        rates = [_exact_float(K.to_number(x)) for x in system.rates(v)]
        self.out_b[i] = [p[0] for p in rates]
        self.out_rb[i] = [p[1] for p in rates]
        self.iterations[i] = w
        self.stop[i] = stop

    def redo_exactly(self) -> None:
        """The cases marked :attr:`redo` run exactly from the start (:func:`verify.laws.rule.solve`,
        rational backend), their exit velocity rounded once."""
        from verify.laws.rule import solve

        for i in map(int, np.flatnonzero(self.redo)):
            self.rung[i] = RUNG_EXACT
            system, velocity = self.batch.exact(i)
            res = solve(
                system, velocity, max_iterations=self.max_iterations, trace=False, certify=False, budget=self.budget
            )
            self.exact_results[i] = res
            K = res.backend
            pairs = [_exact_float(K.to_number(x)) for x in res.exit_velocity]
            self.v0[i] = [p[0] for p in pairs]
            self.rv0[i] = [p[1] for p in pairs]
            self.acc[i] = self.racc[i] = self.Cm[i] = self.rCm[i] = 0.0
            self.stop[i] = res.stop
            self.iterations[i] = res.iterations

    # -- the multiple impacts, on boxes ---------------------------------------------------

    def multiple(
        self, cases: np.ndarray, bb: np.ndarray, rr: np.ndarray, negative: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A multiple impact on the boxes ``bb +- rr`` of ``cases``: the new rates and radii, and
        whether beta was certified (the impulses are added to :attr:`Cm`)."""
        batch, r = self.batch, self.r
        diag = np.arange(r)
        g, rg = batch.G[cases], batch.r_G[cases]
        lam, rlam = _div(bb, rr, g[:, diag, diag], rg[:, diag, diag])
        lam = np.where(negative, lam, 0.0)
        rlam = np.where(negative, rlam, 0.0)
        # beta = sum b_j lambda_j / lambda^T G lambda
        num, rnum = _mul(bb, rr, lam, rlam)
        num, rnum = num.sum(axis=1), _radius(rnum.sum(axis=1), r * U * np.abs(num).sum(axis=1))
        glam, rglam = _matvec(g, rg, lam, rlam)
        den, rden = _mul(lam, rlam, glam, rglam)
        den, rden = den.sum(axis=1), _radius(rden.sum(axis=1), r * U * np.abs(den).sum(axis=1))
        safe = den - rden > 0  # cannot fail for a certified impact set; redone exactly if it does
        beta, rbeta = _div(num, rnum, np.where(safe, den, 1.0), np.where(safe, rden, 0.0))
        one_e = 1.0 + batch.e[cases]  # 1 + e_j: e in [0, 1], so the sum is exact up to one rounding
        c, rc = _mul(*_mul(beta[:, None], rbeta[:, None], one_e, _radius(batch.r_e[cases], U * one_e)), lam, rlam)
        c = -c
        db, rdb = _matvec(g, rg, c, rc)
        nb, rnb = _add(bb, rr, db, rdb)
        total, rtotal = _add(self.Cm[cases], self.rCm[cases], c, rc)
        self.Cm[cases], self.rCm[cases] = total, rtotal
        return nb, rnb, safe

    # -- the results ----------------------------------------------------------------------

    def result(self) -> BatchResult:
        """The velocities ``v0 + U^T C`` and the per-case results."""
        batch = self.batch
        kacc = batch.kappa * self.acc
        C = kacc + self.Cm
        rC = _radius(
            np.abs(batch.kappa) * self.racc, batch.r_kappa * (np.abs(self.acc) + self.racc),
            U * np.abs(kacc), self.rCm, U * np.abs(C),
        )  # fmt: skip
        dv, rdv = _matvec(np.swapaxes(batch.Ut, 1, 2), np.swapaxes(batch.r_Ut, 1, 2), C, rC)
        v, rv = _add(self.v0, self.rv0, dv, rdv)
        still = (C == 0).all(axis=1) & (rC == 0).all(axis=1)  # no impulse since the last exact state
        v = np.where(still[:, None], self.v0, v)
        rv = np.where(still[:, None], self.rv0, rv)
        return BatchResult(
            v, rv, self.out_b, self.out_rb, list(self.stop), self.iterations, self.codes, self.rung > 0,
            self.exact_results, self.rung,
        )  # fmt: skip


class _Plane:
    """The state of the two-constraint float loop (:func:`_plane`): per active case the rates
    ``b0, b1``, the frame bounds ``a, t``, the constants, the sums of the single impacts' rates
    and their radii, and whether each rate is still to be tested (``free``)."""

    FIELDS = ("idx", "b0", "b1", "a", "t", "consts", "acc0", "acc1", "racc0", "racc1", "free0", "free1", "alive")

    def __init__(self, batch: Batch):
        size = batch.size
        self.idx = np.arange(size)
        self.b0, self.b1 = batch.b[:, 0].copy(), batch.b[:, 1].copy()
        self.a, self.t = _frame(self.b0, self.b1, batch.r_b[:, 0], batch.r_b[:, 1])
        # per case: the CORs, the single impacts' S_01 (rate 1 from an impact on 0) and S_10, radii
        self.consts = np.stack([batch.e[:, 0], batch.e[:, 1], batch.r_e[:, 0], batch.r_e[:, 1], batch.S[:, 0, 1],
                                batch.S[:, 1, 0], batch.r_S[:, 0, 1], batch.r_S[:, 1, 0]], axis=1)  # fmt: skip
        self.acc0, self.acc1, self.racc0, self.racc1 = (np.zeros(size) for _ in range(4))
        self.free0 = np.ones(size, dtype=bool)  # False right after a single impact on 0: rate 0 is >= 0
        self.free1 = np.ones(size, dtype=bool)
        self.alive = np.ones(size, dtype=bool)
        self.dead = 0

    def compact(self) -> None:
        """Drop the finished cases once they are a quarter of the arrays."""
        if self.dead * 4 > self.idx.size:
            keep = np.flatnonzero(self.alive)
            for name in self.FIELDS:
                setattr(self, name, getattr(self, name)[keep])
            self.dead = 0

    def radii(self, batch: Batch, w: int) -> tuple[np.ndarray, np.ndarray]:
        """The radii of the rates: as given at w = 0 (each rounded once), else from the frame."""
        if w == 0:  # the rates as given: their boxes are tighter than the frame
            return batch.r_b[:, 0].copy(), batch.r_b[:, 1].copy()
        ab0, ab1 = np.abs(self.b0), np.abs(self.b1)
        return (self.a * ab0 + self.t * ab1) * INFLATE + ETA, (self.a * ab1 + self.t * ab0) * INFLATE + ETA

    def catch_up(self, run: _Run, w: int, rad0: np.ndarray, rad1: np.ndarray) -> None:
        """Decide the signs the radii leave open exactly (:meth:`_Run.catch_up`); the floats go on
        from the exact state, or the case is dropped (redone exactly)."""
        ab0, ab1 = np.abs(self.b0), np.abs(self.b1)
        # decided: |b~| > rad, or rad = 0 (exact); a NaN radius is unsure
        unsure = self.alive & ((~(ab0 > rad0) & (rad0 != 0) & self.free0) | (~(ab1 > rad1) & (rad1 != 0) & self.free1))
        for row in np.flatnonzero(unsure) if unsure.any() else ():
            exact = run.catch_up(int(self.idx[row]), w)
            if exact is None:
                self.alive[row], self.dead = False, self.dead + 1
                continue
            (self.b0[row], self.b1[row]), (rad0[row], rad1[row]) = exact
            pick = slice(row, row + 1)
            self.a[row], self.t[row] = (x[0] for x in _frame(self.b0[pick], self.b1[pick], rad0[pick], rad1[pick]))
            self.acc0[row] = self.acc1[row] = self.racc0[row] = self.racc1[row] = 0.0
            self.free0[row] = self.free1[row] = True

    def finish(self, run: _Run, rows: np.ndarray, w: int, stop: str, radii: tuple[np.ndarray, np.ndarray]) -> None:
        """The cases ``rows`` end after w impulses with ``stop``."""
        columns = (self.b0, self.b1, *radii, self.acc0, self.acc1, self.racc0, self.racc1)
        _finish(run, self.idx[rows], w, stop, *_pairs(rows, *columns))

    def impulse(self, run: _Run, neg0: np.ndarray, neg1: np.ndarray, rad0: np.ndarray, rad1: np.ndarray) -> None:
        """The impulse on every active case hit: single ones in the frame, multiple ones on boxes."""
        hit = self.alive & (neg0 | neg1)
        jsel = neg1 & ~neg0  # a single impact on 1 (else on 0, or a multiple impact)
        one0 = neg0 & ~neg1
        both = hit & neg0 & neg1
        if both.any():  # on boxes, before the rates change
            rows = np.flatnonzero(both)
            bb = np.stack([self.b0[rows], self.b1[rows]], axis=1)
            rr = np.stack([rad0[rows], rad1[rows]], axis=1)
            mb, mr, safe = run.multiple(self.idx[rows], bb, rr, np.ones(bb.shape, dtype=bool))
        # the single impact on j on every row; the multiple ones are redone below
        nb0, nb1, self.a, self.t = _single_in_frame(self.b0, self.b1, self.a, self.t, jsel=jsel, consts=self.consts)
        # the sums of the rates b_j of the single impacts on j, for the velocity
        self.acc0 = self.acc0 + np.where(one0, self.b0, 0.0)
        self.acc1 = self.acc1 + np.where(jsel, self.b1, 0.0)
        self.racc0 = (self.racc0 + np.where(one0, rad0, 0.0) + U * np.abs(self.acc0)) * INFLATE
        self.racc1 = (self.racc1 + np.where(jsel, rad1, 0.0) + U * np.abs(self.acc1)) * INFLATE
        self.b0, self.b1 = nb0, nb1
        self.free0, self.free1 = ~one0, ~jsel  # rate j is -e_j b_j >= 0 after a single impact on j
        if both.any():
            self.b0[rows], self.b1[rows] = mb[:, 0], mb[:, 1]
            self.a[rows], self.t[rows] = _frame(mb[:, 0], mb[:, 1], mr[:, 0], mr[:, 1])
            if not safe.all():
                bad = rows[~safe]
                run.redo[self.idx[bad]] = True
                self.alive[bad] = False
                self.dead += bad.size


def _plane(run: _Run) -> None:
    """The float loop for two constraints, the rates' error bounded in their own frame (module
    docstring): ``b = b~ + alpha b~ + beta n~``, ``|alpha| <= a``, ``|beta| <= t``."""
    st = _Plane(run.batch)
    for w in range(run.max_iterations + 1):
        st.compact()
        if st.idx.size == 0:
            break
        rad0, rad1 = st.radii(run.batch, w)
        st.catch_up(run, w, rad0, rad1)
        neg0, neg1 = st.b0 < 0, st.b1 < 0  # decided: the sign of the midpoint is the sign
        hit = st.alive & (neg0 | neg1)
        out = st.alive & ~hit
        if out.any():
            st.finish(run, out, w, "exit", (rad0, rad1))
            st.alive &= hit
            st.dead += int(out.sum())
        if run.limits.exhausted(w) or not hit.any():
            if hit.any():
                st.finish(run, hit, w, "max_iterations", (rad0, rad1))
            break
        run.codes[st.idx[hit], w] = (neg0.view(np.int8) + 2 * neg1.view(np.int8))[hit]
        st.impulse(run, neg0, neg1, rad0, rad1)


def _single_in_frame(
    b0: np.ndarray, b1: np.ndarray, a: np.ndarray, t: np.ndarray, *, jsel: np.ndarray, consts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A single impact on j (on 1 where ``jsel``, else on 0) in the frame: the new rates and the
    new frame bounds (a, t), from the exact map M of the impulse (module docstring)."""
    bj, bo = np.where(jsel, b1, b0), np.where(jsel, b0, b1)
    abj, abo = np.abs(bj), np.abs(bo)
    e0, e1, re0, re1, s01, s10, rs01, rs10 = consts.T
    ej, rej = np.where(jsel, e1, e0), np.where(jsel, re1, re0)
    sj, rsj = np.where(jsel, s10, s01), np.where(jsel, rs10, rs01)
    nbj = -(ej * bj)
    p = sj * bj
    nbo = bo + p
    anbj, anbo = np.abs(nbj), np.abs(nbo)
    # z = M b~ - b~' (M the exact map of the impulse), componentwise
    zj = (rej * abj + U * anbj) * INFLATE + ETA
    zo = (rsj * abj + U * (np.abs(p) + anbo)) * INFLATE + ETA
    # M n~ = +-(e_j b~_o, b~_j - S_jo b~_o) in (j, o); its coordinates in the new frame are
    # b~'.M n~ and n~'.M n~ over |b~'|^2, with n~' = +-(-b~'_o, b~'_j)
    qj = ej * bo
    ps = sj * bo
    qo = bj - ps
    rqj = (rej * abo + U * np.abs(qj)) * INFLATE + ETA
    rqo = (rsj * abo + U * (np.abs(ps) + np.abs(qo))) * INFLATE + ETA
    x1, x2, y1, y2 = nbj * qj, nbo * qo, nbj * qo, nbo * qj
    s1 = (np.abs(x1 + x2) + anbj * rqj + anbo * rqo + 2 * U * (np.abs(x1) + np.abs(x2))) * INFLATE + ETA
    s2 = (np.abs(y1 - y2) + anbj * rqo + anbo * rqj + 2 * U * (np.abs(y1) + np.abs(y2))) * INFLATE + ETA
    norm = (nbj * nbj + nbo * nbo) * (1 - 4 * U)
    grow = 1.0 + a
    w1 = t * s1 + grow * (anbj * zj + anbo * zo)
    w2 = t * s2 + grow * (anbo * zj + anbj * zo)
    small = ~(norm >= TINY)
    norm = np.where(small, 1.0, norm)
    a = np.where(small, np.inf, (a + w1 / norm) * INFLATE)
    t = np.where(small, np.inf, w2 / norm * INFLATE)
    return np.where(jsel, nbo, nbj), np.where(jsel, nbj, nbo), a, t


def _boxes(run: _Run) -> None:
    """The float loop on boxes (a radius per rate), for any number of constraints."""
    batch, r = run.batch, run.r
    idx = np.arange(batch.size)
    b, rb = batch.b.copy(), batch.r_b.copy()
    acc, racc = np.zeros(b.shape), np.zeros(b.shape)
    alive = np.ones(batch.size, dtype=bool)
    dead = 0
    bits = 1 << np.arange(r)
    for w in range(run.max_iterations + 1):
        if dead * 4 > idx.size:  # compaction
            keep = np.flatnonzero(alive)
            idx, b, rb, acc, racc, alive, dead = idx[keep], b[keep], rb[keep], acc[keep], racc[keep], alive[keep], 0
        if idx.size == 0:
            break
        unsure = alive & ~((np.abs(b) > rb) | (rb == 0)).all(axis=1)
        if unsure.any():
            for row in np.flatnonzero(unsure):
                exact = run.catch_up(int(idx[row]), w)
                if exact is None:
                    alive[row] = False
                    dead += 1
                    continue
                b[row], rb[row] = exact
                acc[row] = racc[row] = 0.0
        neg = b < 0
        hit = alive & neg.any(axis=1)
        out = alive & ~hit
        if out.any():
            _finish(run, idx[out], w, "exit", b[out], rb[out], acc[out], racc[out])
            alive &= hit
            dead += int(out.sum())
        if run.limits.exhausted(w) or not hit.any():
            if hit.any():
                _finish(run, idx[hit], w, "max_iterations", b[hit], rb[hit], acc[hit], racc[hit])
            break
        run.codes[idx[hit], w] = (neg @ bits)[hit]
        count = neg.sum(axis=1)
        single = hit & (count == 1)
        multi = hit & (count >= 2)
        if multi.any():  # on the old rates
            rows = np.flatnonzero(multi)
            mb, mr, safe = run.multiple(idx[rows], b[rows], rb[rows], neg[rows])
        ar = np.arange(idx.size)
        j = np.argmax(neg, axis=1)
        Srow, rS = batch.S[idx, j], batch.r_S[idx, j]
        bj, rbj = b[ar, j], rb[ar, j]
        abj = np.abs(bj)
        p = Srow * bj[:, None]
        nb = b + p
        rnb = (rb + np.abs(Srow) * rbj[:, None] + rS * (abj + rbj)[:, None] + U * (np.abs(p) + np.abs(nb))) * INFLATE
        rnb += ETA
        rnb = np.where((Srow == 0) & (rS == 0), rb, rnb)  # G_ij = 0: rate i keeps its value exactly
        ej, rej = batch.e[idx, j], batch.r_e[idx, j]
        nbj = -(ej * bj)
        ehi = ej + rej
        nb[ar, j] = nbj
        rnb[ar, j] = np.where(ehi == 0, 0.0, ((ehi * rbj + rej * abj + U * np.abs(nbj)) * INFLATE + ETA) * INFLATE)
        acc[ar, j] += np.where(single, bj, 0.0)
        racc[ar, j] += np.where(single, rbj, 0.0)
        racc = (racc + U * np.abs(acc)) * INFLATE
        b, rb = nb, rnb
        if multi.any():
            b[rows], rb[rows] = mb, mr
            if not safe.all():
                bad = rows[~safe]
                run.redo[idx[bad]] = True
                alive[bad] = False
                dead += bad.size


def _pairs(rows: np.ndarray, *columns: np.ndarray) -> list[np.ndarray]:
    """The rows of pairs of columns, as (m, 2) arrays."""
    return [np.stack([x[rows], y[rows]], axis=1) for x, y in zip(columns[::2], columns[1::2])]


def _frame(b0: np.ndarray, b1: np.ndarray, r0: np.ndarray, r1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The frame bounds (a, t) of the boxes ``b +- r``: ``alpha = b.e / |b|^2``,
    ``beta = n.e / |b|^2`` for an error e in the box (infinite when ``|b|^2`` is below :data:`TINY`)."""
    norm = (b0 * b0 + b1 * b1) * (1 - 4 * U)
    small = norm < TINY
    norm = np.where(small, 1.0, norm)
    ab0, ab1 = np.abs(b0), np.abs(b1)
    zero = (r0 == 0) & (r1 == 0)
    a = np.where(zero, 0.0, np.where(small, np.inf, ((ab0 * r0 + ab1 * r1) * INFLATE + ETA) / norm * INFLATE))
    t = np.where(zero, 0.0, np.where(small, np.inf, ((ab1 * r0 + ab0 * r1) * INFLATE + ETA) / norm * INFLATE))
    return a, t


def _finish(run: _Run, cases: np.ndarray, w: int, stop: str, *state: np.ndarray) -> None:
    """The active cases ``cases`` end after w impulses with ``stop``; ``state`` holds their last
    rates and radii, and the sums of their single impacts' rates and radii ((m, r) arrays)."""
    run.stop[cases] = stop
    run.iterations[cases] = w
    run.out_b[cases], run.out_rb[cases], run.acc[cases], run.racc[cases] = state


def solve_batch(
    batch: Batch, max_iterations: int = 100, *, exact_fallback: bool = True, budget: Any = None
) -> BatchResult:
    """Run the rule on every case of the batch; see the module docstring.

    Cases whose branch cannot be certified in floats go to the exact rungs (with
    ``exact_fallback``, under the :class:`~verify.laws.rule.Budget` ``budget``, which bounds
    their exact arithmetic; otherwise they end with stop ``"undecided"``). The cap on the
    impulses is the engines' (:class:`Limits`).

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0], [0, 1]], [[-1, 1]], [0])
    >>> out = solve_batch(systems_batch([s, s], [["1", "0"], ["0", "1"]]))
    >>> out.impact_sets(0), out.impact_sets(1), out.stop, out.v.tolist()
    ([(0,)], [], ['exit', 'exit'], [[0.5, 0.5], [0.0, 1.0]])
    """
    run = _Run(batch, max_iterations, exact_fallback, budget)
    with np.errstate(all="ignore"):  # infinities and NaNs leave signs undecided: exact rungs
        if run.r == 2:
            _plane(run)
        else:
            _boxes(run)
    run.redo_exactly()
    return run.result()
