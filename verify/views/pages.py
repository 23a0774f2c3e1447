"""The reports: ``verify report`` writes ``reports/``, one page per topic, all from the library.

Every number on a page comes from a library call made while writing it; the pages quote the
text views of the commands (:mod:`verify.views.text`) and name the command that prints each
one. Output is deterministic (fixed seeds, derandomised Hypothesis, no timestamps, figure
metadata stripped): writing twice gives the same bytes. Pages are written whole to
temporary names and renamed at the end, so an interrupted run leaves the old reports.

Each page is a function of what it shows (``table1_page(table)``, ...). :data:`PAGES` calls
each with the output folder and the :class:`Findings`, which computes each topic once,
when its page first asks for it (the summary of ``verify all`` reads the same findings).

>>> [name for name, _ in PAGES][:2]
['table1.md', 'cradle-map.md']
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property
from pathlib import Path
from typing import Any

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


def _block(text: str) -> str:
    return "```text\n" + text.rstrip("\n") + "\n```\n"


@dataclass
class OracleFindings:
    """The golden dataset, its self-check, and the worked example's comparison (None outside a checkout)."""

    cases: list[dict[str, Any]]
    results: list[dict[str, Any]]
    skipped: int
    self_check: Any
    example: Any = None


def oracle_findings() -> OracleFindings:
    """The golden dataset and its exact results compared with themselves at zero tolerance, and, in a
    source checkout, the independent float implementation ``examples/float_impl.py`` checked against them."""
    import json
    import sys

    from verify.checks import oracle

    cases, skipped = oracle.golden_dataset()
    results = oracle.golden_results(cases)
    self_check = oracle.compare(cases, results, json.loads(json.dumps(results)), rtol=Fraction(0), atol=Fraction(0),
                                floor=Fraction(0))  # fmt: skip
    candidates = [
        Path.cwd() / "examples" / "float_impl.py",
        Path(__file__).resolve().parent.parent / "examples" / "float_impl.py",
    ]
    example = next((p for p in candidates if p.exists()), None)
    compared = None
    if example is not None:  # a source checkout: the worked example of the README
        text = oracle.run_implementation(f"{sys.executable} {example}", json.dumps({"cases": cases}), 600)
        got = oracle.load_results(text, "examples/float_impl.py")
        compared = oracle.compare(cases, results, got, rtol=oracle.DEFAULT_RTOL, atol=Fraction(0))
    return OracleFindings(cases, results, skipped, self_check, compared)


class Findings:
    """What the reports show, each topic computed by one library call when first asked for.

    ``verdicts`` reuses property verdicts already computed for ``profile``; the long computations (the
    corner's sweeps, the property rows) are tasks of ``runner`` (a :class:`verify.checks.tasks.TaskRunner`:
    local processes or a Dask cluster, with a checkpoint or not; default one process per core).
    """

    def __init__(self, profile: str = "ci", runner: Any = None, verdicts: Any = None) -> None:
        from verify.checks.tasks import TaskRunner

        self.profile, self.runner = profile, runner or TaskRunner(workers=None)
        self.given_verdicts = verdicts
        self._rows: Future[list[Any]] | None = None  # the property rows started by :meth:`start_verdicts`

    def start_verdicts(self) -> None:
        """Start the property rows now, from a thread of this process, on the runner's other processes (a cluster,
        or its :meth:`~verify.checks.tasks.TaskRunner.one_pool`), so that they run while this process computes the
        other topics; :attr:`verdicts` waits for them. Nothing to start when they were given or are started
        already, or when the rows would run in this process (then :attr:`verdicts` computes them)."""
        if self.given_verdicts or self._rows is not None or not self.runner.elsewhere:
            return
        rows: Future[list[Any]] = Future()

        def run() -> None:
            try:
                rows.set_result(self._verdicts())
            except BaseException as exc:  # raised again where the verdicts are asked for
                rows.set_exception(exc)

        self._rows = rows
        threading.Thread(target=run, name="verify property rows", daemon=True).start()

    @cached_property
    def table1(self) -> Any:
        from verify.checks.paper.table1 import table1

        return table1()

    @cached_property
    def cradle_map(self) -> Any:
        from verify.checks.paper.cradle_map import map_report
        from verify.maps.cradle import cradle_map

        return map_report(cradle_map(max_impulses=40), approach=6, paper=True)

    @cached_property
    def corner_example(self) -> Any:
        from verify.models.corner import run_corner

        e = CORNER_EXAMPLE
        return run_corner(alpha=e["alpha"], phi=e["phi"], eps1=e["eps1"], eps2=e["eps2"], v0=e["v0"])

    @cached_property
    def corner_maps(self) -> Any:
        from verify.checks.paper.corner_map import corner_maps

        return corner_maps()

    @cached_property
    def corner(self) -> tuple[Any, ...]:
        from verify.checks.paper.corner_claims import corner_findings

        return corner_findings(CORNER_CASES, seed=0, runner=self.runner)

    @cached_property
    def verdicts(self) -> list[Any]:
        return self._rows.result() if self._rows is not None else self._verdicts()

    def _verdicts(self) -> list[Any]:
        from verify.checks.properties import verdicts

        if self.given_verdicts:
            return list(self.given_verdicts)
        return verdicts.verdicts(self.profile, runner=self.runner)

    @cached_property
    def oracle(self) -> OracleFindings:
        return oracle_findings()


