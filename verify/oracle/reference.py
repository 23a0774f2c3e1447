"""The reference oracle: a golden dataset, and a checker for other implementations.

:func:`golden_cases` builds the dataset deterministically (no randomness but a seeded
``random.Random``): the paper's cases, cradles with several balls and unequal masses,
corners at rational and algebraic angles, random general systems with multiple impacts,
r >= 3 constraints, moving constraints, grazing velocities (p(F_i) = 0), CORs of 0 and 1,
and cases proved never to exit. :func:`export` writes it with its exact results
(``verify oracle export DIR``); regenerating gives the same bytes.

:func:`compare` checks another implementation's result file against the exact results:
the stop reason, the iteration count, the impact sets, the betas, and the exit velocity within
``atol + rtol * |v_exit|`` (max norm of the exact exit velocity; a component that is exactly 0 also
within ``atol + floor * |v_in|``); every mismatch is listed.

>>> [c["id"] for c in golden_cases()][:2]
['paper-table1-eps-1', 'paper-table1-eps-0.99']
"""

from __future__ import annotations

import collections
import copy
import functools
import json
import os
import random
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput
from verify.laws.sequential import Law, Sequential, law_for_case
from verify.models.corner import corner_geometry
from verify.models.cradle import cradle_geometry
from verify.models.rates import velocity_with_rates
from verify.numbers.format import counted
from verify.oracle.grading import DEFAULT_FLOOR, DEFAULT_RTOL, PASSING, Tolerance, impact_sets_of
from verify.records.results import case_from_record, case_record, dumps, read_number, result_record, with_decimals
from verify.records.versions import GOLDEN_DATASET, GOLDEN_VERSION, check_same_dataset, check_versions, stamped

SEED = 2021
#: the iteration cap of every golden case
GOLDEN_MAX_ITERATIONS = 10_000


def _cradle(case_id: str, eps: list[Any], velocity: list[Any], masses: list[Any] | None = None) -> dict[Any, Any]:
    g, normals = cradle_geometry(masses or [1] * len(velocity))
    return case_record(case_id, g, normals, eps, velocity, max_iterations=GOLDEN_MAX_ITERATIONS)


def _corner(case_id: str, slope: Any, eps: list[Any], velocity: list[Any]) -> dict[Any, Any]:
    g, normals = corner_geometry(slope)
    return case_record(case_id, g, normals, eps, velocity, max_iterations=GOLDEN_MAX_ITERATIONS)


def _paper_cases() -> list[dict[Any, Any]]:
    from verify.models.corner import slope_of, velocity_of
    from verify.paper.readings import load_table1

    data = load_table1()
    out = [_cradle(f"paper-table1-eps-{row[0]}", [row[0], row[0]], [data["v0"], 0, 0]) for row in data["rows"]]
    out.append(_corner("paper-corner-pi6-pi12", slope_of(alpha="pi/6"), ["0.999", "0.001"], velocity_of("pi/12")))
    return out


def _family_cases() -> list[dict[Any, Any]]:
    from verify.models.corner import slope_of, velocity_of

    return [
        _cradle("cradle-4-balls-eps-1/2", ["1/2"] * 3, [1, 0, 0, 0]),
        _cradle("cradle-5-balls-masses-12321", ["9/10"] * 4, [2, 0, 0, 0, -1], [1, 2, 3, 2, 1]),
        _cradle("cradle-masses-121-both-contacts", ["1/2", "1"], [1, 0, -1], [1, 2, 1]),
        _cradle("cradle-cors-0-1-energy-rises", [0, 1], [0, -1, -3]),
        _cradle("cradle-3-balls-eps-0-01-never-exits", ["0.01", "0.01"], [100, 0, 0]),
        _cradle("cradle-4-balls-cors-0-repeats", [0, 0, 0], ["3/4", "-1/4", "-1/4", "-1/4"]),
        _corner("corner-slope-1/2-cors-0-1", Fraction(1, 2), [0, 1], [1, Fraction(1, 10), 0]),
        _corner("corner-slope-2-cors-1/3-2/3", Fraction(2), ["1/3", "2/3"], [1, Fraction(-1, 5), 0]),
        _corner("corner-right-angle-cors-1/2-1/5", Fraction(1), ["1/2", "1/5"], [3, 1, 0]),
        _corner("corner-pi8-cors-1-0", slope_of(alpha="pi/8"), [1, 0], [1, Fraction(1, 10), 0]),
        _corner("corner-pi12-ideal", slope_of(alpha="pi/12"), [1, 1], [1, 0, 0]),
        _corner("corner-pi3-cors-0-1/2", slope_of(alpha="pi/3"), [0, "1/2"], velocity_of("pi/6")),
        _corner("corner-pi6-cors-1-0-repeats", slope_of(alpha="pi/6"), [1, 0], velocity_of("pi/12")),
        _corner("corner-slope-1/10-never-exits", Fraction(1, 10), ["1/10", "1/50"], [1, Fraction(1, 20), 0]),
        _corner("corner-grazing-wall-2", Fraction(1, 2), ["1/2", "1/2"], [1, Fraction(-1, 2), 0]),
    ]


