"""The reports: ``verify report`` writes ``reports/``, one page per topic, all from the library.

Every number on a page comes from a library call made while writing it; the pages quote the
text views of the commands (:mod:`verify.views.text`) and name the command that prints each
one. Output is deterministic (fixed seeds, derandomised Hypothesis, no timestamps, figure
metadata stripped): writing twice gives the same bytes. Pages are written whole to
temporary names and renamed at the end, so an interrupted run leaves the old reports.

>>> [name for name, _ in PAGES][:2]
['table1.md', 'cradle-map.md']
"""

from __future__ import annotations

import os
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path
from typing import Any

CORNER_CASES = 2000


def _block(text: str) -> str:
    return "```text\n" + text.rstrip("\n") + "\n```\n"


def _page_table1(out: Path, ctx: dict) -> str:
    from verify.checks.paper.table1 import table1
    from verify.views.text import table1_text

    ctx["table1"] = table = table1()
    return (
        "# Table 1: Newton's cradle (Sect. 4.1)\n\n"
        "The paper's Table 1 beside the exact results and the paper-mode results (the paper's own termination: a\n"
        "cap of 10^4 impulses and the AEEV stop). Every printed entry is marked as agreeing or not, with the\n"
        "reason. Command: `verify table1` (`--json` for exact values).\n\n" + _block(table1_text(table))
    )


def _page_cradle_map(out: Path, ctx: dict) -> str:
    from verify.checks.paper.cradle_map import aeev_rows_explained, approach_counts, cradle_map, termination_boundaries
    from verify.views.figures import cradle_staircase
    from verify.views.text import cradle_map_text

    ctx["cradle_map"] = cmap = cradle_map(max_impulses=40)
    bounds = termination_boundaries(cmap)
    approach = approach_counts(bounds[0], range(2, 7)) if bounds else []
    cradle_staircase(cmap, out / "cradle-staircase.png")
    return (
        "# The cradle for every eps in [0, 1]\n\n"
        "eps runs as a symbol; the interval is cut at the exact roots wherever a sign changes. Thresholds are\n"
        "exact algebraic numbers (with decimals); the termination boundary comes with its certificate\n"
        "(`verify cradle-map --json`); the AEEV rows of Table 1 are read off the map. Command: `verify cradle-map`.\n\n"
        + _block(cradle_map_text(cmap, aeev_rows=aeev_rows_explained(cmap), approach=approach))
        + "\n![Impulse count against eps: the staircase and the termination boundary](cradle-staircase.png)\n"
    )


def _page_corner(out: Path, ctx: dict) -> str:
    from types import SimpleNamespace

    from verify.checks.paper.corner_claims import corner_findings
    from verify.models.corner import run_corner
    from verify.views import figures
    from verify.views.text import corner_claims_text, corner_text

    example = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001")
    args = SimpleNamespace(alpha="pi/6", slope=None, phi="pi/12", eps1="0.999", eps2="0.001", v0="100", json=False)
    findings = corner_findings(CORNER_CASES, seed=0, workers=ctx["workers"])
    ctx["corner"] = (example, findings[0])
    names = [
        ("corner-exit-vs-entrance.png", figures.corner_exit_vs_entrance, "exit speed and direction against entrance"),
        ("corner-multiple-impacts.png", figures.corner_multiple_impacts_map, "where repeated multiple impacts occur"),
        ("wedge-boundary.png", figures.wedge_boundary, "the symmetric termination boundary"),
    ]
    for name, draw, _ in names:
        draw(out / name, workers=ctx["workers"])
    pictures = "".join(f"\n![{what}]({name})\n" for name, _, what in names)
    return (
        "# The disk in a corner (Sect. 4.2)\n\n"
        "The paper's example traced impulse by impulse (`verify corner --alpha pi/6 --phi pi/12 --eps1 0.999 "
        "--eps2 0.001`):\n\n" + _block(corner_text(example, args)) + "\n"
        f"The paper's claims on {CORNER_CASES} exact rational cases, the termination boundary, the rebounds as the\n"
        f"corner narrows, and float against exact (`verify corner-claims --cases {CORNER_CASES}`):\n\n"
        + _block(corner_claims_text(*findings))
        + pictures
    )


