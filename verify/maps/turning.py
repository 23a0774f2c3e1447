"""Boundary cones of a period whose other eigenvalues turn: a complex pair of the same modulus as the meeting ones.

:mod:`verify.maps.boundary` closes the boundary where the two largest eigenvalues of a period meet when the
period's characteristic polynomial splits over Q(eps) into that quadratic factor q and linear ones. For five
unit balls and the period (S1,S3)(S2,S4) it does not: a quartic factor is irreducible over Q(eps) and splits
only over Q(sqrt(5))(eps), into q (real roots mu1 > mu2 below the boundary, mu1 mu2 = eps^2) and a conjugate
factor whose roots are a complex pair of modulus eps, turning the rates around on its plane U.

Here the extension is found exactly (:func:`extension`, from the quartic's resolvent cubic), the boundary is
the root of q's discriminant over Q(sqrt(d)) (:func:`field_collisions`, its sign change and the moduli checked
exactly in the number field of eps*), and the frame W = ker q(M), U = ker of the other factors is computed
over Q(sqrt(d))(eps). The cone (:func:`turning_generators`) is

    cone{ v_mid } + cone{ b_W + P_j },   P_j = +-(M/s)^j b_U,  j < n,

with b the rates at the cone's phase, b_W + b_U its parts on W and U, v_mid as in :mod:`verify.maps.boundary`
and s the modulus of U's eigenvalues (a rational function of eps: eps for the balls). The U-part of the rates
is turned by the period and decays against the W-part (by (s/mu1)^k), so the points P_j, taken around the
orbit, hold the turned rates after enough periods. The frame is exact over Q(sqrt(d))(eps); the generators
are its values with sqrt(d) replaced by a rational within 1e-18, so that the certificate is an ordinary
"invariant cone of a period" over Q(eps), checked exactly on the whole piece as every cone is
(:func:`~verify.maps.widen.closed_cone`) and by ``tests/certificate_check.py``.

No such cone holds at eps* itself (the W-part grows only linearly there, while a polygon of U is not
mapped into itself by a turn of irrational angle), nor on pieces too close to it for the polygons tried:
those stay unexplored, and their reason says so.

>>> from verify.maps.boundary import pattern_map
>>> from verify.models.cradle import cradle_system
>>> M = pattern_map(cradle_system(EPS, 5, backend=SymbolicBackend(Piece.closed(0, 1), RootCache())), [(0, 2), (1, 3)])
>>> extension(M)
sqrt(5)
>>> [str(x) for x, _ in field_collisions(M, sp.sqrt(5), Piece.closed(0, 1))]
['CRootOf(x**4 - 44*x**3 + 166*x**2 - 44*x + 1, 1)']
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from verify import bounds
from verify.laws.rule import solve
from verify.maps import DEFAULT_HALVINGS
from verify.maps.boundary import LAM, Build, Decided, Pattern, characteristic, pattern_map, quadratics, sympified
from verify.maps.cells import Roots
from verify.maps.widen import closed_cone, short_point
from verify.numbers.algebraic import RealAlgebraic, X
from verify.numbers.backends.field import NumberFieldBackend
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend

Y = sp.Symbol("y")
#: digits of the rational that stands for sqrt(d) in the generators
DIGITS = 18
#: (impulses before the cone, at least; points of the orbit of the U-part) tried, in order
TRIES = ((10, 3), (14, 3), (18, 4), (22, 4))


def extension(M: sp.Matrix) -> Any | None:
    """sqrt(d), d a rational that is not a square, over which a quartic factor (in lam) of M's characteristic
    polynomial splits into two quadratics with coefficients in Q(sqrt(d))(eps), or None.

    With the quartic monic, lam^4 + a lam^3 + b lam^2 + c lam + e, and a root theta in Q(eps) of its resolvent
    cubic y^3 - b y^2 + (ac - 4e) y - (a^2 e - 4be + c^2) (theta = r1 r2 + r3 r4 for a pairing of its roots),
    the pairs' sums are the roots of t^2 + a t + (b - theta), their products of t^2 - theta t + e: both
    discriminants must be d times a square in Q(eps)."""
    for f, _ in sp.factor_list(characteristic(M), LAM, EPS)[1]:
        P = sp.Poly(f, LAM)
        if P.degree() != 4:
            continue
        top, *rest = P.all_coeffs()
        a, b, c, e = (sp.cancel(x / top) for x in rest)
        cubic = sp.numer(sp.together(Y**3 - b * Y**2 + (a * c - 4 * e) * Y - (a * a * e - 4 * b * e + c * c)))
        for g, _m in sp.factor_list(cubic, Y, EPS)[1]:
            G = sp.Poly(g, Y)
            if G.degree() != 1:
                continue
            theta = sp.cancel(-G.all_coeffs()[1] / G.all_coeffs()[0])
            found = _square_class([a * a - 4 * (b - theta), theta * theta - 4 * e])
            if found is not None:
                return found
    return None


def _square_class(discriminants: list[Any]) -> Any | None:
    """sqrt(d) when every non-zero discriminant (rational functions of eps) is d times a square, d not a square."""
    root = None
    for D in discriminants:
        D = sp.cancel(D)
        if D == 0:
            continue
        n, d = sp.fraction(D)
        content, factors = sp.factor_list(sp.expand(n * d), EPS)
        if any(m % 2 for _, m in factors):
            return None
        r = sp.sqrt(sp.Rational(content))
        if r.is_rational:
            return None
        r = sp.sqrt(sp.sqrtdenest(r**2 / sp.Rational(r.as_coeff_Mul()[0]) ** 2))  # the square-free part
        if root is not None and root != r:
            return None
        root = r
    return root


def field_factors(M: sp.Matrix, ext: Any) -> list[Any]:
    """The factors of M's characteristic polynomial over Q(ext)(eps) of positive degree in lam.

    >>> from verify.maps.boundary import pattern_map
    >>> from verify.models.cradle import cradle_system
    >>> M = pattern_map(cradle_system(EPS, 5, backend=SymbolicBackend(Piece.closed(0, 1))), [(0, 2), (1, 3)])
    >>> [sp.Poly(f, LAM).degree() for f in field_factors(M, sp.sqrt(5))]
    [2, 2]
    >>> f = turning_frame(M, field_factors(M, sp.sqrt(5))[0], sp.sqrt(5))
    >>> f.W.shape, f.domain.to_sympy(f.scale)
    ((4, 2), eps)
    """
    return [f for f, _ in sp.factor_list(characteristic(M), LAM, EPS, extension=ext)[1] if sp.Poly(f, LAM).degree() > 0]


def _conjugate(expr: Any, ext: Any) -> Any:
    return sp.expand(expr.subs(ext, -ext))


def field_collisions(M: sp.Matrix, ext: Any, piece: Piece) -> list[tuple[RealAlgebraic, Any]]:
    """The points of ``piece`` where the two roots of a quadratic factor q over Q(ext)(eps) meet, its
    discriminant changing sign there, with no other eigenvalue of larger modulus: (eps*, q). Each is a root
    of the norm of the discriminant's factor (a polynomial over Q) at which the factor itself vanishes (the
    number field's exact sign); the moduli are compared exactly there too."""
    K = NumberFieldBackend([ext])
    out = []
    for q, others in quadratics(field_factors(M, ext), 2):
        a, b, _ = sp.Poly(q, LAM).all_coeffs()
        for d, times in sp.factor_list(sp.discriminant(q, LAM), EPS, extension=ext)[1]:
            if times % 2 == 0 or sp.Poly(d, EPS).degree() < 1:
                continue
            norm = sp.Poly(sp.expand(d * _conjugate(d, ext)), EPS)
            for x in RealAlgebraic.roots_in(sp.Poly(norm.as_expr().subs(EPS, X), X, domain="QQ")):
                if not piece.contains(x) or K.sign_at(sp.Poly(d.subs(EPS, X), X, domain=K.field), x) != 0:
                    continue
                if _largest(K, sp.cancel(-b / (2 * a)), others, x):
                    out.append((x, q))
    return out