def random_cases(
    count: int = 16, *, seed: int | None = None, keep: Callable[[dict[Any, Any]], bool] | None = None
) -> tuple[list[dict[Any, Any]], int]:
    """General systems (:func:`random_case`): SPD mass matrices, r = 2..4 independent normals,
    some moving, velocities with exact target rates (several hit, some grazing), CORs with 0
    and 1, drawn with ``seed`` (default the golden dataset's).

    A draw that ``keep`` refuses is replaced by the next one; by default a system whose exact run
    has not ended (exit or proved never to exit) before its numbers reach
    :data:`GENERATION_BITS` bits: the dataset checks answers, and such a run has none yet.
    Returns the cases and how many draws were replaced (the README of the export counts them).
    """
    rng = random.Random(SEED if seed is None else seed)
    keep = _ends if keep is None else keep
    out: list[dict[Any, Any]] = []
    k = 0
    while len(out) < count:
        record = random_case(rng, len(out), k)
        k += 1
        if keep(record):
            out.append(record)
    return out, k - count


GENERATION_BITS = 2048


def _ends(record: dict[Any, Any]) -> bool:
    from verify.laws.rule import Budget, solve

    c = case_from_record(record)
    r = solve(c.system, c.velocity_source, max_iterations=1000, trace=False, budget=Budget(bits=GENERATION_BITS))
    return r.stop in ("exit", "non_terminating")


def random_geometry(
    rng: random.Random, n: int, r: int, diagonal: Callable[[int], Fraction], q: Callable[..., Fraction]
) -> tuple[list[list[Fraction]], list[list[Fraction]]]:
    """A random SPD mass matrix ``L L^T`` (unit lower-triangular part drawn by ``q(-1, 1)``, the
    diagonal of L by ``diagonal(i)``) and r independent normals (a pivot column each, the other
    entries drawn by ``q(-2, 2, 2)``), drawing from ``rng`` in a fixed order.

    >>> import random
    >>> rng = random.Random(0)
    >>> g, normals = random_geometry(rng, 3, 2, lambda i: Fraction(1), lambda lo, hi, den=4: Fraction(lo))
    >>> g[0], len(normals)
    ([Fraction(1, 1), Fraction(-1, 1), Fraction(-1, 1)], 2)
    """
    L = [[diagonal(i) if i == j else q(-1, 1) if j < i else Fraction(0) for j in range(n)] for i in range(n)]
    g = [[sum((L[i][m] * L[j][m] for m in range(n)), Fraction(0)) for j in range(n)] for i in range(n)]
    pivots = sorted(rng.sample(range(n), r))
    normals = [
        [Fraction(rng.choice([1, -1, 2])) if c == pivots[i] else Fraction(0) if c in pivots else q(-2, 2, 2)
         for c in range(n)]
        for i in range(r)
    ]  # fmt: skip
    return g, normals


def random_case(rng: random.Random, index: int, k: int) -> dict[Any, Any]:
    """A random general system and velocity as a case record, drawn from ``rng``: r = 2..4
    constraints (``2 + index % 3``) in n = r+1 or r+2 coordinates (``k``), moving constraints
    for every fourth index, CORs with 0 and 1 drawn often, a velocity that hits two or three
    constraints with exact target rates (one grazing for every fifth index).

    >>> record = random_case(random.Random(0), 1, 0)
    >>> record["id"], len(record["normals"]), len(record["velocity"])
    ('general-01-r3-n4-fixed', 3, 4)
    """

    def q(lo: int, hi: int, den: int = 4) -> Fraction:
        return Fraction(rng.randint(lo * den, hi * den), rng.randint(1, den))

    r = 2 + index % 3
    n = r + 1 + k % 2
    g, normals = random_geometry(rng, n, r, lambda i: q(1, 2), q)
    moving = index % 4 == 3
    time_terms = [q(-2, 2, 2) if moving else Fraction(0) for _ in range(r)]
    eps = [min(max(rng.choice([Fraction(0), Fraction(1), q(0, 1, 10)]), Fraction(0)), Fraction(1)) for _ in range(r)]
    targets = {j: -q(1, 3) for j in range(min(r, 2 + index % 2))}
    if index % 5 == 0:
        targets[r - 1] = Fraction(0)  # grazing
    w = [q(-2, 2) for _ in range(n)]
    v = velocity_with_rates((g, normals, time_terms), w, targets)
    kind = "moving" if moving else "fixed"
    case_id = f"general-{index:02d}-r{r}-n{n}-{kind}"
    return case_record(case_id, g, normals, eps, v, time_terms=time_terms, max_iterations=GOLDEN_MAX_ITERATIONS)


def golden_dataset() -> tuple[list[dict[Any, Any]], int]:
    """The golden dataset's case records in a fixed order, and the number of random draws
    replaced because their numbers grew past :data:`GENERATION_BITS`."""
    randoms, skipped = random_cases()
    return _paper_cases() + _family_cases() + randoms, skipped


