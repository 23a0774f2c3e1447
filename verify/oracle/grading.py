"""Graded verdicts of the oracle: one class per case, the tolerance each case needs, error tables.

:func:`verify.oracle.reference.compare` lists every field that differs; this module reads those
mismatches, with the exact and the implementation's results, and gives each case one class,
the most telling first:

- ``exact``: every number given equals the exact value (a float equal to a rational, say);
- ``within_tolerance``: the same run (stop, impulses, impact sets, betas when given), the exit
  velocity within the tolerance;
- ``gave_up``: the implementation stopped at its own cap (stop ``max_iterations`` with fewer
  impulses than the exact run, whose impact sets it followed), where the exact run goes on or is
  proved never to exit: the documented way for a float implementation to say so;
- ``wrong_branch``: the runs part at some impulse (the first impact set that differs is shown,
  with the exact rates and beta there);
- ``wrong_stop``: an exit reported for a run proved never to exit, or the reverse;
- ``momentum_drift``: the momentum along the directions that no constraint touches (which every
  impulse keeps) differs from the entrance's beyond the tolerance;
- ``energy_error``: the kinetic energy of the exit velocity exceeds the law's beyond the tolerance;
- ``out_of_tolerance``: the same run, the exit velocity off by more than the tolerance;
- ``bad_number``: a number of the result cannot be read (``nan``, ``inf``);
- ``missing`` and ``skipped`` (listed by the implementation as not run), ``limited`` (the exact
  run reached its budget: compared only on its first impulses).

For each case that exits under both, the tolerance it needs to pass is measured in two units:
relative to the exit speed (``max_i |got_i - exact_i| / max_i |exact_i|``) and in binary64 ulps
of the exact components.

>>> from fractions import Fraction
>>> ulps(Fraction(1), Fraction(1) + Fraction(1, 2**52))
1
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal, get_args

from verify.numbers.backends.base import Backend

#: the classes, from the best to the worst (the order of the summary table)
GradeClass = Literal[
    "exact",
    "within_tolerance",
    "gave_up",
    "wrong_branch",
    "wrong_stop",
    "momentum_drift",
    "energy_error",
    "out_of_tolerance",
    "bad_number",
    "missing",
    "skipped",
    "limited",
]
CLASSES: tuple[GradeClass, ...] = get_args(GradeClass)
#: the classes of ``verify oracle explain``'s JUnit cases: a model explains the answer, or none does
ExplainClass = Literal["explained", "unexplained"]
#: the classes that pass
PASSING = ("exact", "within_tolerance")


@dataclass(frozen=True)
class Grade:
    """One case's class, what shows it, and the tolerance it needs (None when not measured)."""

    case_id: str
    cls: GradeClass | ExplainClass
    detail: str = ""
    needed_speed: Fraction | None = None  # max_i |got_i - exact_i| / max_i |exact_i|
    needed_ulps: int | None = None  # max_i of the error in binary64 ulps of exact_i

    def to_json(self) -> dict[str, Any]:
        """The grade as JSON (numbers as strings)."""
        from verify.numbers.format import format_decimal

        return {
            "id": self.case_id,
            "class": self.cls,
            "detail": self.detail,
            "needed_speed_tolerance": None if self.needed_speed is None else format_decimal(self.needed_speed, 3),
            "needed_ulps": self.needed_ulps,
        }


def ulp(x: Fraction) -> Fraction:
    """The binary64 unit in the last place at ``x`` (exact; subnormal spacing near 0).

    >>> ulp(Fraction(1)), ulp(Fraction(3, 2)), ulp(Fraction(0)) == Fraction(1, 2**1074)
    (Fraction(1, 4503599627370496), Fraction(1, 4503599627370496), True)
    """
    a = abs(x)
    if a == 0:
        return Fraction(1, 2**1074)
    e = a.numerator.bit_length() - a.denominator.bit_length()
    if Fraction(2) ** e > a:
        e -= 1
    return Fraction(2) ** (max(e, -1022) - 52)


