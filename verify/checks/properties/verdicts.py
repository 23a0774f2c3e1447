"""Verdicts: each property x law x rule x family proved, holding on N cases, or refuted.

The law is the paper's iterative rule (``rule``) or the simultaneous law (``simultaneous``,
:mod:`verify.core.simultaneous`); the rule column is then the COR variant (the general rule's
own CORs, the symmetric rule's equal ones, the ideal rule's 1), see :data:`LAW_RULES`.

For every row, Hypothesis searches for a counterexample (``hypothesis.find``, derandomised:
the same verdicts on every run): ``holds`` with the number of cases where the property
applied, none failing, or ``refuted`` with the shrunk, exact counterexample (a case
record of the contracts, which ``verify solve --rule R`` reproduces, with ``--law simultaneous``
for the law's rows) and what fails. Where
SymPy proves the property (:mod:`verify.checks.properties.proofs`) the verdict is ``proved``, and the search
still runs: it tests that the implementation agrees with the proof (a counterexample then
means the code is wrong, and the verdict is ``refuted``).

Every run has a size budget (:data:`BUDGET`) and the record's ``max_iterations`` (200), so
that a search never hangs on cases whose exact numbers explode; such runs are counted in
the note. Profiles: ``dev`` (25 cases a row), ``ci`` (100), ``thorough`` (100,000 cases per
property and law, shared evenly between its rows).

>>> v = search(property_named("the exit velocity is outgoing"), "corner", "ideal", 10)
>>> v.verdict, v.cases > 0
('holds', True)
>>> v = search(property_named("the exit velocity is outgoing"), "corner", "ideal", 10, law="simultaneous")
>>> v.law, v.verdict
('simultaneous', 'holds')
"""

from __future__ import annotations

import contextlib
import json
import math
import os
from collections import Counter
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any

from verify.checks.properties.catalogue import PROPERTIES, SKIP, Property, property_named
from verify.checks.properties.profiles import PER_PROPERTY, PROFILES
from verify.checks.properties.proofs import PROOFS, prove
from verify.checks.properties.strategies import FAMILIES, RULES, Drawn, cases
from verify.checks.tasks import Checkpoint, Task, TaskRun, run_tasks
from verify.core.rule import LAWS, Budget

BUDGET = Budget(bits=4096)
INTERVAL_DPS, INTERVAL_MAX_DPS, MP_DPS = 30, 120, 30
#: the COR variants each law is checked with: every rule for the rule; for the simultaneous law
#: the general, symmetric and ideal CORs (the asymmetric rule's cases are general ones with r = 2)
LAW_RULES = {"rule": RULES, "simultaneous": tuple(r for r in RULES if r != "asymmetric")}


class Runner:
    """Runs case records on the engine under one law (``rule`` by default), memoised (a property
    compares several runs). A check may ask another law's run with ``law=``."""

    def __init__(self, law: str = "rule") -> None:
        self.law = law
        self.memo: dict[str, Any] = {}
        self.counts: Counter[str] = Counter()

    def count(self, what: str) -> None:
        self.counts[what] += 1

    def __call__(self, record: dict[str, Any], rule: str, backend: str = "exact", *, law: str | None = None) -> Any:
        law = self.law if law is None else law
        key = json.dumps([record, rule, backend, law], sort_keys=True)
        if key not in self.memo:
            if len(self.memo) > 512:
                self.memo.clear()
            self.memo[key] = run_record(record, rule, backend, law=law)
        return self.memo[key]


def run_record(record: dict[str, Any], rule: str, backend: str = "exact", *, law: str = "rule") -> Any:
    """Solve one case record with the rule (or, with ``law="simultaneous"``, the simultaneous law
    with the rule's CORs), the suite's budget and backend settings."""
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
        system,
        record["velocity"],
        rule=rule,
        law=law,
        max_iterations=record["max_iterations"],
        budget=BUDGET,
        trace=True,
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
    law: str = "rule"  #: ``rule`` or ``simultaneous``; ``rule`` is then the COR variant

    def record(self) -> dict[str, Any]:
        return {
            "property": self.property,
            "law": self.law,
            "rule": self.rule,
            "family": self.family,
            "verdict": self.verdict,
            "cases": self.cases,
            "counterexample": self.counterexample,
            "note": self.note,
        }