def golden_cases() -> list[dict[Any, Any]]:
    """The golden dataset's case records, in a fixed order."""
    return golden_dataset()[0]


def golden_results(
    cases: list[dict[Any, Any]],
    *,
    budget: Any = None,
    progress: Callable[[int, str, int], None] | None = None,
    law: Law = "rule",
) -> list[dict[Any, Any]]:
    """The exact result records of the cases (the default exact engine, with certificates), under
    the paper's rule or, with ``law="simultaneous"``, the simultaneous law.

    ``budget`` (a :class:`verify.laws.rule.Budget`) bounds each run, which then stops with stop
    ``"budget"``; ``progress(k, case_id, impulses)`` is called with impulses 0 when case k
    (from 1) starts and after each of its impulses. Without a budget, each record's result is kept
    for the process (:data:`RESULTS_KEPT` of them): a notebook or a test suite that checks several
    implementations on the same cases runs each exact case once.

    >>> from verify.laws.rule import Budget
    >>> [r["iterations"] for r in golden_results(golden_cases()[:2])]
    [2, 3]
    >>> [(r["stop"], r["iterations"]) for r in golden_results(golden_cases()[:2], budget=Budget(bits=8))]
    [('exit', 2), ('budget', 1)]
    >>> golden_results(golden_cases()[:1], law="simultaneous")[0]["exit_velocity"]
    ['-100/3', '200/3', '200/3']
    """
    out = []
    for k, record in enumerate(cases, 1):
        key = json.dumps(record, sort_keys=True) + "\0" + str(law) if budget is None else None
        if key is not None and key in _KEPT:
            _KEPT.move_to_end(key)
            out.append(copy.deepcopy(_KEPT[key]))
            if progress is not None:
                progress(k, str(record.get("id")), 0)
            continue
        out.append(_exact_result(k, record, law, budget, progress))
        if key is not None:
            _KEPT[key] = copy.deepcopy(out[-1])
            while len(_KEPT) > RESULTS_KEPT:
                _KEPT.popitem(last=False)
    return out


#: how many exact results :func:`golden_results` keeps (the least recently used go first)
RESULTS_KEPT = 4096
_KEPT: collections.OrderedDict[str, dict[Any, Any]] = collections.OrderedDict()


def _exact_result(
    k: int, record: dict[Any, Any], law: Law, budget: Any, progress: Callable[[int, str, int], None] | None
) -> dict[Any, Any]:
    """The exact result record of case k (from 1) of a file."""
    from verify.laws.rule import solve

    c = case_from_record(record, f"case {record['id']}")
    hook = None
    if progress is not None:
        progress(k, c.id, 0)
        hook = functools.partial(progress, k, c.id)
    try:
        case_law = law_for_case(law, c.law_settings, c.system.r)
        if isinstance(case_law, Sequential):  # checked here, to name the case
            case_law.sweep_order(c.system.r)
            case_law.thresholds(c.system.r)
    except InvalidInput as exc:  # the command's settings do not fit this case: name it
        raise InvalidInput(f"cases[{k - 1}] ({c.id}): {exc}") from None
    r = solve(c.system, c.velocity_source, law=case_law, max_iterations=c.max_iterations, trace=False,
              budget=budget, progress=hook)  # fmt: skip
    return result_record(r, c.id)


def _summary(cases: list[dict[Any, Any]], results: list[dict[Any, Any]], skipped: int) -> str:
    decimals = (
        "\nEach case of `cases.json` also carries `decimal`: its numbers correctly rounded to 40 significant\n"
        "digits, for a program that reads numbers with `strtod` (`docs/oracle.md`).\n"
    )
    head = f"# The golden dataset, version {GOLDEN_VERSION} (`{GOLDEN_DATASET}`)\n\n"
    return head + dataset_description(cases, results, skipped) + decimals


def dataset_description(cases: list[dict[Any, Any]], results: list[dict[Any, Any]], skipped: int) -> str:
    """What the golden dataset holds: how it is made, one table row per case, the stops."""
    lines = [
        "Generated by `verify oracle export DIR`; do not edit by hand.",
        "`cases.json` holds the case records, `results.json` the exact results of the general rule (eq. 8),",
        "`results-simultaneous.json` those of the simultaneous law (Newton's restitution with complementarity,",
        "the law of physics engines), with decimals to 30 digits. Check an implementation with",
        "`verify oracle check cases.json ITS_RESULTS.json` or `verify oracle check cases.json --impl COMMAND`",
        "(add `--law simultaneous` for the second law).",
        "",
        "| id | r | n | stop | impulses | multiple impacts |",
        "|---|---|---|---|---|---|",
    ]
    for c, r in zip(cases, results):
        multiple = sum(len(J) > 1 for J in r["impact_sets"])
        stop, impulses = r["stop"], str(r["iterations"])
        if stop == "non_terminating":  # no count of impulses: they never end
            stop, impulses = "never exits", f"infinitely many (proved after {r['iterations']})"
        lines.append(f"| {c['id']} | {len(c['normals'])} | {len(c['velocity'])} | {stop} | {impulses} | {multiple} |")
    stops: dict[str, int] = {}
    for r in results:
        stops[r["stop"]] = stops.get(r["stop"], 0) + 1
    named = {"non_terminating": "never exits (non_terminating)"}
    lines += ["", f"{len(cases)} cases; stops: " + ", ".join(f"{named.get(k, k)} {v}" for k, v in sorted(stops.items()))
              + "."]  # fmt: skip
    lines += [
        f"Random general systems drawn but left out because their exact numbers passed {GENERATION_BITS} bits "
        f"before the run ended: {skipped}.",
        "",
    ]
    return "\n".join(lines)


