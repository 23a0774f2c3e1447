"""reports/index.html, the pages as one self-contained HTML file: every link and every image resolves.

The committed file is read (tests/report/test_reports.py proves it is what ``verify all`` writes); the checker
is tested on a file made to break each rule.
"""

from __future__ import annotations

import base64
from html.parser import HTMLParser
from pathlib import Path

from verify.report.html import anchor
from verify.report.pages import PAGES

REPORTS = Path(__file__).resolve().parents[2] / "reports"
PNG = b"\x89PNG\r\n\x1a\n"


class Links(HTMLParser):
    """The ids, the links and the images of an HTML document."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.hrefs: list[str] = []
        self.images: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(str(a["id"]))
        if tag == "a" and a.get("href") is not None:
            self.hrefs.append(str(a["href"]))
        if tag == "img":
            self.images.append(str(a.get("src") or ""))


def broken(text: str, folder: Path) -> list[str]:
    """What does not resolve in ``text``: a link to no id, a link to no file beside it, an image that is not an
    inline PNG."""
    doc = Links()
    doc.feed(text)
    out = []
    for href in doc.hrefs:
        if href.startswith("#"):
            if href[1:] not in doc.ids:
                out.append(f"no id for {href}")
        elif not href.startswith(("https://", "http://")) and not (folder / href.split("#")[0]).exists():
            out.append(f"no file for {href}")
    for src in doc.images:
        head, _, data = src.partition(",")
        if head != "data:image/png;base64" or not base64.b64decode(data).startswith(PNG):
            out.append(f"not an inline PNG: {src[:40]}")
    return out


def test_every_link_and_image_of_the_report_resolves() -> None:
    text = (REPORTS / "index.html").read_text(encoding="utf-8")
    assert broken(text, REPORTS) == []
    doc = Links()
    doc.feed(text)
    assert {anchor(name) for name, _ in PAGES} | {"top"} <= doc.ids, "a section for every page"
    figures = sum(line.startswith("![") for p in REPORTS.glob("*.md") for line in p.read_text().splitlines())
    assert len(doc.images) == figures > 0, "every figure of the pages, inline"
    assert "<table>" in text and "doi.org/10.1007/s00332-021-09718-0" in text


def test_the_checker_finds_what_does_not_resolve(tmp_path) -> None:
    (tmp_path / "engines.json").write_text("{}")
    good = '<p id="a"><a href="#a">x</a><a href="engines.json">r</a><a href="https://doi.org/1">d</a></p>'
    assert broken(good, tmp_path) == []
    png = base64.b64encode(PNG + b"rest").decode()
    assert broken(f'<img src="data:image/png;base64,{png}">', tmp_path) == []
    assert broken('<a href="#nowhere">x</a>', tmp_path) == ["no id for #nowhere"]
    assert broken('<a href="table1.md">x</a>', tmp_path) == ["no file for table1.md"]
    assert broken('<img src="figure.png">', tmp_path) == ["not an inline PNG: figure.png"]
    jpeg = base64.b64encode(b"\xff\xd8\xff").decode()
    assert broken(f'<img src="data:image/png;base64,{jpeg}">', tmp_path)