def table1_page(table: Any) -> str:
    """The page of Table 1."""
    from verify.views.text import table1_text

    return (
        "# Table 1: Newton's cradle (Sect. 4.1)\n\n"
        "The paper's Table 1 beside the exact results and the paper-mode results (the paper's own termination: a\n"
        "cap of 10^4 impulses and the AEEV stop). Every printed entry is marked as agreeing or not, with the\n"
        "reason. Command: `verify table1` (`--json` for exact values).\n\n" + _block(table1_text(table))
    )


def cradle_map_page(out: Path, report: Any) -> str:
    """The page of the cradle map (a :class:`verify.checks.paper.cradle_map.MapReport`); draws its figure
    into ``out``."""
    from verify.views.figures import cradle_staircase
    from verify.views.text import cradle_map_text

    cradle_staircase(report.cmap, out / "cradle-staircase.png")
    return (
        "# The cradle for every eps in [0, 1]\n\n"
        "eps runs as a symbol; the interval is cut at the exact roots wherever a sign changes. Thresholds are\n"
        "exact algebraic numbers (with decimals); the termination boundary comes with its certificate\n"
        "(`verify cradle-map --json`); the AEEV rows of Table 1 are read off the map. Command: `verify cradle-map`.\n\n"
        + _block(cradle_map_text(report.cmap, aeev_rows=report.aeev_rows, approach=report.approach, exact_in="--json"))
        + "\n![Impulse count against eps: the staircase and the termination boundary](cradle-staircase.png)\n"
    )


def corner_page(out: Path, example: Any, findings: tuple[Any, ...], runner: Any = None, maps: Any = None) -> str:
    """The page of the corner: the paper's example run, the findings of ``verify corner-claims``, and the paper's
    corner mapped over its CORs (``maps``, :func:`verify.checks.paper.corner_map.corner_maps`); draws its figures
    into ``out``."""
    from verify.views import figures
    from verify.views.text import corner_claims_text, corner_map_text, corner_text

    names = [
        ("corner-exit-vs-entrance.png", figures.corner_exit_vs_entrance, "exit speed and direction against entrance"),
        ("corner-multiple-impacts.png", figures.corner_multiple_impacts_map, "where repeated multiple impacts occur"),
        ("wedge-boundary.png", figures.wedge_boundary, "the symmetric termination boundary"),
    ]
    for name, draw, _ in names:
        draw(out / name, runner=runner)
    pictures = "".join(f"\n![{what}]({name})\n" for name, _, what in names)
    return (
        "# The disk in a corner (Sect. 4.2)\n\n"
        "The paper's example traced impulse by impulse (`verify corner --alpha pi/6 --phi pi/12 --eps1 0.999 "
        "--eps2 0.001`):\n\n" + _block(corner_text(example, **CORNER_EXAMPLE)) + "\n"
        f"The paper's claims on {CORNER_CASES} exact rational cases, the termination boundary, the rebounds as the\n"
        f"corner narrows, and float against exact (`verify corner-claims --cases {CORNER_CASES}`):\n\n"
        + _block(corner_claims_text(*findings))
        + pictures
        + ("" if maps is None else _corner_maps_section(out, maps, corner_map_text(maps)))
    )


