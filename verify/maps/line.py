"""One parameter over an interval: the rule run once for every value, cut where a sign changes.

The system is built on the symbolic backend (:mod:`verify.numbers.backends.symbolic`), whose
parameter ``eps`` ranges over a :class:`~verify.numbers.backends.symbolic.Piece`. Whenever the rule
asks a sign that changes inside the current piece, the piece is cut at the real roots of that
polynomial (exact algebraic numbers) and each part is run again. Every part ends

- with an exit after k impulses: on it the impact sequence is fixed and the exit velocity is a
  rational function of the parameter;
- with a proof that the rule never exits (:mod:`verify.proofs.termination`), whose certificate
  holds for every value of the part;
- at the bound on impulses: unexplored.

Neighbouring parts that behave the same are merged, so each endpoint belongs to exactly one
part, decided exactly; the union is the whole piece.

>>> from verify.numbers.backends.ratfunc import EPS
>>> from verify.models.corner import corner_system
>>> def corner(K):  # a corner of slope 1/2, eps1 the parameter and eps2 = 1/2
...     return corner_system("1/2", EPS, "1/2", backend=K)
>>> parts = line_parts(corner, ["1", "-1/10", "0"], Piece.closed(0, 1), 40)
>>> [(str(p.piece), p.stop, p.iterations) for p in parts]
[('[0, 3/65)', 'exit', 2), ('[3/65, 20/117]', 'exit', 1), ('(20/117, 1]', 'exit', 2)]
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps import DEFAULT_HALVINGS, DEFAULT_WIDEN
from verify.maps.boundary import Decided, Pattern, closed_below, pattern_of
from verify.maps.growth import grown_below
from verify.maps.leaving import GAP, exits_above
from verify.maps.meanvalue import PRECISION
from verify.maps.torus import GAP as GAP_CELLS
from verify.maps.torus import Cells, exits_on_cells
from verify.maps.turning import closed_below_turning
from verify.maps.watch import Watch
from verify.maps.widen import around_point, point_run, without
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.numbers.format import counted, format_decimal, format_exact
from verify.proofs.termination import MAX_PERIOD


@dataclass
class Part:
    """One part of a map: an interval of the parameter and what the rule does on all of it."""

    piece: Piece
    stop: str  # "exit", "non_terminating" or "max_iterations"
    iterations: int
    impact_sets: list[tuple[int, ...]]
    exit_velocity: list[Any]  # SymPy expressions in `parameter`: the exit velocity, or the last one when not "exit"
    certificate: dict[str, Any] | None = None
    reason: str = ""
    exits_beyond_bound: bool = False  # unexplored, but every value of it is proved to exit
    parameter: str = "eps"  # the name of the parameter that `exit_velocity` is written in
    stopped_by: str = ""  # unexplored because the map stopped early (a budget, Ctrl-C): why, else ""

    def same_behaviour(self, other: Part) -> bool:
        return (
            self.stop == other.stop
            and self.impact_sets == other.impact_sets
            and _cone_of(self.certificate) == _cone_of(other.certificate)
            and self.reason == other.reason
        )


def _cone_of(certificate: dict[str, Any] | None) -> tuple[Any, ...]:
    """What a certificate's cone is made of (two parts with equal cones can be merged)."""
    c = certificate or {}
    cells = c.get("cuts") if c.get("kind") == "exits on cells" else None  # each part keeps its own cells
    return c.get("mu"), c.get("generators"), c.get("images"), c.get("strict"), cells


