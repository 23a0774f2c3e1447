"""The text of the maps: the cradle for every eps (``verify cradle-map``) and any system over its CORs
(``verify map``): pieces, boundaries, cells of a plane."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from verify.numbers.format import counted, format_decimal, format_exact

if TYPE_CHECKING:
    from verify.maps.cradle import CradleMap
    from verify.maps.general import EpsMap
    from verify.maps.line import Part
    from verify.maps.plane import PlaneMap


def approach_table(rows: Sequence[tuple[Fraction, int | str]]) -> list[str]:
    """The lines of the table of :func:`approach_counts` (a blank line first; none for no rows).

    A count is shown only for a run that exits; any other row says what happened in words,
    and a ratio is shown only between two consecutive rows that both exit.

    >>> rows = [(Fraction(1, 10), 8), (Fraction(1, 100), 24), (Fraction(1, 1000), "> 30 (budget)")]
    >>> print("\\n".join(approach_table(rows)))
    <BLANKLINE>
    Impulses until exit just above the boundary (certified interval runs):
                         eps  impulses   ratio to the row above
                         0.1         8
                        0.01        24                        3
                       0.001  > 30 (budget)
      (each row is about ten times closer to the boundary; ...)
    """
    if not rows:
        return []
    lines = [
        "",
        "Impulses until exit just above the boundary (certified interval runs):",
        f"  {'eps':>22}  {'impulses':>8}  {'ratio to the row above':>23}",
    ]
    previous = None
    for eps, n in rows:
        if isinstance(n, int):
            ratio = "" if previous is None else format_decimal(Fraction(n, previous), 4)
            lines.append(f"  {format_decimal(eps, 16):>22}  {n:>8}  {ratio:>23}")
            previous = n
        else:  # no count: no ratio from this row, nor to the next one
            lines.append(f"  {format_decimal(eps, 16):>22}  {n}")
            previous = None
    lines.append(
        "  (each row is about ten times closer to the boundary; a ratio near sqrt(10) means a count "
        "growing like (eps - boundary)^(-1/2))"
    )
    return lines


def _stopped_line(stopped: str) -> list[str]:
    """The line that says a map stopped early (none for a complete map)."""
    if not stopped:
        return []
    return [f"Stopped early: {stopped}. Below is what was decided; the rest is unexplored, saying so."]


def cradle_map_text(
    cmap: CradleMap,
    *,
    aeev_rows: list[dict[str, Any]],
    approach: Sequence[tuple[Fraction, int | str]],
    exact_in: str = "map_json(cmap)",
) -> str:
    """The cradle map in words and tables. ``exact_in`` says where every exact endpoint and
    certificate is (the command line passes ``"--json"``)."""
    from verify.maps.cradle import termination_boundaries, threshold_between, undecided_measure
    from verify.models.cradle import cradle_system

    masses = ", ".join(format_exact(m) for m in cmap.masses)
    lines = [
        f"Newton's cradle, {cmap.balls} balls (masses {masses}), left velocity "
        f"({', '.join(format_exact(v) for v in cmap.velocity)}), one COR eps for every contact",
        f"eps in {cmap.domain}; explored up to {counted(cmap.max_impulses, 'impulse')}; exact endpoints, "
        "decimals rounded to 12 digits",
        *_stopped_line(cmap.stopped),
        "",
        *parts_table(cmap.parts, contacts=cradle_system("1", cmap.balls).names),
    ]
    points = [cmap.parts[0].piece.lower] + [p.piece.upper for p in cmap.parts]
    lines += ["", f"Exact endpoints (polynomials of degree 4 or less; all of them, exactly, in {exact_in}):"]
    seen: list[Any] = []
    for x in points:
        if (x.is_rational or x.poly.degree() <= 4) and not any(x is y for y in seen):
            seen.append(x)
            lines.append(f"  {format_decimal(x, 12):>16} = {x.words()}")
    t34 = threshold_between(cmap, 4, 3)
    if t34 is not None:
        lines += ["", f"The threshold between 3 and 4 impulses, derived: eps = {t34} = {format_decimal(t34, 20)}"]
    bounds = termination_boundaries(cmap)
    for part in cmap.non_terminating:
        cert = part.certificate or {}
        if "mu" in cert:
            how = f"invariant cones (mu = {', '.join(cert['mu'])})"
        elif cert.get("kind") == "repeating direction":
            cycle = len(cert.get("cycle", []))
            after = counted(cycle, "impulse")
            how = f"a direction of the rates that repeats after {after} (verify solve's run at that point)"
        elif cert.get("kind") == "dominant growth":
            how = (f"the growth of the rates on the plane of the two eigenvalues of the period {cert['pattern']} that "
                   f"meet at the boundary, against the turning pair beside them (verify.maps.growth), from the rates "
                   f"after {counted(cert['impulses'] or 0, 'impulse')}")  # fmt: skip
        else:
            gens, impulses = len(cert.get("generators", [])), cert.get("impulses")
            how = f"a cone of {gens} generators that {impulses} impulses map into itself"
            if "boundary" in cert:
                how += f" (built from the period of the repeating impacts {cert['boundary']['pattern']})"
        lines += [
            "",
            f"Never exits for eps in {part.piece}: proved by {how};",
            f"  the certificate is in {exact_in}; the test suite checks it without the code that found it.",
        ]
    for bound in bounds:
        lines.append(f"Termination boundary: eps = {bound} = {format_decimal(bound, 20)}")
    lines += boundary_lines(cmap.parts, "eps")
    for part in cmap.unexplored:  # a part proved to exit later is decided: said so, with the proof
        label = f"Exits after more than {part.iterations} impulses" if part.exits_beyond_bound else "Unexplored"
        lines += ["", f"{label} {part.piece.brief()}: {part.reason}"]
    lo, hi = undecided_measure(cmap)
    if hi > 0:
        middle, error = format_decimal((lo + hi) / 2, 12), format_decimal((hi - lo) / 2, 2)
        lines += ["", f"Undecided in all: a set of eps of length {middle} (+- {error})"]
    lines += approach_table(approach)
    if aeev_rows:
        lines += ["", "The paper's AEEV rows (Table 1), read off the map:"]
        for row in aeev_rows:
            lines.append(f"  eps = {row['eps']:<7} printed {row['printed']:<10} -> {row['verdict']}")
            if "limit" in row:
                off = format_decimal(row["printed_off"], 2, rounding="ceiling")
                lines.append(f"    tends to ({', '.join(row['limit'])}) (proved: verify cradle --eps {row['eps']}); "
                             f"the printed velocities are within {off} of it")  # fmt: skip
    return "\n".join(lines) + "\n"


def parts_table(parts: Sequence[Part], name: str = "eps", contacts: Sequence[str] | None = None) -> list[str]:
    """The lines of a map's table: each part's interval of the parameter ``name`` (decimals rounded to 12
    digits), its impulses and what happens; impact sets by index, or by the ``contacts``' names."""
    lines = [f"{name + ' from':>16} {'to':>16}  {'impulses':>8}  what happens"]
    for part in parts:
        a, b = format_decimal(part.piece.lower, 12), format_decimal(part.piece.upper, 12)
        left = "[" if part.piece.lower_closed else "("
        right = "]" if part.piece.upper_closed else ")"
        if part.stop == "exit":
            what = "exit: " + _sequence(part.impact_sets, contacts)
        elif part.stop == "non_terminating" and (part.certificate or {}).get("kind") == "repeating direction":
            what = "never exits (certificate: repeating direction)"
        elif part.stop == "non_terminating" and (part.certificate or {}).get("kind") == "dominant growth":
            what = "never exits (certificate: dominant growth)"
        elif part.stop == "non_terminating":
            what = "never exits (certificate: invariant cones)"
        elif getattr(part, "exits_beyond_bound", False):
            what = f"exits after more than {part.iterations} impulses (proved)"
        else:
            what = "unexplored"
        count = str(part.iterations) if part.stop == "exit" else "-"
        lines.append(f"{left}{a:>15} {b:>16}{right} {count:>8}  {what}")
    return lines