def rows(
    properties: Any = None, families: Any = None, rules: Any = None, laws: Any = None
) -> list[tuple[Property, str, str, str]]:
    """The (property, family, rule, law) rows, in a fixed order: a property's row for the
    simultaneous law right after its row for the rule (same rule variant and family).

    >>> [(f, r, law) for p, f, r, law in rows(["the exit velocity"], ["cradle"], ["ideal", "asymmetric"])]
    [('cradle', 'ideal', 'rule'), ('cradle', 'ideal', 'simultaneous'), ('cradle', 'asymmetric', 'rule')]
    """
    chosen = [property_named(p) for p in properties] if properties else list(PROPERTIES)
    out = []
    for prop in chosen:
        for rule in RULES:
            if rule not in prop.rules or (rules and rule not in rules):
                continue
            for family in FAMILIES:
                if family not in prop.families or (families and family not in families):
                    continue
                for law in LAWS:
                    if law in prop.laws and rule in LAW_RULES[law] and (not laws or law in laws):
                        out.append((prop, family, rule, law))
    return out


def _check(prop: Property, runner: Runner, item: Any) -> str | None:
    d, extra = item if prop.extra is not None else (item, None)
    try:
        return prop.check(runner, d, extra)
    except Exception as exc:  # a valid case must not make the engine raise: that is a finding
        return f"the engine raised {type(exc).__name__}: {' '.join(str(exc).split())}"


def search(prop: Property, family: str, rule: str, examples: int, *, law: str = "rule") -> Verdict:
    """Search one row for a counterexample with ``examples`` cases (the law's runs)."""
    from hypothesis import HealthCheck, Phase, find, settings
    from hypothesis import strategies as st
    from hypothesis.errors import NoSuchExample, Unsatisfiable

    runner = Runner(law)
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
    proof_name, explain = prop.statement(law)
    proof = prove(proof_name, rule) if proof_name else None
    try:
        item = find(strategy, fails, settings=config)
    except (NoSuchExample, Unsatisfiable):
        return _holds(prop, (family, rule, law), tally, runner.counts, proof)
    d, extra = item if prop.extra is not None else (item, None)
    why = _check(prop, Runner(law), item) or ""
    note = why + (f" (with {_describe(extra)})" if extra is not None else "")
    if proof:
        note = f"contradicts the proof ({proof}): the implementation is wrong: " + note
    elif explain:
        where = prove(explain, rule) if explain in PROOFS else explain
        note += f". Where it fails: {where}" if where else ""
    law_part = "" if law == "rule" else f"{law}-"
    record = dict(d.record, id=f"{family}-{rule}-{law_part}{_slug(prop.name)}")
    note += f"; reproduce with: verify solve CASE.json --rule {rule}" + ("" if law == "rule" else f" --law {law}")
    tried = tally["applied"]
    if prop.census:
        tried, counts = _census(prop, strategy, examples, law)
        note += f"; a separate census of {tried} cases ends: " + ", ".join(
            f"{k}: {v}" for k, v in sorted(counts.items())
        )
    return Verdict(prop.name, rule, family, "refuted", tried, record, note, extra, law=law)


def _census(prop: Property, strategy: Any, examples: int, law: str) -> tuple[int, Counter]:
    """How the runs of a refuted row end, over all its cases (the search stops at the first failure)."""
    from hypothesis import HealthCheck, Phase, given, settings

    runner = Runner(law)
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


def _holds(prop: Property, row: tuple[str, str, str], tally: Counter, counts: Counter, proof: str | None) -> Verdict:
    family, rule, law = row
    parts = [f"no counterexample in {tally['applied']} cases"]
    if tally["skipped"]:
        parts.append(f"{tally['skipped']} of {tally['drawn']} drawn cases did not apply")
    parts += [f"{k}: {v}" for k, v in sorted(counts.items())]
    if proof:
        note = proof + "; " + "; ".join(parts)
        return Verdict(prop.name, rule, family, "proved", tally["applied"], None, note, law=law)
    return Verdict(prop.name, rule, family, "holds", tally["applied"], None, "; ".join(parts), law=law)


def _describe(extra: Any) -> str:
    if isinstance(extra, (list, tuple)):
        return "[" + ", ".join(_describe(x) for x in extra) + "]"
    return str(extra)


def _slug(name: str) -> str:
    return "-".join("".join(c if c.isalnum() else " " for c in name.lower()).split())[:40]