def _page_properties(out: Path, ctx: dict) -> str:
    from verify.checks.properties.verdicts import verdicts
    from verify.views.text import properties_text

    found = ctx.get("verdicts") or verdicts(ctx["profile"], workers=ctx["workers"])
    ctx["verdicts"] = found
    return (
        "# Properties of the rule\n\n"
        f"Every property x rule x family, profile `{ctx['profile']}` "
        f"(`verify properties --profile {ctx['profile']}`).\n"
        "Each refutation comes with its shrunk exact counterexample; save it as a case file and rerun it\n"
        "with "
        "`verify solve CASE.json --rule RULE` (or let `verify properties --counterexamples DIR` write the files).\n\n"
        + _block(properties_text(ctx["profile"], found))
    )


def _page_oracle(out: Path, ctx: dict) -> str:
    import json
    import sys

    from verify.checks import oracle
    from verify.views.text import oracle_text

    cases, skipped = oracle.golden_dataset()
    results = oracle.golden_results(cases)
    self_check = oracle.compare(cases, results, json.loads(json.dumps(results)), rtol=Fraction(0), atol=Fraction(0))
    candidates = [
        Path.cwd() / "examples" / "float_impl.py",
        Path(__file__).resolve().parent.parent / "examples" / "float_impl.py",
    ]
    example = next((p for p in candidates if p.exists()), candidates[0])
    lines = [
        "# The reference oracle\n",
        "The golden dataset (`golden/`, written by `verify oracle export golden`): what it contains.\n",
        oracle.dataset_description(cases, results, skipped),
        "Self-check: the exact results compared with themselves at zero tolerance "
        "(`verify oracle check golden/cases.json golden/results.json --rtol 0`):\n",
        _block(oracle_text(self_check)),
    ]
    if example.exists():  # a source checkout: the worked example of the README
        text = oracle.run_implementation(f"{sys.executable} {example}", json.dumps({"cases": cases}), 600)
        got = oracle.load_results(text, "examples/float_impl.py")
        lines += [
            "\nAn independent float implementation (`examples/float_impl.py`) checked against it "
            '(`verify oracle check golden/cases.json --impl "python3 examples/float_impl.py"`):\n',
            _block(oracle_text(oracle.compare(cases, results, got, rtol=oracle.DEFAULT_RTOL, atol=Fraction(0)))),
        ]
    else:
        lines.append("\n(The worked example `examples/float_impl.py` is in the source checkout; run from its root.)\n")
    ctx["oracle_ok"] = self_check.ok
    return "\n".join(lines)


def _page_performance(out: Path, ctx: dict) -> str:
    import json

    from verify.checks.bench import bench_text, requirements

    saved = out / "bench.json"
    source = saved if saved.exists() else Path("reports") / "bench.json"
    if not source.exists():
        return (
            "# Performance\n\nNo benchmark record yet: run `verify bench --save reports/bench.json`, then "
            "`verify report`.\n"
        )
    data = source.read_bytes()
    if source != saved:  # keep the record beside the page it feeds
        saved.write_bytes(data)
    record = json.loads(data)
    checks = "\n".join(f"- {line}" for line in requirements(record))
    return (
        "# Performance\n\n"
        "Figures of `verify bench --save reports/bench.json` (the record is `bench.json`, beside this page;\n"
        "`verify report` renders it and never times anything, so the reports stay reproducible). Each ratio is\n"
        "against a baseline timed alternately in the same run, best of 3; see `verify bench --help`.\n\n"
        + _block(bench_text(record))
        + "\nWhat issue 8 asks of these ratios:\n\n"
        + checks
        + "\n\n"
        + PERFORMANCE_NOTES
    )