def _corner(out: Path, f: Findings) -> str:
    """The corner's page; its maps (this process) first, then its sweeps (the runner's, maybe behind the
    property rows)."""
    maps = f.corner_maps
    return corner_page(out, f.corner_example, f.corner, f.runner, maps)


def _corner_maps_section(out: Path, maps: Any, text: str) -> str:
    from verify.views import figures

    figures.plane_figure(maps.plane, out / "corner-cors-plane.png")
    return (
        "\nThe paper's statement that repeated multiple impacts occur when the CORs are very different (its example:\n"
        "eps1 = 0.999, eps2 = 0.001), mapped exactly over the CORs in the number field of the corner's numbers\n"
        "(`verify.checks.paper.corner_map`; the line is also\n"
        "`verify map docs/examples/paper-corner-map.json --max-impulses 12`):\n\n"
        + _block(text)
        + "\n![the square of both CORs as exact cells, up to three impulses](corner-cors-plane.png)\n"
    )


def properties_page(profile: str, found: list[Any]) -> str:
    """The page of the property verdicts."""
    from verify.views.text import properties_text

    return (
        "# Properties of the rule and of the simultaneous law\n\n"
        f"Every property x law x rule x family, profile `{profile}` "
        f"(`verify properties --profile {profile}`); under the simultaneous law the rule column names the CORs.\n"
        "Each refutation comes with its shrunk exact counterexample; save it as a case file and rerun it\n"
        "with "
        "`verify solve CASE.json --rule RULE` (add `--law simultaneous` for that law's rows; or let\n"
        "`verify properties --counterexamples DIR` write the files).\n\n" + _block(properties_text(profile, found))
    )


def oracle_page(found: OracleFindings) -> str:
    """The page of the reference oracle."""
    from verify.checks import oracle
    from verify.views.text import oracle_text

    lines = [
        "# The reference oracle\n",
        "The golden dataset (`golden/`, written by `verify oracle export golden`): what it contains.\n",
        oracle.dataset_description(found.cases, found.results, found.skipped),
        "Self-check: the exact results compared with themselves at zero tolerance "
        "(`verify oracle check golden/cases.json golden/results.json --rtol 0 --floor 0`):\n",
        _block(oracle_text(found.self_check)),
    ]
    if found.example is not None:
        lines += [
            "\nAn independent float implementation (`examples/float_impl.py`) checked against it "
            '(`verify oracle check golden/cases.json --impl "python3 examples/float_impl.py"`):\n',
            _block(oracle_text(found.example)),
        ]
    else:
        lines.append("\n(The worked example `examples/float_impl.py` is in the source checkout; run from its root.)\n")
    return "\n".join(lines + error_tables(found))


