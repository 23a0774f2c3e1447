"""Never-exits on a whole cell of a plane map: the boundary cone of :mod:`verify.maps.boundary` in two parameters.

A cell of a plane map (:mod:`verify.maps.plane`) still impacting at the bound, its impact sets repeating a
pattern of linear impulses (single impacts, or mutually orthogonal ones: :func:`~verify.maps.boundary.pattern_of`),
has a period that is one matrix M over Q(p1, p2), the same on every cell that repeats the pattern. Where a
quadratic factor q of M's characteristic polynomial has real roots (its discriminant is >= 0 on the cell: a sign
asked on the cell like the rule's, so the discriminant's curve cuts the plane), the cone of
:func:`~verify.maps.boundary.boundary_generators` (the rates, their mirror across W = ker q(M), and v_mid +- delta
z_i, each a vector of rational functions of the two parameters) is checked as every cone of a period is
(:func:`~verify.maps.widen.closed_cone`), every sign of the check asked on the cell too. A cell where it closes
never exits, on all of it; the certificate is an ordinary "invariant cone of a period" written in the two
parameters. Only the rates' start is taken from the run: the generators are of low degree, so the curves the
check adds stay few (a cone found at a sample point, of generators built from the rates after many impulses,
would ask signs of the degree of those rates). For the same reason each carried vector's combination of the
generators is found at the cell's rational sample (:meth:`~verify.maps.backends.plane.PlaneBackend.at_sample`), and
only the signs of its coefficients are asked on the cell, not those of every pivot of the search.

>>> from fractions import Fraction
>>> from verify.maps.backends.plane import polys
>>> from verify.dynamics.system import System
>>> masses = [["2", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "2"]]
>>> normals = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]
>>> K = PlaneBackend(polys(), (Fraction(1, 10), Fraction(1, 10)), set(), ("e_out", "e_mid"), point=True)
>>> e_out, e_mid = sp.symbols("e_out e_mid")
>>> build = lambda K: System(masses, normals, [e_out, e_mid, e_out], backend=K)
>>> system = build(K)
>>> run = solve(system, ["1", "0", "0", "0"], max_iterations=12, trace=False, certify=False)
>>> cones = CellCones(build)
>>> start, certificate = cones.prove(system, ["1", "0", "0", "0"], run.impact_sets, 12, (Fraction(1, 10),) * 2)
>>> start, certificate["kind"], certificate["impulses"]
(1, 'invariant cone of a period', 2)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps.backends.plane import NewCurves, PlaneBackend
from verify.maps.boundary import (
    LAM,
    SLABS,
    STARTS,
    Frame,
    Orientation,
    Pattern,
    factors,
    frame,
    generators_of,
    orientation,
    pattern_map,
    pattern_of,
    quadratics,
    sympified,
)
from verify.maps.widen import at_values, closed_cone
from verify.numbers.backends.ratfunc import as_fraction
from verify.numbers.parse import to_sympy


@dataclass
class CellCones:
    """The boundary cones tried on the cells of one plane map of the system ``build(K)`` (K a plane backend): the
    period's matrix and frames of each pattern (and each phase of it) are built once, at the first cell that
    repeats it."""

    build: Callable[[PlaneBackend], System]
    frames: dict[tuple[int, tuple[tuple[int, ...], ...]], list[tuple[Pattern, Any, Frame, list[Any]]]] = field(
        default_factory=dict
    )
    #: for each pattern, the choice (phase, frame, start, slab) that closed last: a neighbouring cell tries it first
    last: dict[tuple[int, tuple[tuple[int, ...], ...]], tuple[Pattern, Frame, int, Fraction]] = field(
        default_factory=dict
    )
    tops: dict[tuple[str, tuple[str, ...]], _Top] = field(default_factory=dict)  #: for each q with its others
    converted: dict[int, Frame] = field(default_factory=dict)  #: each frame, in the plane's arithmetic
    #: each check run on a cell: the functions whose signs it read, with those signs, and what it found. A cell where
    #: every one of them has the same sign needs no new run (cells cut from one another mostly do)
    checked: dict[tuple[Any, ...], tuple[dict[Any, int], tuple[int, dict[str, Any]]]] = field(default_factory=dict)

    def _frames(self, system: System, pattern: Pattern) -> list[tuple[Pattern, Any, Frame, list[Any]]]:
        """(phase, q, frame, the other factors) for each phase of ``pattern`` and each quadratic factor q of its
        period with a frame (the other factors linear)."""
        key = (pattern.start, pattern.sets)
        if key not in self.frames:
            found = []
            p = len(pattern.sets)
            for j in range(p):
                phase = Pattern(pattern.start + j, pattern.sets[j:] + pattern.sets[:j])
                M = pattern_map(system, phase.sets)
                if M is None:
                    break
                for q, others in quadratics(factors(M), 1):
                    f = frame(M, q)
                    if f is not None:
                        found.append((phase, q, f, others))
            self.frames[key] = found
        return self.frames[key]

    def _top(self, K: PlaneBackend, q: Any, others: Sequence[Any]) -> _Top:
        key = (str(q), tuple(str(g) for g in others))
        if key not in self.tops:
            self.tops[key] = _Top.of(K, q, others)
        return self.tops[key]

    def _at(self, K: PlaneBackend, f: Frame, at: tuple[Fraction, Fraction]) -> Frame | None:
        """The frame f at the rational point ``at`` (SymPy rationals), or None where an entry is not defined."""
        g = self._plane(K, f)
        try:
            return _mapped(g, lambda x: to_sympy(x.at(*at)))
        except ZeroDivisionError:
            return None

    def _plane(self, K: PlaneBackend, f: Frame) -> Frame:
        """The frame f with its entries in the plane's arithmetic (converted once)."""
        if id(f) not in self.converted:
            r = len(f.mid)
            flat = Frame(f.W, f.U, f.mid, [f.inverse[i, :] for i in range(r)])
            self.converted[id(f)] = _mapped(flat, K.convert)
        return self.converted[id(f)]

    def prove(
        self,
        system: System,
        velocity: Sequence[Any],
        impact_sets: Sequence[Sequence[int]],
        bound: int,
        at: tuple[Fraction, Fraction],
    ) -> tuple[int, dict[str, Any]] | None:
        """(the impulses up to the cone, its certificate) when a boundary cone closes on the whole cell of
        ``system`` (on the plane backend, over the rationals; its run from ``velocity`` has ``impact_sets`` up to
        ``bound``), else None; ``at`` is a rational point in or near the cell where the generators' orientation and
        slab are chosen.
        The starts and slabs are tried on the exact numbers of ``at`` first (no curve asked); the first that closes
        there is run again with every sign read at the cell's sample and recorded: when one of their curves is not
        known to keep one sign on the cell, :class:`~verify.maps.backends.plane.NewCurves` cuts the cell by all of
        them at once (as a sign of the rule does); else that run is the check of the whole cell. A check run on
        another cell, for the same choice and rates, is the check of this one too where every sign it read is the
        same here: the cells cut from one cell mostly need no new run."""
        pattern = pattern_of(impact_sets)
        K = system.backend
        if pattern is None or not isinstance(K, PlaneBackend) or K.tower is not None:
            return None
        values = {sp.Symbol(n): to_sympy(v) for n, v in zip(K.names, at)}
        exact = at_values(system, values)
        if exact is None:
            return None
        choices = [(phase, f, start, slab) for phase, q, f, others in self._frames(system, pattern)
                   if self._top(K, q, others).on(K)
                   for start in range(phase.start, min(bound, phase.start + STARTS * len(phase.sets)) + 1,
                                      len(phase.sets))
                   for slab in SLABS]  # fmt: skip
        key = (pattern.start, pattern.sets)
        choices.sort(key=lambda c: c != self.last.get(key))  # the choice that closed on the last cell first
        numeric: dict[int, Frame | None] = {}  # each frame at the point
        rates: dict[int, list[Any] | None] = {}  # the cell's rates after each start
        for choice in choices:
            phase, f, start, slab = choice
            if id(f) not in numeric:
                numeric[id(f)] = self._at(K, f, at)
            at_point = numeric[id(f)]
            if at_point is None:
                continue
            chosen = orientation(at_point, phase.sets[0], values)
            if chosen is None:
                continue
            if start not in rates:
                rates[start] = _rates(system, velocity, start)
            b = rates[start]
            if b is None:
                continue
            done = (id(f), phase.start, start, slab, chosen, tuple(K.P.key(p) for x in b for p in (x.n, x.d)))
            if done in self.checked and _holds(K, self.checked[done][0]):
                self.last[key] = choice
                return self.checked[done][1]  # a check made on another cell, every sign of it the same on this one
            if _cone(exact, velocity, (phase, at_point, start, slab), chosen, written=False) is None:
                continue  # tried on the exact numbers of the point ``at``: no curve asked
            self.last[key] = choice
            asked: dict[Any, int] = {}
            point = self.build(PlaneBackend(K.P, K.sample, set(), K.names, point=True, asked=asked))
            # every sign read at the cell's sample, and recorded
            found = _cone(point, velocity, (phase, self._plane(K, f), start, slab), chosen)
            if found is not None:
                self.checked[done] = (asked, found)
            curves = {K.P.key(g): g for h in asked if not K.P.is_zero(h.n) for p in (h.n, h.d) for g in K.factors_of(p)}
            new = [] if K.point else [g for k, g in curves.items() if k not in K.known]
            if new:  # every curve the check asks at once, not one cut per sign
                raise NewCurves(new, f"the boundary cone of {choice[0]} is checked on a cell that {len(new)} "
                                     "of its curves cut")  # fmt: skip
            # every sign the check asked at the sample is of curves with one sign on the cell: the same check, branch
            # for branch, at every point of it, and its certificate (in the parameters) holds on all of it
            return found
        return None