def _library_free(record: dict[Any, Any]) -> dict[Any, Any]:
    """A result record whose ``backend`` does not name the rational library in use (gmpy2, FLINT or pure
    Python give the same numbers): the golden files are the same bytes on every install.

    >>> _library_free({"backend": "exact (rationals, gmpy2), rigorous"})["backend"]
    'exact (rationals), rigorous'
    """
    import re

    return dict(record, backend=re.sub(r"\(rationals, [A-Za-z0-9_-]+\)", "(rationals)", record["backend"]))


def export(folder: str) -> list[str]:
    """Write ``cases.json``, ``results.json`` (the rule), ``results-simultaneous.json`` (the
    simultaneous law) and ``README.md`` into ``folder``. Each case of ``cases.json`` carries its
    ``decimal`` object (:func:`verify.records.results.with_decimals`): its numbers correctly
    rounded to 40 significant digits, beside the exact strings.

    Each file is written whole to a temporary name, then renamed: an interrupted export
    leaves no partial file behind. Returns the paths written.
    """
    cases, skipped = golden_dataset()
    results = golden_results(cases)
    simultaneous = golden_results(cases, law="simultaneous")
    texts = {
        "cases.json": dumps(stamped({"cases": [with_decimals(c) for c in cases]}, GOLDEN_DATASET)),
        "results.json": dumps(stamped({"results": [_library_free(r) for r in results]}, GOLDEN_DATASET)),
        "results-simultaneous.json": dumps(
            stamped({"results": [_library_free(r) for r in simultaneous]}, GOLDEN_DATASET)
        ),
        "README.md": _summary(cases, results, skipped),
    }
    from verify.records.files import write_all_atomic

    os.makedirs(folder, exist_ok=True)
    paths = [os.path.join(folder, name) for name in texts]
    files: dict[str | os.PathLike[str], str | bytes] = dict(zip(paths, texts.values()))
    write_all_atomic(files)
    return paths


# -- checking another implementation -------------------------------------------------------------


@dataclass
class Mismatch:
    """One disagreement: the case id, what differs, and the two values."""

    case_id: str
    field: str
    detail: str


@dataclass
class Comparison:
    """The outcome of :func:`compare`."""

    checked: int = 0
    agreeing: int = 0  # the cases graded in a passing class (verify.oracle.grading.PASSING)
    mismatches: list[Mismatch] = field(default_factory=list)
    #: cases whose exact run reached its budget (stop "budget"): checked only on the impulses it made
    limited: list[str] = field(default_factory=list)
    #: cases the implementation listed as skipped (``"skipped"`` of its result file), with the reason
    skipped: dict[str, str] = field(default_factory=dict)
    #: the fields the results did not give (velocity-only results), with how many results lacked each
    unchecked: dict[str, int] = field(default_factory=dict)
    #: one graded verdict per case (:mod:`verify.oracle.grading`)
    grades: list[Any] = field(default_factory=list)
    #: the basis of the tolerance, in one line (:meth:`verify.oracle.grading.Tolerance.describe`)
    tolerance: str = ""

    def classes(self) -> dict[str, int]:
        """How many cases fell in each class, in the order of :data:`verify.oracle.grading.CLASSES`."""
        from verify.oracle.grading import CLASSES

        counts = {c: 0 for c in CLASSES}
        for g in self.grades:
            counts[g.cls] += 1
        return {c: n for c, n in counts.items() if n}

    @property
    def ok(self) -> bool:
        """No mismatch: every case graded in a passing class, skipped by the implementation, or limited
        by a budget with no mismatch on its first impulses (the exit code of ``verify oracle check``)."""
        return not self.mismatches


def approx(text: str, where: str | None = None) -> Fraction:
    """A number string of a result file as a Fraction (:func:`verify.records.results.read_number`).

    >>> approx("0.1"), approx("1/3")
    (Fraction(1, 10), Fraction(1, 3))
    """
    return read_number(text, where)


#: the fields of a result that are compared when given (a velocity-only result gives none of them)
OPTIONAL_CHECKED = ("stop", "iterations", "impact_sets")


