"""Verdicts: each property x rule x family proved, holding on N cases, or refuted.

For every row, Hypothesis searches for a counterexample (``hypothesis.find``, derandomised:
the same verdicts on every run): ``holds`` with the number of cases where the property
applied, none failing, or ``refuted`` with the shrunk, exact counterexample (a case
record of the contracts, which ``verify solve --rule R`` reproduces) and what fails. Where
SymPy proves the property (:mod:`verify.checks.properties.proofs`) the verdict is ``proved``, and the search
still runs: it tests that the implementation agrees with the proof (a counterexample then
means the code is wrong, and the verdict is ``refuted``).

Every run has a size budget (:data:`BUDGET`) and the record's ``max_iterations`` (200), so
that a search never hangs on cases whose exact numbers explode; such runs are counted in
the note. Profiles: ``dev`` (25 cases a row), ``ci`` (100), ``thorough`` (100,000 cases per
property, shared evenly between its rows).

>>> v = search(property_named("the exit velocity is outgoing"), "corner", "ideal", 10)
>>> v.verdict, v.cases > 0
('holds', True)
"""

from __future__ import annotations

import json
import math
from collections import Counter
from dataclasses import dataclass, field
from typing import Any

from verify.checks.pool import map_in_processes
from verify.checks.properties.catalogue import PROPERTIES, SKIP, Property, property_named
from verify.checks.properties.profiles import PER_PROPERTY, PROFILES
from verify.checks.properties.proofs import PROOFS, prove
from verify.checks.properties.strategies import FAMILIES, RULES, Drawn, cases
from verify.core.rule import Budget

BUDGET = Budget(bits=4096)
INTERVAL_DPS, INTERVAL_MAX_DPS, MP_DPS = 30, 120, 30


class Runner:
    """Runs case records on the engine, memoised (a property compares several runs)."""

    def __init__(self) -> None:
        self.memo: dict[str, Any] = {}
        self.counts: Counter[str] = Counter()

    def count(self, what: str) -> None:
        self.counts[what] += 1

    def __call__(self, record: dict[str, Any], rule: str, backend: str = "exact") -> Any:
        key = json.dumps([record, rule, backend], sort_keys=True)
        if key not in self.memo:
            if len(self.memo) > 512:
                self.memo.clear()
            self.memo[key] = run_record(record, rule, backend)
        return self.memo[key]


def run_record(record: dict[str, Any], rule: str, backend: str = "exact") -> Any:
    """Solve one case record with the rule, the suite's budget and backend settings."""
    from verify.core.backends import IntervalBackend, get_backend
    from verify.core.rule import solve
    from verify.core.system import System

    K = (
        IntervalBackend(dps=INTERVAL_DPS, max_dps=INTERVAL_MAX_DPS)
        if backend == "interval"
        else get_backend(backend, dps=MP_DPS if backend == "mp" else None)
    )
    system = System(record["mass_matrix"], record["normals"], record["restitution"], record["time_terms"], backend=K)
    return solve(
        system, record["velocity"], rule=rule, max_iterations=record["max_iterations"], budget=BUDGET, trace=True
    )


@dataclass
class Verdict:
    """One row of the verdict table (its :meth:`record` is the JSON of the contracts)."""

    property: str
    rule: str
    family: str
    verdict: str
    cases: int
    counterexample: dict[str, Any] | None = None
    note: str = ""
    extra: Any = field(default=None, repr=False)

    def record(self) -> dict[str, Any]:
        return {
            "property": self.property,
            "rule": self.rule,
            "family": self.family,
            "verdict": self.verdict,
            "cases": self.cases,
            "counterexample": self.counterexample,
            "note": self.note,
        }


def rows(properties: Any = None, families: Any = None, rules: Any = None) -> list[tuple[Property, str, str]]:
    """The (property, family, rule) rows, in a fixed order."""
    chosen = [property_named(p) for p in properties] if properties else list(PROPERTIES)
    out = []
    for prop in chosen:
        for rule in RULES:
            if rule not in prop.rules or (rules and rule not in rules):
                continue
            for family in FAMILIES:
                if family in prop.families and (not families or family in families):
                    out.append((prop, family, rule))
    return out


def _check(prop: Property, runner: Runner, item: Any) -> str | None:
    d, extra = item if prop.extra is not None else (item, None)
    try:
        return prop.check(runner, d, extra)
    except Exception as exc:  # a valid case must not make the engine raise: that is a finding
        return f"the engine raised {type(exc).__name__}: {' '.join(str(exc).split())}"


