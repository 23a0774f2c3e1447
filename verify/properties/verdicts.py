"""Verdicts: each property x law x rule x family proved, holding on N cases, or refuted.

The law is the paper's iterative rule (``rule``) or the simultaneous law (``simultaneous``,
:mod:`verify.laws.simultaneous`); the rule column is then the COR variant (the general rule's
own CORs, the symmetric rule's equal ones, the ideal rule's 1), see :data:`LAW_RULES`.

For every row, Hypothesis searches for a counterexample (``hypothesis.find``, derandomised:
the same verdicts on every run): ``holds`` with the number of cases where the property
applied, none failing, or ``refuted`` with the shrunk, exact counterexample (a case
record of the contracts, which ``verify solve --rule R`` reproduces, with ``--law simultaneous``
for the law's rows) and what fails. Where
SymPy proves the property (:mod:`verify.properties.proofs`) the verdict is ``proved``, and the search
still runs: it tests that the implementation agrees with the proof (a counterexample then
means the code is wrong, and the verdict is ``refuted``).

Every run has a size budget (:data:`BUDGET`) and the record's ``max_iterations`` (200, or the
property's own: 4000 for termination), so that a search never hangs on cases whose exact numbers
explode; such runs are counted in the note. Profiles: ``dev`` (25 cases a row), ``ci`` (100),
``thorough`` (100,000 cases per property and law, shared evenly between its rows).

>>> v = search(property_named("the exit velocity is outgoing"), "corner", "ideal", 10)
>>> v.verdict, v.cases > 0
('holds', True)
>>> v = search(property_named("the exit velocity is outgoing"), "corner", "ideal", 10, law="simultaneous")
>>> v.law, v.verdict
('simultaneous', 'holds')
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import random
import secrets
import sys
import threading
import warnings
from collections import Counter, OrderedDict
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import Any, Literal

from verify.laws.rule import LAWS, Budget, RuleName, law_name
from verify.laws.sequential import Law, Sequential
from verify.properties.catalogue import PROPERTIES, SKIP, UNDECIDED_STOPS, Answer, Property, property_named
from verify.properties.profiles import PER_PROPERTY, PROFILES
from verify.properties.proofs import PROOFS, prove
from verify.properties.strategies import FAMILIES, MAX_ITERATIONS, RULES, Drawn, capped, cases
from verify.runner.tasks import Task, TaskRun, TaskRunner, TasksFailed

#: the size budget of a run of the verdicts (bits of its exact numbers; :mod:`verify.bounds`)
CENSUS_BITS = 4096
BUDGET = Budget(bits=CENSUS_BITS)
#: the digits of the certified intervals on which the census decides a run past CENSUS_BITS. Its long runs lose
#: about a digit per impulse (the dependency problem of component-wise intervals), so the precision follows the
#: termination property's cap of 4000 impulses (``LONG_RUNS``) with room to spare
CENSUS_DIGITS = 6400
DECIDING_BUDGET = Budget(bits=CENSUS_BITS, intervals=True, interval_dps=CENSUS_DIGITS)
INTERVAL_DPS, INTERVAL_MAX_DPS, MP_DPS = 30, 120, 30
#: the COR variants each law is checked with: every rule for the rule; for the simultaneous law
#: the general, symmetric and ideal CORs (the asymmetric rule's cases are general ones with r = 2)
LAW_RULES = {
    "rule": RULES,
    "simultaneous": tuple(r for r in RULES if r != "asymmetric"),
    "sequential": tuple(r for r in RULES if r != "asymmetric"),
}


class TableShare:
    """What the rows of one verdict table share in a process: the runs of case records (a case drawn for one
    property is run again by the next ones, under the same law), and the cases each strategy drew for a row
    that held.

    Hypothesis, derandomised, draws the same cases for every row with the same strategy (family, rule, cap,
    what the property draws besides) and number of cases, up to the first failure: the draws depend on the
    choices made, never on a check that passes. So a row whose strategy has already been drawn in full (for a
    row that held) checks those cases again without drawing them; when one of them fails, the row is searched
    by Hypothesis as usual, which draws the same cases, fails at the same one and shrinks it. The verdicts are
    those of rows searched one by one (``tests/properties/test_properties.py`` compares both).

    One share belongs to one table (:func:`row_tasks` gives its rows a token): a process (a thread) keeps the share
    of the last table whose rows it ran, and drops it for the next table's (:func:`share_for`)."""

    #: the most runs kept (the least recently used go first)
    RUNS = 2048
    #: the most strategies whose cases are kept
    STRATEGIES = 128

    def __init__(self, token: str) -> None:
        self.token = token
        self.runs: OrderedDict[str, Any] = OrderedDict()
        self.drawn: OrderedDict[tuple[Any, ...], list[Any]] = OrderedDict()

    def run(self, key: str, compute: Any) -> Any:
        """The run of ``key``, computed once."""
        found = self.runs.get(key)
        if found is None:
            found = self.runs[key] = compute()
            if len(self.runs) > self.RUNS:
                self.runs.popitem(last=False)
        else:
            self.runs.move_to_end(key)
        return found

    def keep_drawn(self, key: tuple[Any, ...], items: list[Any]) -> None:
        """The cases a strategy drew in full (for a row that held)."""
        self.drawn[key] = items
        if len(self.drawn) > self.STRATEGIES:
            self.drawn.popitem(last=False)