def _engine_rows(cases: list[dict[str, Any]], out: Path) -> list[Any]:
    """Each engine of the engines record (``engines.json``), graded on the golden cases it ran against
    the simultaneous law (velocity-only results; the cases it cannot build count as skipped)."""
    import json

    from verify.checks import oracle
    from verify.checks.grading import table_row

    source = out / "engines.json" if (out / "engines.json").exists() else Path("reports") / "engines.json"
    if not source.exists():
        return []
    record = json.loads(source.read_text(encoding="utf-8"))
    exact = oracle.golden_results(cases, law="simultaneous")
    ids = {c["id"] for c in cases}
    rows = []
    for e in record["engines"]:
        got = [{"id": r["id"], "exit_velocity": r["engine_exit_velocity"]} for r in e["cases"] if r["id"] in ids]
        ran = {r["id"] for r in got}
        skipped = {c["id"]: "not built by the engine" for c in cases if c["id"] not in ran}
        compared = oracle.compare(cases, exact, got, rtol=oracle.DEFAULT_RTOL, atol=Fraction(0), skipped=skipped)
        rows.append(table_row(f"{e['name']} {e['version']}", "simultaneous", compared))
    return rows


def error_tables(found: OracleFindings, out: Path = Path("reports")) -> list[str]:
    """The error tables of the oracle page: the float example on the hard cases of level 1, and the
    float example and every engine of the engines record on the golden cases."""
    import json
    import sys

    from verify.checks import oracle
    from verify.checks.grading import table_row
    from verify.checks.hardcases import generate
    from verify.views.text import error_table_text

    lines = ["\n## Error tables\n"]
    if found.example is not None:
        hard = generate(1, 0)
        example = Path("examples") / "float_impl.py"
        text = oracle.run_implementation(f"{sys.executable} {example}", json.dumps({"cases": hard}), 600)
        compared = oracle.compare(hard, oracle.golden_results(hard), oracle.load_results(text, str(example)),
                                  rtol=oracle.DEFAULT_RTOL, atol=Fraction(0))  # fmt: skip
        lines += [
            "The hard cases of `verify oracle generate --level 1 --seed 0` (cases near the exact breakpoints, the",
            "corner's boundaries, grazing contacts, runs that never exit), graded against the paper's rule",
            "(`verify oracle table hard.json floats=RESULTS.json`):\n",
            _block(error_table_text([table_row("float example", "rule", compared)])),
        ]
    rows = [table_row("float example", "rule", found.example)] if found.example is not None else []
    rows += _engine_rows(found.cases, out)
    if rows:
        lines += [
            "\nThe golden cases: the float example against the rule, and each physics engine of",
            "[engines.md](engines.md) against the simultaneous law (the law engines implement; the cases an engine",
            "cannot build count as skipped):\n",
            _block(error_table_text(rows)),
        ]
    return lines


def performance_page(out: Path) -> str:
    """The page of ``out/bench.json`` (copied there from ``reports/bench.json`` when missing)."""
    import json

    from verify.checks.bench import bench_text, requirements
    from verify.records.files import write_atomic

    saved = out / "bench.json"
    source = saved if saved.exists() else Path("reports") / "bench.json"
    if not source.exists():
        return (
            "# Performance\n\nNo benchmark record yet: run `verify bench --save reports/bench.json`, then "
            "`verify report`.\n"
        )
    data = source.read_bytes()
    if source != saved:  # keep the record beside the page it feeds
        write_atomic(saved, data)
    record = json.loads(data)
    checks = "\n".join(f"- {line}" for line in requirements(record))
    return (
        "# Performance\n\n"
        "Figures of `verify bench --save reports/bench.json` (the record is `bench.json`, beside this page;\n"
        "`verify report` renders it and never times anything, so the reports stay reproducible). Each ratio is\n"
        "against a baseline timed alternately in the same run, best of 3; see `verify bench --help`.\n\n"
        + _block(bench_text(record))
        + "\nWhat issue 19 asks of these ratios:\n\n"
        + checks
        + "\n\n"
        + PERFORMANCE_NOTES
    )


