"""The boundary of never-exits, closed exactly: where a repeating pattern of impacts stops attracting.

Below a boundary the runs of a map settle into a pattern: the same p impact sets forever, each one
single or of mutually orthogonal constraints, so that each impulse is a linear map of the rates
(beta = 1, :func:`~verify.proofs.cones.period.linear_step`) and a period is one matrix M(eps) of rational
functions (:func:`pattern_map`). Write its characteristic polynomial over Q(eps); where a quadratic
factor q has the largest roots and its discriminant changes sign, the two largest eigenvalues meet and
turn non-real: that root of the discriminant, eps*, is the boundary (:func:`collisions`). For three balls
it gives 7 - 4*sqrt(3), for four unit balls 3 - 2*sqrt(2), for the masses 2, 1, 1, 2 it gives 2 - sqrt(3).

Up to eps*, a cone closed under the period is built from the pattern itself
(:func:`boundary_generators`): on the plane W = ker q(M), with M|W = B in a basis (w_a, w_b), an
eigenvector is (B_01, lam - B_00), affine in lam, so the vector at the mean of the two eigenvalues,

    v_mid = B_01 w_a + (B_11 - B_00)/2 w_b,

lies between the two eigen-directions while they are real and is the one eigen-direction at eps*: a
rational function of eps. The directions of W flow from the smaller eigenvector to the larger one, so
the sector from v_mid to the rates' own W-part (on the far side of the larger eigenvector) is mapped
into itself, up to and at eps*. The other eigenvalues (the factors of the characteristic polynomial
besides q, each linear) are no larger in modulus there, so a slab of half-width delta around the
sector along their eigenvectors z_i closes it in the full space. The generators are the rates b, their
mirror 2 b_W - b across W, and v_mid +- delta z_i; the cone is checked as every cone of a period is
(:func:`~verify.proofs.cones.period.close`, exact signs on the whole piece, cut where a sign changes), and
at eps* itself on the number field of eps*. The certificate is an ordinary "invariant cone of a
period": ``tests/certificate_check.py`` checks it without this module.

Above eps* the two eigenvalues that met are not real; where, besides, no real eigenvalue of the period is
positive of their modulus (:func:`without_real_top`, exact), its spectral radius is not an eigenvalue and
no cone at all is mapped into itself by the period (Krein-Rutman). That part stays unexplored unless the
runs exit within the bound.

>>> import sympy as sp
>>> from verify.models.cradle import cradle_system
>>> K = SymbolicBackend(Piece.closed(0, 1), RootCache())
>>> M = pattern_map(cradle_system(EPS, 4, backend=K), [(0, 2), (1,)])
>>> [str(x) for x, _ in collisions(M, Piece.closed(0, 1), RootCache())]
['3 - 2*sqrt(2)']
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import reduce
from operator import add
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps.widen import at_point, closed_cone
from verify.numbers.algebraic import RealAlgebraic, X
from verify.numbers.backends.base import Backend
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.numbers.numeric import certified_sign
from verify.proofs.cones.period import linear_step
from verify.proofs.termination import MAX_PERIOD

LAM = sp.Symbol("lam")
#: the slab's half-width, as a share of the most that keeps v_mid +- delta z in the pattern's signs
SLABS = (Fraction(1, 2), Fraction(3, 4), Fraction(1, 4), Fraction(7, 8))
#: periods of the pattern tried as the start of the cone (the run's rates come closer to the larger eigenvector)
STARTS = 4

Build = Callable[[SymbolicBackend], System]


@dataclass
class Decided:
    """A part proved never to exit by a boundary cone: the run's impulses up to the cone, their impact sets,
    the velocity there (SymPy, in eps), the certificate, and the boundary it stops short of when its cones do
    not reach it (:mod:`verify.maps.turning`; None when they do)."""

    piece: Piece
    iterations: int
    impact_sets: list[tuple[int, ...]]
    velocity: list[Any]
    certificate: dict[str, Any]
    short_of: RealAlgebraic | None = None


@dataclass(frozen=True)
class Pattern:
    """Impact sets that repeat from impulse ``start`` on, ``sets`` being one period."""

    start: int
    sets: tuple[tuple[int, ...], ...]

    def __str__(self) -> str:
        return "".join("(" + ",".join(f"S{j + 1}" for j in J) + ")" for J in self.sets)


def pattern_of(impact_sets: Sequence[Sequence[int]], repeats: int = 3) -> Pattern | None:
    """The shortest period (at most ``MAX_PERIOD`` impulses) that the impact sets repeat at their end, at least
    ``repeats`` times, from the earliest impulse on which they do.

    >>> pattern_of([(0,), (1,), (0, 2), (1,), (0, 2), (1,), (0, 2), (1,)])
    Pattern(start=1, sets=((1,), (0, 2)))
    """
    sets = [tuple(J) for J in impact_sets]
    for p in range(1, MAX_PERIOD + 1):
        start = len(sets) - p
        while start > 0 and sets[start - 1] == sets[start - 1 + p]:
            start -= 1
        if len(sets) - start >= repeats * p:
            return Pattern(start, tuple(sets[start : start + p]))
    return None


def sympified(K: Backend, x: Any) -> Any:
    """An element of the backend K as a SymPy expression (in eps on the symbolic backend).

    >>> sympified(SymbolicBackend(Piece.closed(0, 1)), SymbolicBackend(Piece.closed(0, 1)).parameter / 2)
    eps/2
    """
    return sp.sympify(K.to_number(x))


def pattern_map(system: System, sets: Sequence[Sequence[int]]) -> sp.Matrix | None:
    """The matrix of one period of linear impulses on the rates, over Q(eps) (None when an impulse of the
    pattern is not linear): an impulse on J is ``b -> b - sum_j (1 + e_j)(b_j / G_jj) G[:, j]``."""
    K, r = system.backend, system.r
    if not all(linear_step(system, J) for J in sets):
        return None
    G = sp.Matrix(r, r, lambda i, j: sympified(K, system.gram[i][j]))
    e = [sympified(K, x) for x in system.restitution]
    M = sp.eye(r)
    for J in sets:
        A = sp.eye(r)
        for j in J:
            A -= (1 + e[j]) / G[j, j] * G[:, j] * sp.Matrix([[1 if k == j else 0 for k in range(r)]])
        M = (A * M).applyfunc(sp.cancel)
    return M


def characteristic(M: sp.Matrix) -> Any:
    """The numerator of M's characteristic polynomial in lam (a polynomial in lam and the parameters: eps, or
    the two of a plane map)."""
    return sp.Poly(sp.together(M.charpoly(LAM).as_expr()).as_numer_denom()[0], LAM, *_parameters(M)).as_expr()


def _parameters(M: sp.Matrix) -> list[sp.Symbol]:
    """The parameters M is written in: eps on a line, the two of a plane map on a cell."""
    return sorted(M.free_symbols, key=str) or [EPS]


def factors(M: sp.Matrix) -> list[Any]:
    """The irreducible factors of M's characteristic polynomial of positive degree in lam, over Q(parameters)."""
    found = sp.factor_list(characteristic(M), LAM, *_parameters(M))[1]
    return [f for f, _ in found if sp.Poly(f, LAM).degree() > 0]