def ulps(exact: Fraction, got: Fraction, scale: Fraction = Fraction(0)) -> int:
    """``|got - exact|`` in binary64 ulps of ``exact``, rounded up; a component much smaller than
    the vector's ``scale`` (its largest component), such as an exact 0, is measured in ulps of
    ``scale * 2^-53`` instead (otherwise the ulp of 0, 2^-1074, would make any error astronomical).

    >>> ulps(Fraction(0), Fraction(1, 2**105), Fraction(1)), ulps(Fraction(0), Fraction(1, 2**53), Fraction(1))
    (1, 4503599627370496)
    """
    q = abs(got - exact) / ulp(max(abs(exact), scale / 2**53))
    return -((-q.numerator) // q.denominator)


def _numbers(values: list[str], where: str) -> list[Fraction]:
    from verify.records.results import read_number

    return [read_number(x, f"{where}[{i}]") for i, x in enumerate(values)]


def needed(exact: dict[str, Any], mine: dict[str, Any], cid: str) -> tuple[Fraction, int]:
    """The tolerance a case needs: relative to the exit speed, and in ulps."""
    e = _numbers(exact["exit_velocity"], f"{cid}.exit_velocity")
    g = _numbers(mine["exit_velocity"], f"results[{cid}].exit_velocity")
    speed = max(abs(x) for x in e) or Fraction(1)
    return max(abs(a - b) for a, b in zip(e, g)) / speed, max(ulps(a, b, speed) for a, b in zip(e, g))


def free_directions(normals: list[list[Fraction]]) -> list[list[Fraction]]:
    """A basis of the vectors u with ``dF_i . u = 0`` for every constraint (exact: the kernel of
    :func:`verify.properties.formulas.kernel`): ``u . g v`` is kept by every impulse, whose
    momentum change lies in the span of the dF_i.

    >>> free_directions([[Fraction(-1), Fraction(1), Fraction(0)], [Fraction(0), Fraction(-1), Fraction(1)]])
    [[Fraction(1, 1), Fraction(1, 1), Fraction(1, 1)]]
    """
    from verify.properties.formulas import kernel

    return kernel(normals)


def _conservation(
    case: dict[str, Any], exact: dict[str, Any], mine: dict[str, Any], tol: Fraction, *, energy: bool = True
) -> tuple[GradeClass, str] | None:
    """``momentum_drift`` or ``energy_error`` when the exit velocity breaks what the law keeps, with the
    line that shows it: the momentum's drift, or the energy's excess, and the tolerance.

    >>> case = {"id": "c", "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    ...         "normals": [["-1", "1", "0"], ["0", "-1", "1"]], "velocity": ["1", "0", "0"]}
    >>> exact = {"kinetic_energy_in": "1/2", "kinetic_energy_out": "1/2"}
    >>> _conservation(case, exact, {"exit_velocity": ["0", "0", "1.5"]}, Fraction(1, 10**9))
    ('momentum_drift', 'the momentum along the free direction (1, 1, 1) (u . g v) is 1.5
    where the entrance has 1: drift 0.5 > tolerance 3e-9')
    >>> _conservation(case, exact, {"exit_velocity": ["-0.1", "0.1", "1"]}, Fraction(1, 10**9))
    ('energy_error', "the kinetic energy of the exit velocity is 0.51, the law's 0.5: 0.01 too much > tolerance 5e-10")
    """
    from verify.numbers.format import format_decimal

    cid = case["id"]
    g = [_numbers(row, f"{cid}.mass_matrix") for row in case["mass_matrix"]]
    normals = [_numbers(row, f"{cid}.normals") for row in case["normals"]]
    v_in = _numbers(case["velocity"], f"{cid}.velocity")
    got = _numbers(mine["exit_velocity"], f"results[{cid}].exit_velocity")
    scale = max(abs(x) for x in v_in) or Fraction(1)

    def momentum(u: list[Fraction], v: list[Fraction]) -> Fraction:
        return sum((ui * sum((gij * x for gij, x in zip(row, v)), Fraction(0)) for ui, row in zip(u, g)), Fraction(0))

    for u in free_directions(normals):
        before, after = momentum(u, v_in), momentum(u, got)
        size = (
            sum((abs(ui) * sum((abs(gij) for gij in row), Fraction(0)) for ui, row in zip(u, g)), Fraction(0)) * scale
        )
        if abs(after - before) > tol * size:
            direction = ", ".join(str(x) for x in u)
            return "momentum_drift", (
                f"the momentum along the free direction ({direction}) (u . g v) is {format_decimal(after, 12)} "
                f"where the entrance has {format_decimal(before, 12)}: drift {format_decimal(after - before, 3)} "
                f"> tolerance {format_decimal(tol * size, 3)}"
            )
    if not energy or any(_numbers(case.get("time_terms") or ["0"], f"{cid}.time_terms")):
        return None  # moving constraints: energies are measured in their rest frame, not checked here
    out = sum(got[i] * g[i][j] * got[j] for i in range(len(got)) for j in range(len(got))) / 2
    allowed = _numbers([exact["kinetic_energy_out"]], f"{cid}.kinetic_energy_out")[0]
    e_in = _numbers([exact["kinetic_energy_in"]], f"{cid}.kinetic_energy_in")[0]
    bound = tol * max(e_in, Fraction(1, 10**30))
    if out - allowed > bound:
        return "energy_error", (
            f"the kinetic energy of the exit velocity is {format_decimal(out, 12)}, the law's "
            f"{format_decimal(allowed, 12)}: {format_decimal(out - allowed, 3)} too much "
            f"> tolerance {format_decimal(bound, 3)}"
        )
    return None


def impact_sets_of(result: dict[str, Any]) -> list[list[int]] | None:
    """A result's impact sets, each sorted, or None when it gives none."""
    return [sorted(J) for J in result["impact_sets"]] if "impact_sets" in result else None


def _gave_up(exact: dict[str, Any], mine: dict[str, Any]) -> bool:
    """Stop ``max_iterations`` after fewer impulses than the exact run made or needs, on its path (never under
    the sequential law, whose stop ``max_iterations`` is an answer: the velocity after the sweeps)."""
    if exact.get("law") == "sequential":
        return False
    if mine.get("stop") != "max_iterations" or exact["stop"] not in ("exit", "non_terminating", "max_iterations"):
        return False
    sets_e, sets_m = exact["impact_sets"], impact_sets_of(mine)
    if sets_m is None:
        return bool(exact["stop"] != "exit")  # no impulses given: only an endless run can be given up on
    n = mine.get("iterations", len(sets_m))
    longer = exact["stop"] == "non_terminating" or n < exact["iterations"]
    return bool(longer and sets_e[: len(sets_m)] == sets_m[: len(sets_e)])


def grade_case(case: dict[str, Any], exact: dict[str, Any], mine: dict[str, Any], found: Any, tol: Fraction) -> Grade:
    """The class of one case, from what :func:`verify.oracle.reference.compare` found (``found``: its mismatches,
    the differences it tolerated, whether it compared the velocity) and the two results; ``tol`` is the
    relative tolerance of the conservation checks. A velocity that was not compared with an exact one (the
    exact run has none at the implementation's stop) is checked for the momentum every impulse keeps, and
    the case is at best ``within_tolerance``: a number that was not compared is never ``exact``. Under the
    sequential law the velocity after the sweeps is the answer: a wrong one is graded before the counts."""
    cid = case["id"]
    mismatches = found.mismatches
    kinds = {m.field.split("[")[0] for m in mismatches}
    first = mismatches[0].detail if mismatches else ""
    if "bad_number" in kinds:
        return Grade(cid, "bad_number", first)
    kept = None if found.velocity_compared else _conservation(case, exact, mine, tol, energy=False)
    if kept is not None and kept[0] == "momentum_drift":
        return Grade(cid, *kept)
    if "exit_velocity" in kinds and exact.get("law") == "sequential":
        return _velocity_grade(case, exact, mine, found, tol)
    if _gave_up(exact, mine):
        return Grade(
            cid, "gave_up", f"stopped at its cap after {mine.get('iterations', '?')} impulses on the exact path"
        )
    if "impact_sets" in kinds or "betas" in kinds:
        detail = next(m.detail for m in mismatches if m.field.split("[")[0] in ("impact_sets", "betas"))
        return Grade(cid, "wrong_branch", detail + divergence(case, exact, mine, mismatches))
    if "stop" in kinds or "iterations" in kinds:
        return Grade(cid, "wrong_stop", first)
    if "exit_velocity" in kinds:
        return _velocity_grade(case, exact, mine, found, tol)
    speed, ulp_count = needed(exact, mine, cid) if found.velocity_compared else (None, None)
    notes = list(found.tolerated)
    if not found.velocity_compared:
        notes.append("the velocity at this stop is checked for momentum only (the exact run has none to compare)")
    equal = speed == 0 and not notes and _betas_equal(exact, mine, cid) and _same_numbers(exact, mine)
    return Grade(cid, "exact" if equal else "within_tolerance", "; ".join(notes), speed, ulp_count)


def _velocity_grade(
    case: dict[str, Any], exact: dict[str, Any], mine: dict[str, Any], found: Any, tol: Fraction
) -> Grade:
    """A velocity off by more than its tolerance: a conservation law it breaks, else ``out_of_tolerance``
    with the first component off; under the sequential law with the targets and impulses
    (:func:`verify.oracle.bookkeeping.hint`)."""
    cid = case["id"]
    off = next(m for m in found.mismatches if m.field.startswith("exit_velocity"))
    speed, ulp_count = needed(exact, mine, cid)
    found_cls: tuple[GradeClass, str] = ("out_of_tolerance", f"{off.field}: {off.detail}")
    cls, detail = _conservation(case, exact, mine, tol) or found_cls
    if exact.get("law") == "sequential":
        from verify.oracle.bookkeeping import hint

        detail += hint(case, exact, mine, tol)
    return Grade(cid, cls, detail, needed_speed=speed, needed_ulps=ulp_count)


def _same_numbers(exact: dict[str, Any], mine: dict[str, Any]) -> bool:
    """Whether every component given is the exact value itself: equal as rationals, or, where the exact value
    is a closed form (an algebraic number), the same string (its 40-digit decimal is not the number).

    >>> _same_numbers({"exit_velocity": ["1/2", "sqrt(2)"]}, {"exit_velocity": ["0.5", "sqrt(2)"]})
    True
    >>> _same_numbers({"exit_velocity": ["sqrt(2)"]}, {"exit_velocity": ["1.414213562373095048801688724209698078570"]})
    False
    """
    from verify.records.results import is_rational_text, read_number

    for e, m in zip(exact["exit_velocity"], mine["exit_velocity"]):
        if not is_rational_text(e):
            if str(m).replace(" ", "") != e.replace(" ", ""):
                return False
        elif read_number(e) != read_number(str(m)):
            return False
    return True


def _betas_equal(exact: dict[str, Any], mine: dict[str, Any], cid: str) -> bool:
    """Whether every beta given equals the exact one (a beta within its tolerance is not ``exact``)."""
    from verify.records.results import read_number

    return all(
        (e is None) == (m is None)
        and (e is None or read_number(e, f"{cid}.betas[{w}]") == read_number(m, f"results[{cid}].betas[{w}]"))
        for w, (e, m) in enumerate(zip(exact["betas"], mine.get("betas") or []))
    )


def divergence(case: dict[str, Any], exact: dict[str, Any], mine: dict[str, Any], found: list[Any]) -> str:
    """Where the exact run stands at the first impulse (under the sequential law: sweep) the runs part:
    its rates p(F_i) before it (those of its exit velocity when it ends there), and its beta for a
    multiple impact; under the sequential law the accumulated impulses after that sweep, the targets, and
    the implementation's impulses when it gives them (:func:`verify.oracle.bookkeeping.hint`). Each number is
    exact when short (at most 24 characters), else ``~`` and its decimal to 6 significant digits.

    >>> case = {"id": "c", "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    ...         "normals": [["-1", "1", "0"], ["0", "-1", "1"]], "restitution": ["1", "1"], "velocity": ["1", "0", "0"]}
    >>> exact = {"impact_sets": [[0], [1]]}
    >>> class M:
    ...     field, detail = "impact_sets", "from impulse 3: expected none (the run ends), got [0]"
    >>> divergence(case, exact, {}, [M()])
    '; the exact run there: rates p(F) = (0, 1): it has exited (no rate is negative)'
    """
    import dataclasses
    import re

    from verify.laws.rule import solve
    from verify.laws.sequential import Sequential, law_of_record
    from verify.records.results import bare_case

    detail = next((m.detail for m in found if m.field.split("[")[0] in ("impact_sets", "betas")), "")
    match = re.search(r"(?:impulse|sweep) (\d+)", detail)
    if not match:
        return ""
    w = int(match.group(1))
    law = law_of_record(exact)
    if isinstance(law, Sequential):
        law = dataclasses.replace(law, iterations=max(1, min(w, law.iterations)))
    c = bare_case(case)
    run = solve(c.system, c.velocity_source, law=law, max_iterations=w, certify=False)
    K = run.backend
    if isinstance(law, Sequential):
        from verify.oracle.bookkeeping import hint

        settled = "" if len(run.steps) >= w else ": the exact impulses have settled (no sweep changes them)"
        impulses = ", ".join(_value_text(K, x) for x in run.impulses or ())
        return (
            f"; the exact run after sweep {min(w, len(run.steps))}{settled}: accumulated impulses ({impulses})"
            + hint(case, exact, mine, lead="at the end")
        )
    if len(run.steps) >= w:
        step = run.steps[w - 1]
        shown = ", ".join(_value_text(K, x) for x in step.rates)
        beta = "a single impact" if step.beta is None else f"beta = {_value_text(K, step.beta)}"
        return f"; the exact run there: rates p(F) = ({shown}), {beta}"
    shown = ", ".join(_value_text(K, x) for x in run.system.rates(run.exit_velocity))
    return f"; the exact run there: rates p(F) = ({shown}): it has exited (no rate is negative)"


def _value_text(K: Backend, x: Any) -> str:
    """An exact value as its exact string when short, else ``~`` and 6 significant digits."""
    if K.is_exact:
        text = K.to_exact(x)
        if len(text) <= 24:
            return text
    return "~" + K.to_decimal(x, 6)


@dataclass(frozen=True)
class TableRow:
    """One implementation in an error table: its counts per class and its worst errors."""

    name: str
    law: str
    counts: dict[str, int]
    worst_speed: tuple[Fraction, str] | None  # (needed tolerance relative to the exit speed, case)
    worst_ulps: tuple[int, str] | None

    def to_json(self) -> dict[str, Any]:
        from verify.numbers.format import format_decimal

        return {
            "name": self.name,
            "law": self.law,
            "classes": self.counts,
            "worst_relative_error": None
            if self.worst_speed is None
            else {"value": format_decimal(self.worst_speed[0], 3), "id": self.worst_speed[1]},
            "worst_ulps": None if self.worst_ulps is None else {"value": self.worst_ulps[0], "id": self.worst_ulps[1]},
        }


def table_row(name: str, law: str, comparison: Any) -> TableRow:
    """The error-table row of one implementation's comparison (:func:`verify.oracle.reference.compare`)."""
    measured = [g for g in comparison.grades if g.needed_speed is not None]
    speed = max(((g.needed_speed, g.case_id) for g in measured), default=None)
    ulp_worst = max(((g.needed_ulps, g.case_id) for g in measured if g.needed_ulps is not None), default=None)
    return TableRow(name, law, comparison.classes(), speed, ulp_worst)


def hardest(grades: list[Grade], count: int = 5) -> list[Grade]:
    """The cases that need the largest tolerance to pass (relative to the exit speed), largest first."""
    measured = [g for g in grades if g.needed_speed]  # a case that needs no tolerance is not listed
    return sorted(measured, key=lambda g: (-(g.needed_speed or 0), g.case_id))[:count]


#: the default tolerances of ``verify oracle check`` (docs/oracle.md, "The tolerance"): a component of the
#: exit velocity within ``DEFAULT_RTOL`` of the exact exit speed, a component that is exactly 0 also within
#: ``DEFAULT_FLOOR`` of the entrance speed, a beta within ``DEFAULT_BETA`` of its exact value (relative)
DEFAULT_RTOL = Fraction(1, 10**8)
DEFAULT_FLOOR = Fraction(1, 10**12)
DEFAULT_BETA = Fraction(1, 10**9)


@dataclass(frozen=True)
class Tolerance:
    """What the exit velocity and the betas of one case may be off by. A component passes within the
    largest of ``atol + rtol * |v_exit|`` (``|v_exit|`` the exact exit speed, ``max_i |exact_i|``),
    ``speed * |v_exit|`` and ``ulps`` binary64 ulps of the exact component; a component that is exactly
    0 also within ``atol + floor * |v_in|`` (``|v_in|`` the entrance speed, ``max_i |v_in_i|``: an exit
    speed of 0 has no digits to be relative to). A beta passes within ``beta`` times its exact value,
    whatever the velocity's tolerance.

    >>> t = Tolerance(rtol=Fraction(0), ulps=4)
    >>> t.allows(Fraction(1) + 4 * ulp(Fraction(1)), Fraction(1), Fraction(1), Fraction(1))
    True
    >>> d = Tolerance()
    >>> d.allows(Fraction(100) * (1 + Fraction(9, 10**5)), Fraction(100), Fraction(10**4), Fraction(100))
    False
    >>> d.allows(Fraction(1, 10**10), Fraction(0), Fraction(100), Fraction(0))
    True
    """

    rtol: Fraction = DEFAULT_RTOL
    atol: Fraction = Fraction(0)
    speed: Fraction = Fraction(0)
    ulps: int = 0
    beta: Fraction = DEFAULT_BETA
    floor: Fraction = DEFAULT_FLOOR

    def bound(self, exact: Fraction, entrance: Fraction, exit_speed: Fraction) -> Fraction:
        """The largest error allowed on a component whose exact value is ``exact``."""
        relative = self.rtol * exit_speed
        if exact == 0:
            relative = max(relative, self.floor * entrance)
        return max(
            self.atol + relative,
            self.speed * exit_speed,
            self.ulps * ulp(max(abs(exact), exit_speed / 2**53)),
        )

    def allows(self, got: Fraction, exact: Fraction, entrance: Fraction, exit_speed: Fraction) -> bool:
        return abs(got - exact) <= self.bound(exact, entrance, exit_speed)

    @property
    def beta_rtol(self) -> Fraction:
        """The tolerance of a beta, relative to its exact value (its own field, not ``rtol``)."""
        return self.beta

    def describe(self) -> str:
        """The basis of the tolerance in one line (the summary of ``verify oracle check``).

        >>> print(Tolerance().describe())
        |got_i - exact_i| <= 1e-8 |v_exit| (the exact exit speed, max_i |exact_i|); where exact_i = 0,
        also <= 1e-12 |v_in| (the entrance speed); beta within 1e-9 of the exact beta, relative
        >>> print(Tolerance(rtol=Fraction(0), floor=Fraction(0)).describe())
        |got_i - exact_i| <= 0; beta within 1e-9 of the exact beta, relative
        """
        plus = f"{short_number(self.atol)} + " if self.atol else ""
        if self.rtol:
            out = (
                f"|got_i - exact_i| <= {plus}{short_number(self.rtol)} |v_exit| (the exact exit speed, max_i |exact_i|)"
            )
        else:
            out = f"|got_i - exact_i| <= {short_number(self.atol)}"
        extra = [f"{short_number(self.speed)} |v_exit|"] if self.speed else []
        extra += [f"{self.ulps} binary64 ulps of exact_i"] if self.ulps else []
        if extra:
            out += ", or " + ", or ".join(extra)
        if self.floor:
            out += f"; where exact_i = 0, also <= {plus}{short_number(self.floor)} |v_in| (the entrance speed)"
        return out + f"; beta within {short_number(self.beta)} of the exact beta, relative"


def short_number(x: Fraction) -> str:
    """A tolerance in a few characters, computed exactly: decimals from 0.001 up, else ``M e-K``.

    >>> [short_number(x) for x in (Fraction(1, 10**9), Fraction(0), Fraction(25, 10**5), Fraction(1, 3 * 10**7))]
    ['1e-9', '0', '0.00025', '3.33333e-8']
    """
    from verify.numbers.format import format_decimal

    if x == 0 or x >= Fraction(1, 10**5):
        return format_decimal(x, 6)
    e = 0
    while x * 10**e < 1:
        e += 1
    return f"{format_decimal(x * 10**e, 6)}e-{e}"


def _tolerance(spec: Any, where: str, base: Tolerance) -> Tolerance:
    """A tolerance from its JSON object (``rtol``, ``atol``, ``speed``, ``floor``, ``beta``: number strings;
    ``ulps``: an integer), the fields not given taken from ``base``."""
    from verify.errors import InvalidInput
    from verify.records.results import read_number

    if not isinstance(spec, dict):
        raise InvalidInput(f"{where}: expected an object")
    known = {"rtol", "atol", "speed", "ulps", "beta", "floor"}
    unknown = sorted(set(spec) - known)
    if unknown:
        raise InvalidInput(f"{where}: unknown field {unknown[0]!r} (known: {', '.join(sorted(known))})")
    values: dict[str, Any] = {}
    for key in ("rtol", "atol", "speed", "beta", "floor"):
        if key in spec:
            if not isinstance(spec[key], str):
                raise InvalidInput(f'{where}.{key}: expected a number string such as "1e-9"')
            values[key] = read_number(spec[key], f"{where}.{key}")
            if values[key] < 0:
                raise InvalidInput(f"{where}.{key}: must not be negative, got {spec[key]}")
    if "ulps" in spec:
        if isinstance(spec["ulps"], bool) or not isinstance(spec["ulps"], int) or not 0 <= spec["ulps"] <= 2**60:
            raise InvalidInput(f"{where}.ulps: expected a non-negative integer, got {spec['ulps']!r}")
        values["ulps"] = spec["ulps"]
    return Tolerance(**{**base.__dict__, **values})


@dataclass(frozen=True)
class Budgets:
    """Tolerances as data: a default, and others for the cases whose id matches a pattern (shell-style,
    ``cradle3-*``; the first pattern that matches wins). Read from a file by :meth:`load`:

        {"default": {"rtol": "1e-9", "ulps": 4},
         "cases": {"cradle3-eps-*": {"speed": "1e-12"}, "corner-*": {"ulps": 4096, "beta": "1e-6"}}}

    >>> b = Budgets.parse({"default": {"ulps": 4}, "cases": {"c*": {"ulps": 64}}})
    >>> b.for_case("c3").ulps, b.for_case("d").ulps
    (64, 4)
    """

    default: Tolerance = Tolerance()
    cases: tuple[tuple[str, Tolerance], ...] = ()

    def for_case(self, case_id: str) -> Tolerance:
        from fnmatch import fnmatchcase

        return next((t for pattern, t in self.cases if fnmatchcase(case_id, pattern)), self.default)

    @classmethod
    def parse(cls, data: Any, source: str = "tolerances", base: Tolerance | None = None) -> Budgets:
        from verify.errors import InvalidInput

        if not isinstance(data, dict) or set(data) - {"default", "cases"}:
            raise InvalidInput(f'{source}: expected {{"default": {{...}}, "cases": {{"PATTERN": {{...}}}}}}')
        default = _tolerance(data.get("default", {}), f"{source}.default", base or Tolerance())
        patterns = data.get("cases", {})
        if not isinstance(patterns, dict):
            raise InvalidInput(f"{source}.cases: expected an object of id patterns")
        return cls(default, tuple((p, _tolerance(t, f"{source}.cases[{p!r}]", default)) for p, t in patterns.items()))

    @classmethod
    def load(cls, path: str, base: Tolerance | None = None) -> Budgets:
        """Read a tolerance file (errors name the file and the field)."""
        from verify.records.files import load_json

        return cls.parse(load_json(path, path=path), path, base)