def examples_per_row(profile: str, n_rows: int) -> int:
    """Cases per row: the profile's count, or its per-property count shared between rows (the
    ``n_rows`` rows of one property and law)."""
    if profile not in PROFILES:
        from verify.errors import InvalidInput

        raise InvalidInput(f"unknown profile {profile!r} (choose from {', '.join(PROFILES)})")
    if profile in PER_PROPERTY:
        return math.ceil(PROFILES[profile] / max(1, n_rows))
    return PROFILES[profile]


def _run_row(args: tuple[str, str, str, int, str]) -> Verdict:
    name, family, rule, examples, law = args
    return search(property_named(name), family, rule, examples, law=law)


def row_tasks(
    profile: str = "ci", *, properties: Any = None, families: Any = None, rules: Any = None, laws: Any = None
) -> list[Task]:
    """One task a row (its whole search: the verdicts and counterexamples of an unsplit run), with a
    stable id: the row and its number of cases.

    >>> for task in row_tasks("dev", properties=["the exit velocity"], families=["cradle"], rules=["ideal"]):
    ...     print(task.id)
    the exit velocity is outgoing | rule | ideal | cradle | 25
    the exit velocity is outgoing | simultaneous | ideal | cradle | 25
    """
    table = rows(properties, families, rules, laws)
    per_prop = Counter((p.name, law) for p, _, _, law in table)
    out = []
    for p, f, r, law in table:
        examples = examples_per_row(profile, per_prop[p.name, law])
        label = f"{p.name} | {law} | {r} | {f}"
        out.append(Task(f"{label} | {examples}", _run_row, (p.name, f, r, examples, law), label))
    return out


def checkpoint_options(
    profile: str = "ci", *, properties: Any = None, families: Any = None, rules: Any = None, laws: Any = None
) -> dict[str, Any]:
    """The options that change a run's results, as a checkpoint's header keeps them (not how it runs).

    >>> checkpoint_options("dev", properties=["kinetic energy"])
    {'profile': 'dev', 'property': ['kinetic energy'], 'family': None, 'rule': None, 'law': None}
    """
    return {"profile": profile, "property": properties, "family": families, "rule": rules, "law": laws}


def run_verdicts(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    laws: Any = None,
    workers: int | None = 1,
    executor: Executor | None = None,
    checkpoint: str | None = None,
    progress: Any = None,
) -> TaskRun:
    """Every row's verdict as a :class:`verify.checks.tasks.TaskRun`: the verdicts in row order (None for a
    row whose task failed twice) and the failures. ``executor`` runs the rows (a Dask cluster:
    ``Client(...).get_executor()``), else ``workers`` local processes (None: one per core). With
    ``checkpoint`` (a file name) rows finished by an earlier run with the same options are read from it
    and each row finished now is appended. ``progress(done, total, verdict)`` is called as rows finish.
    """
    tasks = row_tasks(profile, properties=properties, families=families, rules=rules, laws=laws)
    options = checkpoint_options(profile, properties=properties, families=families, rules=rules, laws=laws)
    with contextlib.ExitStack() as stack:
        store = stack.enter_context(Checkpoint(checkpoint, options)) if checkpoint else None
        finished = store.open() if store else {}
        count = sum(1 for t in tasks if t.id in finished)

        def done(task: Task, verdict: Verdict) -> None:
            nonlocal count
            count += 1
            if store:
                store.add(task.id, verdict)
            if progress:
                progress(count, len(tasks), verdict)

        return run_tasks(
            tasks, workers=workers or os.cpu_count() or 1, executor=executor, finished=finished, on_result=done
        )


def verdicts(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    laws: Any = None,
    workers: int | None = 1,
    progress: Any = None,
) -> list[Verdict]:
    """Every row's verdict under a profile (``workers`` > 1 runs rows in processes; None:
    one per core); ``laws`` selects the laws (default both). A row that fails twice (its search raised,
    or its process died) raises :class:`RuntimeError` once the others are done."""
    run = run_verdicts(
        profile, properties=properties, families=families, rules=rules, laws=laws, workers=workers, progress=progress
    )
    if run.failures:
        raise RuntimeError("; ".join(f"{f.label}: {f.error}" for f in run.failures))
    return list(run.results)


def report(profile: str, found: list[Verdict]) -> dict[str, Any]:
    """The JSON of ``verify properties --json`` (contracts)."""
    return {"profile": profile, "properties": [v.record() for v in found]}


__all__ = [
    "Drawn",
    "Runner",
    "Verdict",
    "report",
    "row_tasks",
    "rows",
    "run_record",
    "run_verdicts",
    "search",
    "verdicts",
]