def compare(
    cases: list[dict[Any, Any]],
    expected: list[dict[Any, Any]],
    got: list[dict[Any, Any]],
    *,
    rtol: Fraction = DEFAULT_RTOL,
    atol: Fraction = Fraction(0),
    floor: Fraction = DEFAULT_FLOOR,
    skipped: dict[str, str] | None = None,
    budgets: Any = None,
) -> Comparison:
    """Every mismatch between ``got`` (another implementation) and ``expected`` (exact).

    A result may give only ``id`` and ``exit_velocity`` (a velocity-only implementation, such as
    a physics engine): the fields of :data:`OPTIONAL_CHECKED` that it leaves out are counted in
    ``unchecked``, and its velocity is taken as an exit. A case listed in ``skipped`` (id ->
    reason) is not a mismatch: it is reported as skipped. A component of the exit velocity passes
    within ``atol + rtol * |v_exit|`` (the exact exit speed), and a component that is exactly 0 also
    within ``atol + floor * |v_in|`` (the entrance speed); a beta within its own tolerance
    (:data:`verify.oracle.grading.DEFAULT_BETA`, relative). ``budgets`` (a
    :class:`verify.oracle.grading.Budgets`) gives the tolerance per case instead, in more units.

    >>> cases = golden_cases()[:1]
    >>> exact = golden_results(cases)
    >>> wrong = [dict(exact[0], iterations=3)]
    >>> [m.field for m in compare(cases, exact, wrong, rtol=Fraction(1, 10**9), atol=Fraction(0)).mismatches]
    ['iterations']
    >>> bare = [{"id": exact[0]["id"], "exit_velocity": ["0", "0", "100"]}]
    >>> c = compare(cases, exact, bare, rtol=Fraction(1, 10**9), atol=Fraction(0))
    >>> c.ok, c.unchecked
    (True, {'stop': 1, 'iterations': 1, 'impact_sets': 1})
    """
    default = Tolerance(rtol=rtol, atol=atol, floor=floor)
    out = Comparison(skipped=dict(skipped or {}), tolerance=default.describe())
    if budgets is not None:
        out.tolerance = budgets.default.describe() + (
            f"; {len(budgets.cases)} id patterns with their own (--tolerances)" if budgets.cases else ""
        )
    by_id: dict[str, dict[Any, Any]] = {}
    for i, r in enumerate(got):
        if r["id"] in by_id:
            out.mismatches.append(Mismatch(r["id"], "id", f"results[{i}] repeats the id"))
        by_id[r["id"]] = r
    known = {c["id"] for c in cases}
    for r in got:
        if r["id"] not in known:
            out.mismatches.append(Mismatch(r["id"], "id", "a result for a case that is not in the case file"))
    for case, exact in zip(cases, expected):
        out.checked += 1
        tol = default if budgets is None else budgets.for_case(case["id"])
        _check_case(out, case, exact, by_id.get(case["id"]), tol)
    out.agreeing = sum(g.cls in PASSING for g in out.grades)
    return out


@dataclass
class Found:
    """What the comparison of one case found: the mismatches, the differences tolerated as float
    bookkeeping (:mod:`verify.oracle.bookkeeping`), and whether the velocity was compared with an exact one."""

    mismatches: list[Mismatch] = field(default_factory=list)
    tolerated: list[str] = field(default_factory=list)
    velocity_compared: bool = False


def _check_case(
    out: Comparison, case: dict[Any, Any], exact: dict[Any, Any], mine: dict[Any, Any] | None, tol: Tolerance
) -> None:
    """Compare one case: its mismatches, its count in ``unchecked``, and its grade."""
    from verify.oracle.grading import Grade, grade_case

    cid = case["id"]
    if mine is None:
        if cid in out.skipped:
            out.grades.append(Grade(cid, "skipped", out.skipped[cid]))
        else:
            out.mismatches.append(Mismatch(cid, "missing", "no result for this case"))
            out.grades.append(Grade(cid, "missing", "no result for this case"))
        return
    for name in OPTIONAL_CHECKED:
        if name not in mine:
            out.unchecked[name] = out.unchecked.get(name, 0) + 1
    try:
        found = _compare_one(case, exact, mine, tol)
    except InvalidInput as exc:  # nan, inf, a word: a mismatch of this case only
        found = Found([Mismatch(cid, "bad_number", str(exc))])
    out.mismatches += found.mismatches
    if exact["stop"] == "budget":
        out.limited.append(cid)
        out.grades.append(Grade(cid, "limited", "the exact run reached its budget"))
        return
    grade = grade_case(case, exact, mine, found, tol.rtol)
    if grade.cls not in PASSING and not found.mismatches:  # a conservation check failed where no velocity was
        out.mismatches.append(Mismatch(cid, grade.cls, grade.detail))  # compared: a mismatch as well
    out.grades.append(grade)


def _prefix_mismatch(cid: str, sets_e: list[Any], sets_m: list[Any]) -> list[Mismatch]:
    """The first impulse at which two impact-set sequences differ, over their common length."""
    m = min(len(sets_e), len(sets_m))
    if sets_e[:m] == sets_m[:m]:
        return []
    w = next(k for k in range(m) if sets_e[k] != sets_m[k])
    return [Mismatch(cid, "impact_sets", f"from impulse {w + 1}: expected {sets_e[w]}, got {sets_m[w]}")]