#: the share of the table whose rows this thread is running (one at a time; a Dask worker may run rows in
#: several threads, each with its own share)
_SHARE = threading.local()


def share_for(token: str | None) -> TableShare | None:
    """The share of the table with this token in this thread (a new one when the token is new), or None."""
    if token is None:
        return None
    current = getattr(_SHARE, "share", None)
    if current is None or current.token != token:
        current = _SHARE.share = TableShare(token)
    return current


class Runner:
    """Runs case records on the engine under one law (``rule`` by default), memoised (a property
    compares several runs). A check may ask another law's run with ``law=``.

    ``cap``, when set, lowers the records' ``max_iterations`` to it (the search sets it while it shrinks a
    failure); ``deepest`` is the most impulses of a run it returned since it was last set to 0. ``undecided``
    holds the case records whose runs a census left undecided (:meth:`keep`), by stop."""

    def __init__(self, law: Law = "rule", share: TableShare | None = None) -> None:
        self.law = law
        self.share = share
        self.memo: dict[str, Any] = {}
        self.counts: Counter[str] = Counter()
        self.cap: int | None = None
        self.deepest = 0
        self.undecided: dict[str, list[dict[str, Any]]] = {}

    def count(self, what: str) -> None:
        self.counts[what] += 1

    def keep(self, stop: str, record: dict[str, Any]) -> None:
        """Keep a case whose run ended with ``stop`` undecided (once, however often it was drawn)."""
        _keep(self.undecided, stop, record)

    def __call__(
        self, record: dict[str, Any], rule: str, backend: str = "exact", *, law: Law | None = None, decide: bool = False
    ) -> Any:
        law = self.law if law is None else law
        if law == Sequential.name:  # a check asking for the sequential law by name: this runner's settings
            law = self.law if isinstance(self.law, Sequential) else law
        if self.cap is not None and record["max_iterations"] > self.cap:
            record = dict(record, max_iterations=self.cap)
        key = json.dumps([record, rule, backend, str(law), decide], sort_keys=True)
        if key not in self.memo:
            if len(self.memo) > 512:
                self.memo.clear()
            if self.share is not None:
                self.memo[key] = self.share.run(key, lambda: run_record(record, rule, backend, law=law, decide=decide))
            else:
                self.memo[key] = run_record(record, rule, backend, law=law, decide=decide)
        result = self.memo[key]
        self.deepest = max(self.deepest, result.iterations)
        return result


