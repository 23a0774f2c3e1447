"""docs/oracle.md says what the checker does (issue 34, items 1 and 6).

The page lists the fields of a result that ``verify oracle check`` compares and those it does not;
this test reads both lists and changes each field in results of the golden dataset: a compared
field changed gives a mismatch of that field, an uncompared one changes nothing. Under the
simultaneous law, ``impact_sets`` is defined on both pages as the constraints with a positive
impulse, and the exact results and the checker hold to it.
"""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path
from typing import Any

import pytest

from verify.oracle import reference as oracle

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "docs" / "oracle.md"
STOPS = ("exit", "aeev", "max_iterations", "non_terminating", "budget")


def field_list(label: str) -> list[str]:
    """The backquoted field names of the paragraph of docs/oracle.md that starts with **label**."""
    text = DOC.read_text(encoding="utf-8")
    match = re.search(rf"^\*\*{label}\*\*(.*?)\n\n", text, re.S | re.M)
    assert match, f"docs/oracle.md has no paragraph starting with **{label}**"
    return re.findall(r"`([a-z_]+)`", match.group(1))


def listed(label: str) -> list[str]:
    """:func:`field_list`, or no field when the page has no such list (then the test of the lists fails)."""
    try:
        return field_list(label)
    except AssertionError:
        return []


def golden(name: str) -> list[dict[str, Any]]:
    data = json.loads((ROOT / "golden" / name).read_text(encoding="utf-8"))
    return data["cases" if name == "cases.json" else "results"]


def changed(value: Any) -> Any:
    """Another value of the same shape: numbers (strings) doubled plus one, integers plus one, another
    stop, null as "1", and so on inside lists and objects."""
    if isinstance(value, bool):
        return not value
    if isinstance(value, int):
        return value + 1
    if value is None:
        return "1"
    if isinstance(value, str):
        if value in STOPS:
            return STOPS[(STOPS.index(value) + 1) % len(STOPS)]
        try:
            x = oracle.approx(value)
        except Exception:  # not a number: a word
            return value + "-changed"
        y = 2 * x + 1
        return f"{y.numerator}/{y.denominator}"
    if isinstance(value, list):
        return [changed(x) for x in value]
    if isinstance(value, dict):
        return {k: changed(v) for k, v in value.items()} or {"changed": True}
    raise AssertionError(f"no way to change {value!r}")


#: a value for the fields that the golden results of the rule do not carry (taken from what verify writes
#: under the simultaneous law or an interval backend), to be changed like the others
ABSENT = {
    "law": "simultaneous",
    "impulses": ["1", "0"],
    "law_settings": {"iterations": 1, "order": [0], "threshold": ["0"]},
    "notes": ["a note"],
    "exit_velocity_enclosure": [["0", "1"]],
}


def with_field(result: dict[str, Any], name: str) -> dict[str, Any]:
    out = copy.deepcopy(result)
    if name not in out and name not in ABSENT:
        return out  # a field of some results only (certificate: the runs proved never to exit)
    out[name] = changed(out.get(name, ABSENT.get(name)))
    return out


def test_the_page_lists_every_field_of_a_result_once() -> None:
    compared, uncompared = field_list("Compared"), field_list("Not compared")
    assert {"betas", "exit_velocity", "impact_sets"} <= set(compared)
    assert not set(compared) & set(uncompared)
    schema = json.loads((ROOT / "verify/records/schemas/result.schema.json").read_text(encoding="utf-8"))
    written = set(schema["$defs"]["result"]["properties"])
    written |= {k for r in golden("results.json") + golden("results-simultaneous.json") for k in r}
    written |= set(ABSENT)
    assert written == set(compared) | set(uncompared), "docs/oracle.md: every field is compared or not"


def test_an_uncompared_field_can_be_changed_without_a_mismatch() -> None:
    cases, exact = golden("cases.json"), golden("results.json")
    same = oracle.compare(cases, exact, exact, rtol=oracle.DEFAULT_RTOL, atol=oracle.Fraction(0))
    for name in field_list("Not compared"):
        got = [with_field(r, name) for r in exact]
        assert any(g.get(name) != r.get(name) for g, r in zip(got, exact))
        c = oracle.compare(cases, exact, got, rtol=oracle.DEFAULT_RTOL, atol=oracle.Fraction(0))
        assert c.ok, f"{name}: the page says it is not compared, but: {c.mismatches[:1]}"
        assert [g.cls for g in c.grades] == [g.cls for g in same.grades], name


@pytest.mark.parametrize("name", listed("Compared"))
def test_a_compared_field_cannot_be_changed_without_a_mismatch(name: str) -> None:
    """In every case whose exact run exits (the cases the list is about)."""
    cases, exact = golden("cases.json"), golden("results.json")
    exits = [(c, r) for c, r in zip(cases, exact) if r["stop"] == "exit"]
    assert len(exits) >= 40
    for case, result in exits:
        c = oracle.compare([case], [result], [with_field(result, name)], rtol=oracle.DEFAULT_RTOL,
                           atol=oracle.Fraction(0))  # fmt: skip
        fields = {m.field.split("[")[0] for m in c.mismatches}
        expected = {"missing", "id"} if name == "id" else {name}
        assert fields & expected, f"{case['id']}: {name} changed, but the mismatches are {c.mismatches}"


# -- item 6: impact_sets under the simultaneous law ----------------------------------------------------------


@pytest.mark.parametrize("page", ["docs/oracle.md", "docs/engines.md"])
def test_both_pages_define_the_simultaneous_law_s_impact_set(page: str) -> None:
    text = (ROOT / page).read_text(encoding="utf-8")
    paragraphs = [p for p in text.split("\n\n") if "`impact_sets` is" in p and "`[J]`" in p]
    assert paragraphs, f"{page}: no definition of impact_sets under the simultaneous law"
    definition = " ".join(paragraphs[0].split())
    assert "whose impulse `lambda_i` is positive" in definition and "not the set of incoming" in definition


def test_the_simultaneous_impact_set_is_the_constraints_with_a_positive_impulse() -> None:
    cases, exact = golden("cases.json"), golden("results-simultaneous.json")
    for case, result in zip(cases, exact):
        positive = [i for i, x in enumerate(result["impulses"]) if oracle.approx(x) > 0]
        assert result["impact_sets"] == ([positive] if positive else []), case["id"]
        assert result["iterations"] == len(result["impact_sets"])
    # the example of the pages: the cradle with eps = 1, a contact at rate 0 takes an impulse
    first = exact[0]
    assert cases[0]["id"] == "paper-table1-eps-1" and first["impact_sets"] == [[0, 1]]
    rule_only = dict(first, impact_sets=[[0]])
    c = oracle.compare(cases[:1], exact[:1], [rule_only], rtol=oracle.DEFAULT_RTOL, atol=oracle.Fraction(0))
    assert [m.field for m in c.mismatches] == ["impact_sets"]
