"""The committed pages read as a report, not as program output: short lines, no machinery, terms defined.

Each check reads ``reports/*.md`` as committed (tests/report/test_reports.py proves they are what ``verify all``
writes) and is tested on a page made to break it.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from verify.report.glossary import GLOSSARY

REPORTS = Path(__file__).resolve().parents[2] / "reports"
#: the longest line a page may hold
LONGEST = 300
#: the pages together, at most (fewer than the 2,211 lines the pages had when they were judged too long to read;
#: 2,365 just before they were rewritten for the reader)
MOST_LINES = 2210
#: machinery a page must not show: a module or file path of the package, a Python repr, an issue number
MACHINERY = {
    "a module path": re.compile(r"\bverify\.[a-z_]+\.[a-z_]|\bverify/[a-z_]+|\btests/[a-z_/]+\.py\b"),
    "a Python repr": re.compile(r"\[\s*'|\{\s*'|\bFraction\(|\bCRootOf\(|\bRealAlgebraic\(| object at 0x"),
    "an issue number": re.compile(r"\b[Ii]ssue\s+#?\d+|(?<![\w&])#\d+\b"),
}
#: words of the program a reader does not know, and the glossary's term that defines each (None: no page may use
#: the word; its meaning is said in words instead)
JARGON: dict[str, str | None] = {
    "verdict": "verdict", "family": "row, family", "profile": "profile", "rates": "rate p(F_i)",
    "certificate": "certificate", "AEEV": "AEEV", "impact set": "impact set", "census": "census",
    "backend": "backend", "paper mode": "paper mode", "limit velocity": "limit velocity", "explained": "explained",
    "relative distance": "relative distance", "sweeps": "sequential law", "never exits": "never exits",
    "rung": None, "CRootOf": None,
}  # fmt: skip


def pages() -> dict[str, str]:
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(REPORTS.glob("*.md"))}


def long_lines(text: str) -> list[int]:
    return [n for n, line in enumerate(text.splitlines(), 1) if len(line) > LONGEST]


def machinery(text: str) -> list[str]:
    """What machinery ``text`` shows, as "kind: the match" (code blocks included: they are read too)."""
    return [f"{kind}: {m.group(0)}" for kind, pattern in MACHINERY.items() for m in pattern.finditer(text)]


def undefined_terms(text: str, glossary: tuple[tuple[str, str], ...] = GLOSSARY) -> list[str]:
    """The words of :data:`JARGON` that ``text`` uses and ``glossary`` does not define."""
    terms = {term for term, _ in glossary}
    return [w for w, t in JARGON.items() if re.search(rf"\b{re.escape(w)}\b", text, re.I) and t not in terms]


def test_no_line_runs_long() -> None:
    found = {name: long_lines(text) for name, text in pages().items()}
    assert not {name: lines for name, lines in found.items() if lines}


def test_no_page_shows_machinery() -> None:
    found = {name: machinery(text) for name, text in pages().items()}
    assert not {name: hits for name, hits in found.items() if hits}


def test_every_term_a_page_uses_is_in_the_glossary() -> None:
    found = {name: undefined_terms(text) for name, text in pages().items()}
    assert not {name: terms for name, terms in found.items() if terms}


def test_the_pages_are_shorter_than_before() -> None:
    assert sum(len(text.splitlines()) for text in pages().values()) <= MOST_LINES


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("see verify.paper.corner_map.corner_maps", "a module path"),
        ("written by verify/models/paper.py", "a module path"),
        ("the counts {'exact rate 0': 45}", "a Python repr"),
        ("CORs ['1', '1']", "a Python repr"),
        ("a root CRootOf(x**3 - 2, 0)", "a Python repr"),
        ("What issue 19 asks", "an issue number"),
        ("fixed in #42", "an issue number"),
    ],
)
def test_the_checks_find_what_they_refuse(text: str, kind: str) -> None:
    assert [hit for hit in machinery(text) if hit.startswith(kind)]


def test_the_checks_pass_plain_prose() -> None:
    prose = "S(1,2) and S(2,3) are hit; eps = 3 - 2*sqrt(2); the rule exits after 3 impulses (verify table1)."
    assert not machinery(prose) and not long_lines(prose) and not undefined_terms(prose)
    assert long_lines("x" * (LONGEST + 1)) == [1]
    assert undefined_terms("the third rung of the ladder") == ["rung"]
    assert undefined_terms("a verdict per row", glossary=()) == ["verdict"]


# -- one number, one value ------------------------------------------------------------------------------------


def paragraphs(text: str) -> list[str]:
    """The prose of a page, outside code blocks and tables: its paragraphs and list items, each on one line."""
    out: list[str] = []
    current: list[str] = []
    fenced = False
    for line in [*text.splitlines(), ""]:
        if line.startswith("```"):
            fenced = not fenced
            continue
        starts = line.startswith(("- ", "#", "|", "!", "*Figure")) or not line.strip()
        if (starts or fenced) and current:
            out.append(" ".join(current))
            current = []
        if not fenced and line.strip() and not line.startswith(("|", "#", "!")):
            current.append(line.strip())
    return out


def repeated(text: str, shortest: int = 60) -> list[str]:
    """The paragraphs of ``text`` said twice or more (those of ``shortest`` characters or more)."""
    seen: dict[str, int] = {}
    for p in paragraphs(text):
        if len(p) >= shortest:
            seen[p] = seen.get(p, 0) + 1
    return [p for p, n in seen.items() if n > 1]


def test_no_page_says_a_thing_twice() -> None:
    found = {name: repeated(text) for name, text in pages().items()}
    assert not {name: said for name, said in found.items() if said}


def test_the_claim_tables_numbers_are_on_their_pages() -> None:
    """A number of the claim table is the number its page gives (the command printing it is tested in
    test_claims.py): the first screen and the pages say one value."""
    from tests.report.test_claims import NUMBER, rows

    for row in rows():
        page = re.sub(r"^\[[^]]*\]\(([^)]+)\)$", r"\1", row["page"])
        number = NUMBER.search(row["evidence"]).group(1).strip("`")
        shown = (REPORTS / page).read_text(encoding="utf-8").replace("\\*", "*")
        assert number in shown, f"{page} does not give {number!r} ({row['claim']})"


def test_the_property_counts_agree() -> None:
    """The abstract's counts of the paper's rule are the property page's."""
    index = " ".join((REPORTS / "README.md").read_text(encoding="utf-8").split())
    page = " ".join((REPORTS / "properties.md").read_text(encoding="utf-8").split())
    said = re.search(r"properties of the paper's rule \(profile \w+\), (\d+) rows are proved, (\d+) hold and (\d+) "
                     r"are refuted", index)  # fmt: skip
    counted = re.search(r"Under the paper's rule: (\d+) proved, (\d+) holds, (\d+) refuted", page)
    assert said and counted and said.groups() == counted.groups()


def test_the_repeat_check_finds_a_repeat() -> None:
    said = "the same explanation, said once on this page and then said again"
    assert repeated(f"- {said}\n- {said}\n") == [f"- {said}"]
    assert repeated(f"{said}\n\n{said}\n") == [said]
    assert repeated(f"{said}\n\n{said}, but this time with a different ending\n") == []
    assert repeated(f"```\n{said}\n{said}\n```\n") == [], "a command's output is not prose"
    assert repeated("a short line\n\na short line\n") == []
