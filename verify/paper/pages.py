"""The report pages of the paper's checks: Table 1, the cradle map, the corner, the three disks (Fig. 1)."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

from verify.laws.outcome import Result
from verify.paper.figures import FigureRuns
from verify.views.pages import block

if TYPE_CHECKING:
    from verify.models.corner import CornerRun
    from verify.paper.corner_claims import CornerFindings
    from verify.paper.corner_map import CornerMaps
    from verify.paper.cradle_map import MapReport
    from verify.paper.table1 import Table1

CORNER_CASES = 2000


#: the paper's corner example (Sect. 4.2), as given to ``verify corner``
CORNER_EXAMPLE: dict[str, Any] = {
    "alpha": "pi/6",
    "slope": None,
    "phi": "pi/12",
    "v0": "100",
    "eps1": "0.999",
    "eps2": "0.001",
}


def corner_example_command() -> str:
    """The command that traces the paper's corner example (:data:`CORNER_EXAMPLE`).

    >>> corner_example_command()
    'verify corner --alpha pi/6 --phi pi/12 --eps1 0.999 --eps2 0.001'
    """
    e = CORNER_EXAMPLE
    return f"verify corner --alpha {e['alpha']} --phi {e['phi']} --eps1 {e['eps1']} --eps2 {e['eps2']}"


def _table1_found(table: Table1) -> list[str]:
    """The opening of Table 1's page: how many entries agree, which do not and by how much, the AEEV stop
    identified, and where the rows that never exit tend."""
    from verify.models.paper import PAPER_SIGMA_STATED
    from verify.numbers.format import format_decimal, format_exact
    from verify.paper.table1 import off_limit
    from verify.views.pages import wrapped

    entries = [(row, c) for row in table.rows for c in row.checks]
    bad = [(row, c) for row, c in entries if not c.explained]
    agree = sum(c.agrees for _, c in entries)
    some = sum(c.agrees and c.only_some for _, c in entries)
    search = table.identification
    good = [w.reading.name for w in search.reproducing]
    endless = [row for row in table.rows if row.exact.stop == "non_terminating"]
    text = [
        f"**What was found.** All {len(table.rows)} rows of Table 1 are recomputed exactly. {agree} of its "
        f"{len(entries)} printed entries agree with the exact run rounded to the printed digits"
        + (
            f" ({some} of them under only some readings of the digits, or only in exact or in the paper's binary "
            "arithmetic: see the appendix)"
            if some
            else ""
        )
        + (f"; {more} more agree under another reading" if (more := len(entries) - agree - len(bad)) else "")
        + f"; {len(bad)} disagree under every reading and arithmetic tried: "
        + ", ".join(f"{c.column} at eps = {row.eps} ({c.reason.split(' (')[0]})" for row, c in bad)
        + ".",
        f'The paper\'s AEEV stop ("almost equal exit velocities": the run stops once the velocities '
        f"differ by less than sigma = c ||v||) is identified: of the {len(search.windows)} readings of that sentence "
        f"tried, the printed c = {format_decimal(PAPER_SIGMA_STATED)} reproduces every printed impulse count under "
        + (" and ".join(good) if good else "none")
        + " (the appendix lists them all).",
    ]
    if endless:
        limits = []
        for row in endless:
            off = off_limit(row.printed[:3], row.exact)
            if off is not None:
                limits.append(f"eps = {row.eps} within {format_decimal(off, 2, rounding='ceiling')}")
        first = endless[0].exact.limit
        velocity = ", ".join(format_exact(x) for x in first.velocity) if first is not None else ""
        text.append(
            f"The rows eps = {', '.join(row.eps for row in endless)} never exit: the exact run applies infinitely many "
            "impulses (proved; the three-particle inelastic collapse, whose boundary the cradle map gives), so the "
            "paper's AEEV stop cut an endless run there"
            + (
                f". Such a run tends to the common velocity ({velocity}) (proved), and the printed velocities are "
                f"close to that limit: {'; '.join(limits)}."
                if limits
                else "."
            )
        )
    return [line for paragraph in text for line in [*wrapped(paragraph), ""]]


def table1_page(table: Table1) -> str:
    """The page of Table 1: what was found, the table against the exact run, and the readings in an appendix."""
    from verify.paper.text import aeev_text, entries_explained_text, table1_differs, table1_lines

    return (
        "# Table 1: Newton's cradle (Sect. 4.1)\n\n"
        + "\n".join(_table1_found(table))
        + "\nThe paper's Table 1 beside the exact results and the paper-mode results (the paper's own termination: a\n"
        "cap of 10^4 impulses and the AEEV stop). Every printed entry is marked as agreeing or not, with the\n"
        "reason. Command: `verify table1` (`--json` for exact values).\n\n"
        + block("\n".join(table1_lines(table) + table1_differs(table)))
        + "\n## Appendix: the readings of the printed digits and of the AEEV stop\n\n"
        + block("\n".join([*entries_explained_text(table), "", *aeev_text(table.identification)]))
    )


def table1_marks(table: Table1) -> list[tuple[Fraction, int]]:
    """Table 1's rows as points (eps, the impulses it prints, AEEV rows included) for the staircase."""
    from verify.numbers.parse import parse_number
    from verify.paper.readings import parse_printed_iterations

    return [(Fraction(parse_number(row.eps)), parse_printed_iterations(row.printed[-1])[1]) for row in table.rows]