def run_record(
    record: dict[str, Any], rule: str, backend: str = "exact", *, law: Law = "rule", decide: bool = False
) -> Any:
    """Solve one case record with the rule (or, with ``law="simultaneous"``, the simultaneous law
    with the rule's CORs), the suite's budget and backend settings. With ``decide``, an exact run that
    passes the size budget is run again on certified intervals (:attr:`verify.laws.rule.Budget.intervals`)."""
    from verify.dynamics.system import System
    from verify.laws.rule import solve
    from verify.numbers.backends import IntervalBackend, get_backend

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
        budget=DECIDING_BUDGET if decide else BUDGET,
        trace=True,
    )


#: a row's verdict: a SymPy identity (the drawn cases still test the code), every drawn case passed, or a case
#: refuted it (its shrunk counterexample with it)
VerdictName = Literal["proved", "holds", "refuted"]


@dataclass
class Verdict:
    """One row of the verdict table (its :meth:`record` is the JSON of the contracts)."""

    property: str
    rule: str
    family: str
    verdict: VerdictName
    cases: int
    counterexample: dict[str, Any] | None = None
    note: str = ""
    extra: Any = field(default=None, repr=False)
    law: str = "rule"  #: ``rule`` or ``simultaneous``; ``rule`` is then the COR variant
    #: how the search went: cases ``drawn``, those where the property ``applied`` and those ``skipped``
    #: (up to the counterexample for a refuted row); what the checks counted (``counts``: how runs end,
    #: over every case of the row, a census row's census included); the note before its census sentence
    tally: dict[str, int] = field(default_factory=dict, repr=False)
    counts: dict[str, int] = field(default_factory=dict, repr=False)
    detail: str = field(default="", repr=False)
    #: a census row's cases left undecided, by stop (``max_iterations``, ``budget``): case records
    undecided: dict[str, list[dict[str, Any]]] = field(default_factory=dict, repr=False)

    def record(self) -> dict[str, Any]:
        """The row as JSON (contracts); a census row (termination) also has its ``census``."""
        out = {
            "property": self.property,
            "law": self.law,
            "rule": self.rule,
            "family": self.family,
            "verdict": self.verdict,
            "cases": self.cases,
            "counterexample": self.counterexample,
            "note": self.note,
        }
        census = self.census()
        if census is not None:
            out["census"] = census
            out["undecided"] = self.undecided_cases()
        return out

    def undecided_cases(self) -> dict[str, list[dict[str, Any]]]:
        """A census row's distinct cases left undecided, by stop, as case records named after the row (the
        cases of a ``verify solve --rule RULE`` case file); every stop of :data:`UNDECIDED_STOPS` is shown.

        >>> v = Verdict("the rule exits (termination)", "general", "cradle", "holds", 2,
        ...             undecided={"budget": [{"id": "x", "velocity": ["1"]}]})
        >>> v.undecided_cases()
        {'max_iterations': [], 'budget': [{'id': 'cradle-general-budget-1', 'velocity': ['1']}]}
        """
        out: dict[str, list[dict[str, Any]]] = {}
        for stop in UNDECIDED_STOPS:
            kept = self.undecided.get(stop, [])
            out[stop] = [dict(r, id=f"{self.family}-{self.rule}-{stop}-{k}") for k, r in enumerate(kept, 1)]
        return out

    def census(self) -> dict[str, int] | None:
        """How the runs of a census row (termination) end, over its ``cases`` cases: the count of each stop,
        ``exit``, ``non_terminating``, ``max_iterations`` and ``budget`` always (others if any ended so);
        None for the other rows. A holding row counts the runs of its search, a refuted one those of its
        census (the search stops at the counterexample).

        >>> Verdict("the rule exits (termination)", "ideal", "corner", "holds", 2,
        ...         counts={"stop exit": 2}).census()
        {'exit': 2, 'non_terminating': 0, 'max_iterations': 0, 'budget': 0}
        """
        if not any(p.census and p.name == self.property for p in PROPERTIES):
            return None
        ends = dict.fromkeys(CENSUS_STOPS, 0)
        for key, n in sorted(self.counts.items()):
            if key.startswith("stop "):
                ends[key[len("stop ") :]] = n
        return ends