def nearest_above(M: sp.Matrix, ext: Any, piece: Piece) -> list[tuple[RealAlgebraic, Any]]:
    """The first of :func:`field_collisions` above ``piece`` (up to eps = 1, from its upper end when that end is
    open), when none lies in it: the piece lies below that boundary, where the same turning frame gives the cones
    (each is checked on its own part)."""
    one = RealAlgebraic.rational(Fraction(1))
    if piece.upper.cmp(one) >= 0:
        return []
    above = field_collisions(M, ext, Piece(piece.upper, one, not piece.upper_closed, True))  # an open end: from it
    return [min(above, key=lambda c: c[0])] if above else []  # exact order of the algebraic points


def _sign(K: NumberFieldBackend, expr: Any, x: RealAlgebraic) -> int:
    """The sign at x of a rational function of eps over the field, exactly."""
    n, d = sp.fraction(sp.cancel(sp.together(expr)))
    signs = [K.sign_at(sp.Poly(sp.expand(p).subs(EPS, X), X, domain=K.field), x) for p in (n, d)]
    return signs[0] * signs[1]


def _largest(K: NumberFieldBackend, root: Any, others: list[Any], x: RealAlgebraic) -> bool:
    """|root| >= the modulus of every root of the other factors at x: a linear factor's root, or a quadratic's
    pair when it is complex there (its modulus squared is the product c/a); a quadratic with real roots there
    is not handled (False)."""
    for f in others:
        coeffs = sp.Poly(f, LAM).all_coeffs()
        if len(coeffs) == 2:
            other2 = (coeffs[1] / coeffs[0]) ** 2
        else:
            a, b, c = coeffs
            if _sign(K, b * b - 4 * a * c, x) >= 0:
                return False
            other2 = c / a
        if _sign(K, root * root - other2, x) < 0:
            return False
    return True