def quadratics(factors: Sequence[Any], most: int) -> Iterator[tuple[Any, list[Any]]]:
    """Each factor of degree 2 in lam with the other factors, when none of these has a degree above ``most``."""
    for q in factors:
        if sp.Poly(q, LAM).degree() != 2:
            continue
        others = [f for f in factors if f is not q]
        if all(sp.Poly(f, LAM).degree() <= most for f in others):
            yield q, others


def collisions(M: sp.Matrix, piece: Piece, cache: RootCache) -> list[tuple[RealAlgebraic, sp.Poly]]:
    """The points of ``piece`` where the two largest eigenvalues of M meet: (eps*, the quadratic factor q of
    the characteristic polynomial whose double root is there), where q's discriminant changes sign and
    every other factor is linear with roots no larger in modulus at eps*."""
    out = []
    for q, others in quadratics(factors(M), 1):
        a, b, _ = sp.Poly(q, LAM).all_coeffs()
        disc = sp.Poly(sp.discriminant(q, LAM), EPS)
        for d, times in disc.factor_list()[1]:
            if d.degree() < 1 or times % 2 == 0:  # an irreducible factor: of even multiplicity, no change of sign
                continue
            for x in cache.roots(sp.Poly(d.as_expr().subs(EPS, X), X, domain="QQ")):
                if not piece.contains(x) or x.poly.degree() > 2:
                    continue
                if _largest(-b / (2 * a), others, x):
                    out.append((x, q))
    return out