#: the stops a census always shows (a run ends in one of them, or is undecided on a backend that cannot tell)
CENSUS_STOPS = ("exit", "non_terminating", "max_iterations", "budget")


def rows(
    properties: Any = None, families: Any = None, rules: Any = None, laws: Any = None
) -> list[tuple[Property, str, RuleName, Law]]:
    """The (property, family, rule, law) rows, in a fixed order: a property's rows for the
    simultaneous and the sequential law right after its row for the rule (same rule variant and family).
    ``laws`` holds names of laws, or the sequential law's settings (a ``Sequential``: its rows run with them).

    >>> [(f, r, str(law)) for p, f, r, law in rows(["the exit velocity"], ["cradle"], ["ideal", "asymmetric"])]
    [('cradle', 'ideal', 'rule'), ('cradle', 'ideal', 'simultaneous'), ('cradle', 'ideal', 'sequential'), \
('cradle', 'asymmetric', 'rule')]
    >>> [str(law) for *_, law in rows(["the exit velocity"], ["cradle"], ["ideal"], [Sequential(iterations=2)])]
    ['sequential (iterations 2)']
    """
    chosen = [property_named(p) for p in properties] if properties else list(PROPERTIES)
    wanted: dict[str, Law] = {law_name(x): x for x in laws or ()}  # a name, or the sequential law's settings
    out = []
    for prop in chosen:
        for rule in RULES:
            if rule not in prop.rules or (rules and rule not in rules):
                continue
            for family in FAMILIES:
                if family not in prop.families or (families and family not in families):
                    continue
                for law in LAWS:
                    if law in prop.laws and rule in LAW_RULES[law] and (not laws or law in wanted):
                        out.append((prop, family, rule, wanted.get(law, law)))
    return out


def _check(prop: Property, runner: Runner, item: Any) -> Answer:
    d, extra = item if prop.extra is not None else (item, None)
    try:
        return prop.check(runner, d, extra)
    except Exception as exc:  # a valid case must not make the engine raise: that is a finding
        return f"the engine raised {type(exc).__name__}: {' '.join(str(exc).split())}"


def search(
    prop: Property,
    family: str,
    rule: str,
    examples: int,
    *,
    law: Law = "rule",
    seed: int | None = None,
    strategy: Any = None,
    share: TableShare | None = None,
) -> Verdict:
    """Search one row for a counterexample with ``examples`` cases (the law's runs). Hypothesis is
    derandomised (the same cases on every run), or seeded with ``seed`` (another chunk of a split row's
    cases, :func:`merge_chunks`). The cases are the family's, or those of ``strategy`` (of
    :class:`~verify.properties.strategies.Drawn` cases: :mod:`verify.properties.own`). With a
    ``share`` (:class:`TableShare`), the row shares runs and drawn cases with the other rows of its table."""
    from hypothesis import HealthCheck, Phase, find, settings
    from hypothesis import strategies as st
    from hypothesis.errors import NoSuchExample, Unsatisfiable

    # the cases this row's strategy draws, when another row of the table has drawn them all
    key = (family, rule, examples, seed, prop.max_iterations, prop.name if prop.extra is not None else None)
    shared = share if share is not None and strategy is None else None
    drawn = shared.drawn.get(key) if shared is not None else None
    strategy = cases(family, rule) if strategy is None else strategy
    if prop.max_iterations is not None:
        strategy = capped(strategy, prop.max_iterations)
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
    row = (family, rule, law)
    proof = _proof(prop, rule, law)
    probe = _Probe(prop, law, share, record=shared is not None and drawn is None)
    if drawn is not None:
        if not any(probe(item) for item in drawn):
            return probe.holds(row, proof)
        # a shared case fails: Hypothesis searches the row afresh (the same cases, up to this one), and shrinks it
        probe = _Probe(prop, law, share)
    try:
        item = find(strategy, probe, settings=config, random=None if seed is None else random.Random(seed))
    except NoSuchExample:
        if shared is not None and probe.recorded is not None:
            shared.keep_drawn(key, probe.recorded)
        return probe.holds(row, proof)
    except Unsatisfiable:
        return probe.holds(row, proof)
    found = _refuted(prop, row, item, probe, proof)
    if prop.census:
        counts, found.undecided = _census(prop, strategy, examples, law, seed, share=share)
        found.counts = dict(counts)
        found.cases, found.note = _census_note(found.detail, found.counts)
    return found


