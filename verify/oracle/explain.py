"""Which exact model explains an implementation's answers: ``verify oracle explain``.

Any implementation's result file (or the output of ``--impl``) is compared, case by case, with
exact models computed by :func:`verify.laws.rule.solve`:

- the paper's rule (where its run exits) and the simultaneous law;
- the sequential law over a grid: every number of sweeps of ``sweeps``, the contacts in the order
  given and reversed, every restitution threshold of ``thresholds``. One exact run per order and
  per distinct set of restituting contacts gives the velocity after each number of sweeps (the run
  with K sweeps is the first K sweeps of a longer one);
- any models the grid is given (``more``): ``verify oracle explain`` gives it, on a cradle or a corner, the
  exact models of physics engines' own step loops (DART's, Bullet's, Box2D's) with each engine's default
  settings, in each variant: the same models, named the same way, as ``verify engines`` names for the
  engines' answers.

A model **explains** a case when its velocity is within ``tolerance`` of the implementation's
(``max_i |got_i - model_i| / max_i |v_in_i|``, exact on the printed numbers and 30-digit decimals of
the models; ``1e-9`` by default, a float64 program's reach). For the file, the settings that explain
the most cases come first: they are the algorithm the implementation runs, as far as the cases
can tell settings apart (settings that explain the same cases are named together).

>>> from verify.oracle.reference import golden_cases
>>> case = golden_cases()[0]
>>> row = explain_case(case, ["0", "0", "100"], Grid(sweeps=(1, 2), thresholds=(Fraction(0),)))
>>> row.explained_by, row.distance
(["the paper's rule"], Fraction(0, 1))
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.numbers.backends.base import Backend
from verify.numbers.format import format_decimal

#: the default grid: sweeps, and restitution thresholds (speeds, in the case's units)
DEFAULT_SWEEPS = (*range(1, 21), 25, 30, 40, 50, 100)
DEFAULT_THRESHOLDS = (Fraction(0), Fraction(1, 100), Fraction(1, 10), Fraction(1, 4), Fraction(1, 2), Fraction(1),
                      Fraction(2))  # fmt: skip
#: the default tolerance of an explanation, relative to the entrance speed (a float64 program's reach)
DEFAULT_TOLERANCE = Fraction(1, 10**9)
RULE, SIMULTANEOUS = "the paper's rule", "the simultaneous law"


@dataclass(frozen=True)
class Grid:
    """The models to try: the sequential law's sweeps, thresholds and orders, and the tolerance."""

    sweeps: tuple[int, ...] = DEFAULT_SWEEPS
    thresholds: tuple[Fraction, ...] = DEFAULT_THRESHOLDS
    orders: tuple[str, ...] = ("as given", "reversed")
    tolerance: Fraction = DEFAULT_TOLERANCE
    #: more models, from the layers above (``verify oracle explain`` passes the physics engines' step models,
    #: :func:`verify.engines.explain.engine_velocities`): each maps a case to its models' velocities
    more: tuple[Callable[[dict[str, Any]], dict[Settings, list[Fraction] | None]], ...] = ()


@dataclass(frozen=True)
class Settings:
    """One model's settings, the key of the file's tally: the law, and for the sequential law its sweeps,
    order and threshold."""

    law: str
    sweeps: int | None = None
    order: str | None = None
    threshold: Fraction | None = None
    #: for ``law == "engine"``: the engine step model's label, settings and variant included
    model: str | None = None

    def label(self) -> str:
        """The model in words.

        >>> Settings("sequential", 10, "as given", Fraction(1, 2)).label()
        'the sequential law, 10 sweeps, order as given, threshold 1/2'
        """
        if self.law == "engine":
            return self.model or ""
        if self.law != "sequential":
            return RULE if self.law == "rule" else SIMULTANEOUS
        return f"the sequential law, {_plural(self.sweeps or 0)}, order {self.order}, threshold {self.threshold}"

    def flags(self) -> str:
        """The options of ``verify oracle check`` that grade against this model."""
        if self.law == "engine":
            return ""  # an engine's step model: no law of verify oracle check grades against it
        if self.law != "sequential":
            return f"--law {self.law}"
        order = " --order reversed" if self.order == "reversed" else ""
        return f"--law sequential --iterations {self.sweeps} --threshold {self.threshold}{order}"