PERFORMANCE_NOTES = """\
How to read them:

- Each batch (`batch` in `bench.json`; `verify bench --help`) has its own plain loop over
  `fractions.Fraction`, timed in the same run: the corner's eq. (10) with the paper's closed forms, or
  the textbook loop of `verify/checks/baselines.py` for the cradle and general systems. Every
  contestant keeps what the plain loop keeps: the branch sequence and the last velocity of each case.
- The exact engine is the general one: a `System` built and checked per case (symmetric positive
  definite mass matrix, independent normals, CORs in [0, 1]), then `solve` without a trace. It runs
  the rule in rate coordinates (`verify/core/engines/rates.py`: the impulses act on the r rates
  through the Gram matrix alone, and the velocity is formed once, at the end), and a long run over
  integers with one common denominator (`verify/core/engines/integer.py`). The cradle batch uses the
  batch entry point `solve_many`: the geometry is built once and each COR shares it.
- `corner_short` is where the set-up of a case is most of the work. `bare_rates` is the same
  computation written out bare (nothing checked, no object built, `verify/checks/baselines.py`): a
  bound on what Python code reaches there. PARI/GP does the set-up in a few calls into its C library.
- Table 1: `table1.runs` computes the 17 rows in exact and paper mode (exact numbers; exact mode also
  proves that the two lowest rows never exit); `table1.gp` is the paper's loop in GP's reals, the
  paper's own arithmetic, and `table1.gp_rationals` the same loop on exact rationals.
- The certified float path (`verify/core/engines/floats.py`) certifies every branch: for two
  constraints the rounding error is bounded in the frame of the rates themselves, so it does not grow
  with alternating impacts; a sign it cannot certify is decided by an exact catch-up over integers
  from the case's last exact state (`float_path_rung_catch_up`), and a case redone exactly only when
  floats cannot hold it (`float_path_rung_exact`). The plain float loop takes a wrong branch sequence
  on `float_loop_wrong_branches` cases.
- Intervals run on rate midpoints with one radius in the kinetic-energy norm
  (`verify/core/engines/balls.py`), which single impacts do not expand, so the precision stays at its
  start (`interval_digits`) and the cost per impulse stays flat while the exact numbers grow
  (`exact_bits`). A run pays a fixed set-up (the constants of the system, the enclosure of the
  exit velocity), so on short runs (`impulse_cost.interval.10`) intervals cost more than exact numbers.
"""


def fig1_page(out: Path) -> str:
    """The page of the three disks after the impact; draws its figure into ``out``."""
    from verify.views.figures import cradle_motion

    cradle_motion(out / "cradle-motion.png")
    return (
        "# The three disks after the impact (like the paper's Fig. 1)\n\n"
        "Disk D1 hits D2 and D3 at rest with v0 = 1; the exact exit velocities of `verify cradle --eps E --v0 1`\n"
        "for eps = 0.9, 0.5, 0.1 move the disks from where they touched (dotted) for four time units (solid).\n\n"
        "![The three disks after the impact for eps = 0.9, 0.5, 0.1](cradle-motion.png)\n"
    )


def _v(values: list[str] | None, digits: int = 6) -> str:
    """A velocity's components to ``digits`` significant digits (a closed form evaluated), or "-"."""
    from verify.checks.engines import short_decimal

    return "-" if values is None else "(" + ", ".join(short_decimal(x, digits) for x in values) + ")"


def explained_table(record: dict[str, Any]) -> list[str]:
    """Per engine: the share of its default answers an exact model explains (and the model that explains most),
    its largest kinetic-energy gain, and its median distance to the paper's rule and to the simultaneous law."""
    from verify.checks.engines import GAIN, median_distance
    from verify.core.format import format_decimal

    lines = [
        f"| engine | precision | explained by an exact model | most by | largest energy gain (above {GAIN}) | "
        "median distance to the paper's rule | to the simultaneous law |",
        "|---|---|---|---|---|---|---|",
    ]
    for e in record["engines"]:
        s = e.get("explained") or {"explained": 0, "cases": len(e["cases"]), "models": {}, "precision": "?"}
        top = max(s["models"].items(), key=lambda kv: (kv[1], kv[0]))[0] if s["models"] else "-"
        gains = [Fraction(c["energy_change"]) for c in e["cases"] if c["energy_change"]]
        gain = format_decimal(max(gains), 3) if gains and max(gains) > GAIN else "none"
        lines.append(
            f"| {e['name']} | {s['precision']} | {s['explained']} of {s['cases']} | {top} | {gain} | "
            f"{median_distance(e, 'distance_to_rule')} | {median_distance(e, 'distance_to_simultaneous')} |"
        )
    return lines