@dataclass
class TurningFrame:
    """The frame of a period M over Q(ext)(eps) (DomainMatrix): W = ker q(M) (2 columns), U = the kernels of
    the other factors, the inverse of the basis (W, U), v_mid, and s, the modulus of U's eigenvalues."""

    M: Any
    W: Any
    inverse: Any
    mid: Any
    scale: Any
    domain: Any
    ext: Any


def turning_frame(M: sp.Matrix, q: Any, ext: Any) -> TurningFrame | None:
    """The frame for the quadratic factor q, or None when the other factors' roots do not all have one modulus
    that is a rational function of eps, or M is not diagonalisable into W and U over Q(ext)(eps)."""
    r = M.shape[0]
    D = sp.QQ.algebraic_field(ext).frac_field(EPS)
    MD = DomainMatrix.from_Matrix(M).convert_to(D)
    one = DomainMatrix.eye(r, D)

    def kernel(f: Any) -> Any:
        coeffs = [D.from_sympy(c) for c in sp.Poly(f, LAM).all_coeffs()]
        F = one * coeffs[-1]
        power = one
        for c in reversed(coeffs[:-1]):
            power = power * MD
            F = F + power * c
        return F.nullspace().transpose()

    W = kernel(q)
    if W.shape[1] != 2:
        return None
    scales, blocks = set(), [W]
    for f in field_factors(M, ext):
        if sp.expand(f - q) == 0:
            continue
        coeffs = sp.Poly(f, LAM).all_coeffs()
        square = (coeffs[1] / coeffs[0]) ** 2 if len(coeffs) == 2 else coeffs[2] / coeffs[0]
        s = _root(square)
        if s is None:
            return None
        scales.add(s)
        blocks.append(kernel(f))
    basis = blocks[0].hstack(*blocks[1:])
    if len(scales) != 1 or basis.shape[1] != r or basis.rank() != r:
        return None
    inverse = basis.inv()
    B = (inverse[:2, :] * MD * W).to_Matrix()
    Wm = W.to_Matrix()
    mid = DomainMatrix.from_Matrix(B[0, 1] * Wm[:, 0] + (B[1, 1] - B[0, 0]) / 2 * Wm[:, 1]).convert_to(D)
    return TurningFrame(MD, W, inverse, mid, D.from_sympy(scales.pop()), D, ext)