def _value(expr: Any, x: RealAlgebraic) -> Any:
    """A rational function of eps at x, exactly (radicals for a quadratic irrational x)."""
    return sp.radsimp(sp.expand(sp.sympify(expr).subs(EPS, x.expr)))


def _largest(root: Any, others: Sequence[Any], x: RealAlgebraic) -> bool:
    """|root| >= |root of each linear factor| at x (signs certified: intervals, and an exact test of 0)."""
    at = _value(root, x)
    for f in others:
        c1, c0 = sp.Poly(f, LAM).all_coeffs()
        other = _value(-c0 / c1, x)
        if certified_sign(at * at - other * other) < 0:
            return False
    return True


def without_real_top(M: sp.Matrix, q: Any, piece: Piece, cache: RootCache) -> bool:
    """Whether, on all of ``piece``, the roots of the quadratic factor q of M's characteristic polynomial are
    not real and no other eigenvalue (the roots of the linear factors) is a positive real number of at least
    their modulus: then the spectral radius of M is not an eigenvalue, and by the Krein-Rutman theorem M maps
    no closed pointed cone into itself but {0}. Every sign is decided exactly on the piece; a sign that
    changes inside it gives False."""
    K = SymbolicBackend(piece, cache)
    Q = sp.Poly(q, LAM)
    a, b, c = Q.all_coeffs()
    try:
        if K.sign(K.convert(sp.cancel(b * b - 4 * a * c))) >= 0:
            return False
        modulus = K.convert(sp.cancel(c / a))  # the product of the two non-real roots: their modulus squared
        for f in factors(M):
            if sp.Poly(f, LAM).degree() == 1:
                c1, c0 = sp.Poly(f, LAM).all_coeffs()
                root = K.convert(sp.cancel(-c0 / c1))
                if K.sign(root) > 0 and K.sign(modulus - root * root) <= 0:
                    return False
    except Split:
        return False
    return True


@dataclass
class Frame:
    """The plane W = ker q(M) and the other eigenvectors U of a period M, with v_mid (see the module) and the
    inverse of the basis (W, U), all over Q(eps): SymPy matrices, or (:func:`generators_of` reads either) the same
    entries as lists (the inverse a list of rows) of a backend's elements."""

    W: list[Any]
    U: list[Any]
    mid: Any
    inverse: Any


def frame(M: sp.Matrix, q: Any) -> Frame | None:
    """The frame of the period M for its quadratic factor q, or None when M is not diagonalisable into W and
    eigenvectors of linear factors over Q(eps)."""
    r = M.shape[0]
    a2, a1, a0 = sp.Poly(q, LAM).all_coeffs()
    W = (a2 * M * M + a1 * M + a0 * sp.eye(r)).applyfunc(sp.cancel).nullspace(simplify=True)
    if len(W) != 2:
        return None
    U: list[sp.Matrix] = []
    for f in factors(M):
        if sp.Poly(f, LAM).degree() == 1:
            c1, c0 = sp.Poly(f, LAM).all_coeffs()
            U += (M + (c0 / c1) * sp.eye(r)).applyfunc(sp.cancel).nullspace(simplify=True)
    basis = sp.Matrix.hstack(*W, *U)
    if len(U) != r - 2 or sp.cancel(basis.det()) == 0:
        return None
    Wm = sp.Matrix.hstack(*W)
    B = ((Wm.T * Wm).inv() * Wm.T * M * Wm).applyfunc(sp.cancel)
    mid = (B[0, 1] * W[0] + (B[1, 1] - B[0, 0]) / 2 * W[1]).applyfunc(sp.cancel)
    return Frame(W, U, mid, basis.inv().applyfunc(sp.cancel))


