"""Numbers that a reader without an expression parser can use (issue 34, item 4): every exported case
(``verify oracle export``, ``verify oracle generate``) carries beside its exact strings their values
correctly rounded to 40 significant digits (``decimal``), and the exact strings follow the grammar
that docs/oracle.md names.

Correct rounding is checked here independently of the code that writes the decimals: by exact
comparisons of the exact value (a Fraction, or a real algebraic number given by its minimal
polynomial and an isolating interval) with the rounding interval of each decimal.
"""

from __future__ import annotations

import json
import math
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from verify.cli import main
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.parse import parse_number
from verify.oracle.hardcases import generate_file_text
from verify.records.results import CASE_DECIMAL_DIGITS, CASE_NUMBER_FIELDS

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "golden"


class Exact:
    """An exact number string's value, compared exactly with rationals."""

    def __init__(self, text: str):
        value = parse_number(text)
        self.rational = value if isinstance(value, Fraction) else None
        self.algebraic = None if self.rational is not None else RealAlgebraic.from_number(value)

    def cmp(self, q: Fraction) -> int:
        """-1, 0 or 1 as the value is below, at or above q."""
        if self.rational is not None:
            return (self.rational > q) - (self.rational < q)
        assert self.algebraic is not None
        return self.algebraic.cmp(RealAlgebraic.rational(q))


def assert_correctly_rounded(text: str, decimal: str, digits: int) -> None:
    """``decimal`` is the exact value of ``text`` rounded half to even to ``digits`` significant digits."""
    x, d = Exact(text), Fraction(decimal)  # Fraction reads "1.5e-9" exactly
    sign = x.cmp(Fraction(0))
    if sign == 0:
        assert d == 0, f"{text} is 0, not {decimal}"
        return
    e = math.floor(math.log10(abs(d))) if d else 0  # a first guess of the decade of |x|, set exactly below
    while sign * x.cmp(sign * Fraction(10) ** e) < 0:
        e -= 1
    while sign * x.cmp(sign * Fraction(10) ** (e + 1)) >= 0:
        e += 1
    unit = Fraction(10) ** (e - digits + 1)  # one unit in the last of `digits` places of x
    steps = d / unit
    assert steps.denominator == 1, f"{decimal} is not on the grid of {digits} digits of {text}"
    below, above = x.cmp(d - unit / 2), x.cmp(d + unit / 2)
    assert below >= 0 and above <= 0, f"{decimal} is not within half a unit of {text}"
    if below == 0 or above == 0:  # a tie: to even
        assert steps.numerator % 2 == 0, f"{text} is a tie, rounded to odd {decimal}"


def assert_nearest_double(text: str, decimal: str) -> None:
    """strtod of the decimal (Python's float() rounds correctly) is the binary64 nearest to the exact value."""
    x, f = Exact(text), float(decimal)
    if f == 0:
        assert x.cmp(Fraction(0)) == 0 or abs(Fraction(decimal)) < Fraction(math.ulp(0.0)) / 2
        return
    half = Fraction(math.ulp(f)) / 2
    assert x.cmp(Fraction(f) - half) >= 0 and x.cmp(Fraction(f) + half) <= 0, f"{decimal} -> {f!r} for {text}"


def pairs(exact: Any, decimal: Any, where: str) -> list[tuple[str, str, str]]:
    """(where, exact string, decimal) for each number of two rows of the same shape."""
    if isinstance(exact, list):
        assert isinstance(decimal, list) and len(decimal) == len(exact), where
        return [p for i, (a, b) in enumerate(zip(exact, decimal)) for p in pairs(a, b, f"{where}[{i}]")]
    return [(where, exact, decimal)]


def exported_cases() -> dict[str, list[dict[str, Any]]]:
    return {
        "golden/cases.json": json.loads((GOLDEN / "cases.json").read_text(encoding="utf-8"))["cases"],
        "verify oracle generate --level 1 --seed 0": json.loads(generate_file_text(1, 0))["cases"],
    }


