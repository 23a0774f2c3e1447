"""The paper's side of the cradle map: the AEEV rows of Table 1 read off the exact map, and what the
map's text view shows beside it (:func:`map_report`). The map itself is :mod:`verify.maps.cradle`.

>>> from verify.maps.cradle import cradle_map
>>> [row["stop"] for row in aeev_rows_explained(cradle_map(max_impulses=4))]
['max_iterations', 'non_terminating', 'non_terminating']
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.maps.cradle import CradleMap, approach_counts, termination_boundaries, verdict
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.parse import to_number


def aeev_rows_explained(cmap: CradleMap) -> list[dict[str, Any]]:
    """The paper's AEEV rows of Table 1 read off the map: do they exit by themselves?"""
    from verify.paper.readings import load_table1, parse_printed_iterations

    out = []
    for eps, *velocity, printed in load_table1()["rows"]:
        if parse_printed_iterations(printed)[0] != "aeev":
            continue
        part = cmap.locate(RealAlgebraic.rational(to_number(eps)))
        row = {"eps": eps, "printed": printed, "stop": part.stop, "iterations": part.iterations,
               "verdict": verdict(cmap, eps)}  # fmt: skip
        if part.stop == "non_terminating":
            row.update(limit_against(eps, velocity))
        out.append(row)
    return out


def limit_against(eps: str, printed: list[str]) -> dict[str, Any]:
    """For a row of Table 1 whose run never exits: the velocity the run tends to (proved, exact; three unit
    balls at v0 = 100) and how far the printed velocities are from it (the largest difference), or nothing
    when the limit is not proved.

    >>> limit_against("0", ["33.3333335", "33.3333335", "33.33333330"])["limit"]
    ['100/3', '100/3', '100/3']
    """
    from verify.models.cradle import run_cradle
    from verify.numbers.format import format_exact
    from verify.paper.table1 import off_limit

    run = run_cradle(eps)
    off = off_limit(printed, run)
    if run.limit is None or off is None:
        return {}
    return {"limit": [format_exact(x) for x in run.limit.velocity], "printed_off": off}


@dataclass
class MapReport:
    """A map with what its text view shows beside it (``verify cradle-map``, the report's page)."""

    cmap: CradleMap
    aeev_rows: list[dict[str, Any]] = field(default_factory=list)
    approach: list[tuple[Fraction, int | str]] = field(default_factory=list)


def map_report(cmap: CradleMap, *, approach: int = 0, paper: bool = False) -> MapReport:
    """What the text view shows beside ``cmap``: when ``paper`` (the map of the paper's cradle: three balls,
    masses and velocity not given, eps in [0, 1]) the paper's AEEV rows read off it, and the
    :func:`approach_counts` at eps = boundary + 10^-k for k = 2..``approach`` (none below 2).

    >>> from verify.maps.cradle import cradle_map
    >>> report = map_report(cradle_map(max_impulses=4), approach=2, paper=True)
    >>> [row["eps"] for row in report.aeev_rows], [n for _, n in report.approach]
    (['0.0743', '0.01', '0'], [9])
    """
    bounds = termination_boundaries(cmap)
    counts = approach_counts(bounds[0], range(2, approach + 1), cmap) if bounds and approach >= 2 else []
    return MapReport(cmap, aeev_rows_explained(cmap) if paper else [], counts)
