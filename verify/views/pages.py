"""The page frame of the reports: what every feature's page is built with (a text block of a command's output).
The pages themselves are their features' (``verify.FEATURE.pages``); :mod:`verify.report.pages` writes them."""

from __future__ import annotations


def block(text: str) -> str:
    return "```text\n" + text.rstrip("\n") + "\n```\n"