class _Probe:
    """A row's check of one drawn case, as Hypothesis (or a replay of a table's shared cases) calls it: True when
    the case fails. It counts the cases drawn, applied and skipped until the first failure (the shrinking that
    follows is not counted), and with ``record`` keeps the cases it is given."""

    def __init__(self, prop: Property, law: Law, share: TableShare | None, *, record: bool = False) -> None:
        self.prop, self.runner = prop, Runner(law, share)
        self.tally: Counter[str] = Counter()
        self.shrinking = False
        self.recorded: list[Any] | None = [] if record else None

    def __call__(self, item: Any) -> bool:
        runner, prop = self.runner, self.prop
        if self.recorded is not None and not self.shrinking:
            self.recorded.append(item)
        runner.deepest = 0
        why = _check(prop, runner, item)
        if not self.shrinking:
            self.tally["drawn"] += 1
            self.tally["skipped" if why == SKIP else "applied"] += 1
        if why is None or why == SKIP:
            return False
        if not self.shrinking and prop.max_iterations is not None:
            # a property's long runs are not repeated for every smaller candidate: those run no longer than
            # the failure found (which fails again so: a run is the same up to its cap), or the usual cap
            runner.cap = max(MAX_ITERATIONS, runner.deepest)
        self.shrinking = True
        return True

    def holds(self, row: tuple[str, str, Law], proof: str | None) -> Verdict:
        """The row's verdict when no case failed."""
        runner = self.runner
        return _holds(self.prop, row, dict(self.tally), dict(runner.counts), proof, undecided=runner.undecided)


def _refuted(prop: Property, row: tuple[str, str, Law], item: Any, probe: _Probe, proof: str | None) -> Verdict:
    """The verdict of a row whose search found ``item`` (shrunk), with what fails and how to reproduce it."""
    family, rule, law = row
    d, extra = item if prop.extra is not None else (item, None)
    answer = _check(prop, Runner(law, probe.runner.share), item)
    why = answer if isinstance(answer, str) else ""  # the shrunk case fails again: a sentence
    note = why + (f" (with {_describe(extra)})" if extra is not None else "")
    explain = prop.statement(law_name(law))[1]
    if proof:
        note = f"contradicts the proof ({proof}): the implementation is wrong: " + note
    elif explain:
        where = prove(explain, rule) if explain in PROOFS else explain
        note += f". Where it fails: {where}" if where else ""
    name = law_name(law)
    law_part = "" if name == "rule" else f"{name}-"
    record = dict(d.record, id=f"{family}-{rule}-{law_part}{_slug(prop.name)}")
    flags = "" if name == "rule" else " " + (law.flags() if isinstance(law, Sequential) else f"--law {name}")
    note += f"; reproduce with: verify solve CASE.json --rule {rule}{flags}"
    tally = probe.tally
    found = Verdict(prop.name, rule, family, "refuted", tally["applied"], record, note, extra, name, dict(tally))
    found.detail = note
    return found


def _proof(prop: Property, rule: str, law: Law) -> str | None:
    """What SymPy proves of the row (``prop`` under ``law`` and ``rule``), or None."""
    proof_name = prop.statement(law_name(law))[0]
    return prove(proof_name, rule) if proof_name else None


def _census_note(detail: str, counts: dict[str, int]) -> tuple[int, str]:
    """A census row's cases and note: the census' count of cases, and its sentence after ``detail``."""
    tried = counts.get(CENSUS_CASES, 0)
    ends = ", ".join(f"{k}: {v}" for k, v in sorted(counts.items()) if k != CENSUS_CASES)
    return tried, f"{detail}; a separate census of {tried} cases ends: {ends}"