def _sequence(impact_sets: list[tuple[int, ...]], contacts: Sequence[str] | None = None) -> str:
    """``(0)(1)(0)`` with runs folded: ``(0)(1) x 5``; the contacts' names instead of indices when given."""
    words = ["(" + ",".join(contacts[j] if contacts else str(j) for j in J) + ")" for J in impact_sets]
    if len(words) > 8 and len(set(words[0::2])) == 1 and len(set(words[1::2])) == 1:
        return f"{words[0]}{words[1]} alternating, {len(words)} impulses"
    return "".join(words)


def boundary_lines(parts: Sequence[Part], name: str) -> list[str]:
    """A paragraph for each boundary of never-exits that the parts reach with a cone of their repeating impacts
    (:mod:`verify.maps.boundary`): the exact point, what holds up to it and what is known above it."""
    from verify.numbers.algebraic import RealAlgebraic
    from verify.numbers.parse import parse_number

    seen: dict[str, dict[str, Any]] = {}
    highest: dict[str, Any] = {}
    for part in parts:
        b = (part.certificate or {}).get("boundary")
        if b is not None and b["eps"] not in seen:
            seen[b["eps"]] = b
        if b is not None:
            highest[b["eps"]] = part.piece.upper
    out = []
    for star, b in seen.items():
        value = format_decimal(RealAlgebraic.from_number(parse_number(star)), 20)
        if b.get("reached") is False:  # turning cones (verify.maps.turning) stop short of the boundary
            out += [
                "",
                f"Boundary of the repeating impacts {b['pattern']}: {name} = {star} = {value}, where the two largest "
                "eigenvalues of their period meet beside a complex pair of the same modulus (over "
                f"Q({b.get('extension', 'sqrt(d)')})). Cones that the period turns into themselves prove never-exits "
                f"up to {format_decimal(highest[star], 12)}; no polyhedral cone holds at the boundary itself, and the "
                "rest below it stays undecided.",
            ]
            continue
        proof = "the cones above"
        if "extension" in b:  # reached beside a turning pair: by the growth argument (verify.maps.growth)
            proof = (f"the growth of the rates where the two largest eigenvalues of their period meet, against the "
                     f"complex pair of the same modulus beside them, over Q({b['extension']}): "
                     "verify.maps.growth")  # fmt: skip
        out += [
            "",
            f"Boundary of never-exits: {name} = {star} = {value}: up to and at it the impacts {b['pattern']} repeat",
            f"forever ({proof})"
            + (
                "; beyond it the two eigenvalues of their period that meet there are not real and its spectral "
                "radius is not an eigenvalue: no cone is mapped into itself by it."
                if b["no_cone_beyond"]
                else "."
            ),
        ]
    return out