@pytest.mark.parametrize("source", list(exported_cases()))
def test_every_exported_number_has_its_correctly_rounded_decimal(source: str) -> None:
    cases = exported_cases()[source]
    checked = 0
    for c in cases:
        dec = c["decimal"]
        assert dec["digits"] == CASE_DECIMAL_DIGITS >= 36  # IEEE binary128 needs 36 significant digits
        assert set(dec) == {"digits", *(f for f in CASE_NUMBER_FIELDS if f in c)}
        for name in CASE_NUMBER_FIELDS:
            for where, text, decimal in pairs(c.get(name, []), dec.get(name, []), f"{c['id']}.{name}"):
                assert re.fullmatch(r"-?(\d+(\.\d+)?)(e[-+]\d+)?", decimal), f"{where}: {decimal!r}"
                assert_correctly_rounded(text, decimal, dec["digits"])
                assert_nearest_double(text, decimal)
                checked += 1
    assert checked > 500 and any("sqrt" in t for c in cases for row in [c["velocity"], *c["normals"]] for t in row)


def test_the_check_of_correct_rounding_can_fail() -> None:
    assert_correctly_rounded("1/3", "0.333", 3)
    assert_correctly_rounded("5/2", "2", 1)  # a tie, to even
    assert_correctly_rounded("sqrt(2)", "1.41421", 6)
    assert_correctly_rounded("999/1000", "1", 2)  # carried into a new digit
    for text, decimal, digits in [("1/3", "0.334", 3), ("5/2", "3", 1), ("sqrt(2)", "1.41422", 6),
                                  ("sqrt(2)", "1.4142", 6), ("2/3", "0.66", 3)]:  # fmt: skip
        with pytest.raises(AssertionError):
            assert_correctly_rounded(text, decimal, digits)


# -- the exact strings: the grammar that docs/oracle.md names ---------------------------------------------


def documented_grammar() -> re.Pattern[str]:
    """The grammar block of docs/oracle.md (section "Reading the numbers of a case") as a regular
    expression: its rules ``name = ...`` with quoted literals, rule names, ``[ ]`` (optional),
    ``{ }`` (repeated) and ``|``; ``digits`` is one or more decimal digits."""
    page = (ROOT / "docs" / "oracle.md").read_text(encoding="utf-8")
    section = page[page.index("### Reading the numbers of a case") :]
    block = re.search(r"```\n(.*?)```", section, re.DOTALL)
    assert block is not None
    rules = dict(re.fullmatch(r"(\w+)\s*=\s*(.+)", line).groups() for line in block.group(1).splitlines())  # type: ignore[union-attr]
    assert next(iter(rules)) == "exact"
    brackets = {"[": "(?:", "]": ")?", "{": "(?:", "}": ")*", "(": "(?:", ")": ")", "|": "|"}

    def regex(name: str) -> str:
        if name == "digits":
            return r"\d+"
        out = ""
        for literal, word, mark in re.findall(r'"([^"]*)"|(\w+)|([\[\]{}()|])', rules[name]):
            out += re.escape(literal) if literal else regex(word) if word else brackets[mark]
        return f"(?:{out})"

    return re.compile(regex("exact"))


def exact_strings() -> list[str]:
    out = []
    for cases in exported_cases().values():
        for c in cases:
            out += [t for name in CASE_NUMBER_FIELDS for where, t, _ in pairs(c.get(name, []), c.get(name, []), "")]
    for name in ("results.json", "results-simultaneous.json"):
        for r in json.loads((GOLDEN / name).read_text(encoding="utf-8"))["results"]:
            out += r["exit_velocity"] + [b for b in r["betas"] if b is not None] + r.get("impulses", [])
            out += [r["kinetic_energy_in"], r["kinetic_energy_out"]]
    return out