#: the key of a census' count of cases in :attr:`Verdict.counts`
CENSUS_CASES = "cases"


def _census(
    prop: Property, strategy: Any, examples: int, law: Law, seed: int | None = None, *, share: TableShare | None = None
) -> tuple[Counter[str], dict[str, list[dict[str, Any]]]]:
    """How the runs of a refuted row end, over all its cases (the search stops at the first failure),
    with the number of cases under :data:`CENSUS_CASES`; and the cases it left undecided (:attr:`Runner.undecided`)."""
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as seeded

    runner = Runner(law, share)
    seen = 0

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
        nonlocal seen
        seen += 1
        _check(prop, runner, item)

    seeded(CENSUS_SEED if seed is None else seed)(count)()
    return Counter({**runner.counts, CENSUS_CASES: seen}), runner.undecided


#: the seed of an unsplit row's census. Derandomised, Hypothesis would seed it from a digest of the source
#: lines of ``count`` above, read from the file when it runs: any edit above them (or of the file while a
#: long run goes on) would draw other cases
CENSUS_SEED = 0


def _holds(
    prop: Property,
    row: tuple[str, str, Law],
    tally: dict[str, int],
    counts: dict[str, int],
    proof: str | None,
    *,
    undecided: dict[str, list[dict[str, Any]]] | None = None,
) -> Verdict:
    family, rule, law = row[0], row[1], law_name(row[2])
    parts = [f"no counterexample in {tally.get('applied', 0)} cases"]
    if tally.get("skipped"):
        parts.append(f"{tally['skipped']} of {tally['drawn']} drawn cases did not apply")
    parts += [f"{k}: {v}" for k, v in sorted(counts.items())]
    verdict: VerdictName = "proved" if proof else "holds"
    note = proof + "; " + "; ".join(parts) if proof else "; ".join(parts)
    return Verdict(prop.name, rule, family, verdict, tally.get("applied", 0), None, note, law=law, tally=tally,
                   counts=counts, undecided=dict(undecided or {}))  # fmt: skip


def merge_chunks(parts: list[Verdict]) -> Verdict:
    """One row's verdict from the verdicts of its chunks (in chunk order; each searched its own seeded
    cases): the first refuting chunk's counterexample, with the cases checked up to it (and a census
    row's census over every chunk); else the row holds (or is proved) on the cases of every chunk.

    >>> p = "the exit velocity is outgoing"
    >>> a = Verdict(p, "ideal", "corner", "holds", 3, tally={"drawn": 3, "applied": 3}, counts={"stop exit": 3})
    >>> b = Verdict(p, "ideal", "corner", "holds", 2, tally={"drawn": 4, "applied": 2, "skipped": 2},
    ...             counts={"stop exit": 4})
    >>> merge_chunks([a, b]).note
    'no counterexample in 5 cases; 2 of 7 drawn cases did not apply; stop exit: 7'
    """
    if len(parts) == 1:
        return parts[0]
    first = parts[0]
    prop = property_named(first.property)
    refuted = next((i for i, v in enumerate(parts) if v.verdict == "refuted"), None)
    if refuted is None:
        tally = sum((Counter(v.tally) for v in parts), Counter())
        counts = sum((Counter(v.counts) for v in parts), Counter())
        proof, row = _proof(prop, first.rule, first.law), (first.family, first.rule, first.law)
        return _holds(prop, row, dict(tally), dict(counts), proof, undecided=_undecided(parts))
    found = dataclasses.replace(parts[refuted])
    found.cases = sum(v.tally.get("applied", 0) for v in parts[: refuted + 1])
    if prop.census:  # every chunk's census: a holding chunk counted its runs while searching
        counts = Counter[str]()
        for v in parts:
            counts += Counter(v.counts if v.verdict == "refuted" else {**v.counts, CENSUS_CASES: v.tally["drawn"]})
        found.counts = dict(counts)
        found.undecided = _undecided(parts)
        found.cases, found.note = _census_note(found.detail, found.counts)
    return found