def line_parts(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    domain: Piece,
    max_impulses: int,
    cache: RootCache | None = None,
    *,
    parameter: str = "eps",
    watch: Watch | None = None,
    widen: int = DEFAULT_WIDEN,
    leaving: bool = False,
) -> list[Part]:
    """The parts of ``domain``, in order: ``build(K)`` is the system on the symbolic backend ``K`` (its
    parameter, :data:`~verify.numbers.backends.symbolic.EPS`, ranging over one piece), ``velocity`` the
    exact entrance velocity. Each part's exit velocity is written in the parameter's own name,
    ``parameter`` (see the module's example). A point part the parametric run leaves at the bound is
    run again as :func:`~verify.laws.rule.solve` runs it at that value (:func:`~verify.maps.widen.point_run`),
    and an interval it leaves there is tried at up to ``widen`` rational points of it, each run's cone widened
    to the largest interval around its point on which it holds (:func:`widened`). With ``leaving``, an interval
    whose runs repeat a period of eigenvalues all of modulus eps is proved to exit there
    (:mod:`verify.maps.leaving`; minutes where it applies).

    >>> from verify.dynamics.system import System
    >>> one = lambda K: System([[1, 0], [0, 1]], [[-1, 1]], [EPS], backend=K)
    >>> [str(x) for x in line_parts(one, ["1", "0"], Piece.closed(0, 1), 5, parameter="e_out")[0].exit_velocity]
    ['1/2 - e_out/2', 'e_out/2 + 1/2']
    """
    cache = cache or RootCache()
    symbol = sp.Symbol(parameter)
    work: list[Piece] = [domain]
    done: list[Part] = []
    try:
        while work and not (watch is not None and watch.check()):
            piece = work.pop()
            try:
                part = _run_piece(build, velocity, piece, max_impulses=max_impulses, cache=cache, symbol=symbol,
                                  parameter=parameter)  # fmt: skip
            except Split as split:
                cuts = piece.cut([root for p in split.polys for root in cache.roots(p)])
                if len(cuts) < 2:
                    raise RuntimeError(f"cutting {piece} made no progress ({split})") from None
                work.extend(cuts)
                continue
            found = bounded(build, velocity, part, cache, watch=watch, leaving=leaving) if _unexplored(part) else [part]
            found = [x for one in found for x in (widened(build, velocity, one, cache, max_points=widen, watch=watch)
                                                   if _unexplored(one) else [one])]  # fmt: skip
            done.extend(found)
            if watch is not None:
                for one in found:
                    watch.done(one)
    except KeyboardInterrupt:
        if watch is None:
            raise
        watch.stopped, watch.interrupted = "interrupted (Ctrl-C)", True
    done.sort(key=lambda p: (p.piece.lower, not p.piece.is_point))
    if watch is not None and watch.stopped:  # what the map did not reach (wherever Ctrl-C fell): unexplored
        for piece in uncovered(domain, [p.piece for p in done]):
            done.append(Part(piece, "max_iterations", 0, [], [], reason=f"not explored: {watch.stopped}",
                             parameter=parameter, stopped_by=watch.stopped))  # fmt: skip
        done.sort(key=lambda p: (p.piece.lower, not p.piece.is_point))
    return merge(done)