def _root(square: Any) -> Any | None:
    """A rational function of eps whose square is ``square`` (up to sign), or None."""
    n, d = sp.fraction(sp.cancel(sp.together(square)))
    out = sp.Integer(1)
    for part, power in ((n, 1), (d, -1)):
        content, factors = sp.factor_list(sp.expand(part), EPS)
        c = sp.sqrt(sp.Rational(content))
        if not c.is_rational or any(m % 2 for _, m in factors):
            return None
        out *= (c * sp.Mul(*[g ** (m // 2) for g, m in factors])) ** power
    return sp.cancel(out)


def _rational_sqrt(ext: Any) -> sp.Rational:
    """A convergent h/k of the continued fraction of sqrt(d) (ext = sqrt(d), d = p/q rational, from that of the
    integer sqrt(pq), divided by q) within 10^-DIGITS: the best approximation for its size, so the generators'
    numbers stay short.

    >>> _rational_sqrt(sp.sqrt(5))
    5374978561/2403763488
    """
    d = sp.Rational(ext**2)
    n, q = int(d.p) * int(d.q), int(d.q)
    a0 = math.isqrt(n)
    m, den, a = 0, 1, a0
    h, h1, k, k1 = a0, 1, 1, 0
    while k * k * q * q < 10**DIGITS:  # |sqrt(n) - h/k| < 1/k^2
        m = den * a - m
        den = (n - m * m) // den
        a = (a0 + m) // den
        h, h1, k, k1 = a * h + h1, h, a * k + k1, k
    return sp.Rational(h, k * q)


def _entries(D: Any, g: Any) -> list[Any]:
    return [D.to_sympy(g[i, 0].element) for i in range(g.shape[0])]


def turning_generators(
    f: TurningFrame, first: tuple[int, ...], b: list[Any], n: int, sample: Fraction
) -> list[list[Any]] | None:
    """The generators of the turning cone (see the module) as SymPy rational functions of eps, sqrt(d) replaced
    by a rational within 1e-18: v_mid (oriented so that the pattern's first impact set is incoming at
    ``sample``) and b_W + P_j, j < n; None when v_mid is not incoming on all of the first impact set there."""
    D = f.domain
    R = _rational_sqrt(f.ext)
    at = {EPS: sp.Rational(sample.numerator, sample.denominator), f.ext: R}
    v = f.mid
    values = [x.subs(at) for x in _entries(D, v)]
    if all(values[i] > 0 for i in first):
        v, values = -v, [-x for x in values]
    if not all(values[i] < 0 for i in first):
        return None
    bD = DomainMatrix.from_Matrix(sp.Matrix(b)).convert_to(D)
    b_w = f.W * (f.inverse * bD)[:2, :]
    point, orbit, turn = bD - b_w, [], D.one / f.scale
    for _ in range(n):
        orbit += [point, -point]
        point = (f.M * point) * turn
    return [[sp.cancel(x.subs(f.ext, R)) for x in _entries(D, g)] for g in [v] + [b_w + p for p in orbit]]


@dataclass
class _Search:
    """What the turning cones of one phase of a pattern are built from (see :func:`closed_below_turning`)."""

    build: Build
    velocity: list[Any]
    pattern: Pattern
    frame: TurningFrame
    bound: int
    roots: Roots
    built: dict[Any, Any] = field(default_factory=dict)
    easiest: int = 0  #: the first of TRIES worth trying: the one that closed the last piece
    stop: Callable[[], bool] | None = None  #: whether the map's budget says stop, asked before each piece
    halvings: int = DEFAULT_HALVINGS  #: how many times a piece without a cone is halved

    def decide(self, piece: Piece) -> list[Decided]:
        """The parts of ``piece`` with a turning cone, from its lower end up: cut where a sign of the check changes,
        halved (at a rational of least denominator in its middle third, the lower half first) where no cone
        closes, at most ``halvings`` times (towards the boundary the cones need narrower pieces); the first part
        still without a cone then ends the search (the cones only get harder towards the boundary), and what lies
        above it is left out. When ``stop()`` says so (the map's budget), the search stops there too."""
        out: list[Decided] = []
        work = [(piece, 0)]
        while work and not (self.stop is not None and self.stop()):
            part, depth = work.pop(0)
            system = self.build(SymbolicBackend(part, self.roots))
            sample = part.lower.lo if part.is_point else part.sample()
            try:
                found = self._cone(system, sample)
            except Split as split:
                cuts = part.cut([x for p in split.polys for x in self.roots.roots_of(_key(p))])
                work[:0] = [(c, depth) for c in cuts]
                continue
            if found is not None:
                bounds.use("turning_halvings", depth)
                run = solve(system, self.velocity, max_iterations=found[0], trace=False, certify=False)
                shown = [sp.sympify(system.backend.to_number(x)) for x in run.exit_velocity]
                out.append(Decided(part, found[0], list(run.impact_sets), shown, found[1]))
            elif depth < self.halvings and not part.is_point:
                work[:0] = [(c, depth + 1) for c in part.cut([RealAlgebraic.rational(short_point(part))])]
            else:
                bounds.reached("turning_halvings")
                break
        return out

    def _cone(self, system: Any, sample: Fraction) -> tuple[int, dict[str, Any]] | None:
        p, first = len(self.pattern.sets), self.pattern.sets[0]
        for t, (least, n) in enumerate(TRIES):
            if t < self.easiest:  # the pieces come in increasing eps, and nearer the boundary a cone needs more
                continue
            start = self.pattern.start + p * max(0, -(-(least - self.pattern.start) // p))
            if start > self.bound:
                break
            run = solve(system, self.velocity, max_iterations=start, trace=False, certify=False)
            if run.stop != "max_iterations" or run.iterations != start:
                return None
            b = list(system.rates(run.exit_velocity))
            key = (tuple(run.impact_sets), n)
            if key not in self.built:  # the same impulses give the same rates on every piece: built once
                rates = [sympified(system.backend, x) for x in b]
                self.built[key] = turning_generators(self.frame, first, rates, n, sample)
            gens = self.built[key]
            if gens is None:
                continue
            cert = closed_cone(system, b, p, gens)
            if cert is not None:
                self.easiest = t
                return start, cert
        return None


def _key(p: sp.Poly) -> tuple[Fraction, ...]:
    return tuple(Fraction(int(c.p), int(c.q)) for c in reversed(p.all_coeffs()))


def closed_below_turning(
    build: Build,
    velocity: list[Any],
    piece: Piece,
    pattern: Pattern,
    *,
    bound: int,
    cache: RootCache,
    stop: Callable[[], bool] | None = None,
    halvings: int = DEFAULT_HALVINGS,
) -> list[Decided]:
    """The parts of ``piece`` below a boundary over Q(sqrt(d)) proved never to exit by a turning cone of
    ``pattern`` (see the module), in order; each certificate names the boundary (``"boundary"``), which the
    cones do not reach (``"reached": False``). The search stops where ``stop()`` (the map's budget) says so, and
    halves a piece without a cone at most ``halvings`` times."""
    p = len(pattern.sets)
    found: list[Decided] = []
    for j in range(p):
        phase = Pattern(pattern.start + j, pattern.sets[j:] + pattern.sets[:j])
        M = pattern_map(build(SymbolicBackend(piece, cache)), phase.sets)
        ext = extension(M) if M is not None else None
        if M is None or ext is None:
            return []
        for star, q in field_collisions(M, ext, piece) or nearest_above(M, ext, piece):
            f = turning_frame(M, q, ext)
            if f is None or piece.lower.cmp(star) >= 0:
                continue
            below = Piece(piece.lower, star, piece.lower_closed, False) if piece.contains(star) else piece
            decided = _Search(build, velocity, phase, f, bound, Roots(), stop=stop, halvings=halvings).decide(below)
            for d in decided:
                d.short_of = star
                d.certificate["boundary"] = {
                    "pattern": str(pattern),
                    "eps": str(star),
                    "factor": str(q),
                    "no_cone_beyond": False,
                    "reached": False,
                    "extension": str(ext),
                }
            found += decided
        if found:
            break
    found.sort(key=lambda f: (f.piece.lower, not f.piece.is_point))
    return found
