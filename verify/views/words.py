"""Words of the reports and summaries: counts with their nouns."""

from __future__ import annotations


def plural(n: int, word: str) -> str:
    """``word`` for one, ``word + "s"`` otherwise.

    >>> plural(1, "mismatch"), plural(2, "case")
    ('mismatch', 'cases')
    """
    if n == 1:
        return word
    return word + ("es" if word.endswith(("s", "sh", "ch", "x")) else "s")


def count(n: int, word: str) -> str:
    """``n`` and its noun, singular or plural.

    >>> count(1, "mismatch"), count(0, "case")
    ('1 mismatch', '0 cases')
    """
    return f"{n} {plural(n, word)}"