def test_every_exact_string_follows_the_documented_grammar() -> None:
    grammar = documented_grammar()
    strings = exact_strings()
    assert any("sqrt" in s for s in strings) and any("/" in s for s in strings) and any("." in s for s in strings)
    assert [s for s in strings if not grammar.fullmatch(s)] == []
    for bad in ("sqrt(2)/2 + pi", "CRootOf(x**2 - 2, 1)", "1e-9", "-sqrt(3)/3 +1", "(1 + sqrt(5))/2"):
        assert not grammar.fullmatch(bad)  # the grammar is not everything numbers.md accepts


def test_the_example_of_the_page_is_the_golden_case() -> None:
    page = (ROOT / "docs" / "oracle.md").read_text(encoding="utf-8")
    section = page[page.index("### Reading the numbers of a case") :]
    block = re.search(r"```json\n(.*?)```", section, re.DOTALL)
    assert block is not None
    shown = json.loads(block.group(1))
    (case,) = [c for c in exported_cases()["golden/cases.json"] if c["id"] == "paper-corner-pi6-pi12"]
    decimal = {"digits": case["decimal"]["digits"], "velocity": case["decimal"]["velocity"]}
    assert shown == {"velocity": case["velocity"], "decimal": decimal}


# -- a decimal that is not the exact value's is refused ------------------------------------------------------


def write_case(tmp_path: Path, change: Any) -> Path:
    case = json.loads((GOLDEN / "cases.json").read_text(encoding="utf-8"))["cases"][17]
    change(case)
    path = tmp_path / "cases.json"
    path.write_text(json.dumps({"cases": [case]}), encoding="utf-8")
    return path


def set_velocity(case: dict[str, Any], text: str) -> None:
    case["velocity"][0] = text


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (
            lambda c: c["decimal"]["velocity"].__setitem__(0, "1"),
            r"cases\[0\]\.decimal\.velocity\[0\]: '1' is not velocity\[0\] = '.*' correctly rounded to 40 significant "
            r"digits \('96\.59258262890682867497431997288973676339'\)",
        ),
        (
            lambda c: set_velocity(c, "1"),  # the exact value edited, its decimal left stale
            r"cases\[0\]\.decimal\.velocity\[0\]: '96\.59.*' is not velocity\[0\] = '1' correctly rounded",
        ),
        (lambda c: c["decimal"]["normals"].pop(), r"cases\[0\]\.decimal\.normals: expected 2 entries, as normals has"),
        (lambda c: c["decimal"].pop("time_terms"), r"cases\[0\]\.decimal: missing field 'time_terms'"),
        (
            lambda c: c["decimal"].__setitem__("velocity", ["1", "0"]),
            r"cases\[0\]\.decimal\.velocity: expected 3 entries, as velocity has, got 2 entries",
        ),
        (
            lambda c: c["decimal"]["restitution"].__setitem__(0, "1/2"),
            r"cases\[0\]\.decimal\.restitution\[0\]: expected a decimal such as \"0\.25\" or \"1\.5e-9\", got '1/2'",
        ),
        (lambda c: c["decimal"].__setitem__("digits", 0), r"cases\[0\]\.decimal\.digits: .*"),
    ],
)
def test_a_decimal_that_is_not_the_exact_values_is_refused(tmp_path: Path, capsys: Any, change: Any,
                                                          message: str) -> None:  # fmt: skip
    path = write_case(tmp_path, change)
    assert main(["solve", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1
    assert re.fullmatch(rf"verify: error: {re.escape(str(path))}: {message}.*\n", err), err  # the file named


def test_a_case_with_its_decimals_solves_as_without_them(tmp_path: Path, capsys: Any) -> None:
    with_dec = write_case(tmp_path, lambda c: None)
    assert main(["solve", str(with_dec), "--json"]) == 0
    first = capsys.readouterr().out
    without = write_case(tmp_path, lambda c: c.pop("decimal"))
    assert main(["solve", str(without), "--json"]) == 0
    assert capsys.readouterr().out == first