def engines_tables(record: dict[str, Any]) -> list[str]:
    """The engines page's tables: the engines, the exact references, and each engine's cases."""
    lines = ["## The engines", "", "| engine | version | combines restitution | one COR per contact | settings |",
             "|---|---|---|---|---|"]  # fmt: skip
    for e in record["engines"]:
        settings = ", ".join(f"{k} = {v:g}" for k, v in e["settings"].items())
        lines.append(f"| {e['name']} | {e['version']} | {e['combine_rule']} | {e['cor_setting']} | {settings} |")
    lines += [f"- **{s['name']}** was not run: {s['reason']}" for s in record["skipped"]]
    ids = {c["id"] for e in record["engines"] for c in e["cases"]}
    lines += ["", "## The exact references", "", "| case | paper's rule | simultaneous law |", "|---|---|---|"]
    rows = {c["id"]: c for e in record["engines"] for c in e["cases"]}
    for case in record["cases"]:
        if case["id"] in ids:
            r = rows[case["id"]]
            rule = _v(r["rule_exit_velocity"]) if r["rule_exit_velocity"] else f"no exit ({r['rule_stop']})"
            lines.append(f"| `{case['id']}` | {rule} | {_v(r['simultaneous_exit_velocity'])} |")
    for e in record["engines"]:
        lines += ["", f"## {e['name']} {e['version']}, default settings", "",
                  "| case | engine exit velocity | to the rule | to the simultaneous law | kinetic energy in -> out | "
                  "nearest exact model (distance) |",
                  "|---|---|---|---|---|---|"]  # fmt: skip
        for c in e["cases"]:
            energy = f"{c['kinetic_energy_in']} -> {c['kinetic_energy_out']}"
            model = "-" if "nearest_model" not in c else (
                f"{c['nearest_model']} ({c['model_distance']})" + ("" if c.get("model") else f"; not within "
                                                                  f"precision: {c.get('why', '')}"))  # fmt: skip
            lines.append(f"| `{c['id']}` | {_v(c['engine_exit_velocity'])} | {c['distance_to_rule'] or 'no exit'} | "
                         f"{c['distance_to_simultaneous']} | {energy} | {model} |")  # fmt: skip
        lines += [f"- skipped `{s['id']}`: {s['reason']}" for s in e["skipped_cases"]]
    return lines


def engines_page_text(record: dict[str, Any]) -> str:
    """The engines page for a record of :func:`verify.checks.engines.engines_record`."""
    from verify.checks.engines import AGREES, findings

    names = ", ".join(e["name"] for e in record["engines"]) or "none"
    head = [
        "# Physics engines against the paper's rule and the simultaneous law",
        "",
        "Each engine runs as a subprocess adapter (`python -m verify.physics.NAME`, the `verify oracle check",
        "--impl` protocol) with gravity and friction off, on the cradles and corners below; its exit velocity",
        "stands beside the exact ones of the paper's rule and of the simultaneous law (Newton's restitution with",
        "complementarity, all contacts at once: `verify solve --law simultaneous`). The distances are relative:",
        "`max_i |engine_i - exact_i| / max_i |v_in_i|`. Written by `verify engines --report` (record:",
        "`engines.json`, beside this page); `verify report` renders the record and runs no engine. Floats of an",
        "engine are read exactly as printed.",
        "",
        f"Engines that ran: {names}.",
        "",
        "## Findings (measured on the record)",
        "",
        *[f"- {line}" for line in findings(record)],
        "",
        f"An engine agrees with a law on a case when the relative distance is at most {AGREES}.",
        "",
    ]
    if record["engines"]:
        head += [
            "## Each engine explained",
            "",
            "Each answer of an engine at its default settings is compared with exact models of its own algorithm",
            "(`verify.checks.explain`): the paper's rule, the simultaneous law (also with the engine's documented",
            "restitution threshold), and the sequential law (`verify solve --law sequential`: projected Gauss-Seidel",
            "sweeps, exactly) with the engine's documented sweeps, the neighbouring counts, both contact orders and",
            "its threshold. An answer is explained when a model is within the engine's precision (float32: 1e-5 of",
            "the speed; float64: 1e-9); when several are, they give the same answer to that precision, and the first",
            "of the engine's own kind of solver is named. The last columns are medians over the cases where the law",
            "exits.",
            "",
            *explained_table(record),
            "",
            "![The three-ball cradle against eps: the rule, the simultaneous law and each engine](engines-cradle.png)",
            "",
        ]
    return "\n".join(head + engines_tables(record)) + "\n"


