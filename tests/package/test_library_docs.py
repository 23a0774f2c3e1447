"""docs/library.md documents the library's result classes, and stays true.

- Every ``python`` example of the page runs and prints what the page shows (doctest, with ELLIPSIS and
  NORMALIZE_WHITESPACE, each block on its own: each example is complete).
- The section of each class (``## `Result```, ...) names every field of the dataclass, in backticks:
  a field added to a class without a line on the page fails here.
"""

from __future__ import annotations

import dataclasses
import doctest
import re
from pathlib import Path

import pytest

from verify.laws.outcome import Result
from verify.maps.general import EpsMap
from verify.maps.line import Part
from verify.properties.verdicts import Verdict

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "library.md"
CLASSES = {"Result": Result, "EpsMap": EpsMap, "Part": Part, "Verdict": Verdict}
_BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def page() -> str:
    return PAGE.read_text(encoding="utf-8")


def examples() -> list[tuple[int, str]]:
    """The ``python`` blocks of the page, with the line each starts on."""
    text = page()
    return [(text.count("\n", 0, m.start()) + 2, m.group(1)) for m in _BLOCK.finditer(text)]


def section(name: str) -> str:
    """The text of the page's section ``## `name```, up to the next section."""
    text = page()
    found = re.search(rf"^## `{name}`\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert found, f"docs/library.md has no section ## `{name}`"
    return found.group(1)


def test_every_class_has_an_example() -> None:
    """A guard for the two tests below: each class's section holds a runnable example."""
    for name in CLASSES:
        assert "```python\n>>> " in section(name), name


@pytest.mark.parametrize(("line", "source"), examples(), ids=lambda x: str(x) if isinstance(x, int) else "")
def test_the_example_runs_as_shown(line: int, source: str) -> None:
    parser = doctest.DocTestParser()
    test = parser.get_doctest(source, {}, f"docs/library.md:{line}", str(PAGE), line - 1)
    assert test.examples, "a python block of docs/library.md without >>> examples"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    out: list[str] = []
    result = runner.run(test, out=out.append)
    assert result.failed == 0, "".join(out)


@pytest.mark.parametrize("name", CLASSES)
def test_the_page_names_every_field(name: str) -> None:
    fields = [f.name for f in dataclasses.fields(CLASSES[name]) if not f.name.startswith("_")]
    assert fields, name
    text = section(name)
    missing = [f for f in fields if f"`{f}`" not in text]
    assert not missing, f"docs/library.md, section {name}: no line for the field(s) {', '.join(missing)}"