#: the most curves a map of cells lists in its text (all of them are in its JSON)
SHOWN_CURVES = 12


def behaviour_lines(m: PlaneMap, contacts: Sequence[str] | None = None) -> list[str]:
    """The area of each behaviour of a map of cells (:class:`verify.maps.plane.PlaneMap`), exact bounds: one line
    per stop and impact sequence (what :func:`plane_lines` shows before its cells); impact sets by index, or by
    the ``contacts``' names."""
    from verify.maps.plane import describe_area

    out = ["Area of each behaviour (exact bounds):"]
    kinds: dict[tuple[Any, ...], list[Any]] = {}
    for p in m.parts:
        if p.stop == "exit":
            key = (p.stop, p.iterations, tuple(p.impact_sets), "")
        else:
            kind = (p.certificate or {}).get("kind", "") if p.stop == "non_terminating" else p.reason
            key = (p.stop, 0, (), kind)
        kinds.setdefault(key, []).append(p)
    for (stop, n, sets, kind), parts in kinds.items():
        low, high = m.bounds_of(parts)
        what = {"exit": f"{stop} after {counted(n, 'impulse')} {_sequence(list(sets), contacts)}",
                "non_terminating": f"never exits (proved on each cell: {kind})",
                "max_iterations": f"unexplored ({kind})"}.get(stop, f"not run ({kind})")  # fmt: skip
        out.append(f"  {what}: {counted(len(parts), 'cell')}, area {describe_area((low, high))}")
    return out


