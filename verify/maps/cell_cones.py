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
would ask signs of the degree of those rates).

>>> from fractions import Fraction
>>> from verify.core.backends.plane import polys
>>> from verify.core.system import System
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

from verify.core.backends.plane import NewCurves, PlaneBackend
from verify.core.backends.ratfunc import as_fraction
from verify.core.rule import solve
from verify.core.system import System
from verify.maps.boundary import (
    LAM,
    SLABS,
    STARTS,
    Frame,
    Pattern,
    boundary_generators,
    factors,
    frame,
    pattern_map,
    pattern_of,
    quadratics,
    sympified,
)
from verify.maps.widen import at_values, closed_cone


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

    def prove(
        self,
        system: System,
        velocity: Sequence[Any],
        impact_sets: Sequence[Sequence[int]],
        bound: int,
        at: tuple[Fraction, Fraction],
    ) -> tuple[int, dict[str, Any]] | None:
        """(the impulses up to the cone, its certificate) when a boundary cone closes on the whole cell of
        ``system`` (on the plane backend; its run from ``velocity`` has ``impact_sets`` up to ``bound``), else
        None; ``at`` is a rational point in or near the cell where the generators' orientation and slab are chosen.
        The starts and slabs are tried on the exact numbers of ``at`` first (no curve asked); the first that closes
        there is run again with every sign read at the cell's sample and recorded: when one of their curves is not
        known to keep one sign on the cell, :class:`~verify.core.backends.plane.NewCurves` cuts the cell by all of
        them at once (as a sign of the rule does); else that run is the check of the whole cell."""
        pattern = pattern_of(impact_sets)
        K = system.backend
        if pattern is None or not isinstance(K, PlaneBackend):
            return None
        values = {sp.Symbol(n): sp.Rational(v.numerator, v.denominator) for n, v in zip(K.names, at)}
        exact = at_values(system, values)
        if exact is None:
            return None
        choices = [(phase, f, start, slab) for phase, q, f, others in self._frames(system, pattern)
                   if _on_top(K, q, others)
                   for start in range(phase.start, min(bound, phase.start + STARTS * len(phase.sets)) + 1,
                                      len(phase.sets))
                   for slab in SLABS]  # fmt: skip
        key = (pattern.start, pattern.sets)
        choices.sort(key=lambda c: c != self.last.get(key))  # the choice that closed on the last cell first
        numeric: dict[int, Frame] = {}  # each frame at the point
        for choice in choices:  # tried on the exact numbers of the point ``at``: no curve asked
            phase, f, start, slab = choice
            if id(f) not in numeric:
                numeric[id(f)] = Frame([w.subs(values) for w in f.W], [u.subs(values) for u in f.U],
                                       f.mid.subs(values), f.inverse.subs(values))  # fmt: skip
            if _cone(exact, velocity, (phase, numeric[id(f)], start, slab), values, written=False) is None:
                continue
            self.last[key] = choice
            asked: dict[Any, None] = {}
            point = self.build(PlaneBackend(K.P, K.sample, set(), K.names, point=True, tower=K.tower, asked=asked))
            found = _cone(point, velocity, choice, values)  # every sign read at the cell's sample, and recorded
            curves = {K.P.key(g): g for h in asked if not K.P.is_zero(h.n) for p in (h.n, h.d) for g in K.factors_of(p)}
            new = [] if K.point else [g for k, g in curves.items() if k not in K.known]
            if new:  # every curve the check asks at once, not one cut per sign
                raise NewCurves(new, f"the boundary cone of {choice[0]} is checked on a cell that {len(new)} "
                                     "of its curves cut")  # fmt: skip
            # every sign the check asked at the sample is of curves with one sign on the cell: the same check, branch
            # for branch, at every point of it, and its certificate (in the parameters) holds on all of it
            return found
        return None


def _on_top(K: Any, q: Any, others: Sequence[Any]) -> bool:
    """Whether, on the cell of the plane backend K, the roots of the quadratic factor q are real and the larger
    r2 is at least the modulus t of every other eigenvalue (the root of a linear factor): where it is not, no
    cone meets its two eigenvalues (the 1-D :func:`~verify.maps.boundary.collisions` asks the same). With a the
    leading coefficient and -b/(2a) the mean of the roots, t <= r2 when a q(t) <= 0 (t between the roots) or t is
    below the mean. Every sign is asked on the cell, so their curves (the discriminant, q(t) = 0: where another
    eigenvalue takes the top) cut it."""
    a, b, c = (sp.cancel(x) for x in sp.Poly(q, LAM).all_coeffs())
    if K.sign(K.convert(sp.cancel(b * b - 4 * a * c))) < 0:
        return False
    for g in others:
        c1, c0 = sp.Poly(g, LAM).all_coeffs()
        root = sp.cancel(-c0 / c1)
        t = root if K.sign(K.convert(root)) >= 0 else -root
        if (
            K.sign(K.convert(sp.cancel(a * sp.Poly(q, LAM).as_expr().subs(LAM, t)))) > 0
            and K.sign(K.convert(sp.cancel(-b / (2 * a) - t))) <= 0
        ):
            return False
    return True


def _cone(
    system: System,
    velocity: Sequence[Any],
    choice: tuple[Pattern, Frame, int, Fraction],
    at: dict[sp.Symbol, Any],
    *,
    written: bool = True,
) -> tuple[int, dict[str, Any]] | None:
    """(start, certificate) of the boundary cone of ``choice`` (the phase, its frame, the impulse the cone starts
    at, the slab) for the run of ``system`` from ``velocity``, or None when it does not close (``written``: see
    :func:`~verify.maps.widen.closed_cone`)."""
    phase, f, start, slab = choice
    run = solve(system, velocity, max_iterations=start, trace=False, certify=False)
    if run.stop != "max_iterations" or run.iterations != start:
        return None
    b = list(system.rates(run.exit_velocity))
    gens = boundary_generators(f, phase.sets[0], [sympified(system.backend, x) for x in b], slab=slab, at=at)
    if gens is not None and not isinstance(system.backend, PlaneBackend):  # the exact numbers of the point ``at``
        values = [[sp.sympify(x).subs(at) for x in g] for g in gens]
        if not all(x.is_Rational for g in values for x in g):  # a generator not defined there
            return None
        gens = [[as_fraction(x) for x in g] for g in values]
    cert = closed_cone(system, b, len(phase.sets), gens, written=written) if gens is not None else None
    return (start, cert) if cert is not None else None