def _read_velocity(case: dict[Any, Any], mine: dict[Any, Any]) -> None:
    """Every component of the implementation's velocity read as a number, as many as the case has
    (InvalidInput names a bad one: graded ``bad_number``)."""
    n, got = len(case["velocity"]), len(mine["exit_velocity"])
    if got != n:
        raise InvalidInput(f"results[{case['id']}].exit_velocity: expected {n} components, got {got}")
    for i, x in enumerate(mine["exit_velocity"]):
        approx(x, f"results[{case['id']}].exit_velocity[{i}]")


def _compare_one(case: dict[Any, Any], exact: dict[Any, Any], mine: dict[Any, Any], tol: Tolerance) -> Found:
    """One case's comparison. The velocity is compared with the exact one wherever that is known: at an exit,
    after the sweeps of the sequential law whatever its stop, and at any stop the implementation reached after
    as many impulses as the exact run. A result without ``stop`` (velocity-only) gives an exit velocity, or
    under the sequential law the velocity after the sweeps."""
    cid, found = case["id"], Found()
    _read_velocity(case, mine)
    sequential = exact.get("law") == "sequential"
    if exact["stop"] == "budget":  # how far the exact run got is known only for its first impulses
        if "impact_sets" in mine:
            found.mismatches += _budget_mismatch(cid, exact, mine)
        return found
    if "stop" not in mine:  # a velocity-only result: the velocity only
        if sequential or exact["stop"] == "exit":
            _velocity(found, case, exact, mine, tol)
        else:
            found.mismatches.append(
                Mismatch(cid, "stop", _no_exit_text(exact) + "; a result without stop gives an exit velocity")
            )
        return found
    if sequential:
        return _compare_sequential(found, case, exact, mine, tol)
    count = _count(mine)
    if exact["stop"] == "non_terminating":  # the exact impact sets are a prefix of an endless run
        if mine["stop"] != "non_terminating":
            found.mismatches.append(Mismatch(cid, "stop", f"{_no_exit_text(exact)}, got {_stop_text(mine)}"))
        found.mismatches += _prefix_mismatch(cid, exact["impact_sets"], impact_sets_of(mine) or [])
        if not found.mismatches and count == exact["iterations"]:
            _velocity(found, case, exact, mine, tol)
        return found
    if mine["stop"] != exact["stop"]:
        found.mismatches.append(Mismatch(cid, "stop", f"expected {exact['stop']}, got {_stop_text(mine)}"))
    if "iterations" in mine and mine["iterations"] != exact["iterations"]:
        found.mismatches.append(
            Mismatch(cid, "iterations", f"expected {exact['iterations']}, got {mine['iterations']}")
        )
    found.mismatches += _sets_mismatch(cid, exact, mine)
    if not found.mismatches and "betas" in mine:
        found.mismatches += _compare_betas(cid, exact, mine, tol.beta_rtol)
    same_point = mine["stop"] == exact["stop"] and count == exact["iterations"]
    if (exact["stop"] == "exit" and mine["stop"] == "exit") or same_point:
        _velocity(found, case, exact, mine, tol)
    return found


def _count(mine: dict[Any, Any]) -> int | None:
    """The impulses (or sweeps) a result says it made: its ``iterations``, else the length of its
    ``impact_sets``, else None."""
    if "iterations" in mine:
        return int(mine["iterations"])
    return len(mine["impact_sets"]) if "impact_sets" in mine else None


def _compare_sequential(
    found: Found, case: dict[Any, Any], exact: dict[Any, Any], mine: dict[Any, Any], tol: Tolerance
) -> Found:
    """The sequential law: the velocity after the sweeps always; the stop and the sweeps' counts up to the
    float bookkeeping that :mod:`verify.oracle.bookkeeping` tolerates when the velocity agrees."""
    from verify.oracle import bookkeeping as sweeps

    cid = case["id"]
    _velocity(found, case, exact, mine, tol)
    velocity_agrees = not found.mismatches
    if mine["stop"] != exact["stop"]:
        bound = _velocity_bound(case, exact, tol)
        if velocity_agrees and sweeps.stop_tolerated(case, exact, mine["stop"], bound):
            found.tolerated.append(f"stop {mine['stop']} for {exact['stop']}: a rate within the tolerance of 0")
        else:
            found.mismatches.append(
                Mismatch(cid, "stop", f"expected {exact['stop']}, got {_stop_text(mine, 'sweeps')}")
            )
    if any(b is not None for b in mine.get("betas") or []):
        found.mismatches.append(Mismatch(cid, "betas", "the sequential law has no beta: null for every sweep"))
    counts = sweeps.bookkeeping(case, exact, mine, tol.rtol)
    if counts is not None and velocity_agrees:
        found.tolerated.append(counts)
        return found
    if "iterations" in mine and mine["iterations"] != exact["iterations"]:
        found.mismatches.append(
            Mismatch(cid, "iterations", f"expected {exact['iterations']} sweeps, got {mine['iterations']}")
        )
    found.mismatches += _sets_mismatch(cid, exact, mine, unit="sweep")
    return found


