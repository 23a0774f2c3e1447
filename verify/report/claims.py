"""The claims of the paper and the suite's findings beyond it, one row each, for the first screen of the reports.

Each row says where the paper states the claim, its status, one sentence of evidence with its number in bold,
the page with the details and the command that prints that number (``tests/report/test_claims.py`` runs each
command and finds the number in what it prints). The rows are computed from the same findings as the pages
(:class:`verify.report.findings.Findings`): nothing here runs anything.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

from verify.paper.pages import CORNER_CASES

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.paper.table1 import Table1
    from verify.properties.verdicts import Verdict
    from verify.report.findings import Findings

#: a claim's status: as the paper states it; under the one reading of its text that fits; where the computation
#: and the paper part; shown false by a case; proved (a certificate or a SymPy identity); holding on every case drawn;
#: found where the paper says it happens; a finding the paper does not state
ClaimStatus = Literal[
    "reproduced", "reproduced under one reading", "disagrees", "refuted", "proved", "holds", "found", "new"
]

#: where the AEEV rows' findings stand: what the exact rule does where the paper's own stop cut the run
BEYOND_AEEV = "Sect. 4.1, Table 1: beyond its AEEV stop"
#: the command that prints the corner's claims (the corner page quotes its output whole)
CORNER_CLAIMS = f"verify corner-claims --cases {CORNER_CASES}"


@dataclass(frozen=True)
class ClaimRow:
    """One row of the claim table: ``evidence`` holds its number between ``**`` (a closed form also between
    backticks), which ``command`` prints."""

    claim: str
    where: str
    status: ClaimStatus
    evidence: str
    page: str
    command: str


def claim_rows(found: Findings) -> list[ClaimRow]:
    """Every row of the claim table, in the paper's order, then the findings beyond it."""
    return [*_table1_rows(found), *_corner_rows(found), *_property_rows(found)]


def _table1_rows(found: Findings) -> list[ClaimRow]:
    from verify.maps.cradle import termination_boundaries, threshold_between
    from verify.paper.readings import parse_printed_iterations

    table = found.table1
    bad = table.disagreeing()
    exiting = [row for row in table.rows if row.exact.stop == "exit" and all(c.agrees for c in row.checks)]
    last = exiting[-1]
    cmap = found.cradle_map.cmap
    t34 = threshold_between(cmap, 4, 3)
    boundary = termination_boundaries(cmap)[0]
    first = next(row for row in table.rows if row.eps == "0.0743")
    return [
        ClaimRow("Table 1: the exit velocities and iteration counts of the rows that exit", "Sect. 4.1, Table 1",
                 "reproduced", f"every printed entry agrees with the exact run, down to eps = {last.eps} "
                 f"(**{last.exact.iterations}** impulses)", "table1.md", "verify table1"),
        ClaimRow("Table 1: the remaining printed entries", "Sect. 4.1, Table 1", "disagrees",
                 f"{len(bad)} printed entries are no rounding of any state of the run: "
                 + ", ".join(f"**eps = {e}, {c}**" if k == 0 else f"eps = {e}, {c}" for k, (e, c) in enumerate(bad)),
                 "table1.md", "verify table1"),
        ClaimRow("Table 1: the AEEV stop, sigma = 10^-9 ||v0||", "Sect. 4.1", "reproduced under one reading",
                 "one reading reproduces every printed count with **c = 1e-9**: the norm of the pairwise differences "
                 "against c ||v||, before each impulse", "table1.md", "verify table1"),
        ClaimRow("The threshold between 3 and 4 impulses", "Sect. 4.1", "reproduced",
                 f"derived from the exact map, not typed in: **`eps = {t34}`**", "cradle-map.md", "verify cradle-map"),
        ClaimRow("What the exact rule does on the AEEV row eps = 0.0743", BEYOND_AEEV, "new",
                 f"the exact run **exits after {first.exact.iterations} impulses**, where the paper's stop cut it "
                 f"after {parse_printed_iterations(first.printed[-1])[1]}", "cradle-map.md", "verify cradle-map"),
        *_limit_rows(table),
        ClaimRow("Three balls never exit below a boundary (the inelastic collapse)", "beyond the paper", "proved",
                 f"every eps in **`[0, {boundary}]`** never exits, one certificate for the whole interval",
                 "cradle-map.md", "verify cradle-map"),
    ]  # fmt: skip