PERFORMANCE_NOTES = """\
How to read them:

- The exact engine is the general one (a `System` built and validated per case, then `solve` without
  a trace): it runs the first impulses on gmpy2 rationals and a long run over integers with one common
  denominator (`verify/core/engines/integer.py`), where the rationals would pay gcds on every operation.
  `exact_engine_pure_python` is the same engine on `fractions.Fraction`.
- The float path (`verify/core/engines/floats.py`) certifies every branch with a rigorous error radius and
  redoes exactly each case it cannot certify. Its slowness has two causes: NumPy calls on the few
  hundred cases still running after the first impulses (the run lasts up to 100 impulses) cost more
  than the plain loop's scalar operations, and the cases redone exactly (`float_path_exact_fallbacks`)
  are the long runs sliding into the corner. There each impulse cancels part of the rate, so the
  certified radius grows relative to the rate until a sign can no longer be certified; the exact redo
  of those runs is most of the time. The plain float loop is fast and takes a wrong branch sequence
  on `float_loop_wrong_branches` cases; the float path takes none.
- On the interval backend each impulse loses about half a digit: `y + (-2 y)` is enclosed as if the
  two `y` were independent (the dependency problem of interval arithmetic), so the run is repeated at
  doubled precision (`interval_digits`) and the cost per impulse grows with the run, like the exact
  numbers' size (`exact_bits`) does for the exact backend.
"""


def _page_fig1(out: Path, ctx: dict) -> str:
    from verify.views.figures import cradle_motion

    cradle_motion(out / "cradle-motion.png")
    return (
        "# The three disks after the impact (like the paper's Fig. 1)\n\n"
        "Disk D1 hits D2 and D3 at rest with v0 = 1; the exact exit velocities of `verify cradle --eps E --v0 1`\n"
        "for eps = 0.9, 0.5, 0.1 move the disks from where they touched (dotted) for four time units (solid).\n\n"
        "![The three disks after the impact for eps = 0.9, 0.5, 0.1](cradle-motion.png)\n"
    )


PAGES: list[tuple[str, Callable[[Path, dict], str]]] = [
    ("table1.md", _page_table1),
    ("cradle-map.md", _page_cradle_map),
    ("corner.md", _page_corner),
    ("properties.md", _page_properties),
    ("oracle.md", _page_oracle),
    ("performance.md", _page_performance),
    ("fig1.md", _page_fig1),
]

TITLES = {
    "table1.md": "Table 1: printed, exact and paper mode, every entry checked",
    "cradle-map.md": "The cradle for every eps: thresholds, termination boundary, staircase, AEEV rows",
    "corner.md": "The disk in a corner: the paper's example, claims, figures, termination, float vs exact",
    "properties.md": "Properties: verdicts and counterexamples",
    "oracle.md": "The reference oracle: golden dataset and how to check an implementation",
    "performance.md": "Performance",
    "fig1.md": "The three disks after the impact (Fig. 1)",
}


def write_reports(out: str | Path = "reports", *, profile: str = "ci", workers: int | None = None,
                  progress: Callable[[str], None] | None = None, verdicts: Any = None) -> dict[str, Any]:  # fmt: skip
    """Write every page and the index into ``out``; returns what the summary of
    ``verify all`` needs (the results of each topic, whether the oracle self-check passed).
    ``verdicts`` reuses property verdicts already computed for ``profile``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    ctx: dict[str, Any] = {"profile": profile, "workers": workers, "verdicts": verdicts}
    texts: dict[str, str] = {}
    for i, (name, page) in enumerate(PAGES, 1):
        if progress:
            progress(f"[report {i}/{len(PAGES)}] {TITLES[name]} ...")
        texts[name] = page(out, ctx)
    index = ["# Reports\n", "Generated by `verify report` (also run by `verify all`); do not edit by hand.\n"]
    index += [f"- [{TITLES[name]}]({name})" for name, _ in PAGES]
    texts["README.md"] = "\n".join(index) + "\n"
    written: list[Path] = []
    try:
        for name, text in texts.items():
            with open(out / (name + ".tmp"), "w", encoding="utf-8", newline="\n") as fh:
                written.append(out / (name + ".tmp"))
                fh.write(text)
    except BaseException:  # a failed or interrupted write leaves no temporary file of its own
        for tmp in written:
            tmp.unlink(missing_ok=True)
        raise
    for name in texts:
        os.replace(out / (name + ".tmp"), out / name)
    return ctx
