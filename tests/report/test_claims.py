"""The claim table on the first screen of reports/README.md: every row gives a status, a number and a command, and
the command prints that number (issue 62, item 1).

The committed index is read (tests/report/test_reports.py proves it is what ``verify all`` writes). Each row's
command runs here, in this process, once per command; the corner's claims (2,000 exact cases, computed once by
``verify all`` for the corner page) are found in reports/corner.md, which quotes that command's output whole.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
from pathlib import Path

import pytest

from verify.cli import main
from verify.report.claims import CORNER_CLAIMS

ROOT = Path(__file__).resolve().parents[2]
INDEX = ROOT / "reports" / "README.md"
#: a row's number: in bold, a closed form also between backticks
NUMBER = re.compile(r"\*\*(`[^`]+`|[^*`]+)\*\*")
STATUSES = {"reproduced", "reproduced under one reading", "disagrees", "refuted", "proved", "holds", "found", "new"}


def rows() -> list[dict[str, str]]:
    """The claim table's rows, as the first screen shows them."""
    lines = INDEX.read_text(encoding="utf-8").splitlines()[:40]
    head = next(i for i, line in enumerate(lines) if line.startswith("| # | claim |"))
    names = [c.strip() for c in lines[head].strip("|").split("|")]
    out = []
    for line in lines[head + 2 :]:
        if not line.startswith("| "):
            break
        out.append(dict(zip(names, (c.strip() for c in line.strip("|").split(" | ")))))
    return out


@pytest.fixture(scope="module")
def printed() -> dict[str, str]:
    """What each command prints (stdout), run once."""
    return {}


def output_of(command: str, cache: dict[str, str]) -> str:
    if command not in cache:
        text = io.StringIO()
        with contextlib.redirect_stdout(text), contextlib.redirect_stderr(io.StringIO()):
            main(shlex.split(command)[1:])
        cache[command] = text.getvalue()
    return cache[command]


def test_the_first_screen_has_the_abstract_and_the_claim_table() -> None:
    first = INDEX.read_text(encoding="utf-8").splitlines()[:40]
    assert first[0].startswith("# ") and any("Table 1 is reproduced" in line for line in first)
    table = rows()
    assert len(table) >= 10, "the guard: the table is on the first screen"
    for row in table:
        assert row["status"] in STATUSES, row
        assert NUMBER.search(row["evidence"]), row
        assert row["command"].startswith("`verify ") and row["command"].endswith("`"), row
        assert (INDEX.parent / re.sub(r"^\[[^]]*\]\(([^)]+)\)$", r"\1", row["page"])).exists(), row


@pytest.mark.slow(seconds=10)
def test_every_command_prints_its_rows_number(printed) -> None:
    checked = 0
    for row in rows():
        command = row["command"].strip("`")
        number = NUMBER.search(row["evidence"]).group(1).strip("`")
        if command == CORNER_CLAIMS:  # the corner page quotes this command's output whole
            shown = (INDEX.parent / "corner.md").read_text(encoding="utf-8")
            assert command in shown, row
        else:
            shown = output_of(command, printed)
        assert number in shown, f"{command} does not print {number!r}"
        checked += 1
    assert checked == len(rows())
