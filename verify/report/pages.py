"""The reports: ``verify report`` writes ``reports/``, one page per topic, each rendered by its feature from the
:class:`~verify.report.findings.Findings` computed once.

>>> [name for name, _ in PAGES][:2]
['table1.md', 'cradle-map.md']
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from verify.bench.pages import performance_page
from verify.engines.pages import engines_page
from verify.oracle.pages import oracle_page
from verify.paper.pages import corner_page, cradle_map_page, fig1_page, table1_marks, table1_page
from verify.properties.pages import properties_page
from verify.report.findings import Findings
from verify.report.glossary import glossary_page
from verify.report.html import html_report
from verify.views.pages import block, literal_products

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.properties.verdicts import Verdict
    from verify.runner.tasks import TaskRunner


def _corner(out: Path, f: Findings) -> str:
    """The corner's page; its maps (this process) first, then its sweeps (the runner's, maybe behind the
    property rows)."""
    maps = f.corner_maps
    return corner_page(out, f.corner_example, f.corner, f.corner_figures, maps)


#: each page: its file name, and how it is written from the output folder and the findings
PAGES: list[tuple[str, Callable[[Path, Findings], str]]] = [
    ("table1.md", lambda out, f: table1_page(f.table1)),
    ("cradle-map.md", lambda out, f: cradle_map_page(out, f.cradle_map, table1_marks(f.table1))),
    ("corner.md", _corner),
    ("properties.md", lambda out, f: properties_page(f.profile, f.verdicts)),
    ("oracle.md", lambda out, f: oracle_page(f.oracle)),
    ("performance.md", lambda out, f: performance_page(out)),
    ("fig1.md", lambda out, f: fig1_page(out, f.fig1_runs)),
    ("engines.md", lambda out, f: engines_page(out)),
    ("glossary.md", lambda out, f: glossary_page()),
]


TITLES = {
    "table1.md": "Table 1: printed, exact and paper mode, every entry checked",
    "cradle-map.md": "The cradle for every eps: thresholds, termination boundary, staircase, AEEV rows",
    "corner.md": "The disk in a corner: the paper's example, claims, figures, termination, float vs exact",
    "properties.md": "Properties: verdicts and counterexamples",
    "oracle.md": "The reference oracle: golden dataset and how to check an implementation",
    "performance.md": "Performance",
    "fig1.md": "The three disks after the impact (Fig. 1)",
    "engines.md": "Physics engines against the paper's rule and the simultaneous law",
    "glossary.md": "Glossary: the terms the pages use",
}

#: the command that draws each figure of the reports on its own (``verify report`` draws them all)
FIGURE_COMMANDS = {
    "cradle-staircase.png": "verify cradle-map --figure cradle-staircase.png",
    "corner-exit-vs-entrance.png": "verify corner-claims --figures DIR",
    "corner-multiple-impacts.png": "verify corner-claims --figures DIR",
    "wedge-boundary.png": "verify corner-claims --figures DIR",
    "corner-cors-plane.png": "verify report",
    "cradle-motion.png": "verify report",
    "engines-cradle.png": "verify engines --report",
}


def write_reports(out: str | Path = "reports", *, profile: str = "ci", workers: int | None = None,
                  progress: Callable[[str], None] | None = None, verdicts: Sequence[Verdict] | None = None,
                  runner: TaskRunner | None = None) -> Findings:  # fmt: skip
    """Write every page and the index into ``out``; returns the :class:`Findings` shown, which the
    summary of ``verify all`` reads. ``verdicts`` reuses property verdicts already computed for ``profile``.
    The long computations run on ``runner`` (:class:`verify.runner.tasks.TaskRunner`), else on ``workers``
    local processes (None: one per core): the property rows from the start (:meth:`Findings.start_verdicts`),
    while this process computes the pages before theirs (on one pool:
    :meth:`~verify.runner.tasks.TaskRunner.one_pool`)."""
    from verify.errors import require
    from verify.records.files import write_all_atomic

    require("matplotlib", "the reports' figures")  # before anything is computed or written
    require("markdown_it", "the HTML of the reports", "figures")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    from verify.runner.tasks import TaskRunner

    findings = Findings(profile, runner or TaskRunner(workers=workers), verdicts)
    texts: dict[str, str] = {}
    with findings.runner.one_pool():
        findings.start_verdicts()  # on the pool (or a cluster) while this process writes the pages
        for i, (name, page) in enumerate(PAGES, 1):
            if progress:
                progress(f"[report {i}/{len(PAGES)}] {TITLES[name]} ...")
            texts[name] = page(out, findings)
        index = index_page(findings)  # on the same pool: what the pages did not compute, it does
    numbered(texts, [name for name, _ in PAGES])
    texts["README.md"] = index
    for name, text in list(texts.items()):
        texts[name] = literal_products(text) + f"\n---\n\n{provenance()}\n"
    files: dict[str | os.PathLike[str], str | bytes] = {out / name: text for name, text in texts.items()}
    if findings.computed("verdicts"):  # the property page's record, beside it
        files[out / "properties.json"] = properties_record(findings)
    images = {p.name: p.read_bytes() for p in sorted(out.glob("*.png"))}
    files[out / "index.html"] = html_report(texts, ["README.md", *[name for name, _ in PAGES]], images)
    write_all_atomic(files)
    return findings


def properties_record(found: Findings) -> str:
    """``properties.json``: the property page's record (``verify properties --json``), every counterexample in
    it as an exact case file."""
    from verify.properties.verdicts import report
    from verify.records.results import dumps

    return dumps(report(found.profile, list(found.verdicts)))


#: the works the reports cite, with their DOIs
REFERENCES = (
    "S. Pasquero, Symmetric and asymmetric multiple impulsive constraints without friction and their "
    "characterization, J. Nonlinear Sci. 31 (2021), doi:[10.1007/s00332-021-09718-0](https://doi.org/10.1007/s00332-021-09718-0)",
    "S. McNamara and W. R. Young, Inelastic collapse and clumping in a one-dimensional granular medium, "
    "Phys. Fluids A 4 (1992) 496, doi:[10.1063/1.858323](https://doi.org/10.1063/1.858323): the three-particle "
    "inelastic collapse below a COR threshold",
    "Y. Zhou and L. P. Kadanoff, Inelastic collapse of three particles, Phys. Rev. E 54 (1996) 623, "
    "doi:[10.1103/PhysRevE.54.623](https://doi.org/10.1103/PhysRevE.54.623)",
    "C. Fassino and S. Pasquero, An algorithmic approach to the multiple impact of a disk in a corner, "
    "Multidiscip. Model. Mater. Struct. 16 (2019) 476-500: the corner of Sect. 4.2",
)


def index_page(found: Findings) -> str:
    """``reports/README.md``: the abstract, the claim table, the summary of ``verify all``, the pages, the
    references. The first screen (its first 40 lines) holds the abstract and the claim table."""
    from verify.report.claims import claim_rows, claim_table
    from verify.report.summary import abstract, all_summary

    rows = claim_rows(found)
    summary, _ = all_summary(found.table1, found.cradle_map.cmap, found.corner_example, found.corner.claims,
                             profile=found.profile, found=found.verdicts,
                             oracle_ok=found.oracle.self_check.ok)  # fmt: skip
    lines = [
        "# Pasquero (2021), checked exactly",
        "",
        "Generated by `verify report` (also run by `verify all`); do not edit by hand. Every number below is printed",
        "by the command in its row.",
        "",
        *abstract(found),
        "",
        *claim_table(rows),
        "",
        "## The summary of `verify all`",
        "",
        block(summary.strip("\n")).rstrip("\n"),
        "",
        "## The pages",
        "",
        *[f"- [{TITLES[name]}]({name})" for name, _ in PAGES],
        "",
        "## References",
        "",
        *[f"- {ref}" for ref in REFERENCES],
    ]
    return "\n".join(lines) + "\n"


def provenance() -> str:
    """The line at the foot of every page: the version that wrote it and the command (no clock time, so that
    the reports stay the same bytes when written again)."""
    from verify import __version__

    return f"Written by verify {__version__} (`verify report`, also run by `verify all`)."


def numbered(texts: dict[str, str], order: Sequence[str]) -> None:
    """Number every figure of the pages in ``order``, in place: each image gets a caption under it, "Figure N.",
    what it shows and the command that draws it (:data:`FIGURE_COMMANDS`).

    >>> pages = {"a.md": "x\\n![the staircase](cradle-staircase.png)\\n"}
    >>> numbered(pages, ["a.md"]); print(pages["a.md"])
    x
    ![Figure 1: the staircase](cradle-staircase.png)
    <BLANKLINE>
    *Figure 1.* the staircase. Drawn by `verify cradle-map --figure cradle-staircase.png`.
    <BLANKLINE>
    """
    import re

    count = 0

    def caption(match: re.Match[str]) -> str:
        nonlocal count
        count += 1
        what, file = match.group(1), match.group(2)
        command = FIGURE_COMMANDS.get(file, "verify report")
        return f"![Figure {count}: {what}]({file})\n\n*Figure {count}.* {what}. Drawn by `{command}`."

    for name in order:
        if name in texts:
            texts[name] = re.sub(r"^!\[([^\]]*)\]\(([^)]+)\)$", caption, texts[name], flags=re.M)