def _keep(undecided: dict[str, list[dict[str, Any]]], stop: str, record: dict[str, Any]) -> None:
    """Add ``record`` to the cases of ``stop`` in ``undecided``, unless it is there already."""
    kept = undecided.setdefault(stop, [])
    if record not in kept:
        kept.append(record)


def _undecided(parts: list[Verdict]) -> dict[str, list[dict[str, Any]]]:
    """The undecided cases of a row's chunks, in chunk order (each once)."""
    out: dict[str, list[dict[str, Any]]] = {}
    for v in parts:
        for stop, records in v.undecided.items():
            for record in records:
                _keep(out, stop, record)
    return out


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


#: the most cases one task searches: a row with more (the thorough profile) is split into chunks of its
#: cases, each searched on its own with its own seed, so that the work balances over many workers
CHUNK = 2000


def _run_row(args: tuple[Any, ...]) -> Verdict:
    """One row's task: (property, family, rule, cases, law[, seed[, token]]); the token of its table's share."""
    name, family, rule, examples, law, *rest = args
    seed, token = [*rest, None, None][:2]
    with warnings.catch_warnings():
        if _in_dask_worker():
            # Hypothesis warns when the global random state changes while a case is drawn; in a Dask worker
            # the worker's own threads use the random module meanwhile (our strategies do not: in one process
            # the warning is an error of the test suite). The cases come from Hypothesis' own generator.
            warnings.filterwarnings("ignore", message="Do not use the `random` module inside strategies")
        return search(property_named(name), family, rule, examples, law=law, seed=seed, share=share_for(token))


def _in_dask_worker() -> bool:
    """Whether this runs in a task of a Dask worker."""
    if "distributed" not in sys.modules:
        return False
    from dask.distributed import get_worker

    try:
        get_worker()
    except ValueError:  # no worker here
        return False
    return True


def _chunk_seed(task_id: str) -> int:
    """The seed of a chunk: from its id (the row, its cases and the chunk's number), the same on every run."""
    return int.from_bytes(hashlib.sha256(task_id.encode()).digest()[:8], "big")


def row_tasks(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    laws: Any = None,
    chunk: int = CHUNK,
) -> list[Task]:
    """The tasks of each row, with stable ids: the row and its number of cases; a row of more than
    ``chunk`` cases (:data:`CHUNK`) is split into chunks (ids ending ``chunk j/n``): the first chunk derandomised as
    an unsplit row is, each other one seeded from its id. :func:`merge_chunks` makes the row's verdict.

    >>> for task in row_tasks("dev", properties=["the exit velocity"], families=["cradle"], rules=["ideal"]):
    ...     print(task.id)
    the exit velocity is outgoing | rule | ideal | cradle | 25
    the exit velocity is outgoing | simultaneous | ideal | cradle | 25
    the exit velocity is outgoing | sequential | ideal | cradle | 25
    >>> [t.id.split(" | ", 4)[-1] for t in row_tasks("thorough", properties=["the exit velocity"])][:2]
    ['8334 | chunk 1/5', '8334 | chunk 2/5']
    """
    table = rows(properties, families, rules, laws)
    per_prop = Counter((p.name, law) for p, _, _, law in table)
    token = secrets.token_hex(8)  # the table's share (:class:`TableShare`): its rows, and none of another table
    out = []
    for p, f, r, law in table:
        examples = examples_per_row(profile, per_prop[p.name, law])
        label = f"{p.name} | {law} | {r} | {f}"
        n = math.ceil(examples / chunk)
        if n == 1:
            out.append(Task(f"{label} | {examples}", _run_row, (p.name, f, r, examples, law, None, token), label))
            continue
        for j in range(n):
            size = examples // n + (1 if j < examples % n else 0)
            task_id = f"{label} | {examples} | chunk {j + 1}/{n}"
            seed = None if j == 0 else _chunk_seed(task_id)
            payload = (p.name, f, r, size, law, seed, token)
            out.append(Task(task_id, _run_row, payload, f"{label} (chunk {j + 1}/{n})"))
    return out