def _cradle_map_found(report: MapReport) -> list[str]:
    """The opening of the cradle map's page: the collapse boundary and how it meets the literature, the
    thresholds, how the counts grow near the boundary, and what stays undecided."""
    import sympy as sp

    from verify.maps.cradle import termination_boundaries, threshold_between, undecided_measure
    from verify.numbers.algebraic import RealAlgebraic
    from verify.numbers.format import brief, format_decimal, format_exact
    from verify.views.pages import wrapped

    cmap = report.cmap
    bounds = termination_boundaries(cmap)
    t34 = threshold_between(cmap, 4, 3)
    _, hi = undecided_measure(cmap)
    masses = ", ".join(format_exact(m) for m in cmap.masses)
    text = [f"**What was found.** For {cmap.balls} balls of masses {masses} (one COR eps for every contact, the "
            "first ball entering)"]  # fmt: skip
    if bounds:
        b = bounds[0]
        text[0] += (
            f", every eps in [0, {brief(b)}] never exits: one certificate (invariant cones) proves it for the whole "
            f"interval"
            + (f", and above eps = {brief(b)} = {format_decimal(b, 12)} every run exits" if hi == 0 else "")
            + ". This is the inelastic collapse of the balls"
        )
        known = RealAlgebraic.from_number(7 - 4 * sp.sqrt(3))  # McNamara and Young's threshold for three balls
        if len(cmap.masses) == 3 and len(set(cmap.masses)) == 1 and b.cmp(known) == 0:
            text[0] += (", and its boundary is the known one, 7 - 4*sqrt(3) (McNamara and Young 1992; Zhou and "
                        "Kadanoff 1996): the map meets the literature exactly")  # fmt: skip
        text[0] += ". A run that never exits tends to the common velocity of the balls (proved for Table 1's rows)."
    if t34 is not None:
        text[0] += f" The paper's threshold between 3 and 4 impulses is derived: eps = {brief(t34)}."
    if report.approach:
        eps, count = report.approach[-1]
        text[0] += (f" Just above the boundary the count of impulses grows without bound ({count} at eps = "
                    f"{format_decimal(eps, 8)}; the table below).")  # fmt: skip
    text[0] += (f" What the map leaves undecided is a set of eps of length at most "
                f"{format_decimal(hi, 2, rounding='ceiling')}."
                if hi > 0 else " The map decides every eps in [0, 1].")  # fmt: skip
    return [*wrapped(text[0]), ""]


def cradle_map_page(out: Path, report: MapReport, marks: Sequence[tuple[Fraction, int]] = ()) -> str:
    """The page of the cradle map (a :class:`verify.paper.cradle_map.MapReport`); draws its figure
    into ``out``."""
    from verify.maps.figures import cradle_staircase
    from verify.maps.text import cradle_map_text

    cradle_staircase(report.cmap, out / "cradle-staircase.png", marks)
    return (
        "# The cradle for every eps in [0, 1]\n\n"
        + "\n".join(_cradle_map_found(report))
        + "\neps runs as a symbol; the interval is cut at the exact roots wherever a sign changes. Thresholds are\n"
        "exact algebraic numbers (with decimals); the termination boundary comes with its certificate\n"
        "(`verify cradle-map --json`); the AEEV rows of Table 1 are read off the map. Command: `verify cradle-map`.\n\n"
        + block(cradle_map_text(report.cmap, aeev_rows=report.aeev_rows, approach=report.approach, exact_in="--json"))
        + "\n![Impulse count against eps: the staircase, the termination boundary and Table 1's printed counts (x)]"
        "(cradle-staircase.png)\n"
    )