def _mapped(f: Frame, g: Callable[[Any], Any]) -> Frame:
    """The frame with g applied to each entry, as lists (the inverse as a list of rows)."""
    return Frame([[g(x) for x in w] for w in f.W], [[g(x) for x in u] for u in f.U], [g(x) for x in f.mid],
                 [[g(x) for x in row] for row in f.inverse])  # fmt: skip


def _rates(system: System, velocity: Sequence[Any], start: int) -> list[Any] | None:
    """The rates after ``start`` impulses of the run from ``velocity``, or None when it stops before."""
    run = solve(system, velocity, max_iterations=start, trace=False, certify=False)
    return list(system.rates(run.exit_velocity)) if run.stop == "max_iterations" and run.iterations == start else None


def _holds(K: PlaneBackend, asked: dict[Any, int]) -> bool:
    """Whether every function of ``asked`` (with the sign a check read of it on some cell) has that sign on all of
    the cell of K: then that check, branch for branch, holds on this cell too."""
    try:
        return all(K.sign(h) == s for h, s in asked.items())
    except NewCurves:
        return False


@dataclass
class _Top:
    """The functions whose signs say, on a cell, whether the larger root r2 of a quadratic factor q of the period's
    characteristic polynomial is real and at least the modulus t of every other eigenvalue (the root of a linear
    factor): where it is not, no cone meets its two eigenvalues (the 1-D :func:`~verify.maps.boundary.collisions`
    asks the same). With a the leading coefficient and -b/(2a) the mean of the roots, t <= r2 when a q(t) <= 0 (t
    between the roots) or t is below the mean. Each is an element of the map's plane arithmetic, converted once."""

    discriminant: Any
    #: for each other root: the root, then a q(t) and -b/(2a) - t for t = the root and for t = -(the root)
    others: list[tuple[Any, tuple[Any, Any], tuple[Any, Any]]]

    @classmethod
    def of(cls, K: PlaneBackend, q: Any, others: Sequence[Any]) -> _Top:
        a, b, c = (sp.cancel(x) for x in sp.Poly(q, LAM).all_coeffs())
        q_at = sp.Poly(q, LAM).as_expr()
        found = []
        for g in others:
            c1, c0 = sp.Poly(g, LAM).all_coeffs()
            root = sp.cancel(-c0 / c1)
            tests = [
                tuple(K.convert(sp.cancel(x)) for x in (a * q_at.subs(LAM, t), -b / (2 * a) - t)) for t in (root, -root)
            ]
            found.append((K.convert(root), tests[0], tests[1]))
        return cls(K.convert(sp.cancel(b * b - 4 * a * c)), found)

    def on(self, K: PlaneBackend) -> bool:
        """Whether r2 is real and on top on the cell of K. Every sign is asked on the cell, so their curves (the
        discriminant, q(t) = 0: where another eigenvalue takes the top) cut it."""
        if K.sign(self.discriminant) < 0:
            return False
        for root, plus, minus in self.others:
            value, below = plus if K.sign(root) >= 0 else minus
            if K.sign(value) > 0 and K.sign(below) <= 0:
                return False
        return True