def _sets_mismatch(cid: str, exact: dict[Any, Any], mine: dict[Any, Any], unit: str = "impulse") -> list[Mismatch]:
    """The first impulse (or sweep) at which the impact sets differ, when the result gives them."""
    sets_e, sets_m = exact["impact_sets"], impact_sets_of(mine)
    if sets_m is None or sets_m == sets_e:
        return []
    w = next((k for k, (a, b) in enumerate(zip(sets_e, sets_m)) if a != b), min(len(sets_e), len(sets_m)))
    allowed = (exact.get("law_settings") or {}).get("iterations")
    end = "none (the run ends)"
    if unit == "sweep":
        end = "none (the sweeps allowed are used up)" if allowed == len(sets_e) else "none (the impulses have settled)"
    a = sets_e[w] if w < len(sets_e) else end
    b = sets_m[w] if w < len(sets_m) else end
    return [Mismatch(cid, "impact_sets", f"from {unit} {w + 1}: expected {a}, got {b}")]


def _budget_mismatch(cid: str, exact: dict[Any, Any], mine: dict[Any, Any]) -> list[Mismatch]:
    """The exact run reached its budget: only its first impulses are known."""
    n, found = exact["iterations"], []
    if mine.get("stop") in ("exit", "max_iterations", "aeev") and mine.get("iterations", n + 1) <= n:
        found.append(
            Mismatch(
                cid,
                "stop",
                f"expected more than {counted(n, 'impulse')} (the exact run was still impacting when it reached "
                f"the budget), got {mine['stop']} after {counted(mine['iterations'], 'impulse')}",
            )
        )
    return found + _prefix_mismatch(cid, exact["impact_sets"], impact_sets_of(mine) or [])


def _stop_text(mine: dict[Any, Any], unit: str = "impulses") -> str:
    """The implementation's stop, with its impulse (or sweep) count when given."""
    n = mine.get("iterations")
    return str(mine["stop"]) + ("" if n is None else f" after {n} {unit}")


def _no_exit_text(exact: dict[Any, Any]) -> str:
    """Why a velocity given as an exit velocity is wrong where the exact run does not exit."""
    if exact["stop"] == "non_terminating":
        what = f"non_terminating (never exits; proved after {counted(exact['iterations'], 'impulse')})"
    else:
        what = f"{exact['stop']} (the exact run had not exited after {counted(exact['iterations'], 'impulse')})"
    return f"expected {what}"


def _speeds(case: dict[Any, Any], exact: dict[Any, Any]) -> tuple[Fraction, list[Fraction], Fraction]:
    """The entrance speed ``max|v_in|``, the exact velocity's components and its speed ``max|v_exit|``: what
    the tolerance of a component is measured against."""
    cid = case["id"]
    entrance = max(abs(approx(x, f"{cid}.velocity[{i}]")) for i, x in enumerate(case["velocity"]))
    values = [approx(e, f"{cid}.exit_velocity[{i}]") for i, e in enumerate(exact["exit_velocity"])]
    return entrance, values, max(abs(x) for x in values)


def _velocity_bound(case: dict[Any, Any], exact: dict[Any, Any], tol: Tolerance) -> Fraction:
    """The largest error allowed on a component of the velocity (that of its largest component)."""
    entrance, values, speed = _speeds(case, exact)
    return max(tol.bound(x, entrance, speed) for x in values)


def _velocity(found: Found, case: dict[Any, Any], exact: dict[Any, Any], mine: dict[Any, Any], tol: Tolerance) -> None:
    found.velocity_compared = True
    found.mismatches += _compare_velocity(case, exact, mine, tol)


def _compare_betas(cid: str, exact: dict[Any, Any], mine: dict[Any, Any], rtol: Fraction) -> list[Mismatch]:
    """beta at each impulse of the same run, within ``rtol`` of the exact one (null for a single impact)."""
    for w, (e, m) in enumerate(zip(exact["betas"], mine["betas"])):
        if (e is None) != (m is None):
            return [Mismatch(cid, f"betas[{w}]", f"impulse {w + 1}: expected {e}, got {m}")]
        if e is not None and abs(approx(e, f"{cid}.betas[{w}]") - approx(m, f"results[{cid}].betas[{w}]")) > rtol * abs(
            approx(e)
        ):
            return [Mismatch(cid, f"betas[{w}]", f"impulse {w + 1}: expected beta {e}, got {m}")]
    return []


