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


def table1_page(table: Table1) -> str:
    """The page of Table 1."""
    from verify.paper.text import table1_text

    return (
        "# Table 1: Newton's cradle (Sect. 4.1)\n\n"
        "The paper's Table 1 beside the exact results and the paper-mode results (the paper's own termination: a\n"
        "cap of 10^4 impulses and the AEEV stop). Every printed entry is marked as agreeing or not, with the\n"
        "reason. Command: `verify table1` (`--json` for exact values).\n\n" + block(table1_text(table))
    )


def table1_marks(table: Table1) -> list[tuple[Fraction, int]]:
    """Table 1's rows as points (eps, the impulses it prints, AEEV rows included) for the staircase."""
    from verify.numbers.parse import parse_number
    from verify.paper.readings import parse_printed_iterations

    return [(Fraction(parse_number(row.eps)), parse_printed_iterations(row.printed[-1])[1]) for row in table.rows]


def cradle_map_page(out: Path, report: MapReport, marks: Sequence[tuple[Fraction, int]] = ()) -> str:
    """The page of the cradle map (a :class:`verify.paper.cradle_map.MapReport`); draws its figure
    into ``out``."""
    from verify.maps.figures import cradle_staircase
    from verify.maps.text import cradle_map_text

    cradle_staircase(report.cmap, out / "cradle-staircase.png", marks)
    return (
        "# The cradle for every eps in [0, 1]\n\n"
        "eps runs as a symbol; the interval is cut at the exact roots wherever a sign changes. Thresholds are\n"
        "exact algebraic numbers (with decimals); the termination boundary comes with its certificate\n"
        "(`verify cradle-map --json`); the AEEV rows of Table 1 are read off the map. Command: `verify cradle-map`.\n\n"
        + block(cradle_map_text(report.cmap, aeev_rows=report.aeev_rows, approach=report.approach, exact_in="--json"))
        + "\n![Impulse count against eps: the staircase, the termination boundary and Table 1's printed counts (x)]"
        "(cradle-staircase.png)\n"
    )


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
        "The paper's example traced impulse by impulse (`verify corner --alpha pi/6 --phi pi/12 --eps1 0.999 "
        "--eps2 0.001`):\n\n" + block(corner_text(example, **CORNER_EXAMPLE)) + "\n"
        f"The paper's claims on {CORNER_CASES} exact rational cases, the termination boundary, the rebounds as the\n"
        f"corner narrows, and float against exact (`verify corner-claims --cases {CORNER_CASES}`):\n\n"
        + block(corner_claims_text(findings))
        + pictures
        + ("" if maps is None else _corner_maps_section(out, maps, corner_map_text(maps)))
    )


def _corner_maps_section(out: Path, maps: CornerMaps, text: str) -> str:

    from verify.maps.figures import plane_figure

    plane_figure(maps.plane, out / "corner-cors-plane.png")
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
