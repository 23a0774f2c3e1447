"""The reports as one self-contained HTML file (``reports/index.html``): every page in the index's order, converted
from its markdown by markdown-it-py (CommonMark and tables), the figures inline, links between pages as links
within the file, and the records (``engines.json``, ``properties.json``) linked beside it.

>>> page = html_report({"README.md": "# R\\n\\nSee [the glossary](glossary.md).\\n", "glossary.md": "# G\\n"},
...                    ["README.md", "glossary.md"], images={})
>>> '<a href="#glossary">the glossary</a>' in page, '<section id="glossary">' in page
(True, True)
"""

from __future__ import annotations

import base64
import html
from collections.abc import Mapping, Sequence
from typing import Any

#: the look of the file: readable line lengths, tables that scroll rather than squeeze, figures that fit
STYLE = """
body { font-family: system-ui, sans-serif; line-height: 1.5; max-width: 72rem; margin: 0 auto; padding: 1rem 2rem;
       color: #1a1a1a; }
nav { border-bottom: 1px solid #ccc; padding-bottom: .5rem; margin-bottom: 1rem; font-size: .95rem; }
nav a { margin-right: 1rem; }
section { border-top: 2px solid #888; margin-top: 2.5rem; padding-top: .5rem; }
section:first-of-type { border-top: none; margin-top: 0; }
table { border-collapse: collapse; display: block; overflow-x: auto; font-size: .9rem; margin: 1rem 0; }
th, td { border: 1px solid #ccc; padding: .25rem .5rem; vertical-align: top; }
th { background: #f2f2f2; }
pre { background: #f7f7f7; padding: .75rem; overflow-x: auto; font-size: .85rem; }
code { font-size: .9em; }
img { max-width: 100%; height: auto; }
""".strip()


def anchor(name: str) -> str:
    """The id of a page's section: its file name without ``.md`` (the index is ``top``).

    >>> anchor("cradle-map.md"), anchor("README.md")
    ('cradle-map', 'top')
    """
    return "top" if name == "README.md" else name.removesuffix(".md")


def html_report(texts: Mapping[str, str], order: Sequence[str], images: Mapping[str, bytes], title: str = "") -> str:
    """One HTML document of the pages ``texts`` (name -> markdown) in ``order``: a link to another page becomes a
    link to its section, an image (name -> PNG bytes in ``images``) a data URI; other links are kept."""
    from verify.errors import require

    markdown_it = require("markdown_it", "the HTML of the reports", "figures")
    md = markdown_it.MarkdownIt("commonmark", {"html": False}).enable("table")
    sections = []
    for name in order:
        tokens = md.parse(texts[name])
        _rewrite(tokens, set(order), images)
        body = md.renderer.render(tokens, md.options, {})
        sections.append(f'<section id="{anchor(name)}">\n{body}</section>')
    nav = " ".join(f'<a href="#{anchor(n)}">{html.escape(_title(texts[n], n))}</a>' for n in order)
    head = title or _title(texts[order[0]], order[0])
    return (
        '<!doctype html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{html.escape(head)}</title>\n<style>\n{STYLE}\n</style>\n</head>\n<body>\n"
        f"<nav>{nav}</nav>\n" + "\n".join(sections) + "\n</body>\n</html>\n"
    )


def _title(text: str, name: str) -> str:
    """A page's first heading (its file name without one)."""
    first = next((line for line in text.splitlines() if line.startswith("# ")), "")
    return first[2:].strip() or name


def _rewrite(tokens: list[Any], pages: set[str], images: Mapping[str, bytes]) -> None:
    """Links to pages become links to their sections; images become data URIs (in place, through inline tokens)."""
    for token in tokens:
        if token.children:
            _rewrite(token.children, pages, images)
        if token.type == "link_open":
            href = str(token.attrGet("href") or "")
            page, _, fragment = href.partition("#")
            if page in pages:
                token.attrSet("href", f"#{fragment or anchor(page)}")
        elif token.type == "image":
            src = str(token.attrGet("src") or "")
            if src in images:
                token.attrSet("src", "data:image/png;base64," + base64.b64encode(images[src]).decode("ascii"))