def bounded(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    part: Part,
    cache: RootCache,
    *,
    watch: Watch | None = None,
    leaving: bool = False,
) -> list[Part]:
    """The unexplored interval ``part`` with what a cone of its own repeating impacts decides up to the boundary
    where the two largest eigenvalues of their period meet (:mod:`verify.maps.boundary`): the parts proved
    never to exit, and the rest unexplored, its reason naming the boundary.

    >>> from verify.models.cradle import cradle_system
    >>> build = lambda K: cradle_system(EPS, 4, backend=K)
    >>> cache = RootCache()
    >>> part = _run_piece(build, ["1", "0", "0", "0"], Piece.closed("0.16", "0.175"), max_impulses=24, cache=cache,
    ...                   symbol=EPS, parameter="eps")
    >>> part.stop, part.iterations
    ('max_iterations', 24)
    >>> for p in bounded(build, ["1", "0", "0", "0"], part, cache):
    ...     print(p.piece, p.stop)
    [4/25, 3 - 2*sqrt(2)) non_terminating
    {3 - 2*sqrt(2)} non_terminating
    (3 - 2*sqrt(2), 7/40] max_iterations
    """
    pattern = pattern_of(part.impact_sets)
    decided = closed_below(build, velocity, part.piece, pattern, bound=part.iterations, cache=cache) if pattern else []
    if pattern and not decided:  # the period's largest eigenvalues meet over a quadratic field, beside a turning pair
        decided = _below_turning(build, velocity, part, pattern, cache=cache, watch=watch)
    stopped = watch.stopped if watch is not None else ""  # the budget ran out during the search for cones
    if stopped and not decided:
        return [_stopped(part, stopped)]
    if pattern is None:
        return _left_the_period(build, velocity, part, cache, watch=watch) if leaving else [part]
    if not decided and not leaving:
        return [part]
    if not decided:  # no boundary here: it may lie above one, where every eps exits
        undecided = part.reason or f"still impacting after {counted(part.iterations, 'impulse')}"
        later = _exits_later(build, velocity, part, part.piece, pattern=pattern, undecided=undecided, cache=cache,
                             watch=watch)  # fmt: skip
        return later if later is not None else [part]
    symbol = sp.Symbol(part.parameter)
    out = [Part(d.piece, "non_terminating", d.iterations, d.impact_sets, [x.subs(EPS, symbol) for x in d.velocity],
                d.certificate, parameter=part.parameter) for d in decided]  # fmt: skip
    boundary = decided[-1].certificate["boundary"]
    star = decided[-1].short_of  # a boundary the cones stop short of: what lies between is below it
    left = uncovered(part.piece, [d.piece for d in decided])
    if star is not None:
        left = [q for piece in left for q in (piece.cut([star]) if piece.contains(star) else [piece])]
    for piece in left:
        reason = ""
        if star is not None and piece.upper.cmp(star) <= 0 and piece.lower.cmp(decided[-1].piece.upper) >= 0:
            where = "at" if piece.is_point else "below"
            reason = (f"still impacting after {counted(part.iterations, 'impulse')}; {where} the boundary eps = "
                      f"{boundary['eps']} of the repeating impacts {pattern}, where the two largest eigenvalues of "
                      "their period meet beside a complex pair of the same modulus: no polyhedral cone is mapped "
                      "into itself at the boundary, and the turning cones tried do not close this close to it; "
                      "not decided")  # fmt: skip
        elif leaving and star is None and piece.lower.cmp(decided[-1].piece.upper) >= 0 and not piece.is_point:
            undecided = _above_reason(part.iterations, pattern, boundary)
            at = piece.lower.cmp(decided[-1].piece.upper) == 0
            later = _exits_later(build, velocity, part, piece, pattern=pattern, undecided=undecided, cache=cache,
                                 watch=watch, above_boundary=at)  # fmt: skip
            out += later if later is not None else [Part(piece, part.stop, part.iterations, part.impact_sets,
                                                         part.exit_velocity, reason=undecided + "; not decided",
                                                         parameter=part.parameter)]  # fmt: skip
            continue
        elif piece.lower.cmp(decided[-1].piece.upper) >= 0:  # above the boundary
            reason = _above_reason(part.iterations, pattern, boundary) + "; not decided"
        left_part = Part(piece, part.stop, part.iterations, part.impact_sets, part.exit_velocity, reason=reason,
                         parameter=part.parameter)  # fmt: skip
        below_star = star is not None and piece.upper.cmp(star) <= 0 and not piece.is_point  # eps*: no cone at all
        out.append(_stopped(left_part, stopped) if stopped and below_star else left_part)
    out.sort(key=lambda p: (p.piece.lower, not p.piece.is_point))
    return out