def boundary_generators(
    f: Frame, first: Sequence[int], b: Sequence[Any], *, slab: Fraction, at: Mapping[sp.Symbol, Any]
) -> list[list[Any]] | None:
    """The generators of the boundary cone (see the module) as SymPy expressions in the parameters: the rates'
    mirror across W, then v_mid +- delta z_i; ``first`` is the pattern's first impact set (the signs at the cone's
    phase), ``at`` rational values of the parameters inside the piece (or cell) where the orientation and the
    slab's width are chosen (:func:`orientation`; the cone is checked on all of it afterwards)."""
    chosen = orientation(f, first, at)
    return None if chosen is None else generators_of(f, b, sp.Rational(slab.numerator, slab.denominator), chosen)


#: what :func:`orientation` chooses at a point: whether v_mid is turned, and for each z_i the entry of v_mid and z_i
#: whose ratio is the least in modulus there, with the sign of that ratio
Orientation = tuple[bool, tuple[tuple[int, int], ...]]


def orientation(f: Frame, first: Sequence[int], at: Mapping[sp.Symbol, Any]) -> Orientation | None:
    """The choices :func:`boundary_generators` makes at the point ``at`` (the same for a frame already taken
    at that point), or None when v_mid points into no orthant of ``first``'s approaching rates there."""
    turn = all(f.mid[i].subs(at) > 0 for i in first)
    v = [-x for x in f.mid] if turn else list(f.mid)
    if not all(v[i].subs(at) < 0 for i in first):
        return None
    widest = []
    for z in f.U:
        ratios = [(sp.cancel(v[i] / z[i]).subs(at), i) for i in range(len(z)) if z[i] != 0 and v[i] != 0]
        if not ratios:
            return None
        value, i = min(ratios, key=lambda t: abs(t[0]))
        widest.append((i, int(sp.sign(value))))
    return turn, tuple(widest)


def generators_of(f: Frame, b: Sequence[Any], slab: Any, chosen: Orientation) -> list[list[Any]]:
    """The boundary cone's generators (:func:`boundary_generators`) for the choices ``chosen`` of
    :func:`orientation`, in the frame's arithmetic: SymPy expressions (in lowest terms; over a frame taken at a
    point, numbers), or a backend's elements (``b`` and ``slab`` then of that backend too)."""
    W, U, mid = [list(w) for w in f.W], [list(u) for u in f.U], list(f.mid)
    inverse = f.inverse.tolist() if isinstance(f.inverse, sp.MatrixBase) else f.inverse
    turn, widest = chosen
    v = [-x for x in mid] if turn else mid
    coords = [_cancelled(reduce(add, (inverse[i][j] * b[j] for j in range(len(b))))) for i in range(2)]
    b_w = [coords[0] * W[0][k] + coords[1] * W[1][k] for k in range(len(b))]
    gens = [[_cancelled(x + x - y) for x, y in zip(b_w, b)]]
    for z, (i, s) in zip(U, widest):
        delta = _cancelled(slab * (v[i] / z[i]))
        delta = delta if s > 0 else -delta if s < 0 else delta - delta  # the last: the zero of delta's arithmetic
        gens += [[_cancelled(x + delta * y) for x, y in zip(v, z)], [_cancelled(x - delta * y) for x, y in zip(v, z)]]
    return gens


def _cancelled(x: Any) -> Any:
    """x in lowest terms: a number, or a backend's element, already is."""
    return sp.cancel(x) if isinstance(x, sp.Basic) and x.free_symbols else x


