"""Every eps above a boundary exits: the rates leave the repeating impacts, and where they leave them they exit.

Above the boundary eps* of :mod:`verify.maps.boundary` the two eigenvalues of the period M that met there are
not real. For four unit balls (the period (S1,S3)(S2)) and for the masses 2, 1, 1, 2 the characteristic
polynomial of M is, up to a constant, (lam + eps)(lam^2 - tau lam + eps^2): above eps* every eigenvalue has
modulus eps, none is eps itself, and the rates do not settle. On the plane W = ker q(M) (q the quadratic
factor) A = M/eps has determinant 1, and in a basis of W it keeps the definite quadratic form

    Q = [[A_10, (A_11 - A_00)/2], [(A_11 - A_00)/2, -A_01]],   A^T Q A = Q.

Write the rates at the start of the period x_0 = w_0 + c u (w_0 in W, u the eigenvectors of -eps). After k
periods (while the run follows them) the rates are x_k = M^k x_0, and x_k / eps^k = A^k w_0 + (-1)^k c u lies on
one of the two ellipses E+- = {w in W : Q(w) = Q(w_0)} +- c u. Two facts then prove that every eps exits:

1. **The rates leave the period.** The mean of x_k / eps^k over k < n tends to 0 (neither -1 nor an eigenvalue
   of A is 1), while every x_k lies in the orthant where the constraints of the period's first impact set
   approach and those of its last separate (together every constraint, once): a linear form (the sum of the
   separating rates less the approaching ones) is there at least a positive multiple of |x|, and on the
   ellipses |x| stays away from 0, so its mean cannot tend to 0.
2. **Where they leave, they exit.** For every point z of E+ and E- and every eps of the interval at once, if the
   run from z follows one period, then from there it exits within one impulse, or follows the period again.
   The points of each ellipse are rational in (eps, t): the line through w_0 of slope t (or 1/t) meets it once
   more, at w_0 - 2 Q(w_0, d)/Q(d, d) d, d = (1, t) or (t, 1), t in [-1, 1]; the rule is run from them for
   two periods on the exact cells of (eps, t) (:mod:`verify.maps.plane`), and every cell is checked.

So the first period the rates do not follow is the last: the run exits right after it (the rule depends only on
the direction of the rates). The interval starts a rational just above eps* (at eps* itself A is not
diagonalisable and Q degenerates): what lies between stays undecided, a length below :data:`GAP`. Cells at an
irrational eps (measure 0, no rational point) are not run; those eps stay undecided, listed.

>>> from verify.models.cradle import cradle_system
>>> K = SymbolicBackend(Piece.closed(0, 1), RootCache())
>>> M = pattern_map(cradle_system(EPS, 4, backend=K), [(0, 2), (1,)])
>>> q, linear = unit_modulus(M)
>>> sp.factor(q), linear
(-eps**2*lam + 2*eps**2 + 2*eps*lam + 2*lam**2 - lam, [eps + lam])
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps.boundary import LAM, Pattern, characteristic, frame, pattern_map, sympified
from verify.maps.plane import plane_parts
from verify.maps.watch import Watch
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.numbers.format import format_exact

#: the largest length left undecided between the boundary and the interval the argument covers
GAP = Fraction(1, 10**9)
#: the slope of the lines through w_0 (see the module)
T = sp.Symbol("t")

Build = Callable[[Any], System]  #: the system on any backend whose parameter is eps (a line's, or a plane's)


@dataclass
class Leaving:
    """What :func:`exits_above` proves: every eps of [lower, upper] exits, except the irrational ``not_run`` ones
    (where a cell of the check lies, not run), with the certificate."""

    lower: Fraction
    upper: Fraction
    certificate: dict[str, Any]
    not_run: list[RealAlgebraic]


def _rational_above(x: RealAlgebraic, width: Fraction) -> Fraction:
    """A rational above ``x``, within ``width`` of it."""
    hi = x.narrowed(width)[1]
    return hi if hi > x.hi or not x.is_rational else hi + width


def unit_modulus(M: sp.Matrix) -> tuple[Any, list[Any]] | None:
    """(q, the linear factors) when M's characteristic polynomial is a quadratic q in lam with q(0) = eps^2 times
    its leading coefficient, times factors lam + eps (each up to a constant); else None."""
    factors = [f for f, _ in sp.factor_list(characteristic(M), LAM, EPS)[1] if sp.Poly(f, LAM).degree() > 0]
    quads = [f for f in factors if sp.Poly(f, LAM).degree() == 2]
    linear = [f for f in factors if sp.Poly(f, LAM).degree() == 1]
    if len(quads) != 1 or len(quads) + len(linear) != len(factors):
        return None
    a2, _, a0 = sp.Poly(quads[0], LAM).all_coeffs()
    if sp.cancel(a0 / a2 - EPS**2) != 0:
        return None
    for f in linear:
        c1, c0 = sp.Poly(f, LAM).all_coeffs()
        if sp.cancel(c0 / c1 - EPS) != 0:
            return None
    return quads[0], linear


def kept_form(a: Any, b: Any, c: Any, d: Any) -> list[list[Any]]:
    """The rows of the quadratic form Q = [[c, h], [h, -b]], h = (d - a)/2, that A = [[a, b], [c, d]] keeps when
    det A = 1 (A^T Q A = Q), in any arithmetic with a division by 2 (each caller checks it in its own).

    >>> kept_form(*(sp.Integer(x) for x in (2, 1, 1, 1)))
    [[1, -1/2], [-1/2, -1]]
    """
    h = (d - a) / 2
    return [[c, h], [h, -b]]


def invariant_form(B: sp.Matrix) -> sp.Matrix | None:
    """The quadratic form that A = B/eps keeps (A^T Q A = Q), checked exactly; None when det A is not 1."""
    A = (B / EPS).applyfunc(sp.cancel)
    if sp.cancel(A.det() - 1) != 0:
        return None
    Q = sp.Matrix(kept_form(A[0, 0], A[0, 1], A[1, 0], A[1, 1])).applyfunc(sp.cancel)
    if any(sp.cancel(x) != 0 for x in (A.T * Q * A - Q)):
        return None
    return Q


def _sign_on(expr: Any, piece: Piece, cache: RootCache) -> int | None:
    """The sign of the rational function ``expr`` of eps on all of ``piece``, exactly; None when it changes there."""
    K = SymbolicBackend(piece, cache)
    try:
        return K.sign(K.convert(sp.cancel(expr)))
    except Split:
        return None


def ellipse_velocities(
    system: System, M: sp.Matrix, q: Any, x0: sp.Matrix, *, box: Piece, cache: RootCache
) -> list[list[Any]] | None:
    """The velocities whose rates run over E+ and E- (see the module), rational in eps and :data:`T`, one list per
    chart and sign; None when M has no frame for q, A keeps no form, or a velocity is not defined on all of
    ``box`` x [-1, 1] (:func:`_defined`)."""
    f = frame(M, q)
    if f is None:
        return None
    Wm = sp.Matrix.hstack(*f.W)
    B = ((Wm.T * Wm).inv() * Wm.T * M * Wm).applyfunc(sp.cancel)
    Q = invariant_form(B)
    if Q is None:
        return None
    coords = (f.inverse * x0).applyfunc(sp.cancel)
    w0 = sp.Matrix(coords[:2])
    cu = sum((coords[2 + i] * f.U[i] for i in range(len(f.U))), sp.zeros(system.r, 1))
    K = system.backend
    shapes = [sp.Matrix([sympified(K, x) for x in system.combine_normals([(j, K.one)])]) for j in range(system.r)]
    G = sp.Matrix(system.r, system.r, lambda i, j: sympified(K, system.gram[i][j]))
    Ginv = G.inv()
    out = []
    for d in (sp.Matrix([1, T]), sp.Matrix([T, 1])):
        qdd = sp.cancel((d.T * Q * d)[0])
        s = sp.cancel(-2 * (w0.T * Q * d)[0] / qdd)
        w = (w0 + s * d).applyfunc(sp.cancel)
        for sign in (1, -1):
            z = w[0] * f.W[0] + w[1] * f.W[1] + sign * cu
            y = Ginv * z  # the impulse magnitudes whose rates are z: the velocity sum_j y_j U_j
            v = sum((y[j] * shapes[j] for j in range(system.r)), sp.zeros(system.n, 1)).applyfunc(sp.cancel)
            if not _defined(list(v), qdd, box, cache):
                return None
            out.append(list(v))
    return out


def _defined(v: Sequence[Any], qdd: Any, box: Piece, cache: RootCache) -> bool:
    """Whether ``v`` is defined on all of ``box`` x [-1, 1], exactly: every factor of its denominators that is a
    polynomial in eps alone keeps one sign on the box, and every other one divides the numerator of Q(d, d), which
    does not vanish there (Q is definite where q's roots are not real, d is not 0, and the denominator of Q(d, d)
    is checked as the others)."""
    qn, qd = sp.fraction(sp.cancel(qdd))
    factors = [f for x in [*v, qdd] for f, _ in sp.factor_list(sp.fraction(sp.cancel(x))[1], EPS, T)[1]]
    for f in factors:
        if T not in f.free_symbols:
            if EPS in f.free_symbols and _sign_on(f, box, cache) in (None, 0):
                return False
        elif sp.div(qn, f, EPS, T)[1] != 0 or T in qd.free_symbols:
            return False
    return True


def leaves_then_exits(impact_sets: Sequence[Sequence[int]], stop: str, sets: Sequence[tuple[int, ...]]) -> bool:
    """Fact 2 for one run from a point of an ellipse: it does not follow the period, or after one period it exits
    within one impulse or follows the period again.

    >>> leaves_then_exits([(0, 2), (1,), (0,)], "exit", [(0, 2), (1,)])
    True
    >>> leaves_then_exits([(0, 2), (1,), (0,), (1,)], "max_iterations", [(0, 2), (1,)])
    False
    """
    runs = [tuple(J) for J in impact_sets]
    p = len(sets)
    if runs[:p] != list(sets):
        return True
    rest = runs[p:]
    return (stop == "exit" and len(rest) <= 1) or rest[:p] == list(sets)


def exits_above(
    build: Build,
    velocity: Sequence[Any],
    piece: Piece,
    pattern: Pattern,
    cache: RootCache | None = None,
    *,
    watch: Watch | None = None,
) -> Leaving | None:
    """The proof (see the module) that every eps of ``piece``, whose runs follow ``pattern`` up to the map's bound,
    exits; None when the period is not of that kind there or a cell breaks fact 2. The proof covers ``piece``
    whole, or, when its lower end is the boundary where the eigenvalues of the period turn non-real, all but a gap
    below :data:`GAP` above it; the irrational eps where a cell of the check lies (not run) are listed. Each phase of
    the period is tried (the one whose last impact set the rates leave after), the phases that a few exact runs
    refute first left out. With a ``watch`` (:class:`~verify.maps.watch.Watch`), its wall-clock budget and Ctrl-C
    also stop the cells of the check: then there is no proof (None), and ``watch.stopped`` says why."""
    cache = cache or RootCache()
    p = len(pattern.sets)
    upper = piece.upper.narrowed(GAP)[1]
    for lower in (piece.lower.narrowed(GAP)[0], _rational_above(piece.lower, GAP)):
        if lower >= upper:
            continue
        box = Piece.closed(lower, upper)
        phases = [Pattern(pattern.start + j, pattern.sets[j:] + pattern.sets[:j]) for j in range(p)]
        ready = [x for x in (_ellipses(build, velocity, box, phase, cache) for phase in phases) if x is not None]
        if not ready:
            continue
        for phase, families, M in ready:
            found = _cells_checked(build, box, phase, families, watch)
            if watch is not None and watch.stopped:
                return None
            if found is not None:
                cells, not_run = found
                certificate = {
                    "kind": "leaves and exits",
                    "pattern": str(phase),
                    "interval": [format_exact(lower), format_exact(upper)],
                    "characteristic": str(sp.factor(characteristic(M))),
                    "families": len(families),
                    "cells": cells,
                }
                return Leaving(lower, upper, certificate, not_run)
        return None
    return None


def _ellipses(
    build: Build, velocity: Sequence[Any], box: Piece, pattern: Pattern, cache: RootCache
) -> tuple[Pattern, list[list[Any]], sp.Matrix] | None:
    """The phase ``pattern`` with the velocities of its ellipses on ``box`` (and its period), when facts 1 and 2
    may hold there: the period is of the kind (see the module), the eigenvalues of q are non-real on all of the box,
    and exact runs from 33 points of each ellipse at a rational eps of the box keep fact 2."""
    first, last = set(pattern.sets[0]), set(pattern.sets[-1])
    system = build(SymbolicBackend(box, cache))
    if first & last or first | last != set(range(system.r)):
        return None
    M = pattern_map(system, pattern.sets)
    found = unit_modulus(M) if M is not None else None
    if M is None or found is None:
        return None
    q = found[0]
    a2, a1, a0 = sp.Poly(q, LAM).all_coeffs()
    if _sign_on(a1**2 - 4 * a2 * a0, box, cache) != -1:  # the eigenvalues of q are not real on all of it
        return None
    try:
        run = solve(system, list(velocity), max_iterations=pattern.start, trace=False, certify=False)
    except Split:
        return None
    x0 = sp.Matrix([sympified(system.backend, x) for x in system.rates(run.exit_velocity)])
    families = ellipse_velocities(system, M, q, x0, box=box, cache=cache)
    if families is None:
        return None
    e = box.sample()
    point = build(SymbolicBackend(Piece.closed(e, e), cache))
    for v in families:
        for k in range(-16, 17):
            at = [sp.sympify(x).subs({EPS: sp.Rational(e.numerator, e.denominator), T: sp.Rational(k, 16)}) for x in v]
            r = solve(point, at, max_iterations=2 * len(pattern.sets), trace=False, certify=False)
            if not leaves_then_exits(r.impact_sets, r.stop, pattern.sets):
                return None
    return pattern, families, M


def _cells_checked(
    build: Build, box: Piece, pattern: Pattern, families: list[list[Any]], watch: Watch | None = None
) -> tuple[int, list[RealAlgebraic]] | None:
    """Fact 2 on the exact cells of (eps, t) over ``box`` x [-1, 1], for each family of points: (the cells, the
    irrational eps of the cells not run), or None when a cell breaks it or ``watch``'s clock or Ctrl-C stops the
    cells (``watch.stopped`` then says why; the cells are not counted as the map's parts)."""
    names = (str(EPS), str(T))
    lower, upper = box.lower.lo, box.upper.lo
    cells, not_run = 0, []
    for v in families:
        inner = Watch(seconds=watch.seconds, started=watch.started) if watch is not None else None
        m = plane_parts(build, v, (lower, upper, Fraction(-1), Fraction(1)), names, 2 * len(pattern.sets),
                        velocities=False, certify=False, watch=inner)  # fmt: skip
        if watch is not None and inner is not None and inner.stopped:
            watch.stopped, watch.interrupted = inner.stopped, inner.interrupted
            return None
        for part in m.parts:
            if part.stop == "not_run":
                not_run.append(part.cell.x_lo)
            elif not leaves_then_exits(part.impact_sets, part.stop, pattern.sets):
                return None
        cells += len(m.parts)
    return cells, sorted(set(not_run), key=lambda x: (x.lo, x.hi))
