"""Two parameters over a box: the rule run once for every point of the plane, as exact cells.

The system is built on the plane backend (:mod:`verify.maps.backends.plane`), whose two parameters are
read on one cell of a decomposition of the box (:mod:`verify.maps.cells`). Whenever the rule asks a sign
of a rational function whose factors are not yet known to keep one sign on the cell, the run stops
(:class:`~verify.maps.backends.plane.NewCurves`), that cell alone is cut by the new curves
(:func:`~verify.maps.cells.refine`: a cylindrical decomposition of the cell) and each part runs again,
until no run asks for a new curve. Then on each cell every sign the rule asked is the same at every point,
so the run at its sample point is the run of the whole cell: the same impact sets and stop, and an exit
velocity that is one rational function of the two parameters. Each cell ends

- with an exit after k impulses;
- at the bound on impulses: unexplored, with its reason (the area of such cells is bounded exactly);
- at an irrational x (a vertical segment or a point: measure 0, no rational point): not run, said so.

>>> from verify.models.corner import corner_system
>>> build = lambda K: corner_system("1/2", sp.Symbol("e1"), sp.Symbol("e2"), backend=K)
>>> m = plane_parts(build, ["1", "-1/10", "0"], (Fraction(0), Fraction(1), Fraction(0), Fraction(1)), ("e1", "e2"), 40)
>>> part, v = m.at(Fraction(1, 10), Fraction(1, 2))
>>> part.stop, part.iterations, [str(x) for x in v]
('exit', 1, ['-94/725', '11/1450', '0'])
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.errors import InvalidInput
from verify.laws.rule import solve
from verify.maps.backends.plane import Frac, NewCurves, OutOfTime, PlaneBackend, Polys, polys
from verify.maps.backends.tower import Tower
from verify.maps.cell_cones import CellCones
from verify.maps.cells import Box, Cell, Roots, decompose, meets, refine, set_areas
from verify.maps.watch import Watch
from verify.maps.widen import at_values, run_at
from verify.numbers.format import counted, format_decimal, format_exact
from verify.proofs.termination import cone_halt


@dataclass
class CellPart:
    """One cell and what the rule does on all of it."""

    cell: Cell
    stop: str  # "exit", "non_terminating" (proved), "max_iterations" (unexplored) or "not_run" (irrational x)
    iterations: int
    impact_sets: list[tuple[int, ...]]
    exit_velocity: list[Any]  # SymPy expressions in the two parameters (the last velocity when not "exit")
    reason: str = ""
    velocity: list[Frac] = field(default_factory=list, repr=False)  # the exit velocity as rational functions
    certificate: dict[str, Any] | None = None  # a proof of never-exits, valid on the whole cell


@dataclass
class PlaneMap:
    """The cells of a box of two parameters (``names``) and what the rule does on each."""

    P: Polys
    names: tuple[str, str]
    box: Box
    max_impulses: int
    curves: list[Any]
    parts: list[CellPart]
    seconds: float = 0.0
    stopped: str = ""  #: why the map stopped before it was complete (a budget, Ctrl-C), else ""

    def locate(self, x: Fraction, y: Fraction) -> CellPart:
        """The cell that holds the rational point (x, y) of the box."""
        a, b, c, d = self.box
        if not (a <= x <= b and c <= y <= d):
            raise InvalidInput(f"({format_exact(x)}, {format_exact(y)}) is outside the box of the map")
        cache = Roots()
        for part in self.parts:
            if part.cell.contains(self.P, x, y, self.box, cache):
                return part
        raise AssertionError(f"no cell holds ({x}, {y})")  # pragma: no cover - the cells cover the box

    def at(self, x: Any, y: Any) -> tuple[CellPart, list[Fraction] | None]:
        """The cell of the rational point (x, y) and, when the cell exits, the exact exit velocity there."""
        x, y = Fraction(x), Fraction(y)
        part = self.locate(x, y)
        if part.stop != "exit":
            return part, None
        return part, [f.at(x, y) for f in part.velocity]

    @property
    def box_area(self) -> Fraction:
        a, b, c, d = self.box
        return (b - a) * (d - c)

    def bounds_of(self, parts: Sequence[CellPart]) -> tuple[Fraction, Fraction]:
        """Bounds of the total area of ``parts``: the sums of their cells' bounds, the upper one at most the box's."""
        low = sum((p.cell.area[0] for p in parts), Fraction(0))
        return low, min(sum((p.cell.area[1] for p in parts), Fraction(0)), self.box_area)

    def area(self, stop: str) -> tuple[Fraction, Fraction]:
        """Bounds of the total area of the cells that end with ``stop`` (exact rationals): the sums of their
        cells' bounds, the upper one no more than the box's area less the lower bounds of the other cells."""
        a, b, c, d = self.box
        low = sum((p.cell.area[0] for p in self.parts if p.stop == stop), Fraction(0))
        high = sum((p.cell.area[1] for p in self.parts if p.stop == stop), Fraction(0))
        others = sum((p.cell.area[0] for p in self.parts if p.stop != stop), Fraction(0))
        return low, min(high, (b - a) * (d - c) - others)


#: the cells still to run, each with the curves already known to cut around it
Pending = list[tuple[Cell, frozenset[tuple[Any, ...]]]]


def plane_parts(
    build: Callable[[PlaneBackend], System],
    velocity: Sequence[Any],
    box: Box,
    names: tuple[str, str],
    max_impulses: int,
    *,
    arithmetic: str | None = None,
    watch: Watch | None = None,
    number_field: Any = None,
    velocities: bool = True,
    certify: bool = True,
    cell_cones: bool = False,
) -> PlaneMap:
    """The map of the box: ``build(K)`` is the system on the plane backend ``K`` (its CORs written in the
    two parameters ``names``), ``velocity`` the exact entrance velocity (see the module's example). ``watch``
    (:class:`~verify.maps.line.Watch`) gives a wall-clock and a size budget (cells run) and the progress; when
    the map stops early (a budget, or Ctrl-C with a watch), the cells not run are unexplored, with the reason,
    and ``stopped`` says why. ``number_field`` is the number field of the system's numbers when they are not all
    rational (a :class:`~verify.numbers.backends.field.NumberFieldBackend`). ``velocities=False`` leaves out each cell's
    exit velocity as a SymPy expression (``exit_velocity``; ``velocity`` is kept), for a map read only for its
    impact sets and stops. With ``certify`` (the default) a cell of a system of two constraints still impacting at
    ``max_impulses`` is tried for a proof of never-exits: its rates there in an alternating invariant cone
    (:mod:`verify.proofs.termination`). The cone's conditions are signs on the cell like the rule's, so a cell proved
    never to exit (stop ``non_terminating``) is proved on all of it, and carries the certificate. A cell that is a
    rational point is decided as :func:`~verify.laws.rule.solve` decides it there
    (:func:`~verify.maps.widen.run_at`). ``cell_cones`` (slow: off by default) tries the other cells of three or more
    constraints for a boundary cone of their period (:mod:`verify.maps.cell_cones`), proved on the whole cell too."""
    P = polys(arithmetic)
    tower = Tower.over(P, number_field) if number_field is not None else None
    cache, cones = Roots(), (CellCones(build) if certify and cell_cones else None)
    curves: dict[tuple[Any, ...], Any] = {}
    started = shown = time.monotonic()
    deadline = watch.started + watch.seconds if watch is not None and watch.seconds is not None else None

    def stop() -> None:
        if deadline is not None and time.monotonic() > deadline:
            raise OutOfTime("the map's wall-clock budget ran out while a cell was cut")

    work: Pending = [(c, frozenset()) for c in reversed(decompose(P, [], box, cache))]
    parts: list[CellPart] = []
    try:
        while work and not (watch is not None and watch.check()):
            cell, known = work.pop()
            try:
                part = _run_cell(build, velocity, cell, (P, known, names), max_impulses, deadline=deadline,
                                 tower=tower, velocities=velocities, certify=certify, cones=cones)  # fmt: skip
            except OutOfTime:
                work.append((cell, known))
                watch.check()  # type: ignore[union-attr]
                break
            except NewCurves as found:
                try:
                    new, (children, cutting) = found.polys, _cut(P, cell, found.polys, box, (cache, stop))
                except OutOfTime:  # the cell stays whole and unexplored
                    work.append((cell, known))
                    watch.check()  # type: ignore[union-attr]
                    break
                curves.update(cutting)
                known = known | frozenset(P.key(f) for f in new)
                work += [(child, known) for child in reversed(children)]
                continue
            parts.append(part)
            if watch is not None:
                watch.parts, watch.deepest = watch.parts + 1, max(watch.deepest, part.iterations)
                if watch.progress is not None and time.monotonic() >= shown + 1:
                    shown = time.monotonic()
                    watch.progress(f"map: {len(parts)} cells done, {len(work)} to run, {len(curves)} curves, "
                                   f"deepest impulse {watch.deepest}, {round(shown - started)} s")  # fmt: skip
    except KeyboardInterrupt:
        if watch is None:
            raise
        watch.stopped, watch.interrupted = "interrupted (Ctrl-C)", True
    stopped = watch.stopped if watch is not None else ""
    for cell, _ in work:  # what the map did not reach: unexplored
        parts.append(CellPart(cell, "max_iterations", 0, [], [], reason=f"not explored: {stopped}"))
    set_areas(P, [p.cell for p in parts], box, cache)
    parts.sort(key=lambda p: (p.cell.x_lo, p.cell.x_hi.cmp(p.cell.x_lo) != 0, p.cell.sample is None))
    return PlaneMap(P, names, box, max_impulses, list(curves.values()), parts, seconds=time.monotonic() - started,
                    stopped=stopped)  # fmt: skip


def _cut(
    P: Polys, cell: Cell, new: Sequence[Any], box: Box, using: tuple[Roots, Any]
) -> tuple[list[Cell], dict[Any, Any]]:
    """The cell's parts cut by the curves of ``new`` that meet it, and those curves (by key): a curve that does not
    meet the cell keeps one sign on it, so it is known there and cuts nothing (``using``: the root cache and the
    wall-clock check)."""
    cache, stop = using
    cutting = {P.key(f): f for f in new if meets(P, cell, f, box, cache, stop=stop)}
    return (refine(P, cell, list(cutting.values()), box, cache, stop=stop) if cutting else [cell]), cutting


def _run_cell(
    build: Callable[[PlaneBackend], System],
    velocity: Sequence[Any],
    cell: Cell,
    known: tuple[Polys, frozenset[tuple[Any, ...]], tuple[str, str]],
    max_impulses: int,
    *,
    deadline: float | None = None,
    tower: Tower | None = None,
    velocities: bool = True,
    certify: bool = True,
    cones: CellCones | None = None,
) -> CellPart:
    """The part of one cell (raises :class:`NewCurves` when its run asks a sign the cell does not decide);
    ``known`` is the polynomials' arithmetic, the keys of the curves with one sign on it and the parameters."""
    P, keys, names = known
    if cell.sample is None:
        return CellPart(cell, "not_run", 0, [], [], reason="an irrational abscissa: no rational point, measure 0")
    K = PlaneBackend(P, cell.sample, set(keys), names, point=cell.dim == 0, deadline=deadline, tower=tower)
    system = build(K)
    r = solve(system, velocity, max_iterations=max_impulses, trace=False, certify=False)
    stop, certificate = r.stop, None
    if certify and stop == "max_iterations" and system.r == 2:
        # the rates at the cap in an invariant cone (verify.proofs.termination): its conditions are signs asked on the
        # cell like the rule's, so the proof holds on all of it; at the cap only, since a cone is invariant (rates
        # that enter it earlier are in it at the cap), and each condition asked earlier would be one more curve
        test = cone_halt(system)
        found = test(system, list(r.exit_velocity)) if test is not None else None
        if found is not None:
            stop, certificate = found.stop, found.certificate
    proved = r
    x, y = cell.sample
    if certify and stop == "max_iterations" and cell.dim == 0 and isinstance(y, Fraction):
        values = {sp.Symbol(n): sp.Rational(v.numerator, v.denominator) for n, v in zip(names, (x, y))}
        at = run_at(at_values(system, values), velocity, max_impulses)
        if at is not None and at.stop == "non_terminating":
            stop, certificate, proved = at.stop, at.certificate, at
    if certify and stop == "max_iterations" and system.r > 2 and cones is not None and tower is None:
        near = y if isinstance(y, Fraction) else y.narrowed(Fraction(1, 10**6))[0]
        on_cell = cones.prove(system, velocity, r.impact_sets, r.iterations, (x, near))
        if on_cell is not None:
            stop, certificate = "non_terminating", on_cell[1]
            proved = solve(system, velocity, max_iterations=on_cell[0], trace=False, certify=False)
    v = [proved.backend.to_number(x) for x in proved.exit_velocity] if velocities else []
    reason = {"max_iterations": f"still impacting after {counted(r.iterations, 'impulse')}",
              "non_terminating": f"never exits: {(certificate or {}).get('kind', 'proved')}, on the whole cell, "
                                 f"from impulse {proved.iterations} on"}.get(stop, "")  # fmt: skip
    return CellPart(cell, stop, proved.iterations, list(proved.impact_sets), v, reason, list(r.exit_velocity),
                    certificate)  # fmt: skip


def plane_json(m: PlaneMap) -> dict[str, Any]:
    """A map of cells in its JSON shape (``docs/json-outputs.md``): the curves that cut the box, the area of
    each stop (exact bounds) and every cell with its exact description, sample point, area bounds and run.

    >>> from verify.models.corner import corner_system
    >>> build = lambda K: corner_system("1/2", sp.Symbol("e1"), sp.Symbol("e2"), backend=K)
    >>> box = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
    >>> out = plane_json(plane_parts(build, ["1", "-1/10", "0"], box, ("e1", "e2"), 4))
    >>> out["curves"][:2], out["cells"][0]["x"], out["cells"][0]["y"], out["cells"][0]["stop"]
    (['e1 - 2*e2/5 + 2/13', 'e1 - 10*e2/9 + 5/13'], '0', 'e2 = 0', 'exit')
    """
    stops = sorted({p.stop for p in m.parts})
    return {
        "parameters": list(m.names),
        "curves": [m.P.show(f, m.names) for f in m.curves],
        "area": {stop: [format_exact(v) for v in m.area(stop)] for stop in stops},
        "cells": [
            {
                "dimension": p.cell.dim,
                "x": str(p.cell.x_lo) if p.cell.on_line else f"({p.cell.x_lo}, {p.cell.x_hi})",
                "y": (
                    p.cell.y_lo.describe(m.P, m.names)
                    if p.cell.y_lo == p.cell.y_hi
                    else f"({p.cell.y_lo.value_text(m.P, m.names)}, {p.cell.y_hi.value_text(m.P, m.names)})"
                ),
                "sample": None if p.cell.sample is None else [str(v) for v in p.cell.sample],
                "area": [format_exact(v) for v in p.cell.area],
                "stop": p.stop,
                "iterations": p.iterations,
                "impact_sets": [list(J) for J in p.impact_sets],
                "exit_velocity": [str(sp.factor(v)) for v in p.exit_velocity] if p.stop == "exit" else [],
                "reason": p.reason,
                "certificate": p.certificate,
            }
            for p in m.parts
        ],
    }


def describe_area(bounds: tuple[Fraction, Fraction]) -> str:
    """Area bounds as text."""
    lo, hi = bounds
    if lo == hi:
        return format_exact(lo)
    return f"between {format_decimal(lo, 6, rounding='floor')} and {format_decimal(hi, 6, rounding='ceiling')}"


__all__ = ["CellPart", "PlaneMap", "describe_area", "plane_json", "plane_parts"]