def _limit_rows(table: Table1) -> list[ClaimRow]:
    """The AEEV rows whose runs never exit (where the paper's stop cut them), and the velocity they are proved to
    tend to (a finding beyond the paper)."""
    from verify.numbers.format import format_exact
    from verify.paper.readings import parse_printed_iterations

    endless = [row for row in table.rows if row.exact.stop == "non_terminating"]
    if not endless:
        return []
    eps = " and ".join(row.eps for row in endless)
    cut = " and ".join(str(parse_printed_iterations(row.printed[-1])[1]) for row in endless)
    command = f"verify cradle --eps {endless[-1].eps}"
    out = [ClaimRow(f"What the exact rule does on the AEEV rows eps = {eps}", BEYOND_AEEV, "new",
                    f"the exact runs never exit (**infinitely many** impulses, proved), where the paper's stop cut "
                    f"them after {cut}", "table1.md", command)]  # fmt: skip
    limits = [(row, row.exact.limit) for row in endless if row.exact.limit is not None]
    if limits:
        velocity = ", ".join(format_exact(x) for x in limits[0][1].velocity)
        out.append(ClaimRow("Where those runs tend", "beyond the paper", "proved",
                            f"to the common velocity **`{velocity}`** (proved: the rates fall geometrically), which "
                            "the printed velocities approach (by how much: table1.md)",
                            "table1.md", command))  # fmt: skip
    return out


def _corner_rows(found: Findings) -> list[ClaimRow]:
    from verify.paper.pages import CORNER_EXAMPLE, corner_example_command

    e, zones = CORNER_EXAMPLE, " -> ".join(found.corner_example.zones)
    rows = [
        ClaimRow("The disk in the corner: repeated multiple impacts for very different CORs", "Sect. 4.2, example",
                 "reproduced", f"alpha = {e['alpha']}, phi = {e['phi']}, eps = {e['eps1']}, {e['eps2']}: zones "
                 f"**{zones}**, exact", "corner.md", corner_example_command()),
    ]  # fmt: skip
    for c in found.corner.claims:
        status: ClaimStatus = "holds" if c.verdict == "holds" else "refuted" if c.verdict == "refuted" else "found"
        rows.append(ClaimRow(c.name, "Sect. 4.2", status, f"{c.verdict} on **{c.cases} cases**", "corner.md",
                             CORNER_CLAIMS))  # fmt: skip
    return rows


#: the properties of Sects. 2-3, as the property suite names them, with the row that shows each and where the paper
#: says it (the energy is stated for one constraint only: Sect. 3.1)
PAPER_PROPERTIES: tuple[tuple[str, str, str, str], ...] = (
    ("beta = 1 for one constraint", "general", "general", "Sect. 3.2, after eq. (5), from Prop. 1"),
    ("the exit velocity is outgoing", "general", "general", "Sects. 3.2-3.5: the iteration ends outgoing"),
    (
        "kinetic energy does not increase",
        "symmetric",
        "cradle",
        "Sect. 3.1, one constraint; here every impulse",
    ),
    (
        "kinetic energy does not increase",
        "asymmetric",
        "cradle",
        "Sect. 3.1, one constraint; here every impulse",
    ),
)


def _property_rows(found: Findings) -> list[ClaimRow]:
    rows = []
    for name, rule, family, where in PAPER_PROPERTIES:
        verdict = next(v for v in _rule_rows(found.verdicts) if (v.property, v.rule, v.family) == (name, rule, family))
        status: ClaimStatus = verdict.verdict
        command = f"verify properties --property '{name.split(' does ')[0]}' --law rule --rule {rule} --family {family}"
        n = verdict.cases
        evidence = {"proved": f"proved (SymPy); the **{n}** cases drawn agree",
                    "holds": f"no counterexample in **{n}** cases",
                    "refuted": f"a counterexample after **{n}** cases"}[verdict.verdict]  # fmt: skip
        rows.append(ClaimRow(f"{name} ({rule} rule, {family})", where, status, evidence,
                             "properties.md", command))  # fmt: skip
    return rows


def _rule_rows(verdicts: Sequence[Verdict]) -> list[Verdict]:
    return [v for v in verdicts if v.law == "rule"]


def claim_table(rows: Sequence[ClaimRow]) -> list[str]:
    """The rows as a markdown table (the claim, where the paper states it, status, evidence, page, command)."""
    lines = ["| # | claim | paper | status | evidence | page | command |", "|---|---|---|---|---|---|---|"]
    for i, r in enumerate(rows, 1):
        claim, evidence = (text.replace("|", "\\|") for text in (r.claim, r.evidence))  # a norm's bars, escaped
        lines.append(f"| {i} | {claim} | {r.where} | {r.status} | {evidence} | [{r.page}]({r.page}) | "
                     f"`{r.command}` |")  # fmt: skip
    return lines