@dataclass
class Row:
    """One case: the models that explain its answer, the nearest model and its distance."""

    case_id: str
    explained_by: list[str] = field(default_factory=list)
    settings: list[Settings] = field(default_factory=list)
    nearest: str = ""
    distance: Fraction | None = None
    note: str = ""

    def to_json(self) -> dict[str, Any]:
        return {
            "id": self.case_id,
            "explained": bool(self.settings),
            "explained_by": self.explained_by,
            "nearest_model": self.nearest,
            "distance": None if self.distance is None else format_decimal(self.distance, 3),
            "note": self.note,
        }


def _decimals(K: Backend, v: Sequence[Any]) -> list[Fraction]:
    return [Fraction(K.to_decimal(x, 30)) for x in v]


def _sequential_velocities(case: dict[str, Any], grid: Grid) -> dict[Settings, list[Fraction]]:
    """The sequential law's velocity after each number of sweeps of the grid, for each order and threshold:
    one exact run per order and per distinct set of restituting contacts."""
    from verify.laws.rule import solve
    from verify.laws.sequential import Sequential, restitution_targets
    from verify.records.results import bare_case

    c = bare_case(case)
    r = c.system.r
    out: dict[Settings, list[Fraction]] = {}
    for order_name in grid.orders:
        if order_name == "reversed" and r < 2:
            continue
        order = tuple(reversed(range(r))) if order_name == "reversed" else None
        runs: dict[tuple[bool, ...], Any] = {}
        shown: dict[tuple[tuple[bool, ...], int], list[Fraction]] = {}  # each velocity's decimals once
        for t in grid.thresholds:
            law = Sequential(max(grid.sweeps), order, t)
            system, targets = restitution_targets(c.system, c.velocity_source, law)
            key = tuple(not system.backend.known_zero(x) for x in targets)
            if key not in runs:
                runs[key] = solve(c.system, c.velocity_source, law=law)
            run = runs[key]
            K = run.backend
            for k in grid.sweeps:
                step = min(k, len(run.steps))  # a run that settles stays where it is
                if (key, step) not in shown:
                    shown[key, step] = _decimals(K, run.steps[step - 1].velocity if step else run.velocity_in)
                out[Settings("sequential", k, order_name, t)] = shown[key, step]
    return out


def model_velocities(case: dict[str, Any], grid: Grid) -> dict[Settings, list[Fraction] | None]:
    """Every model's velocity on the case (None where the model has no exit: the rule never exits or
    stops at its cap); each case's models run once per process (implementations explained on the same
    cases share them)."""
    import json

    return _model_velocities(json.dumps(case, sort_keys=True), grid)


@functools.lru_cache(maxsize=1024)
def _model_velocities(case_text: str, grid: Grid) -> dict[Settings, list[Fraction] | None]:
    import json

    from verify.laws.rule import solve
    from verify.records.results import bare_case

    case = json.loads(case_text)
    c = bare_case(case)
    out: dict[Settings, list[Fraction] | None] = {}
    for law in ("rule", "simultaneous"):
        run = solve(c.system, c.velocity_source, law=law, max_iterations=c.max_iterations, trace=False)
        out[Settings(law)] = _decimals(run.backend, run.exit_velocity) if run.stop == "exit" else None
    out.update(_sequential_velocities(case, grid))
    for models in grid.more:
        out.update(models(case))
    return out


def explain_case(case: dict[str, Any], velocity: Sequence[str], grid: Grid) -> Row:
    """One case: the models whose velocity is within the grid's tolerance of ``velocity`` (the implementation's
    numbers as strings), the nearest model and its distance."""
    from verify.records.results import read_number

    row = Row(case["id"])
    try:
        got = [read_number(str(x), f"results[{case['id']}].exit_velocity[{i}]") for i, x in enumerate(velocity)]
    except ValueError as exc:
        row.note = f"a number of the answer cannot be read ({exc})"
        return row
    if len(got) != len(case["velocity"]):
        row.note = f"expected {len(case['velocity'])} components, got {len(got)}"
        return row
    scale = max(abs(read_number(x)) for x in case["velocity"]) or Fraction(1)
    scored = []
    for settings, v in model_velocities(case, grid).items():
        if v is not None:
            scored.append((max(abs(a - b) for a, b in zip(got, v)) / scale, settings))
    row.settings = [s for d, s in scored if d <= grid.tolerance]
    row.explained_by = describe_settings(row.settings)
    d, nearest = min(scored, key=lambda t: t[0])
    row.nearest, row.distance = nearest.label(), d
    if not row.settings and Settings("rule") not in {s for _, s in scored}:
        row.note = "the paper's rule does not exit on this case"
    return row