def _below_turning(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    part: Part,
    pattern: Pattern,
    *,
    cache: RootCache,
    watch: Watch | None,
) -> list[Decided]:
    """What is proved never to exit below a boundary where the period's largest eigenvalues meet beside a turning
    pair: the top of the part, up to and at the boundary, by the growth of the rates on W
    (:mod:`verify.maps.growth`), and what lies below that by turning cones (:mod:`verify.maps.turning`)."""
    grown = grown_below(build, velocity, part.piece, pattern, bound=part.iterations, cache=cache)
    piece = part.piece
    if grown is not None:
        top = grown.piece
        if top.lower.cmp(piece.lower) == 0 and (top.lower_closed or not piece.lower_closed):
            return [grown]
        piece = Piece(piece.lower, top.lower, piece.lower_closed, not top.lower_closed)
    decided = closed_below_turning(build, list(velocity), piece, pattern, bound=part.iterations, cache=cache,
                                   stop=watch.check if watch is not None else None,
                                   halvings=watch.halvings if watch is not None else DEFAULT_HALVINGS)  # fmt: skip
    return decided + ([grown] if grown is not None else [])


def _exits_later(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    part: Part,
    piece: Piece,
    *,
    pattern: Pattern,
    undecided: str,
    cache: RootCache,
    watch: Watch | None = None,
    above_boundary: bool = False,
) -> list[Part] | None:
    """The unexplored ``piece`` (of ``part``), whose runs repeat ``pattern``, with what
    :func:`~verify.maps.leaving.exits_above` proves there: every eps exits, but in a gap just above a boundary and at
    the irrational eps it lists, which keep ``undecided`` (the reason that says where they lie); None without a
    proof. Where the period is two turning pairs, the certified cells of :mod:`verify.maps.torus` decide instead
    (``above_boundary``: the piece starts at the boundary). When ``watch``'s budget or Ctrl-C stops the proof's
    cells, ``piece`` is unexplored with that reason."""
    found = exits_above(build, velocity, piece, pattern, cache, watch=watch)
    if found is None and not (watch is not None and watch.stopped):
        cells = exits_on_cells(build, velocity, piece, pattern, cache, above_boundary=above_boundary, watch=watch)
        if cells is not None and not (watch is not None and watch.stopped):
            return _cell_parts(part, piece, pattern, cells, undecided)
    if found is None and watch is not None and watch.stopped:
        whole = Part(piece, part.stop, part.iterations, part.impact_sets, part.exit_velocity, parameter=part.parameter)
        return [_stopped(whole, watch.stopped, "the proof that it exits")]
    if found is None:
        return None

    def left(p: Piece, reason: str, certificate: dict[str, Any] | None = None) -> Part:
        return Part(p, part.stop, part.iterations, part.impact_sets, part.exit_velocity, certificate, reason,
                    certificate is not None, parameter=part.parameter)  # fmt: skip

    start = RealAlgebraic.rational(found.lower)
    after = counted(part.iterations, "impulse")
    exits = (f"every eps here exits, after more than {after}: every eigenvalue of the period of "
             f"{pattern} has modulus eps here and none is eps, so the rates leave the pattern, and from every point "
             f"of the two ellipses its periods keep them on, the run exits within one impulse of leaving it (checked "
             f"on {found.certificate['cells']} exact cells of eps and a slope; verify.maps.leaving)")  # fmt: skip
    out = []
    for p in piece.cut([x for x in [start, *found.not_run] if piece.contains(x)]):
        if p.lower.cmp(start) < 0:
            out.append(left(p, undecided + f"; within {format_decimal(GAP, 12)} of it, not decided"))
        elif p.is_point and any(p.lower.cmp(x) == 0 for x in found.not_run):
            out.append(left(p, undecided + "; the exact cells of the proof that every eps here exits are not run at "
                                           "this irrational eps (a line of measure 0); not decided"))  # fmt: skip
        else:
            out.append(left(p, exits, found.certificate))
    return out


