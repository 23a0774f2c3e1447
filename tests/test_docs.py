"""The user documentation (docs/) ships with the project and stays true.

- No file of the project points at a documentation folder outside the repository (a
  user's clone has only what is in it).
- Every relative link of README.md and docs/*.md leads to a file that exists, and every
  ``#anchor`` to a heading of that file.
- The worked example of docs/records.md is the real, current output of ``verify solve``.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from verify.cli import main

ROOT = Path(__file__).resolve().parents[1]
#: built from pieces, so that this file does not contain what it looks for
FORBIDDEN = ("shared" + "/docs", ".." + "/shared")
SCANNED = ("README.md", "docs", "verify", "tests", "examples", "golden")


def project_text_files() -> list[Path]:
    """The text files of the project's tracked folders (build output and caches left out)."""
    out = []
    for name in SCANNED:
        path = ROOT / name
        candidates = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
        for p in candidates:
            if "__pycache__" in p.parts or p.suffix in (".pyc", ".png", ".pdf"):
                continue
            try:
                p.read_text(encoding="utf-8")
            except UnicodeDecodeError:
                continue  # not text
            out.append(p)
    return out


def test_the_scan_sees_the_project():
    """A guard for the next test: it must look at the files that matter."""
    names = {p.relative_to(ROOT).as_posix() for p in project_text_files()}
    assert {"README.md", "docs/README.md", "docs/records.md", "verify/cli/__init__.py", "tests/test_docs.py"} <= names


def test_no_file_points_outside_the_repository():
    found = [
        f"{p.relative_to(ROOT)}:{i}: {line.strip()}"
        for p in project_text_files()
        for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if any(bad in line for bad in FORBIDDEN)
    ]
    assert not found, "these lines point at a folder that users do not have:\n" + "\n".join(found)


# -- links -------------------------------------------------------------------------------------

_FENCE = re.compile(r"^```.*?^```", re.S | re.M)
_INLINE_CODE = re.compile(r"`[^`\n]*`")
_LINK = re.compile(r"\[[^\]\n]*\]\(([^)\s]+)\)")


def markdown_pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def links(page: Path) -> list[str]:
    """The link targets of a Markdown page, outside code blocks and inline code."""
    text = _FENCE.sub("", page.read_text(encoding="utf-8"))
    text = re.sub(r"\[(`[^`\n]*`)\]", lambda m: "[" + m.group(1).strip("`") + "]", text)  # [`x`](y) is a link
    text = _INLINE_CODE.sub("", text)
    return _LINK.findall(text)


def slug(heading: str) -> str:
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces as hyphens."""
    text = heading.strip().lower().replace("`", "")
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page: Path) -> set[str]:
    text = _FENCE.sub("", page.read_text(encoding="utf-8"))
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6} (.+)$", text, re.M)}


def test_slug_matches_github():
    assert slug("`verify oracle check --json`") == "verify-oracle-check---json"
    assert slug("The certificate") == "the-certificate"


def test_links_are_found():
    """A guard: the link reader sees the README's link to docs/ and the index's pages."""
    assert "docs/README.md" in links(ROOT / "README.md")
    assert {"numbers.md", "records.md", "json-outputs.md", "cli.md", "oracle.md"} <= set(links(ROOT / "docs/README.md"))


@pytest.mark.parametrize("page", markdown_pages(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_relative_links_lead_to_files_that_exist(page: Path):
    broken = []
    for target in links(page):
        if re.match(r"[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            broken.append(f"{target}: no such file")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            broken.append(f"{target}: no heading #{anchor} in {dest.relative_to(ROOT)}")
    assert not broken, f"{page.relative_to(ROOT)}: " + "; ".join(broken)


# -- the worked example of docs/records.md -------------------------------------------------------

EXAMPLE = "docs/examples/cases.json"


_BLOCK = re.compile(r"^```[^\n]*\n(.*?)^```", re.S | re.M)


def fenced_blocks(text: str) -> list[str]:
    """The contents of the fenced code blocks of a Markdown text, in order."""
    return [m.group(1) for m in _BLOCK.finditer(text)]


def block_after(text: str, line: str) -> str:
    """The content of the first fenced code block after the block whose content is ``line``."""
    at = text.index("```\n" + line + "\n```") + len(line) + 8
    return next(m.group(1) for m in _BLOCK.finditer(text, at))


def normalise(text: str) -> str:
    """The exact backend's label names the rational library installed (gmpy2, flint or python)."""
    return re.sub(r"exact \(rationals, [a-z0-9-]+\)", "exact (rationals, LIBRARY)", text)


def run_cli(argv: list[str], capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch) -> str:
    monkeypatch.chdir(ROOT)
    capsys.readouterr()
    code = main(argv)
    out = capsys.readouterr()
    assert code == 0, out.err
    return out.out


def test_records_example_shows_the_case_file():
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    assert (ROOT / EXAMPLE).read_text(encoding="utf-8") in fenced_blocks(doc)


def test_records_example_shows_the_current_json_output(capsys, monkeypatch):
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    shown = block_after(doc, f"$ verify solve {EXAMPLE} --json")
    real = run_cli(["solve", EXAMPLE, "--json"], capsys, monkeypatch)
    assert '"stop": "non_terminating"' in real and '"certificate"' in real  # the example shows both stops
    assert normalise(shown) == normalise(real), "docs/records.md: rerun the worked example and copy its output"


def test_records_example_shows_the_current_text_output(capsys, monkeypatch):
    doc = (ROOT / "docs/records.md").read_text(encoding="utf-8")
    marker = f"$ verify solve {EXAMPLE}"
    block = next(b for b in fenced_blocks(doc) if b.startswith(marker + "\n"))
    real = run_cli(["solve", EXAMPLE], capsys, monkeypatch)
    assert normalise(block[len(marker) + 1 :]) == normalise(real), "docs/records.md: rerun the worked example"
