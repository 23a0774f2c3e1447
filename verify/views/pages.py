"""The page frame of the reports: what every feature's page is built with (a text block of a command's output).
The pages themselves are their features' (``verify.FEATURE.pages``); :mod:`verify.report.pages` writes them."""

from __future__ import annotations


def block(text: str, *, width: int = 200) -> str:
    """A command's output as a text block of a page; a line longer than ``width`` is folded at ``width`` (its
    continuation indented four more than it), so that no line of a page runs long.

    >>> block("  one two three", width=10)  # doctest: -NORMALIZE_WHITESPACE
    '```text\\n  one two\\n      three\\n```\\n'
    """
    import textwrap

    lines = []
    for line in text.rstrip("\n").splitlines():
        indent = " " * (len(line) - len(line.lstrip(" ")))
        if len(line) <= width:
            lines.append(line)
            continue
        lines += textwrap.wrap(line.lstrip(" "), width, initial_indent=indent, subsequent_indent=indent + "    ",
                               break_long_words=False, break_on_hyphens=False)  # fmt: skip
    return "```text\n" + "\n".join(lines) + "\n```\n"


def wrapped(text: str, *, bullet: str = "", width: int = 110) -> list[str]:
    """A paragraph (or a list item, with ``bullet``) broken into lines of at most ``width`` characters, so that
    no line of a page runs long; words are never split, so a longer word keeps its line.

    A line is never begun with what markdown reads as the start of a list item or a heading (``- 4*sqrt(3)``):
    the word before it comes down to that line.

    >>> wrapped("one two three four", bullet="- ", width=12)
    ['- one two', '  three four']
    >>> wrapped("eps in [0, 7 - 4*sqrt(3)]", width=12)
    ['eps in [0,', '7 - 4*sqrt(3)]']
    """
    import re
    import textwrap

    lines = textwrap.wrap(text, width, initial_indent=bullet, subsequent_indent=" " * len(bullet),
                          break_long_words=False, break_on_hyphens=False)  # fmt: skip
    marker = re.compile(r"^\s*([-+*>#]|\d+[.)])(\s|$)")
    for i in range(1, len(lines)):
        while marker.match(lines[i]) and " " in lines[i - 1].strip():
            head, _, word = lines[i - 1].rpartition(" ")
            lines[i - 1], lines[i] = head, " " * len(bullet) + word + " " + lines[i].lstrip()
    return lines


def literal_products(page: str) -> str:
    """A page whose multiplication signs in prose (``2*sqrt(2)``) are escaped (``2\\*sqrt(2)``), so that markdown
    shows them as written rather than as emphasis between two of them; code blocks and code spans are left as
    they are, and so is bold (``**17**``).

    >>> print(literal_products("eps = 3 - 2*sqrt(2), **4** rows, `7 - 4*sqrt(3)`\\n```\\n2*x\\n```"))
    eps = 3 - 2\\*sqrt(2), **4** rows, `7 - 4*sqrt(3)`
    ```
    2*x
    ```
    """
    import re

    product = re.compile(r"(?<=[\w)])\*(?=[\w(])")
    out, fenced = [], False
    for line in page.split("\n"):
        if line.startswith("```"):
            fenced = not fenced
        if not fenced and not line.startswith("```"):
            parts = line.split("`")
            line = "`".join(product.sub(r"\\*", p) if k % 2 == 0 else p for k, p in enumerate(parts))
        out.append(line)
    return "\n".join(out)