def _left_the_period(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    part: Part,
    cache: RootCache,
    *,
    watch: Watch | None = None,
) -> list[Part]:
    """The unexplored ``part`` whose runs do not end on a period at the map's bound, with what the certified cells
    of :mod:`verify.maps.torus` prove there when they repeated a period of two turning pairs before (runs that
    left it and had not exited yet)."""
    sets = [tuple(J) for J in part.impact_sets]
    for start in range(len(sets)):
        for p in range(1, MAX_PERIOD + 1):
            block = sets[start : start + 3 * p]
            if len(block) < 3 * p or block != block[:p] * 3:
                continue
            found = exits_on_cells(build, velocity, part.piece, Pattern(start, tuple(block[:p])), cache, watch=watch)
            if watch is not None and watch.stopped:
                return [_stopped(part, watch.stopped, "the proof that it exits")]
            if found is not None:
                undecided = part.reason or f"still impacting after {counted(part.iterations, 'impulse')}"
                return _cell_parts(part, part.piece, Pattern(start, tuple(block[:p])), found, undecided)
            return [part]
    return [part]


def _cell_parts(part: Part, piece: Piece, pattern: Pattern, cells: Cells, undecided: str) -> list[Part]:
    """``piece`` cut into what the certified cells decide (every eps exits; one part for each run of adjacent
    cells, its certificate listing them) and what they leave: the gap below the first cell, and the cells that
    stayed undecided."""
    after = counted(part.iterations, "impulse")
    exits = (f"every eps here exits, after more than {after}: the rule run from the start on "
             f"certified cells of eps, the period of {pattern} in closed form (its two pairs of eigenvalues turn) "
             f"and every undecided sign followed both ways (verify.maps.torus)")  # fmt: skip
    runs: list[list[tuple[Fraction, Fraction]]] = []
    for a, b in cells.cells:
        if runs and runs[-1][-1][1] == a:
            runs[-1].append((a, b))
        else:
            runs.append([(a, b)])
    spans = [(run[0][0], run[-1][1], run) for run in runs] + [(a, b, None) for a, b in cells.undecided]
    out = []
    for p in piece.cut([RealAlgebraic.rational(x) for a, b, _ in spans for x in (a, b) if piece.contains(
            RealAlgebraic.rational(x))]):  # fmt: skip
        run = next((r for a, b, r in spans if r is not None and p.lower.cmp(RealAlgebraic.rational(a)) >= 0
                    and p.upper.cmp(RealAlgebraic.rational(b)) <= 0), None)  # fmt: skip
        if run is None:
            reason = undecided + (f"; within {format_decimal(GAP_CELLS, 12)} of it, not decided"
                                  if p.upper.cmp(RealAlgebraic.rational(cells.lower)) <= 0 else
                                  "; a cell of eps whose signs the certified runs do not decide")  # fmt: skip
            out.append(Part(p, part.stop, part.iterations, part.impact_sets, part.exit_velocity, reason=reason,
                            parameter=part.parameter))  # fmt: skip
            continue
        certificate = {"kind": "exits on cells", "pattern": str(pattern), "precision": PRECISION,
                       "cuts": [format_exact(run[0][0])] + [format_exact(b) for _, b in run]}  # fmt: skip
        out.append(Part(p, part.stop, part.iterations, part.impact_sets, part.exit_velocity, certificate, exits, True,
                        parameter=part.parameter))  # fmt: skip
    return out


def _above_reason(bound: int, pattern: Pattern, boundary: dict[str, Any]) -> str:
    """Where a part above the boundary of ``pattern`` lies, and what is known there (without the verdict)."""
    reason = (f"still impacting after {counted(bound, 'impulse')}; above the boundary eps = {boundary['eps']} of the "
              "repeating "
              f"impacts {pattern}")  # fmt: skip
    if boundary["no_cone_beyond"]:
        reason += (", where the two eigenvalues of their period that meet there are not real and its spectral "
                   "radius is not an eigenvalue, so no cone is mapped into itself by it")  # fmt: skip
    return reason


def _stopped(part: Part, stopped: str, what: str = "the search for cones") -> Part:
    """``part``, left by a search (``what``) that the map's budget (or Ctrl-C) stopped: its reason says so."""
    reason = f"still impacting after {counted(part.iterations, 'impulse')}; {what} stopped: {stopped}"
    return Part(part.piece, part.stop, part.iterations, part.impact_sets, part.exit_velocity, reason=reason,
                parameter=part.parameter, stopped_by=stopped)  # fmt: skip


