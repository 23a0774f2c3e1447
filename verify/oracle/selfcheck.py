"""The oracle's self-check: the golden dataset compared with itself, the worked float example checked against it
on the golden and the hard cases, and the engines of an engines record graded on the golden cases (what the
oracle page and the summary of ``verify all`` show; the page renders these, it runs nothing).

>>> found = oracle_findings(example=False)
>>> found.self_check.ok, found.example is None, found.hard is None
(True, True, True)
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from verify.dynamics.policy import JSONObject
from verify.oracle import reference as oracle
from verify.oracle.grading import DEFAULT_RTOL, TableRow, table_row
from verify.oracle.reference import Comparison

#: the worked example of docs/oracle.md, in a source checkout
EXAMPLE = Path("examples") / "float_impl.py"


@dataclass
class OracleFindings:
    """The golden dataset, its self-check, and the worked example's comparisons on the golden cases
    (``example``) and on the hard cases of level 1 (``hard``), both None outside a checkout; ``engine_rows``:
    each engine of the engines record graded on the golden cases against the simultaneous law."""

    cases: list[JSONObject]
    results: list[JSONObject]
    skipped: int
    self_check: Comparison
    example: Comparison | None = None
    hard: Comparison | None = None
    engine_rows: list[TableRow] = field(default_factory=list)


def oracle_findings(out: Path = Path("reports"), *, example: bool = True) -> OracleFindings:
    """The golden dataset and its exact results compared with themselves at zero tolerance; in a source
    checkout (``example``), the independent float implementation ``examples/float_impl.py`` checked against
    them and against the hard cases of ``verify oracle generate --level 1 --seed 0``; and the engines of
    ``out/engines.json`` (else ``reports/engines.json``) graded on the golden cases."""
    cases, skipped = oracle.golden_dataset()
    results = oracle.golden_results(cases)
    self_check = oracle.compare(cases, results, json.loads(json.dumps(results)), rtol=Fraction(0), atol=Fraction(0),
                                floor=Fraction(0))  # fmt: skip
    found = OracleFindings(cases, results, skipped, self_check, engine_rows=engine_rows(cases, out))
    program = _example_program() if example else None
    if program is not None:  # a source checkout: the worked example of docs/oracle.md
        found.example = _run_example(program, cases, results)
        from verify.oracle.hardcases import generate

        hard = generate(1, 0)
        found.hard = _run_example(program, hard, oracle.golden_results(hard))
    return found


def _example_program() -> Path | None:
    candidates = [Path.cwd() / EXAMPLE, Path(__file__).resolve().parents[2] / EXAMPLE]
    return next((p for p in candidates if p.exists()), None)


def _run_example(program: Path, cases: list[dict[str, Any]], exact: list[dict[str, Any]]) -> Comparison:
    """The float example run on ``cases`` and compared with their ``exact`` results at its tolerance."""
    text = oracle.run_implementation(f"{sys.executable} {program}", json.dumps({"cases": cases}), 600)
    got = oracle.load_results(text, str(EXAMPLE))
    return oracle.compare(cases, exact, got, rtol=DEFAULT_RTOL, atol=Fraction(0))


def engine_rows(cases: list[dict[str, Any]], out: Path) -> list[TableRow]:
    """Each engine of the engines record (``engines.json``), graded on the golden cases it ran against
    the simultaneous law (velocity-only results; the cases it cannot build count as skipped)."""
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
        compared = oracle.compare(cases, exact, got, rtol=DEFAULT_RTOL, atol=Fraction(0), skipped=skipped)
        rows.append(table_row(f"{e['name']} {e['version']}", "simultaneous", compared))
    return rows