def _cone(
    system: System,
    velocity: Sequence[Any],
    choice: tuple[Pattern, Frame, int, Fraction],
    chosen: Orientation,
    *,
    written: bool = True,
) -> tuple[int, dict[str, Any]] | None:
    """(start, certificate) of the boundary cone of ``choice`` (the phase, its frame, the impulse the cone starts
    at, the slab) oriented as ``chosen`` for the run of ``system`` from ``velocity``, or None when it does not close
    (``written``: see :func:`~verify.maps.widen.closed_cone`). On the plane backend the frame's entries are its
    elements; on exact numbers the frame is taken at their point (SymPy rationals)."""
    phase, f, start, slab = choice
    b = _rates(system, velocity, start)
    if b is None:
        return None
    K = system.backend
    if isinstance(K, PlaneBackend):
        gens = generators_of(f, b, K.convert(slab), chosen)
    else:
        at_point = generators_of(f, [sympified(K, x) for x in b], to_sympy(slab), chosen)
        if not all(sp.sympify(x).is_Rational for g in at_point for x in g):  # a generator not defined there
            return None
        gens = [[as_fraction(sp.sympify(x)) for x in g] for g in at_point]
    cert = closed_cone(system, b, len(phase.sets), gens, written=written)
    return (start, cert) if cert is not None else None