def _unexplored(part: Part) -> bool:
    return (
        part.stop == "max_iterations"
        and not part.piece.is_point
        and not part.stopped_by
        and not part.exits_beyond_bound
    )


def widened(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    part: Part,
    cache: RootCache,
    *,
    max_points: int = DEFAULT_WIDEN,
    watch: Watch | None = None,
) -> list[Part]:
    """The parts that replace the unexplored interval ``part``: intervals around rational points of it where
    the cone of the single run at the point holds for the whole interval (non-terminating, with the
    certificate; :func:`~verify.maps.widen.around_point`), and what is left, unexplored as before. At most
    ``max_points`` points are tried (a budget of the map, ``--widen``).

    >>> from verify.models.cradle import cradle_system
    >>> build = lambda K: cradle_system(EPS, 4, backend=K)
    >>> part = line_parts(build, ["1", "0", "0", "0"], Piece.closed("0.161", "0.168"), 16, widen=0)[0]
    >>> part.stop, part.iterations
    ('max_iterations', 16)
    >>> [(p.stop, p.iterations) for p in widened(build, ["1", "0", "0", "0"], part, RootCache(), max_points=1)]
    [('max_iterations', 16), ('non_terminating', 16), ('max_iterations', 16)]
    """
    todo, out, tried = [part.piece], [], 0
    while todo:
        piece = todo.pop()
        if piece.is_point or tried >= max_points or (watch is not None and watch.check()):
            out.append(Part(piece, part.stop, part.iterations, part.impact_sets, part.exit_velocity,
                            reason=part.reason, parameter=part.parameter))  # fmt: skip
            continue
        tried += 1
        found = around_point(build, velocity, piece, part.iterations, cache)
        if found is None:
            out.append(Part(piece, part.stop, part.iterations, part.impact_sets, part.exit_velocity,
                            reason=part.reason, parameter=part.parameter))  # fmt: skip
            continue
        inner, run, certificate = found
        symbol = sp.Symbol(part.parameter)
        exit_velocity = [sp.sympify(run.backend.to_number(x)).subs(EPS, symbol) for x in run.exit_velocity]
        out.append(Part(inner, "non_terminating", run.iterations, list(run.impact_sets), exit_velocity, certificate,
                        parameter=part.parameter))  # fmt: skip
        todo.extend(without(piece, inner))
    out.sort(key=lambda p: (p.piece.lower, not p.piece.is_point))
    return out


def uncovered(domain: Piece, pieces: Sequence[Piece]) -> list[Piece]:
    """The parts of ``domain`` that none of ``pieces`` (disjoint, in order, inside it) holds.

    >>> from verify.numbers.algebraic import RealAlgebraic
    >>> half = Piece(RealAlgebraic.rational(Fraction(0)), RealAlgebraic.rational(Fraction(1, 2)), True, False)
    >>> [str(p) for p in uncovered(Piece.closed(0, 1), [half])]
    ['[1/2, 1]']
    """
    out: list[Piece] = []
    at, closed = domain.lower, domain.lower_closed  # the next value not yet held, and whether it is itself free
    for piece in pieces:
        side = at.cmp(piece.lower)
        if side < 0:
            out.append(Piece(at, piece.lower, closed, not piece.lower_closed))
        elif side == 0 and closed and not piece.lower_closed:  # the one value between two open ends
            out.append(Piece(at, at, True, True))
        at, closed = piece.upper, not piece.upper_closed
    side = at.cmp(domain.upper)
    if side < 0:
        out.append(Piece(at, domain.upper, closed, domain.upper_closed))
    elif side == 0 and closed and domain.upper_closed:
        out.append(Piece(at, at, True, True))
    return out


