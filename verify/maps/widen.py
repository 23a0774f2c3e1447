"""A single run's proof, widened to an interval: what a map does where its own parametric run stops.

Where the one-parameter map (:mod:`verify.maps.line`) leaves an interval at its bound on impulses, the
rule is run at a rational point inside it (the one of least denominator in its middle third) as
:func:`~verify.laws.rule.solve` runs it there (:func:`point_run`). When that run is proved never to exit
by a cone that a period of p impulses maps into itself, cones around the direction its rates tend to
are built at the point, of a radius from 1/4 of the rates down
(:func:`~verify.proofs.cones.period.limit_cone`), and each is checked for the whole interval on the
symbolic backend with the parametric rates after as many impulses (rational functions of the
parameter) as the first one inside it, and one period more (:func:`around_point`). Where a condition
of the check changes sign inside the interval, the interval is cut at the roots of that condition
and the check goes on on the part that holds the point: the certificate ends up on the widest
interval around the point bounded by the roots of its own conditions, every sign of it decided
exactly there. :func:`verify.maps.line.widened` tries the rest of the interval in the same way, up to
a number of points (``--widen``).

>>> from verify.models.cradle import cradle_system
>>> build = lambda K: cradle_system(EPS, 4, backend=K)
>>> piece, run, certificate = around_point(build, ["1", "0", "0", "0"], Piece.closed("0.161", "0.168"), 16, RootCache())
>>> from verify.numbers.format import format_decimal
>>> format_decimal(piece.lower, 6), format_decimal(piece.upper, 6), run.iterations, certificate["impulses"]
('0.163636', '0.164506', 16, 2)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.errors import InvalidInput, Undecided
from verify.laws.rule import solve
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.proofs.cones.lp import pivot_budget
from verify.proofs.cones.period import MAX_PIVOTS, certificate_of, close, limit_cone, member, rates_after

#: the radii (2^-bits of the rates) of the cones tried around the direction the rates tend to at a point
RADII = (2, 4, 6, 8, 10, 12)
CONE = "invariant cone of a period"
#: periods run past the first state inside the cone at the point, so that the rates lie well inside it
MARGIN = 1

Build = Callable[[SymbolicBackend], System]


def at_point(system: System, point: RealAlgebraic) -> System | None:
    """The system on the exact numbers of one value of its parameter (rationals, or the number field of a
    quadratic irrational), or None for a point of higher degree."""
    if not (point.is_rational or point.poly.degree() == 2):
        return None
    return at_values(system, {EPS: sp.sympify(str(point))})


def at_values(system: System, values: Mapping[sp.Symbol, Any]) -> System | None:
    """The system with its parameters (SymPy symbols) replaced by exact values (SymPy numbers), or None when
    that is not a system (a COR outside [0, 1] there, say).

    >>> from verify.models.cradle import cradle_system
    >>> system = cradle_system(EPS, 3, backend=SymbolicBackend(Piece.closed(0, 1)))
    >>> [str(e) for e in at_values(system, {EPS: sp.Rational(1, 2)}).restitution]
    ['1/2', '1/2']
    """
    src = system.source
    cors = [sp.sympify(e).subs(values, simultaneous=True) if getattr(e, "free_symbols", None) else e
            for e in src["restitution"]]  # fmt: skip
    try:
        return System(src["mass_matrix"], src["normals"], [str(e) for e in cors], src["time_terms"],
                      names=system.names, coordinates=system.coordinates)  # fmt: skip
    except InvalidInput:
        return None


def point_run(system: System, velocity: Sequence[Any], point: RealAlgebraic, max_impulses: int) -> Any:
    """The run at one value of the parameter as :func:`~verify.laws.rule.solve` makes it on the exact
    numbers of that value (:func:`at_point`, :func:`run_at`): its result when it decides what the parametric
    run left undecided, else None."""
    r = run_at(at_point(system, point), velocity, max_impulses)
    return r if r is not None and r.stop != "max_iterations" else None


def run_at(exact: System | None, velocity: Sequence[Any], max_impulses: int) -> Any:
    """The run on a system of exact numbers (a map's system at one point: :func:`at_point`, :func:`at_values`) as
    :func:`~verify.laws.rule.solve` makes it, with every proof of non-termination it has (repeating directions
    and cones of periods, which a parametric run does not look for), or None (no system, or a run that fails).

    >>> from verify.models.cradle import cradle_system
    >>> system = cradle_system(EPS, 4, backend=SymbolicBackend(Piece.closed(0, 1)))
    >>> r = run_at(at_values(system, {EPS: 0}), ["1", "0", "0", "0"], 8)
    >>> r.stop, r.iterations, r.certificate["kind"]
    ('non_terminating', 3, 'repeating direction')
    """
    if exact is None:
        return None
    try:
        return solve(exact, velocity, max_iterations=max_impulses, trace=False)
    except (InvalidInput, Undecided):
        return None


def without(piece: Piece, inner: Piece) -> list[Piece]:
    """``piece`` less ``inner`` (an interval inside it): what lies below and what lies above."""
    out = []
    if piece.lower.cmp(inner.lower) < 0 or (piece.lower_closed and not inner.lower_closed):
        out.append(Piece(piece.lower, inner.lower, piece.lower_closed, not inner.lower_closed))
    if inner.upper.cmp(piece.upper) < 0 or (piece.upper_closed and not inner.upper_closed):
        out.append(Piece(inner.upper, piece.upper, not inner.upper_closed, piece.upper_closed))
    return out


def short_point(piece: Piece) -> Fraction:
    """The rational of least denominator in the middle third of ``piece`` (an interval): its run has short
    numbers, so its cone is made of them, not of a box around long ones; and the parts left on either side
    are at most two thirds of the piece, so that points tried one after the other close in on a value the
    cones cannot pass from both sides.

    >>> short_point(Piece.closed("0.1604", "0.1730"))
    Fraction(1, 6)
    """
    lo, hi = RealAlgebraic(piece.lower.poly, piece.lower.lo, piece.lower.hi), piece.upper
    hi = RealAlgebraic(hi.poly, hi.lo, hi.hi)
    while not 4 * (lo.hi - lo.lo) < hi.lo - lo.hi or not 4 * (hi.hi - hi.lo) < hi.lo - lo.hi:
        lo.refine()
        hi.refine()
    third = (hi.lo - lo.hi) / 3
    return _simplest(lo.hi + third, hi.lo - third)


def _simplest(a: Fraction, b: Fraction) -> Fraction:
    """The rational of least denominator in the open interval (a, b), a < b (continued fractions)."""
    whole = a.numerator // a.denominator
    if whole + 1 < b:
        return Fraction(whole + 1)
    if a == whole:  # (whole, b): whole + 1/n with the least n such that 1/n < b - whole
        return whole + Fraction(1, (1 / (b - whole)).__floor__() + 1)
    return whole + 1 / _simplest(1 / (b - whole), 1 / (a - whole))


def around_point(
    build: Build, velocity: Sequence[Any], piece: Piece, bound: int, cache: RootCache
) -> tuple[Piece, Any, dict[str, Any]] | None:
    """(the largest part of ``piece`` around its point of least denominator on which a cone of the run at that
    point holds, the parametric run to where the cone begins, its certificate), or None.

    The run at the point must be proved never to exit by a cone of a period (:func:`point_run`). Its cone
    hugs the direction the rates tend to at the point, so cones around that direction of a larger radius
    (:func:`~verify.proofs.cones.period.limit_cone`, from 1/4 of the rates down to what the run found) are tried
    first: a wider cone holds over a wider interval."""
    q = short_point(piece)
    at = RealAlgebraic.rational(q)
    exact = at_point(build(SymbolicBackend(Piece.closed(q, q), cache)), at)
    r = point_run(build(SymbolicBackend(Piece.closed(q, q), cache)), velocity, at, bound)
    cert = r.certificate if r is not None else None
    if exact is None or r is None or r.stop != "non_terminating" or (cert or {}).get("kind") != CONE:
        return None
    k, p = r.iterations, int(r.certificate["impulses"])
    b = exact.rates(r.exit_velocity)
    for bits in RADII:
        found = limit_cone(exact, p, b, bits)
        if found is None:
            continue
        gens, strict = found[0], found[1]
        start = _inside(exact, b, k, p, bound=bound, gens=gens, strict=strict)
        if start is None:
            continue
        shown = [[exact.backend.to_number(x) for x in g] for g, s in zip(gens, strict) if s]
        widest = _widest(build, velocity, piece, at, k=start, p=p, gens=shown, cache=cache)
        if widest is not None:
            return widest
    return None


def _inside(
    exact: System, b: Sequence[Any], k: int, p: int, *, bound: int, gens: Any, strict: Sequence[bool]
) -> int | None:
    """The first number of impulses k + j p (at most ``bound``) after which the rates, from b after k, lie in the
    cone of ``gens`` with weight on a strict generator, or None."""
    x: Any = list(b)
    for start in range(k, bound + 1, p):
        if x is None:
            return None
        d = member(exact.backend, x, gens)
        if d is not None and any(strict[i] for i in d):
            return min(start + p * MARGIN, bound - (bound - start) % p)
        x = rates_after(exact, x, p)
    return None


def _widest(
    build: Build, velocity: Sequence[Any], piece: Piece, at: RealAlgebraic, *, k: int, p: int,
    gens: Sequence[Sequence[Any]], cache: RootCache,
) -> tuple[Piece, Any, dict[str, Any]] | None:  # fmt: skip
    """The part of ``piece`` around ``at`` on which the cone of ``gens`` (constants) and the parametric rates
    after k impulses closes under p impulses: cut at the roots of each condition that changes sign (the run's
    own impact sets among them)."""
    while True:
        try:
            system = build(SymbolicBackend(piece, cache))
            run = solve(system, velocity, max_iterations=k, trace=False, certify=False)
            if run.stop != "max_iterations" or run.iterations != k:
                return None
            found = closed_cone(system, list(system.rates(run.exit_velocity)), p, gens)
        except Split as split:
            cuts = [c for c in piece.cut([x for poly in split.polys for x in cache.roots(poly)]) if c.contains(at)]
            if not cuts or cuts[0].is_point or str(cuts[0]) == str(piece):
                return None
            piece = cuts[0]
            continue
        return (piece, run, found) if found is not None else None


def _outside(x: Any) -> bool:
    """Whether x is a number or expression for a backend to convert (not already one of its elements)."""
    return isinstance(x, (Fraction, int, str, sp.Basic))


def closed_cone(
    system: System, b: Sequence[Any], p: int, gens: Sequence[Sequence[Any]], *, written: bool = True
) -> dict[str, Any] | None:
    """The certificate of the cone of the rates b (elements of the system's backend) and ``gens`` (rationals or
    SymPy numbers and expressions in eps, converted by the backend, or its own elements) when p impulses map it
    into itself on all of the system's piece, else None (a :class:`Split` asks to cut the piece). With
    ``written=False`` the certificate is not written out (a cone only tried): an empty dict says that it closes."""
    K = system.backend
    extra = [
        [K.convert(x if isinstance(x, Fraction) else sp.sympify(x)) if _outside(x) else x for x in g] for g in gens
    ]
    try:
        with pivot_budget(MAX_PIVOTS):
            found = close(system, p, [list(b)], extra, 2)
    except Undecided as exc:
        if hasattr(exc, "polys"):
            raise
        return None
    if found is None:
        return None
    return certificate_of(system, p, found, b) if written else {}