def search(prop: Property, family: str, rule: str, examples: int) -> Verdict:
    """Search one row for a counterexample with ``examples`` cases."""
    from hypothesis import HealthCheck, Phase, find, settings
    from hypothesis import strategies as st
    from hypothesis.errors import NoSuchExample, Unsatisfiable

    runner = Runner()
    tally: Counter[str] = Counter()
    shrinking = False  # once a failure is found, Hypothesis shrinks it: those calls are not counted

    def fails(item: Any) -> bool:
        nonlocal shrinking
        why = _check(prop, runner, item)
        if not shrinking:
            tally["drawn"] += 1
            tally["skipped" if why == SKIP else "applied"] += 1
        if why is None or why == SKIP:
            return False
        shrinking = True
        return True

    strategy: Any = cases(family, rule)
    if prop.extra is not None:
        strategy = st.tuples(strategy, prop.extra)
    config = settings(
        max_examples=examples,
        database=None,
        deadline=None,
        derandomize=True,
        phases=[Phase.generate, Phase.shrink],
        suppress_health_check=list(HealthCheck),
    )
    proof = prove(prop.proof, rule) if prop.proof else None
    try:
        item = find(strategy, fails, settings=config)
    except (NoSuchExample, Unsatisfiable):
        return _holds(prop, (family, rule), tally, runner.counts, proof)
    d, extra = item if prop.extra is not None else (item, None)
    why = _check(prop, Runner(), item) or ""
    note = why + (f" (with {_describe(extra)})" if extra is not None else "")
    if proof:
        note = f"contradicts the proof ({proof}): the implementation is wrong: " + note
    elif prop.explain:
        where = prove(prop.explain, rule) if prop.explain in PROOFS else prop.explain
        note += f". Where it fails: {where}" if where else ""
    record = dict(d.record, id=f"{family}-{rule}-{_slug(prop.name)}")
    note += f"; reproduce with: verify solve CASE.json --rule {rule}"
    tried = tally["applied"]
    if prop.census:
        tried, counts = _census(prop, strategy, examples)
        note += f"; a separate census of {tried} cases ends: " + ", ".join(
            f"{k}: {v}" for k, v in sorted(counts.items())
        )
    return Verdict(prop.name, rule, family, "refuted", tried, record, note, extra)


def _census(prop: Property, strategy: Any, examples: int) -> tuple[int, Counter]:
    """How the runs of a refuted row end, over all its cases (the search stops at the first failure)."""
    from hypothesis import HealthCheck, Phase, given, settings

    runner = Runner()
    seen: Counter[str] = Counter()

    @settings(
        max_examples=examples,
        database=None,
        deadline=None,
        derandomize=True,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def count(item: Any) -> None:
        seen["cases"] += 1
        _check(prop, runner, item)

    count()
    return seen["cases"], runner.counts


def _holds(prop: Property, row: tuple[str, str], tally: Counter, counts: Counter, proof: str | None) -> Verdict:
    family, rule = row
    parts = [f"no counterexample in {tally['applied']} cases"]
    if tally["skipped"]:
        parts.append(f"{tally['skipped']} of {tally['drawn']} drawn cases did not apply")
    parts += [f"{k}: {v}" for k, v in sorted(counts.items())]
    if proof:
        return Verdict(prop.name, rule, family, "proved", tally["applied"], None, proof + "; " + "; ".join(parts))
    return Verdict(prop.name, rule, family, "holds", tally["applied"], None, "; ".join(parts))


def _describe(extra: Any) -> str:
    if isinstance(extra, (list, tuple)):
        return "[" + ", ".join(_describe(x) for x in extra) + "]"
    return str(extra)


def _slug(name: str) -> str:
    return "-".join("".join(c if c.isalnum() else " " for c in name.lower()).split())[:40]


def examples_per_row(profile: str, n_rows: int) -> int:
    """Cases per row: the profile's count, or its per-property count shared between rows."""
    if profile not in PROFILES:
        from verify.errors import InvalidInput

        raise InvalidInput(f"unknown profile {profile!r} (choose from {', '.join(PROFILES)})")
    if profile in PER_PROPERTY:
        return math.ceil(PROFILES[profile] / max(1, n_rows))
    return PROFILES[profile]


def _run_row(args: tuple[str, str, str, int]) -> Verdict:
    name, family, rule, examples = args
    return search(property_named(name), family, rule, examples)


def verdicts(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    workers: int | None = 1,
    progress: Any = None,
) -> list[Verdict]:
    """Every row's verdict under a profile (``workers`` > 1 runs rows in processes; None:
    one per core)."""
    table = rows(properties, families, rules)
    per_prop = Counter(p.name for p, _, _ in table)
    jobs = [(p.name, f, r, examples_per_row(profile, per_prop[p.name])) for p, f, r in table]

    def done(count: int, verdict: Verdict) -> None:
        progress(count, len(jobs), verdict)

    return map_in_processes(_run_row, jobs, workers=workers, on_done=done if progress else None)


def report(profile: str, found: list[Verdict]) -> dict[str, Any]:
    """The JSON of ``verify properties --json`` (contracts)."""
    return {"profile": profile, "properties": [v.record() for v in found]}


__all__ = ["Drawn", "Runner", "Verdict", "report", "rows", "run_record", "search", "verdicts"]