def _run_piece(
    build: Callable[[SymbolicBackend], System],
    velocity: Sequence[Any],
    piece: Piece,
    *,
    max_impulses: int,
    cache: RootCache,
    symbol: sp.Symbol,
    parameter: str,
) -> Part:
    """The part of one piece (raises :class:`Split` when a sign changes inside it)."""
    K = SymbolicBackend(piece, cache)
    system = build(K)
    r = solve(system, velocity, max_iterations=max_impulses, trace=False)
    if r.stop == "max_iterations" and piece.is_point:
        r = point_run(system, velocity, piece.lower, max_impulses) or r
    velocity_out = [sp.sympify(r.backend.to_number(x)).subs(EPS, symbol) for x in r.exit_velocity]
    return Part(piece, r.stop, r.iterations, list(r.impact_sets), velocity_out, r.certificate, parameter=parameter)


def merge(parts: list[Part]) -> list[Part]:
    """Neighbouring parts (in order) that behave the same, joined into one."""
    out: list[Part] = []
    for part in parts:
        if out and out[-1].same_behaviour(part):
            prev = out[-1]
            prev.piece = Piece(prev.piece.lower, part.piece.upper, prev.piece.lower_closed, part.piece.upper_closed)
        else:
            out.append(part)
    return out


def undecided_length(parts: Sequence[Part], width: Fraction = Fraction(1, 10**15)) -> tuple[Fraction, Fraction]:
    """Bounds (exact rationals, at most ``width`` apart per endpoint) of the total length of the unexplored
    parts not proved to exit later: the measure of the values still undecided.

    >>> undecided_length([Part(Piece.closed(0, "1/4"), "max_iterations", 9, [], [])])
    (Fraction(1, 4), Fraction(1, 4))
    """
    lo = hi = Fraction(0)
    for part in parts:
        if part.stop != "max_iterations" or part.exits_beyond_bound:
            continue
        a, b = part.piece.lower, part.piece.upper
        for x in (a, b):
            while x.hi - x.lo > width:
                x.refine()
        lo, hi = lo + max(Fraction(0), b.lo - a.hi), hi + (b.hi - a.lo)
    return lo, hi


def piece_json(piece: Piece) -> dict[str, Any]:
    """A piece's exact ends (as SymPy prints them), whether each is closed, and 30-digit decimals.

    >>> piece_json(Piece.closed(0, "1/3"))["upper_decimal"]
    '0.333333333333333333333333333333'
    """
    return {
        "lower": str(piece.lower),
        "upper": str(piece.upper),
        "lower_closed": piece.lower_closed,
        "upper_closed": piece.upper_closed,
        "lower_decimal": format_decimal(piece.lower, 30),
        "upper_decimal": format_decimal(piece.upper, 30),
    }


def parts_json(parts: Sequence[Part], *, name: str | None = None) -> dict[str, Any]:
    """The parts in the JSON shape of the maps: exits, non-terminating parts, unexplored parts and the
    measure of the undecided values (exit velocities as SymPy prints them, factored, in each part's own
    parameter, or renamed to ``name`` when given)."""
    return {
        "pieces": [
            {
                **piece_json(p.piece),
                "iterations": p.iterations,
                "impact_sets": [list(J) for J in p.impact_sets],
                "exit_velocity": [str(sp.factor(_renamed(x, p.parameter, name))) for x in p.exit_velocity],
            }
            for p in parts
            if p.stop == "exit"
        ],
        "non_terminating": [
            {**piece_json(p.piece), "impulses_before": p.iterations, "certificate": p.certificate}
            for p in parts
            if p.stop == "non_terminating"
        ],
        "unexplored": [
            {**piece_json(p.piece), "reason": p.reason, **({"certificate": p.certificate} if p.certificate else {})}
            for p in parts
            if p.stop == "max_iterations"
        ],
        "undecided_measure": [str(x) for x in undecided_length(parts)],
    }


def _renamed(x: Any, parameter: str, name: str | None) -> Any:
    """``x``, an expression in ``parameter``, written in ``name`` instead (when given)."""
    x = sp.sympify(x)
    return x if name is None or name == parameter else x.subs(sp.Symbol(parameter), sp.Symbol(name))