def _compare_velocity(
    case: dict[Any, Any], exact: dict[Any, Any], mine: dict[Any, Any], tol: Tolerance
) -> list[Mismatch]:
    cid = case["id"]
    n = len(case["velocity"])
    if len(mine["exit_velocity"]) != n:
        return [Mismatch(cid, "exit_velocity", f"expected {n} components, got {len(mine['exit_velocity'])}")]
    entrance, values, exit_speed = _speeds(case, exact)
    out = []
    for i, (e, m) in enumerate(zip(values, mine["exit_velocity"])):
        diff = abs(e - approx(m, f"results[{cid}].exit_velocity[{i}]"))
        bound = tol.bound(e, entrance, exit_speed)
        if diff > bound:
            from verify.numbers.format import format_decimal

            out.append(
                Mismatch(
                    cid,
                    f"exit_velocity[{i}]",
                    f"expected {exact['exit_velocity_decimal'][i]}, got {m} "
                    f"(off by {format_decimal(diff, 3)} > tolerance {format_decimal(bound, 3)})",
                )
            )
    return out


def load_results(text: str, source: str) -> list[dict[Any, Any]]:
    """Parse and validate a result file (schema of the contracts); errors name the field."""
    return load_result_file(text, source)[0]


#: the fields of a result that hold one number, and those that hold a list of numbers
RESULT_NUMBERS = ("kinetic_energy_in", "kinetic_energy_out")
RESULT_NUMBER_LISTS = ("exit_velocity", "exit_velocity_decimal", "betas", "impulses")


def _constants_as_text(data: Any) -> None:
    """A bare ``NaN`` or ``Infinity`` where a result holds a number becomes its text (``"NaN"``),
    which is graded as that string is: ``bad_number`` for that case only. Anywhere else the schema
    names its field."""
    from verify.records.files import BareJSONConstant

    def text(x: Any) -> Any:
        return x.json_constant_text if isinstance(x, BareJSONConstant) else x

    results = data.get("results") if isinstance(data, dict) else None
    for r in results if isinstance(results, list) else ():
        if not isinstance(r, dict):
            continue
        for name in RESULT_NUMBERS:
            if name in r:
                r[name] = text(r[name])
        for name in RESULT_NUMBER_LISTS:
            if isinstance(r.get(name), list):
                r[name] = [text(x) for x in r[name]]


def load_result_file(text: str, source: str, dataset: str | None = None) -> tuple[list[dict[Any, Any]], dict[str, str]]:
    """A result file's results, and the cases it lists as skipped (id -> reason). A bare ``NaN``
    (what Python's ``json.dump`` writes) or ``Infinity`` in a number's place is kept as its text,
    to be graded ``bad_number`` as the string ``"nan"`` is; anywhere else it is refused, naming
    the file and the field. Its versions are checked (:func:`verify.records.versions.check_versions`), and a
    file made for another dataset than ``dataset`` (the case file's) is refused.

    >>> load_result_file('{"results": [], "skipped": [{"id": "a", "reason": "no corner"}]}', "x")
    ([], {'a': 'no corner'})
    >>> load_result_file('{"results": [{"id": "a", "exit_velocity": [NaN, "1"]}]}', "x")[0]
    [{'id': 'a', 'exit_velocity': ['NaN', '1']}]
    >>> load_result_file('{"results": [{"id": "a", "exit_velocity": ["1"], "iterations": NaN}]}', "x")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: x: results[0].iterations: expected an integer, got the bare JSON constant NaN ...
    """
    from verify.records.files import load_json
    from verify.records.schema import validate

    data = load_json(source, text=text, constants=True)
    _constants_as_text(data)
    named = check_versions(data, source)  # first: a newer file's new fields are not what is wrong with it
    validate(data, "result", source)
    check_same_dataset(dataset, named, source)
    return data["results"], {s["id"]: s["reason"] for s in data.get("skipped", [])}


def run_implementation(command: str, case_text: str, timeout: float) -> str:
    """Run ``command`` (split like a shell would, not run by one) with the case file on stdin; returns
    its stdout, the result file (:func:`verify.oracle.impl.run_implementation`: one clear line for
    every way it can fail, the process group ended on timeout, the output capped while read)."""
    from verify.oracle import impl

    return impl.run_implementation(command, case_text, timeout)


def comparison_json(comparison: Comparison) -> dict[str, Any]:
    """The comparison as JSON: counts and every mismatch."""
    out: dict[str, Any] = {
        "checked": comparison.checked,
        "agreeing": comparison.agreeing,
        "mismatches": [{"id": m.case_id, "field": m.field, "detail": m.detail} for m in comparison.mismatches],
    }
    if comparison.tolerance:  # the basis of the tolerance, as the text summary prints it
        out["tolerance"] = comparison.tolerance
    if comparison.limited:  # only when a budget was given (verify oracle check --max-bits, --case-time-limit)
        out["limited_by_budget"] = comparison.limited
    if comparison.skipped:  # only when the implementation listed cases it could not run
        out["skipped"] = [{"id": k, "reason": v} for k, v in comparison.skipped.items()]
    if comparison.unchecked:  # only for results that leave fields out (velocity-only results)
        out["unchecked"] = dict(comparison.unchecked)
    out["classes"] = comparison.classes()
    out["grades"] = [g.to_json() for g in comparison.grades]
    return out
