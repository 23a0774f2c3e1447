"""The summary that ``verify all`` prints: what was reproduced, what disagrees with the paper, what was refuted."""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

from verify.numbers.format import counted, format_exact
from verify.paper.table1 import (
    Table1,
)

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.maps.cradle import CradleMap
    from verify.models.corner import CornerRun
    from verify.paper.corner_claims import Claim
    from verify.properties.verdicts import Verdict
    from verify.report.findings import Findings


def all_summary(
    table: Table1,
    cmap: CradleMap,
    example: CornerRun,
    claims: Sequence[Claim],
    *,
    profile: str,
    found: Sequence[Verdict],
    oracle_ok: bool,
) -> tuple[str, bool]:
    """The closing summary of ``verify all`` (Table 1, the cradle map, the corner example and claims,
    the property verdicts of ``profile``, the oracle's self-check), and whether the program
    contradicted itself."""
    from verify.maps.cradle import termination_boundaries

    lines = ["", "Summary", "======="]
    bad = table.disagreeing()
    lines.append(f"Table 1: {counted(len(table.rows), 'row')} recomputed; {counted(len(bad), 'printed entry')} "
                 f"{'disagrees' if len(bad) == 1 else 'disagree'} "
                 f"({', '.join(f'eps {e} {c}' for e, c in bad)}); see reports/table1.md")  # fmt: skip
    bounds = termination_boundaries(cmap)
    three = next((p for p in cmap.parts if p.stop == "exit" and p.iterations == 3), None)
    lines.append(f"Cradle: threshold 3 -> 4 impulses at eps = {three.piece.lower if three else '?'} (derived); "
                 f"never exits for eps <= {bounds[0] if bounds else '?'}; see reports/cradle-map.md")  # fmt: skip
    impulses = counted(example.result.iterations, "impulse")
    lines.append(f"Corner example: {impulses}, stop {example.result.stop}; claims: "
                 + ", ".join(f"{c.verdict}" for c in claims))  # fmt: skip
    refuted = [v for v in found if v.verdict == "refuted"]
    lines.append(f"Properties ({profile}): {sum(v.verdict == 'proved' for v in found)} proved, "
                 f"{sum(v.verdict == 'holds' for v in found)} hold, {len(refuted)} refuted:")  # fmt: skip
    for name in dict.fromkeys(v.property for v in refuted):
        rows = [f"{v.rule}/{v.family}" + ("" if v.law == "rule" else f" ({v.law} law)") for v in refuted
                if v.property == name]  # fmt: skip
        lines.append(f"  - {name}: {', '.join(rows)}")
    contradictions = [v for v in refuted if v.note.startswith("contradicts the proof")]
    lines.append("Oracle self-check: " + ("passed" if oracle_ok else "FAILED"))
    failed = bool(contradictions) or not oracle_ok
    if contradictions:
        wrong = counted(len(contradictions), "row")
        lines.append(f"PROGRAM ERROR: {wrong} {'contradicts' if len(contradictions) == 1 else 'contradict'} a SymPy "
                     "proof (see reports/properties.md)")  # fmt: skip
    return "\n".join(lines) + "\n", failed


def abstract(found: Findings) -> list[str]:
    """The reports' abstract, in the paper's terms: what reproduces, what does not and why, and what goes beyond
    the paper (a few lines of prose, computed from the findings)."""
    from verify.maps.cradle import termination_boundaries, threshold_between

    table = found.table1
    bad = table.disagreeing()
    cmap = found.cradle_map.cmap
    boundary = termination_boundaries(cmap)[0]
    claims = found.corner.claims
    held = sum(c.verdict == "holds" for c in claims)
    found_where = sum(c.verdict == "found" for c in claims)
    from verify.properties.verdicts import verdict_counts  # its strategies need hypothesis: asked for here only

    rule = [v for v in found.verdicts if v.law == "rule"]
    proved, holds, refuted = verdict_counts(rule).values()
    laws = [v for v in found.verdicts if v.law != "rule"]
    failing = "; ".join(dict.fromkeys(v.property for v in rule if v.verdict == "refuted"))
    endless = [row for row in table.rows if row.exact.stop == "non_terminating" and row.exact.limit is not None]
    limit = ""
    if endless:
        first = endless[0].exact.limit
        assert first is not None
        velocity = ", ".join(format_exact(x) for x in first.velocity)
        limit = f" They tend, as proved here, to the common velocity ({velocity}), which the printed values approach."
    text = (
        "The paper's rule (eqs. 4-8) runs here in exact arithmetic. Table 1 is reproduced: every row that exits, "
        f"to every printed digit, and the threshold eps = {threshold_between(cmap, 4, 3)} between 3 and 4 impulses, "
        f"derived. {counted(len(bad), 'printed entry').capitalize()} of Table 1 are no rounding of any state of the "
        f"run. The AEEV rows 0.01 and 0 are runs that never end: every eps in [0, {boundary}] never exits, the "
        "three-ball inelastic collapse (McNamara and Young 1992), so their printed velocities are where the paper's "
        f"stop cut the run.{limit} The corner's example is reproduced; {held} of its {len(claims)} claims hold on "
        f"every exact case sampled, and {found_where} (repeated multiple impacts where the CORs differ) is found where "
        f"the paper says. Of the properties of the paper's rule (profile {found.profile}), {proved} rows are "
        f"proved, {holds} hold and {refuted} are refuted ({failing}: below, and properties.md); of the "
        f"{len(laws)} rows of the two laws engines run, {sum(v.verdict == 'refuted' for v in laws)} are refuted."
    )
    return textwrap.wrap(text, 110, break_long_words=False, break_on_hyphens=False)