def _rows_of(tasks: list[Task], run: TaskRun) -> TaskRun:
    """The verdict of each row (its chunks merged, None if one of them failed) from a run of its tasks."""
    groups: dict[str, list[int]] = {}
    for i, task in enumerate(tasks):
        groups.setdefault(task.id.split(" | chunk ")[0], []).append(i)
    failed = {f.id for f in run.failures}
    results = [
        None if any(tasks[i].id in failed for i in chunk) else merge_chunks([run.results[i] for i in chunk])
        for chunk in groups.values()
    ]
    return TaskRun(results, run.failures)


def checkpoint_options(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    laws: Any = None,
    chunk: int = CHUNK,
) -> dict[str, Any]:
    """The options that change a run's results, as a checkpoint's header keeps them (not how it runs).

    >>> checkpoint_options("dev", properties=["kinetic energy"])
    {'profile': 'dev', 'property': ['kinetic energy'], 'family': None, 'rule': None, 'law': None, 'chunk': 2000}
    """
    chosen_laws = [str(x) for x in laws] if laws else laws
    return {
        "profile": profile,
        "property": properties,
        "family": families,
        "rule": rules,
        "law": chosen_laws,
        "chunk": chunk,
    }


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
    runner: TaskRunner | None = None,
    chunk: int = CHUNK,
) -> TaskRun:
    """Every row's verdict as a :class:`verify.runner.tasks.TaskRun`: the verdicts in row order (None for a
    row whose task failed twice) and the failures. ``executor`` runs the rows (a Dask cluster:
    ``Client(...).get_executor()``), else ``workers`` local processes (None: one per core). With
    ``checkpoint`` (a file name) rows finished by an earlier run with the same options are read from it
    and each row finished now is appended. ``progress(done, total, verdict)`` is called as tasks finish
    (a row, or a chunk of one).
    ``runner`` (a :class:`verify.runner.tasks.TaskRunner`, e.g. shared with other stages of ``verify all``)
    replaces ``workers``, ``executor`` and ``checkpoint``. Rows of more than ``chunk`` cases are split
    (:func:`row_tasks`).
    """
    chosen = {"properties": properties, "families": families, "rules": rules, "laws": laws, "chunk": chunk}
    tasks = row_tasks(profile, **chosen)
    options = checkpoint_options(profile, **chosen)
    with contextlib.ExitStack() as stack:
        if runner is None:
            runner = stack.enter_context(
                TaskRunner(workers=workers, executor=executor, checkpoint=checkpoint, options=options)
            )
        shown = (lambda done, total, task, verdict: progress(done, total, verdict)) if progress else None
        return _rows_of(tasks, runner.run(tasks, progress=shown))


def verdicts(
    profile: str = "ci",
    *,
    properties: Any = None,
    families: Any = None,
    rules: Any = None,
    laws: Any = None,
    workers: int | None = 1,
    progress: Any = None,
    runner: TaskRunner | None = None,
) -> list[Verdict]:
    """Every row's verdict under a profile (``workers`` > 1 runs rows in processes; None:
    one per core; ``runner`` as for :func:`run_verdicts`); ``laws`` selects the laws (default both). A row
    that fails twice (its search raised, or its process died) raises :class:`verify.runner.tasks.TasksFailed`
    once the others are done."""
    chosen = {"properties": properties, "families": families, "rules": rules, "laws": laws}
    run = run_verdicts(profile, **chosen, workers=workers, progress=progress, runner=runner)
    if run.failures:
        raise TasksFailed(run.failures)
    return list(run.results)


def verdict_counts(found: Sequence[Any]) -> dict[str, int]:
    """How many rows are proved, hold and are refuted (the counts the texts and pages print).

    >>> from types import SimpleNamespace as Row
    >>> verdict_counts([Row(verdict="holds"), Row(verdict="refuted"), Row(verdict="holds")])
    {'proved': 0, 'holds': 2, 'refuted': 1}
    """
    return {k: sum(v.verdict == k for v in found) for k in ("proved", "holds", "refuted")}


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
    "verdict_counts",
    "verdicts",
]