def engines_page(out: Path) -> str:
    """The page of ``out/engines.json`` (copied there from ``reports/engines.json`` when missing); draws its figure."""
    import json

    from verify.records.files import write_atomic
    from verify.views.figures import engines_cradle

    saved = out / "engines.json"
    source = saved if saved.exists() else Path("reports") / "engines.json"
    if not source.exists():
        return (
            '# Physics engines\n\nNo engines record yet: `pip install ".[engines]"`, then `verify engines --report`.\n'
        )
    data = source.read_bytes()
    if source != saved:
        write_atomic(saved, data)
    record = json.loads(data)
    if record["engines"]:
        engines_cradle(record, out / "engines-cradle.png")
    return engines_page_text(record)


#: each page: its file name, and how it is written from the output folder and the findings
PAGES: list[tuple[str, Callable[[Path, Findings], str]]] = [
    ("table1.md", lambda out, f: table1_page(f.table1)),
    ("cradle-map.md", lambda out, f: cradle_map_page(out, f.cradle_map)),
    ("corner.md", _corner),
    ("properties.md", lambda out, f: properties_page(f.profile, f.verdicts)),
    ("oracle.md", lambda out, f: oracle_page(f.oracle)),
    ("performance.md", lambda out, f: performance_page(out)),
    ("fig1.md", lambda out, f: fig1_page(out)),
    ("engines.md", lambda out, f: engines_page(out)),
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
}


def write_reports(out: str | Path = "reports", *, profile: str = "ci", workers: int | None = None,
                  progress: Callable[[str], None] | None = None, verdicts: Any = None,
                  runner: Any = None) -> Findings:  # fmt: skip
    """Write every page and the index into ``out``; returns the :class:`Findings` shown, which the
    summary of ``verify all`` reads. ``verdicts`` reuses property verdicts already computed for ``profile``.
    The long computations run on ``runner`` (:class:`verify.checks.tasks.TaskRunner`), else on ``workers``
    local processes (None: one per core): the property rows from the start (:meth:`Findings.start_verdicts`),
    while this process computes the pages before theirs (on one pool:
    :meth:`~verify.checks.tasks.TaskRunner.one_pool`)."""
    from verify.errors import require
    from verify.records.files import write_all_atomic

    require("matplotlib", "the reports' figures")  # before anything is computed or written
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    from verify.checks.tasks import TaskRunner

    findings = Findings(profile, runner or TaskRunner(workers=workers), verdicts)
    texts: dict[str, str] = {}
    with findings.runner.one_pool():
        findings.start_verdicts()  # on the pool (or a cluster) while this process writes the pages
        for i, (name, page) in enumerate(PAGES, 1):
            if progress:
                progress(f"[report {i}/{len(PAGES)}] {TITLES[name]} ...")
            texts[name] = page(out, findings)
    index = ["# Reports\n", "Generated by `verify report` (also run by `verify all`); do not edit by hand.\n"]
    index += [f"- [{TITLES[name]}]({name})" for name, _ in PAGES]
    texts["README.md"] = "\n".join(index) + "\n"
    write_all_atomic({out / name: text for name, text in texts.items()})
    return findings