def plane_lines(m: PlaneMap, contacts: Sequence[str] | None = None) -> list[str]:
    """A map of cells (:class:`verify.maps.plane.PlaneMap`) in words: the curves, the area of each behaviour
    (exact bounds) and one row per cell; impact sets by index, or by the ``contacts``' names.

    >>> import sympy as sp
    >>> from fractions import Fraction
    >>> from verify.maps.plane import plane_parts
    >>> from verify.models.corner import corner_system
    >>> build = lambda K: corner_system("1/2", sp.Symbol("e1"), sp.Symbol("e2"), backend=K)
    >>> box = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
    >>> m = plane_parts(build, ["1", "-1/10", "0"], box, ("e1", "e2"), 4)
    >>> print("\\n".join(plane_lines(m)[:3]))
    <BLANKLINE>
    The box cut into 29 exact cells (6 open regions, 14 arcs, 9 points) by 2 curves:
      e1 - 2*e2/5 + 2/13 = 0; e1 - 10*e2/9 + 5/13 = 0
    """
    dims = Counter(p.cell.dim for p in m.parts)
    curves = (
        "; ".join(f"{m.P.show(f, m.names)} = 0" for f in m.curves)
        if len(m.curves) <= SHOWN_CURVES
        else f"(more than {SHOWN_CURVES}: each in the JSON, --json)"
    )
    counts = f"{dims[2]} open regions, {dims[1]} arcs, {dims[0]} points"
    out = ["", f"The box cut into {len(m.parts)} exact cells ({counts}) by {len(m.curves)} curves:", f"  {curves}", "",
           *behaviour_lines(m, contacts)]  # fmt: skip
    out += [
        "",
        "Cells (x, then y; root k: the k-th real root in y in the box, counted from below; an irrational x "
        "to 12 digits, exact in the JSON):",
    ]
    for p in m.parts:
        shown = _sequence(p.impact_sets, contacts)
        what = {"exit": f"{p.stop} after {p.iterations}: {shown}", "non_terminating": f"{p.reason}: {shown}",
                "max_iterations": f"unexplored: {p.reason}"}.get(p.stop, f"not run: {p.reason}")  # fmt: skip
        out.append(f"  {p.cell.describe(m.P, m.names, digits=12)}: {what}")
    return out


def eps_map_text(m: EpsMap, *, exact_in: str = "eps_map_json(m)") -> str:
    """A map of :func:`verify.maps.general.eps_map` in words and tables, one table per line;
    ``exact_in`` says where the exact endpoints are (the command line passes ``"--json"``).

    >>> from verify.maps.general import eps_map
    >>> from verify.dynamics.system import System
    >>> m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1], names=["spring"]), ["1", "0"], ["e"])
    >>> print(eps_map_text(m))
    A system of 2 coordinates and 1 contacts (spring), velocity (1, 0); CORs spring = e
    e in [0, 1]; explored up to 40 impulses; exact endpoints (in eps_map_json(m)), decimals rounded to 12 digits
    <BLANKLINE>
    e in [0, 1]:
    ...
    """
    from verify.maps.line import undecided_length

    cors = ", ".join(f"{name} = {cor}" for name, cor in zip(m.system.names, m.restitution))
    ranges = ", ".join(f"{n} in [{format_exact(lo)}, {format_exact(hi)}]" for n, (lo, hi) in m.parameters.items())
    lines = [
        f"A system of {m.system.n} coordinates and {m.system.r} contacts ({', '.join(m.system.names)}), velocity "
        f"({', '.join(format_exact(v) for v in m.velocity)}); CORs {cors}",
        f"{ranges}; explored up to {counted(m.max_impulses, 'impulse')}; exact endpoints (in {exact_in}), decimals "
        "rounded to "
        "12 digits",
        *_stopped_line(m.stopped),
    ]
    if m.plane is not None:
        return "\n".join(lines + plane_lines(m.plane, m.system.names)) + "\n"
    if m.layout != "interval":
        grid = "; ".join(f"{n}: {', '.join(format_exact(x) for x in xs)}" for n, xs in m.grid.items())
        lines.append(
            f"Two or more parameters: an exact grid of {len(m.lines)} lines, each parameter running over its "
            f"interval while the others take the grid values ({grid}); points off the lines are not mapped."
        )
    for line in m.lines:
        fixed = ", ".join(f"{n} = {format_exact(v)}" for n, v in line.fixed.items())
        lines += ["", f"{line.free} in {line.domain}" + (f", {fixed}" if fixed else "") + ":"]
        lines += parts_table(line.parts, line.free, m.system.names)
        lines += ["  " + x for x in boundary_lines(line.parts, line.free) if x]
        lo, hi = undecided_length(line.parts)
        if hi > 0:
            middle, error = format_decimal((lo + hi) / 2, 12), format_decimal((hi - lo) / 2, 2)
            lines.append(f"  undecided: a set of {line.free} of length {middle} (+- {error})")
    return "\n".join(lines) + "\n"