def _corner_found(example: CornerRun, findings: CornerFindings, maps: CornerMaps | None) -> list[str]:
    """The opening of the corner's page: the paper's example, its claims, the symmetric corner's boundary, the
    CORs where repeated multiple impacts occur, and float against exact."""
    from verify.maps.plane import describe_area
    from verify.numbers.format import format_decimal
    from verify.views.pages import wrapped

    e = CORNER_EXAMPLE
    claims = findings.claims
    verdicts = {v: sum(c.verdict == v for c in claims) for v in dict.fromkeys(c.verdict for c in claims)}
    k_star, _ = findings.boundary
    floats = findings.floats
    text = (
        f"**What was found.** The paper's example (alpha = {e['alpha']}, phi = {e['phi']}, eps1 = {e['eps1']}, "
        f"eps2 = {e['eps2']}) is reproduced exactly: zones {' -> '.join(example.zones)}, after "
        f"{example.result.iterations} impulses. Of the paper's {len(claims)} claims on the corner, checked on "
        f"{CORNER_CASES} exact rational cases each: "
        + ", ".join(f"{n} {'hold' if v == 'holds' and n > 1 else v}" for v, n in verdicts.items())
        + f". In the symmetric corner (one COR eps) invariant cones, which the runs that enter them never leave, "
        f"exist exactly when tan(alpha) <= {k_star} (derived); above it every alternating run is turned out of "
        "the corner."
    )
    if maps is not None and maps.repeated_plane:
        lo = min(p.cell.x_lo for p in maps.repeated_plane)
        text += (f" Over both CORs, the first two impulses are multiple impacts on an area "
                 f"{describe_area(maps.repeated_area())} of the square of CORs, all with eps1 above "
                 f"{format_decimal(lo, 3, rounding='floor')}: the paper's \"very different CORs\" (the figure "
                 "below).")  # fmt: skip
    text += (f" A plain float implementation of eq. (10) takes another branch than the exact one on "
             f"{floats['differing']} of {floats['cases']} random cases.")  # fmt: skip
    return [*wrapped(text), ""]


def corner_page(
    out: Path,
    example: CornerRun,
    findings: CornerFindings,
    figures: Sequence[FigureRuns],
    maps: CornerMaps | None = None,
) -> str:
    """The page of the corner: the paper's example run, the findings of ``verify corner-claims``, the figures'
    runs (:func:`verify.paper.figures.run_corner_figures`), drawn into ``out``, and the paper's corner mapped over
    its CORs (``maps``, :func:`verify.paper.corner_map.corner_maps`)."""
    from verify.paper.text import corner_claims_text, corner_map_text
    from verify.records.text import corner_text

    for f in figures:
        f.figure.draw(f.cases, f.results, out / f.figure.file)
    pictures = "".join(f"\n![{f.figure.caption}]({f.figure.file})\n" for f in figures)
    return (
        "# The disk in a corner (Sect. 4.2)\n\n"
        + "\n".join(_corner_found(example, findings, maps))
        + f"\nThe paper's example traced impulse by impulse (`{corner_example_command()}`):\n\n"
        + block(corner_text(example, **CORNER_EXAMPLE))
        + "\n"
        f"The paper's claims on {CORNER_CASES} exact rational cases, the termination boundary, the rebounds as the\n"
        f"corner narrows, and float against exact (`verify corner-claims --cases {CORNER_CASES}`):\n\n"
        + block(corner_claims_text(findings))
        + pictures
        + ("" if maps is None else _corner_maps_section(out, maps, corner_map_text(maps)))
    )


def _corner_maps_section(out: Path, maps: CornerMaps, text: str) -> str:

    from verify.maps.figures import plane_figure

    n = maps.plane.max_impulses
    plane_figure(maps.plane, out / "corner-cors-plane.png",
                 f"The paper's corner (alpha = {CORNER_EXAMPLE['alpha']}, phi = {CORNER_EXAMPLE['phi']}) over both "
                 "CORs, eps1 of S1 and eps2 of S2: "
                 f"{len(maps.cells.parts)} exact cells, up to {n} impulses")  # fmt: skip
    return (
        "\nThe paper's statement that repeated multiple impacts occur when the CORs are very different (its example:\n"
        "eps1 = 0.999, eps2 = 0.001), mapped exactly over the CORs in the number field of the corner's numbers\n"
        "(the line is `verify map docs/examples/paper-corner-map.json --max-impulses 12`):\n\n"
        + block(text)
        + "\n![the square of both CORs as exact cells, up to three impulses](corner-cors-plane.png)\n"
    )


def fig1_page(out: Path, runs: Sequence[Result]) -> str:
    """The page of the three disks after the impact: draws the runs of
    :func:`verify.paper.figures.cradle_motion_runs` into ``out``."""
    from verify.paper.figures import FIG1_EPS, draw_cradle_motion

    draw_cradle_motion(FIG1_EPS, list(runs), out / "cradle-motion.png")
    return (
        "# The three disks after the impact (like the paper's Fig. 1)\n\n"
        "Disk D1 hits D2 and D3 at rest with v0 = 1; the exact exit velocities of `verify cradle --eps E --v0 1`\n"
        "for eps = 0.9, 0.5, 0.1 move the disks from where they touched (dotted) for four time units (solid).\n\n"
        "![The three disks after the impact for eps = 0.9, 0.5, 0.1](cradle-motion.png)\n"
    )
