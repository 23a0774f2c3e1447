"""Result records: the JSON shape described in ``docs/records.md`` (in the source repository).

A result record carries the exit velocity (exact strings on exact backends, decimals
otherwise), its decimals with 30 significant digits, the iteration count, the impact sets
(0-based), beta per impulse (``null`` for single impacts), the stop reason and the
kinetic energies in and out. Two fields are added beyond the contract's example:
``backend`` (which backend produced it) and ``rigorous`` (whether every branch was
decided exactly or with proof); interval results also carry ``exit_velocity_enclosure``
and any run carries ``notes`` when there is something to say (precision raised).

>>> from verify.models.cradle import run_cradle
>>> rec = result_record(run_cradle("1/2"), "cradle")
>>> rec["exit_velocity"], rec["impact_sets"], rec["stop"]
(['325/16', '375/16', '225/4'], [[0], [1], [0]], 'exit')
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput
from verify.laws.outcome import Result
from verify.laws.rule import DEFAULT_MAX_ITERATIONS
from verify.numbers.backends.base import Backend

DECIMAL_DIGITS = 30


@dataclass(frozen=True)
class Case:
    """A case read from a case record: its id, system, velocity and iteration cap."""

    id: str
    system: Any
    velocity_source: Any
    velocity: tuple[Any, ...]
    max_iterations: int
    #: the sequential law's settings of this case (its record's ``law_settings``), or None
    law_settings: dict[Any, Any] | None = None


def value_string(K: Backend, x: Any, digits: int = DECIMAL_DIGITS) -> str:
    """The exact string of ``x`` on exact backends, its decimal string otherwise."""
    return K.to_exact(x) if K.is_exact else K.to_decimal(x, digits)


_RATIONAL = re.compile(r"-?\d+(/\d+)?")
_HEX_FLOAT = re.compile(r"([+-]?)0[xX]([0-9a-fA-F]*)(?:\.([0-9a-fA-F]*))?(?:[pP]([+-]?\d+))?")


def is_rational_text(text: str) -> bool:
    """Whether a number string is a rational written as ``p`` or ``p/q`` (a closed form is not).

    >>> is_rational_text("-3/4"), is_rational_text("sqrt(2)")
    (True, False)
    """
    return bool(_RATIONAL.fullmatch(text))


def read_number(text: str, where: str | None = None) -> Fraction:
    """A number string of a result record as a Fraction: an exact rational of any length as it
    is (``verify``'s own records hold runs of thousands of digits), a decimal or a float's
    shortest string exactly as written, a closed form to 40 digits; BadNumber names ``where``
    for ``nan`` or ``inf``.

    A C program's hexadecimal float (``%a``: ``0x1.8p+1``) is read exactly too.

    >>> read_number("0.1"), read_number("-1/3"), Fraction(14142, 10**4) < read_number("sqrt(2)") < 2
    (Fraction(1, 10), Fraction(-1, 3), True)
    >>> read_number("0x1.8p+1"), read_number("-0x1p-2")
    (Fraction(3, 1), Fraction(-1, 4))
    >>> read_number("nan", "v[0]")
    Traceback (most recent call last):
    ...
    verify.errors.BadNumber: v[0]: 'nan' is not a finite number (NaN or an infinity)
    """
    from verify.errors import BadNumber
    from verify.numbers.format import format_decimal, str_to_int
    from verify.numbers.parse import parse_number, to_number

    prefix = f"{where}: " if where else ""
    if _RATIONAL.fullmatch(text):
        num, _, den = text.partition("/")
        if den and str_to_int(den) == 0:
            raise BadNumber(f"{prefix}{text!r} divides by zero")
        return Fraction(str_to_int(num), str_to_int(den) if den else 1)
    if text.strip().lower().lstrip("+-") in ("nan", "inf", "infinity"):
        raise BadNumber(f"{prefix}{text!r} is not a finite number (NaN or an infinity)")
    hexadecimal = _HEX_FLOAT.fullmatch(text.strip())
    if hexadecimal and (hexadecimal.group(2) or hexadecimal.group(3)):
        sign, whole, frac, exp = hexadecimal.groups()
        digits = whole + (frac or "")
        value = Fraction(int(digits, 16), 16 ** len(frac or "")) * Fraction(2) ** int(exp or "0")
        return -value if sign == "-" else value
    value = to_number(parse_number(text, where=where), where=where)
    return value if isinstance(value, Fraction) else Fraction(format_decimal(value, 40))


def result_record(result: Result, case_id: str, *, digits: int = DECIMAL_DIGITS) -> dict[str, Any]:
    """The result record of the contracts for one run."""
    K = result.backend
    record: dict[str, Any] = {
        "id": case_id,
        "exit_velocity": [value_string(K, x, digits) for x in result.exit_velocity],
        "exit_velocity_decimal": [K.to_decimal(x, digits) for x in result.exit_velocity],
        "iterations": result.iterations,
        "impact_sets": [list(J) for J in result.impact_sets],
        "betas": [None if b is None else value_string(K, b, digits) for b in result.betas],
        "stop": result.stop,
        "kinetic_energy_in": value_string(K, result.kinetic_energy_in, digits),
        "kinetic_energy_out": value_string(K, result.kinetic_energy_out, digits),
        "backend": K.describe(),
        "rigorous": K.is_rigorous,
    }
    if K.encloses:
        record["exit_velocity_enclosure"] = [list(K.enclosure(x, digits)) for x in result.exit_velocity]
    if result.notes:
        record["notes"] = list(result.notes)
    if result.certificate is not None:
        record["certificate"] = result.certificate
    if result.law != "rule":  # the rule's records keep the contract's fields only
        record["law"] = result.law
        record["impulses"] = [value_string(K, x, digits) for x in result.impulses or ()]
    if result.sequential is not None:
        record["law_settings"] = result.sequential.settings(result.system.r)
    return record


def corner_record(run: Any, case_id: str = "corner") -> dict[str, Any]:
    """The result record of a corner run (:class:`verify.models.corner.CornerRun`) with the zones
    visited, whether multiple impacts repeat, and the run's notes (``verify corner --json``)."""
    record = result_record(run.result, case_id)
    record["zones"] = run.zones
    record["repeated_multiple_impacts"] = run.repeated_multiple_impacts
    if run.notes:
        record["notes"] = run.notes
    return record


def dumps(obj: Any) -> str:
    """JSON text as written by :mod:`verify`: sorted keys, two-space indentation, final newline."""
    return json.dumps(obj, indent=2, sort_keys=True, ensure_ascii=False) + "\n"


# -- case records (input) ---------------------------------------------------------------------

#: the annotation fields a case record may carry: each a string for people to read, which the rule
#: does not read (``why`` says why a generated case is hard); any other unknown field is refused
ANNOTATION_FIELDS = ("why", "comment", "note", "source")
CASE_FIELDS = {"id", "mass_matrix", "normals", "time_terms", "restitution", "velocity", "max_iterations",
               "names", "decimal", "law_settings", *ANNOTATION_FIELDS}  # fmt: skip
REQUIRED_FIELDS = ("id", "mass_matrix", "normals", "restitution", "velocity")


def case_record(
    case_id: str,
    mass_matrix: Sequence[Sequence[Any]],
    normals: Sequence[Sequence[Any]],
    restitution: Sequence[Any],
    velocity: Sequence[Any],
    *,
    time_terms: Sequence[Any] | None = None,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    names: Sequence[str] | None = None,
) -> dict[str, Any]:
    """The case record (contracts) of a system's exact inputs and a velocity: every number as
    its exact string, the time terms 0 unless given, the contacts' ``names`` when given. The one
    place that writes case records.

    >>> from fractions import Fraction
    >>> r = case_record("a", [[1]], [[1]], [Fraction(1, 2)], [-2], max_iterations=5)
    >>> r["time_terms"], r["restitution"], r["velocity"], r["max_iterations"], "names" in r
    (['0'], ['1/2'], ['-2'], 5, False)
    >>> case_record("b", [[1]], [[1]], [1], [-1], names=["floor"])["names"]
    ['floor']
    """
    from verify.numbers.format import format_exact

    named = {"names": list(names)} if names is not None else {}
    return {
        "id": case_id,
        "mass_matrix": [[format_exact(x) for x in row] for row in mass_matrix],
        "normals": [[format_exact(x) for x in row] for row in normals],
        "time_terms": [format_exact(x) for x in (time_terms if time_terms is not None else [0] * len(normals))],
        "restitution": [format_exact(x) for x in restitution],
        "velocity": [format_exact(x) for x in velocity],
        "max_iterations": max_iterations,
        **named,
    }


# -- decimals beside the exact strings of a case (verify oracle export, verify oracle generate) -----

#: significant digits of the decimals of a case's ``decimal`` object: binary64 needs 17 to be
#: read back to the nearest double, IEEE binary128 36
CASE_DECIMAL_DIGITS = 40
#: the fields of a case record that hold numbers (rows of exact strings)
CASE_NUMBER_FIELDS = ("mass_matrix", "normals", "time_terms", "restitution", "velocity")
_PLAIN_DECIMAL = re.compile(r"-?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")


def exact_decimal(text: str, digits: int = CASE_DECIMAL_DIGITS, where: str | None = None) -> str:
    """The value of the exact number string ``text``, correctly rounded (half to even) to ``digits``
    significant digits, from the exact value (rationals in integer arithmetic, closed forms from
    certified enclosures: :func:`verify.numbers.format.format_decimal`); trailing zeros dropped, an
    exponent outside [1e-7, 1e30). ``strtod`` reads it.

    >>> exact_decimal("1/3"), exact_decimal("-25*sqrt(2) + 25*sqrt(6)", 20), exact_decimal("1/2")
    ('0.3333333333333333333333333333333333333333', '25.881904510252076235', '0.5')
    """
    from verify.numbers.format import format_decimal
    from verify.numbers.parse import parse_number

    return format_decimal(parse_number(text, where=where), digits)


def _decimals_of(value: Any, digits: int, where: str) -> Any:
    if isinstance(value, list):
        return [_decimals_of(x, digits, f"{where}[{i}]") for i, x in enumerate(value)]
    return exact_decimal(value, digits, where)


def case_decimals(record: dict[str, Any], digits: int = CASE_DECIMAL_DIGITS) -> dict[str, Any]:
    """The ``decimal`` object of a case record: ``digits``, and for each number field of the record
    (:data:`CASE_NUMBER_FIELDS`) the same rows with each exact string correctly rounded to ``digits``
    significant digits (:func:`exact_decimal`), for readers without an expression parser.

    >>> case_decimals({"id": "a", "mass_matrix": [["1"]], "normals": [["sqrt(2)"]], "restitution": ["1/3"],
    ...                "velocity": ["-2"]}, 10)
    {'digits': 10, 'mass_matrix': [['1']], 'normals': [['1.414213562']], 'restitution': ['0.3333333333'],
     'velocity': ['-2']}
    """
    out: dict[str, Any] = {"digits": digits}
    for name in CASE_NUMBER_FIELDS:
        if name in record:
            out[name] = _decimals_of(record[name], digits, name)
    return out


def with_decimals(record: dict[str, Any], digits: int = CASE_DECIMAL_DIGITS) -> dict[str, Any]:
    """The case record with its ``decimal`` object (:func:`case_decimals`): what ``verify oracle
    export`` and ``verify oracle generate`` write."""
    return {**record, "decimal": case_decimals(record, digits)}


def _check_decimal_rows(given: Any, exact: Any, digits: int, where: str, field: str) -> None:
    if isinstance(exact, list):
        if not isinstance(given, list) or len(given) != len(exact):
            shown = f"{len(given)} entries" if isinstance(given, list) else type(given).__name__
            raise InvalidInput(f"{where}: expected {len(exact)} entries, as {field} has, got {shown}")
        for i, (g, e) in enumerate(zip(given, exact)):
            _check_decimal_rows(g, e, digits, f"{where}[{i}]", f"{field}[{i}]")
        return
    if not isinstance(given, str) or not _PLAIN_DECIMAL.fullmatch(given):
        raise InvalidInput(f'{where}: expected a decimal such as "0.25" or "1.5e-9", got {given!r}')
    expected = exact_decimal(exact, digits, field)
    if Fraction(given) != Fraction(expected):
        raise InvalidInput(
            f"{where}: {given!r} is not {field} = {exact!r} correctly rounded to {digits} significant digits "
            f"({expected!r})"
        )


def check_decimals(record: dict[str, Any], where: str = "case") -> None:
    """Refuse a ``decimal`` object that does not hold exactly the case's numbers: the same number
    fields, the same shapes, each decimal the exact string's value correctly rounded to
    ``digits`` significant digits (the same value as :func:`exact_decimal`'s, trailing zeros free).

    >>> r = with_decimals({"id": "a", "mass_matrix": [["1"]], "normals": [["1"]], "restitution": ["1/3"],
    ...                    "velocity": ["-2"]}, 5)
    >>> check_decimals(r)
    >>> check_decimals(dict(r, decimal=dict(r["decimal"], restitution=["0.3333"])))
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: case.decimal.restitution[0]: '0.3333' is not restitution[0] = '1/3' correctly
    rounded to 5 significant digits ('0.33333')
    """
    given = record["decimal"]
    here = f"{where}.decimal"
    if not isinstance(given, dict):
        raise InvalidInput(f"{here}: expected an object, got {type(given).__name__}")
    digits = given.get("digits")
    if isinstance(digits, bool) or not isinstance(digits, int) or not 1 <= digits <= 1000:
        raise InvalidInput(f"{here}.digits: expected an integer from 1 to 1000, got {digits!r}")
    unknown = sorted(set(given) - {"digits", *CASE_NUMBER_FIELDS})
    if unknown:
        raise InvalidInput(f"{here}: unknown field {unknown[0]!r}")
    for name in CASE_NUMBER_FIELDS:
        if (name in record) != (name in given):
            what = "missing field" if name in record else "a field the case does not have:"
            raise InvalidInput(f"{here}: {what} {name!r}")
        if name in record:
            _check_decimal_rows(given[name], record[name], digits, f"{here}.{name}", name)


def _prefixed(where: str, exc: InvalidInput) -> InvalidInput:
    text = str(exc)
    return type(exc)(f"{where}.{text}") if not text.startswith(where) else exc


def case_from_record(record: Any, where: str = "case", *, backend: Any = "exact", dps: int | None = None) -> Case:
    """A case record (contracts) as a :class:`Case`; errors name the case and field.

    >>> c = case_from_record({"id": "a", "mass_matrix": [["1"]], "normals": [["1"]],
    ...                       "restitution": ["1/2"], "velocity": ["-2"]})
    >>> c.id, c.max_iterations
    ('a', 10000)
    """
    from verify.dynamics.system import System

    if not isinstance(record, dict):
        raise InvalidInput(f"{where}: expected an object, got {type(record).__name__}")
    unknown = sorted(set(record) - CASE_FIELDS)
    if unknown:
        raise InvalidInput(f"{where}: unknown field {unknown[0]!r}")
    missing = [f for f in REQUIRED_FIELDS if f not in record]
    if missing:
        raise InvalidInput(f"{where}: missing field {missing[0]!r}")
    for name in ANNOTATION_FIELDS:
        if name in record and not isinstance(record[name], str):
            raise InvalidInput(f"{where}.{name}: an annotation is a string, got {type(record[name]).__name__}")
    case_id = record["id"]
    if not isinstance(case_id, str) or not case_id:
        raise InvalidInput(f"{where}.id: expected a non-empty string")
    cap = record.get("max_iterations", DEFAULT_MAX_ITERATIONS)
    if isinstance(cap, bool) or not isinstance(cap, int) or cap < 0:
        raise InvalidInput(f"{where}.max_iterations: expected a non-negative integer, got {cap!r}")
    try:
        system = System(
            record["mass_matrix"],
            record["normals"],
            record["restitution"],
            record.get("time_terms"),
            backend=backend,
            dps=dps,
            names=record.get("names"),
        )
        if system.backend.widens_to_inputs:  # a velocity outside the field of the system widens it
            from verify.dynamics.system import exact_backend_for_velocity

            system, velocity = exact_backend_for_velocity(system, record["velocity"])
        else:
            velocity = system.velocity(record["velocity"])
    except InvalidInput as exc:
        raise _prefixed(where, exc) from None
    if "decimal" in record:  # every number read: the decimals beside them must be theirs
        check_decimals(record, where)
    settings = record.get("law_settings")
    if settings is not None:
        from verify.laws.sequential import case_settings

        try:
            case_settings(settings, system.r)
        except InvalidInput as exc:
            raise InvalidInput(f"{where}.law_settings: {exc}") from None
    return Case(case_id, system, record["velocity"], velocity, cap, settings)


#: the fields of a case record that the rule reads
RULE_FIELDS = ("id", "mass_matrix", "normals", "time_terms", "restitution", "velocity", "max_iterations")


def bare_case(record: dict[str, Any]) -> Case:
    """The case of a record from the fields the rule reads alone (annotations, decimals and the sequential
    law's own settings left out): for a run that replays or varies a case already read.

    >>> bare_case({"id": "a", "mass_matrix": [["1"]], "normals": [["1"]], "restitution": ["1"],
    ...            "velocity": ["-2"], "why": "a note", "law_settings": {"iterations": 2}}).law_settings is None
    True
    """
    return case_from_record({k: v for k, v in record.items() if k in RULE_FIELDS}, f"case {record.get('id')}")


def load_cases(path: str, *, backend: Any = "exact", dps: int | None = None) -> list[Case]:
    """Read a case file ``{"cases": [...]}`` (``-``: standard input); every error names the file, case and
    field."""
    from verify.records.files import STDIO, display_name, load_json, read_text
    from verify.records.schema import validate
    from verify.records.versions import check_versions

    name = display_name(path)
    if path == STDIO:  # a bare NaN: the schema names its field
        data = load_json(name, text=read_text(path), constants=True)
    else:
        data = load_json(name, path=path, constants=True)
    path = name
    if not isinstance(data, dict) or not isinstance(data.get("cases"), list):
        raise InvalidInput(f'{path}: expected an object {{"cases": [...]}}')
    check_versions(data, path)  # first: a newer file's new fields are not what is wrong with it
    validate(data, "case", path)
    check_case_ids(data["cases"], path)
    return [case_from_record(c, f"{path}: cases[{i}]", backend=backend, dps=dps) for i, c in enumerate(data["cases"])]


def check_case_ids(records: list[Any], path: str) -> None:
    """A case file holds at least one case, and each id once (a result is matched to its case by id).

    >>> check_case_ids([{"id": "a"}, {"id": "a"}], "c.json")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: c.json: cases[1].id: 'a' is the id of cases[0] too (each case needs its own id)
    >>> check_case_ids([], "c.json")
    Traceback (most recent call last):
    ...
    verify.errors.InvalidInput: c.json: no cases ("cases" is empty): nothing to run or check
    """
    if not records:
        raise InvalidInput(f'{path}: no cases ("cases" is empty): nothing to run or check')
    seen: dict[Any, int] = {}
    for i, record in enumerate(records):
        case_id = record.get("id") if isinstance(record, dict) else None
        if isinstance(case_id, str) and case_id in seen:
            raise InvalidInput(
                f"{path}: cases[{i}].id: {case_id!r} is the id of cases[{seen[case_id]}] too "
                "(each case needs its own id)"
            )
        seen.setdefault(case_id, i)