@dataclass
class _Search:
    """What the boundary cones of one phase of a pattern are built from."""

    build: Build
    velocity: Sequence[Any]
    pattern: Pattern
    frame: Frame
    bound: int
    cache: RootCache

    def decide(self, piece: Piece) -> list[Decided]:
        """The parts of ``piece`` (an interval up to eps*, or eps* itself) with a boundary cone, cut where a sign
        changes."""
        out, work = [], [piece]
        while work:
            part = work.pop()
            system: System | None = self.build(SymbolicBackend(part, self.cache))
            value = None
            if part.is_point:
                value, system = part.lower.expr, at_point(system, part.lower)  # type: ignore[arg-type]
            if system is None:
                continue
            sample = Fraction(part.lower.lo) if part.is_point else part.sample()
            try:
                cert = self._first_cone(system, sample, value)
            except Split as split:
                work.extend(part.cut([x for poly in split.polys for x in self.cache.roots(poly)]))
                continue
            if cert is not None:
                run = solve(system, self.velocity, max_iterations=cert[0], trace=False, certify=False)
                shown = [sp.sympify(system.backend.to_number(x)) for x in run.exit_velocity]
                out.append(Decided(part, cert[0], list(run.impact_sets), shown, cert[1]))
        return out

    def _first_cone(self, system: System, sample: Fraction, value: Any) -> tuple[int, dict[str, Any]] | None:
        """(impulses to the cone, its certificate) for the first start and slab that close, or None; at a point
        (``value``) the generators are taken at that value, in its number field."""
        p = len(self.pattern.sets)
        starts = range(self.pattern.start, min(self.bound, self.pattern.start + STARTS * p) + 1, p)
        for start in starts:
            run = solve(system, self.velocity, max_iterations=start, trace=False, certify=False)
            if run.stop != "max_iterations" or run.iterations != start:
                return None
            b = list(system.rates(run.exit_velocity))
            at = {EPS: sp.Rational(sample.numerator, sample.denominator)}
            for slab in SLABS:
                gens = boundary_generators(self.frame, self.pattern.sets[0], [sympified(system.backend, x) for x in b],
                                           slab=slab, at=at)  # fmt: skip
                if gens is None:
                    continue
                if value is not None:
                    gens = [[sp.radsimp(sp.expand(x.subs(EPS, value))) for x in g] for g in gens]
                cert = closed_cone(system, b, p, gens)
                if cert is not None:
                    return start, cert
        return None


def closed_below(
    build: Build, velocity: Sequence[Any], piece: Piece, pattern: Pattern, *, bound: int, cache: RootCache
) -> list[Decided]:
    """The parts of ``piece`` proved never to exit by a boundary cone of ``pattern`` (the run's rates after
    ``pattern.start + k p`` impulses, k < :data:`STARTS`, at most ``bound``), in order; the rest of ``piece`` is
    not in the list. Each certificate names the boundary it reaches (``"boundary"``)."""
    p = len(pattern.sets)
    found: list[Decided] = []
    for j in range(p):  # each phase of the period in turn, until one gives cones
        phase = Pattern(pattern.start + j, pattern.sets[j:] + pattern.sets[:j])
        M = pattern_map(build(SymbolicBackend(piece, cache)), phase.sets)
        if M is None:
            return []
        for star, q in collisions(M, piece, cache):
            f = frame(M, q)
            if f is None:
                continue
            search = _Search(build, velocity, phase, f, bound, cache)
            parts = [Piece(star, star, True, True)]
            if piece.lower.cmp(star) < 0:
                parts = Piece(piece.lower, star, piece.lower_closed, True).cut([star])
            decided = [d for part in parts for d in search.decide(part)]
            beyond = star.cmp(piece.upper) < 0 and without_real_top(
                M, q, Piece(star, piece.upper, False, piece.upper_closed), cache
            )
            for d in decided:
                d.certificate["boundary"] = {
                    "pattern": str(pattern),
                    "eps": str(star),
                    "factor": str(q),
                    "no_cone_beyond": beyond,  # above it, up to the piece's end: no cone is mapped into itself
                }
            found += decided
        if found:
            break
    found.sort(key=lambda f: (f.piece.lower, not f.piece.is_point))
    return found