def describe_settings(settings: Sequence[Settings]) -> list[str]:
    """The models in words, the sequential law's grid points grouped: per order, the thresholds that explain
    with the same sweeps.

    >>> one = Fraction(1)
    >>> describe_settings([Settings("sequential", k, "as given", t) for k in (9, 10) for t in (Fraction(0), one)])
    ['the sequential law, 9-10 sweeps, order as given, threshold 0 or 1']
    """
    out = [s.label() for s in settings if s.law != "sequential"]
    sweeps: dict[tuple[str | None, Fraction | None], list[int]] = {}
    for s in settings:
        if s.law == "sequential":
            sweeps.setdefault((s.order, s.threshold), []).append(s.sweeps or 0)
    merged: dict[tuple[str | None, tuple[int, ...]], list[str]] = {}
    for (order, t), counts in sweeps.items():
        merged.setdefault((order, tuple(sorted(counts))), []).append(str(t))
    for (order, ks), ts in merged.items():
        many = "sweep" if ks == (1,) else "sweeps"
        out.append(f"the sequential law, {_ranges(list(ks))} {many}, order {order}, threshold {' or '.join(ts)}")
    return out


def _plural(k: int) -> str:
    return f"{k} sweep" + ("" if k == 1 else "s")


def _ranges(ks: list[int]) -> str:
    """Integers as runs: ``1-3, 5``.

    >>> _ranges([1, 2, 3, 5, 10, 11])
    '1-3, 5, 10-11'
    """
    parts: list[str] = []
    start: int = ks[0]
    for a, b in zip(ks, [*ks[1:], None]):
        if b != a + 1:
            parts.append(str(start) if start == a else f"{start}-{a}")
            start = b if b is not None else a
    return ", ".join(parts)


@dataclass
class Explanation:
    """The explanation of a result file: a row per case, and the settings ranked by the cases they explain."""

    rows: list[Row]
    ranking: list[tuple[int, list[Settings]]]  # (cases explained, the settings that explain exactly those)
    tolerance: Fraction
    #: the cases that carry their own law_settings (the grid replaces them)
    own_settings: list[str] = field(default_factory=list)

    @property
    def best(self) -> list[Settings]:
        return self.ranking[0][1] if self.ranking else []

    def to_json(self) -> dict[str, Any]:
        return {
            "tolerance": format_decimal(self.tolerance, 3),
            "cases": len(self.rows),
            "explained": sum(bool(r.settings) for r in self.rows),
            "own_law_settings": self.own_settings,
            "best": [
                {"explains": n, "settings": [s.label() for s in group], "flags": [s.flags() for s in group]}
                for n, group in self.ranking[:5]
            ],
            "rows": [r.to_json() for r in self.rows],
        }


def explain(cases: list[dict[str, Any]], results: list[dict[str, Any]], grid: Grid = Grid()) -> Explanation:
    """Each case's explanation, and the settings that explain the most cases (those explaining the same
    cases grouped; the implementation's results matched to the cases by id, a case without one left out).

    >>> from verify.oracle.reference import golden_cases
    >>> cases = golden_cases()[:2]
    >>> e = explain(cases, [{"id": c["id"], "exit_velocity": ["0", "0", "100"]} for c in cases],
    ...             Grid(sweeps=(1,), thresholds=(Fraction(0),)))
    >>> [r.explained_by for r in e.rows][0][0], e.ranking[0][0]
    ("the paper's rule", 1)
    """
    by_id = {r["id"]: r for r in results}
    rows = [explain_case(c, by_id[c["id"]]["exit_velocity"], grid) for c in cases if c["id"] in by_id]
    explained: dict[Settings, frozenset[str]] = {}
    for row in rows:
        for s in row.settings:
            explained[s] = explained.get(s, frozenset()) | {row.case_id}
    same: dict[frozenset[str], list[Settings]] = {}
    for s, ids in explained.items():
        same.setdefault(ids, []).append(s)
    ranking = sorted(((len(ids), group) for ids, group in same.items()), key=lambda t: (-t[0], _order(t[1][0])))
    own = [c["id"] for c in cases if c.get("law_settings") and c["id"] in by_id]
    return Explanation(rows, ranking, grid.tolerance, own)


def _order(s: Settings) -> tuple[int, int, str, Fraction]:
    """Ties broken for reading: the rule, the simultaneous law, then the fewest sweeps, order given first."""
    rank = {"rule": 0, "simultaneous": 1, "engine": 3}.get(s.law, 2)
    return rank, s.sweeps or 0, s.order or "", s.threshold or Fraction(0)
