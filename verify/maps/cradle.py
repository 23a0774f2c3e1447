"""The exact eps-map of Newton's cradle: every eps in an interval at once.

The cradle is run once on the symbolic backend (:mod:`verify.numbers.backends.symbolic`) with eps a
symbol ranging over [lower, upper] (default [0, 1]); whenever the rule asks a sign that
changes inside the current range, the range is cut at the real roots of that polynomial
(exact algebraic numbers) and each part is run again. Every part ends

- with an exit after k impulses: a *piece*, on which the impact sequence is fixed and the
  exit velocity is a rational function of eps;
- with a proof that the rule never exits (:mod:`verify.proofs.termination`): a *non-terminating*
  interval with its certificate, whose conditions hold for every eps of the interval;
- at the bound on impulses: an *unexplored* interval, with the reason (for two contacts,
  whether every eps there is known to exit after more impulses).

Neighbouring parts that behave the same are merged, so each endpoint belongs to exactly
one part, decided exactly. The union is the whole range.

>>> m = cradle_map(max_impulses=8)
>>> [(str(p.piece), p.iterations) for p in m.pieces][-3:]
[('[CRootOf(x**4 - 8*x**3 - 2*x**2 - 8*x + 1, 0), 3 - 2*sqrt(2))', 4), ('[3 - 2*sqrt(2), 1)', 3), ('{1}', 2)]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput, InvalidSystem
from verify.maps import DEFAULT_WIDEN
from verify.maps.line import Part, line_parts, parts_json, piece_json, undecided_length
from verify.maps.watch import Watch
from verify.models.cradle import cradle_system, cradle_velocity
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.numbers.format import counted, format_exact
from verify.numbers.parse import to_number

DEFAULT_MAX_IMPULSES = 40


@dataclass
class CradleMap:
    """The map: pieces (exits), non-terminating intervals and unexplored intervals."""

    balls: int
    masses: list[Fraction]
    velocity: list[Fraction]
    domain: Piece
    max_impulses: int
    parts: list[Part] = field(default_factory=list)
    stopped: str = ""  #: why the map stopped before it was complete (a budget, Ctrl-C), else ""

    @property
    def pieces(self) -> list[Part]:
        return [p for p in self.parts if p.stop == "exit"]

    @property
    def non_terminating(self) -> list[Part]:
        return [p for p in self.parts if p.stop == "non_terminating"]

    @property
    def unexplored(self) -> list[Part]:
        return [p for p in self.parts if p.stop == "max_iterations"]

    def locate(self, eps: Fraction | RealAlgebraic) -> Part:
        """The part that contains eps (a rational or an exact algebraic number)."""
        x = eps if isinstance(eps, RealAlgebraic) else RealAlgebraic.rational(Fraction(eps))
        for part in self.parts:
            if part.piece.contains(x):
                return part
        raise InvalidInput(f"eps = {x} is outside the map's range {self.domain}")

    def thresholds(self) -> list[tuple[RealAlgebraic, Part, Part]]:
        """The points where the behaviour changes: (point, part below, part above)."""
        return [(b.piece.lower, a, b) for a, b in zip(self.parts, self.parts[1:])]


def _validate(lower: Fraction, upper: Fraction, balls: int, given: tuple[Any, Any] | None = None) -> None:
    if lower > upper:
        shown = given if given is not None else (format_exact(lower), format_exact(upper))
        raise InvalidInput(f"the eps interval is reversed: lower = {shown[0]} > upper = {shown[1]}")
    if not (0 <= lower <= upper <= 1):
        raise InvalidInput(f"the eps interval [{format_exact(lower)}, {format_exact(upper)}] must lie in [0, 1]")
    if not isinstance(balls, int) or balls < 2:
        raise InvalidSystem(f"balls must be an integer >= 2, got {balls!r}")


def cradle_map(
    balls: int | None = None,
    masses: Sequence[Any] | None = None,
    velocity: Sequence[Any] | None = None,
    *,
    v0: Any = "1",
    lower: Any = 0,
    upper: Any = 1,
    max_impulses: int = DEFAULT_MAX_IMPULSES,
    watch: Watch | None = None,
    widen: int = DEFAULT_WIDEN,
    leaving: bool | None = False,
) -> CradleMap:
    """The cradle for every eps in [lower, upper] (one COR for all contacts); ``balls`` by default the
    length of ``masses`` or ``velocity``, else 3.

    ``max_impulses`` bounds the exploration: a part still impacting after that many
    impulses, and not proved never to exit, is reported as unexplored. The interval must
    lie in [0, 1] with ``lower <= upper``; otherwise :class:`~verify.errors.InvalidInput`
    names the values. ``watch`` (:class:`~verify.maps.line.Watch`) gives a wall-clock and a size budget
    and a progress callback; a map stopped by one (or by Ctrl-C) says why in ``stopped``. ``widen``: the points
    of each unexplored interval at which a single run's cone is widened (:func:`~verify.maps.line.widened`).
    ``leaving``: prove, where the runs repeat a period whose eigenvalues all have modulus eps (above a boundary),
    that every eps exits (:mod:`verify.maps.leaving`); None tries it on the parts the map leaves undecided
    without it, and only there (seconds for four balls, nothing for three: ``verify cradle-map``'s default);
    False (the default here) never.

    >>> cradle_map(lower="0.5", upper="0.2")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: the eps interval is reversed: lower = 0.5 > upper = 0.2
    """
    if balls is None:
        balls = len(masses or velocity or [0, 0, 0])
    lo, hi = to_number(lower, where="lower"), to_number(upper, where="upper")
    if not (isinstance(lo, Fraction) and isinstance(hi, Fraction)):
        raise InvalidInput("the ends of the eps interval must be rational")
    _validate(lo, hi, balls, (lower, upper))
    if not isinstance(max_impulses, int) or max_impulses < 0:
        raise InvalidInput(f"max_impulses must be a non-negative integer, got {max_impulses!r}")
    v = cradle_velocity(balls, v0, velocity)
    cache = RootCache()
    domain = Piece.closed(lo, hi)

    def build(K: Any) -> Any:
        return cradle_system(EPS, balls, masses, backend=K)

    def explained(parts: list[Part]) -> list[Part]:
        for part in parts:
            if _undecided(part):
                reason, part.exits_beyond_bound = _unexplored_reason(part, balls, masses, cache)
                part.reason = reason if part.exits_beyond_bound or not part.reason else part.reason
        return parts

    parts = explained(line_parts(build, v, domain, max_impulses, cache, watch=watch, widen=widen,
                                 leaving=bool(leaving)))  # fmt: skip
    if leaving is None:  # the proof of exits above a boundary, where nothing else decided the part
        parts = [q for p in parts for q in (
            explained(line_parts(build, v, p.piece, max_impulses, cache, watch=watch, widen=widen, leaving=True))
            if _undecided(p) and not p.piece.is_point else [p])]  # fmt: skip
    system0 = cradle_system("1", balls, masses)
    return CradleMap(
        balls,
        [system0.source["mass_matrix"][i][i] for i in range(balls)],
        [to_number(x) for x in v],
        domain,
        max_impulses,
        parts,
        watch.stopped if watch is not None else "",
    )


def _undecided(part: Part) -> bool:
    """A part still impacting at the bound that nothing has decided (not stopped by a budget either)."""
    return part.stop == "max_iterations" and not part.stopped_by and not part.exits_beyond_bound


def _unexplored_reason(part: Part, balls: int, masses: Sequence[Any] | None, cache: RootCache) -> tuple[str, bool]:
    """Why a part is unexplored, and whether every eps of it is proved to exit later."""
    bound = part.iterations
    if balls != 3:
        return (
            f"still impacting after {counted(bound, 'impulse')}; no invariant cone found for the whole interval"
        ), False
    K = SymbolicBackend(part.piece, cache)
    system = cradle_system(EPS, 3, masses, backend=K)
    G, e = system.gram, system.restitution
    g = K.zero - G[0][1]
    c0 = (K.one + e[0]) * g / G[0][0]
    c1 = (K.one + e[1]) * g / G[1][1]
    four = K.convert(Fraction(4))
    try:
        rotating = not K.nonnegative(c0 * c1 - four * e[0])
    except Split:
        rotating = False
    if rotating:
        return (
            f"every eps here exits, after more than {counted(bound, 'impulse')}: the impacts alternate, and the "
            "two-step "
            f"map of the rates has non-real eigenvalues (c_0 c_1 < 4 eps, c_k = (1 + eps)|G_01|/G_kk), so it "
            "turns every direction out of the cone where an impact remains"
        ), True
    return f"still impacting after {counted(bound, 'impulse')}; not decided", False


# -- what the map says about given values -------------------------------------------------


def verdict(cmap: CradleMap, eps: Any) -> str:
    """One line: what the rule does at eps, read off the map."""
    part = cmap.locate(RealAlgebraic.from_number(to_number(eps)))
    if part.stop == "exit":
        return f"exits after {counted(part.iterations, 'impulse')}"
    if part.stop == "non_terminating":
        return "never exits (a certificate covers the whole interval)"
    if part.exits_beyond_bound:
        return f"exits after more than {counted(part.iterations, 'impulse')} (proved): {part.reason}"
    return f"unexplored: {part.reason}"


APPROACH_MAX_IMPULSES = 10**6


def approach_counts(
    boundary: RealAlgebraic,
    exponents: Sequence[int] = range(2, 8),
    cmap: CradleMap | None = None,
    *,
    max_impulses: int = APPROACH_MAX_IMPULSES,
) -> list[tuple[Fraction, int | str]]:
    """Runs at eps just above a termination boundary: (eps, impulses until exit).

    The runs are of the cradle of ``cmap`` (its balls, masses and left velocity; without a
    map, three unit balls with ball 1 at v0 = 1), so pass the map the boundary was read off.
    For each k, eps is the rational with k + 4 decimals just above boundary + 10^-k. The
    run is on certified intervals (every branch decided with proof; exact rationals would
    grow too large), and the count grows like a constant times (eps - boundary)^(-1/2).

    A run that does not exit gives, instead of a count, what happened in words: ``"> N
    (budget)"`` after ``max_impulses`` impulses, ``"never exits (proved)"``, or
    ``"undecided at the precision limit"`` when the rates shrink below what the interval
    backend resolves at its largest precision (unit balls: past k = 7, below 10^-3000 of
    the velocities before the exit).

    >>> m = cradle_map(masses=["1", "2", "3"], max_impulses=4)
    >>> approach_counts(termination_boundaries(m)[0], [2, 3], m)
    [(Fraction(65729, 1000000), 8), (Fraction(567281, 10000000), 24)]
    >>> approach_counts(termination_boundaries(m)[0], [3], m, max_impulses=10)
    [(Fraction(567281, 10000000), '> 10 (budget)')]
    """
    from verify.errors import NoConvergence
    from verify.models.cradle import run_cradle
    from verify.numbers.backends import get_backend

    if not isinstance(max_impulses, int) or max_impulses < 0:
        raise InvalidInput(f"max_impulses must be a non-negative integer, got {max_impulses!r}")
    system: dict[str, Any] = {"v0": "1"}
    if cmap is not None:
        system = {"balls": cmap.balls, "masses": cmap.masses, "velocity": cmap.velocity}
    out: list[tuple[Fraction, int | str]] = []
    for k in exponents:
        while boundary.hi - boundary.lo > Fraction(1, 10 ** (k + 6)):
            boundary.refine()
        target = boundary.hi + Fraction(1, 10**k)
        scale = 10 ** (k + 4)
        eps = Fraction(-((-target.numerator * scale) // target.denominator), scale)  # rounded up
        try:
            r = run_cradle(
                eps, **system, trace=False, max_iterations=max_impulses, backend=get_backend("interval", dps=40)
            )
        except NoConvergence:
            out.append((eps, "undecided at the precision limit"))
            continue
        if r.stop == "exit":
            out.append((eps, r.iterations))
        elif r.stop == "non_terminating":
            out.append((eps, "never exits (proved)"))
        else:
            out.append((eps, f"> {r.iterations} (budget)"))
    return out


# -- output -------------------------------------------------------------------------------------


def map_json(cmap: CradleMap) -> dict[str, Any]:
    """The map in the JSON shape of the contracts (exit velocities for the map's v0)."""
    return {
        "balls": cmap.balls,
        "masses": [format_exact(m) for m in cmap.masses],
        "velocity": [format_exact(v) for v in cmap.velocity],
        "max_impulses": cmap.max_impulses,
        "interval": piece_json(cmap.domain),
        **parts_json(cmap.parts),
        **({"stopped": cmap.stopped} if cmap.stopped else {}),
    }


def undecided_measure(cmap: CradleMap, width: Fraction = Fraction(1, 10**15)) -> tuple[Fraction, Fraction]:
    """Bounds (exact rationals, at most ``width`` apart per endpoint) of the total length of the unexplored
    parts whose runs are not proved to exit later: the measure of the eps still undecided.

    >>> undecided_measure(cradle_map(max_impulses=6))
    (Fraction(0, 1), Fraction(0, 1))
    """
    return undecided_length(cmap.parts, width)


def termination_boundaries(cmap: CradleMap) -> list[RealAlgebraic]:
    """Upper ends of non-terminating intervals where terminating eps begin (the exact boundary): followed by
    a piece that exits, or by an unexplored part proved to exit after more impulses."""
    out = []
    for a, b in zip(cmap.parts, cmap.parts[1:]):
        if a.stop == "non_terminating" and (b.stop == "exit" or b.exits_beyond_bound):
            out.append(a.piece.upper)
    return out


def threshold_between(cmap: CradleMap, high: int, low: int) -> RealAlgebraic | None:
    """The point where the iteration count goes from ``high`` (below) to ``low`` (above)."""
    for a, b in zip(cmap.parts, cmap.parts[1:]):
        if a.stop == b.stop == "exit" and a.iterations == high and b.iterations == low:
            return b.piece.lower
    return None
