"""The oracle's graded verdicts as JUnit XML, so that another project's CI shows each case as a test.

One ``<testcase>`` per case of the case file (``classname`` is the grade's class, ``name`` the
case id). How each class is reported is the user's choice (:func:`parse_report_as`, ``verify
oracle check --junit-as``): as a ``<failure>`` with the class and what shows it, as
``<skipped>``, or as passed (no child). By default (:func:`default_report`) the passing classes
pass, ``skipped`` is skipped and every other class fails. Written with
:mod:`xml.etree.ElementTree`, so every text is escaped.

>>> from verify.checks.grading import Grade
>>> grades = [Grade("a", "exact"), Grade("b", "wrong_stop", "expected exit"), Grade("c", "gave_up", "cap")]
>>> import xml.etree.ElementTree as ET
>>> suite = ET.fromstring(junit_xml(grades, "oracle"))
>>> suite.get("tests"), suite.get("failures"), suite.get("skipped"), [c.get("name") for c in suite]
('3', '2', '0', ['a', 'b', 'c'])
>>> suite = ET.fromstring(junit_xml(grades, "oracle", parse_report_as("gave_up=skipped")))
>>> suite.get("failures"), suite.get("skipped"), [child.tag for child in suite[2]]
('1', '1', ['skipped'])
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from typing import Any

#: how a class can be reported
KINDS = ("failure", "skipped", "passed")


def default_report() -> dict[str, str]:
    """How each class is reported unless the user says otherwise: the passing classes
    (:data:`verify.checks.grading.PASSING`) pass, ``skipped`` is skipped, every other class fails.

    >>> r = default_report()
    >>> r["exact"], r["within_tolerance"], r["skipped"], r["gave_up"], r["limited"]
    ('passed', 'passed', 'skipped', 'failure', 'failure')
    """
    from verify.checks.grading import CLASSES, PASSING

    return {c: "passed" if c in PASSING else "skipped" if c == "skipped" else "failure" for c in CLASSES}


def parse_report_as(text: str) -> dict[str, str]:
    """The report of every class, from the default with the changes ``CLASS=KIND,CLASS=KIND``
    (``--junit-as``); KIND is ``failure``, ``skipped`` or ``passed``. A bad entry raises
    ``ValueError`` with one line that names it.

    >>> r = parse_report_as("gave_up=skipped, within_tolerance=failure")
    >>> r["gave_up"], r["within_tolerance"], r["exact"]
    ('skipped', 'failure', 'passed')
    >>> parse_report_as("gave_up=ignored")
    Traceback (most recent call last):
    ...
    ValueError: gave_up=ignored: 'ignored' is not one of failure, skipped, passed
    >>> parse_report_as("gaveup=skipped")
    Traceback (most recent call last):
    ...
    ValueError: gaveup=skipped: 'gaveup' is not a class (exact, within_tolerance, gave_up, ...)
    """
    from verify.checks.grading import CLASSES

    out = default_report()
    seen: set[str] = set()
    for entry in (e.strip() for e in text.split(",")):
        cls, sep, kind = (part.strip() for part in entry.partition("="))
        if not sep or not cls or not kind:
            raise ValueError(f"{entry!r}: expected CLASS=KIND, e.g. gave_up=skipped")
        if cls not in CLASSES:
            raise ValueError(f"{entry}: {cls!r} is not a class ({', '.join(CLASSES)})")
        if kind not in KINDS:
            raise ValueError(f"{entry}: {kind!r} is not one of {', '.join(KINDS)}")
        if cls in seen:
            raise ValueError(f"{entry}: {cls} is given twice")
        seen.add(cls)
        out[cls] = kind
    return out


def junit_counts(grades: Sequence[Any], report: Mapping[str, str] | None = None) -> dict[str, int]:
    """How many grades ``--junit`` reports as passed, failures and skipped (the summary prints the same).

    >>> from verify.checks.grading import Grade
    >>> junit_counts([Grade("a", "exact"), Grade("b", "gave_up"), Grade("c", "skipped")])
    {'tests': 3, 'passed': 1, 'failures': 1, 'skipped': 1}
    """
    kinds = {**default_report(), **(report or {})}
    failures = sum(kinds[g.cls] == "failure" for g in grades)
    skipped = sum(kinds[g.cls] == "skipped" for g in grades)
    return {"tests": len(grades), "passed": len(grades) - failures - skipped, "failures": failures, "skipped": skipped}


def junit_xml(
    grades: Sequence[Any], suite: str, report: Mapping[str, str] | None = None, prefix: str = "oracle"
) -> str:
    """The JUnit XML text of the grades (one test suite named ``suite``), each class reported as
    ``report`` says (class -> ``failure``, ``skipped`` or ``passed``; default :func:`default_report`)."""
    kinds = {**default_report(), **(report or {})}
    counts = junit_counts(grades, report)
    root = ET.Element(
        "testsuite",
        {
            "name": suite,
            "tests": str(counts["tests"]),
            "failures": str(counts["failures"]),
            "errors": "0",
            "skipped": str(counts["skipped"]),
        },
    )
    for g in grades:
        case = ET.SubElement(root, "testcase", {"classname": f"{prefix}.{g.cls}", "name": g.case_id})
        if kinds[g.cls] == "skipped":
            if g.cls == "skipped":
                message = g.detail or "skipped by the implementation"
            else:  # another class reported as skipped (--junit-as): the class says why
                message = f"{g.cls}: {g.detail}" if g.detail else g.cls
            ET.SubElement(case, "skipped", {"message": message})
        elif kinds[g.cls] == "failure":
            failure = ET.SubElement(case, "failure", {"message": g.cls, "type": g.cls})
            failure.text = g.detail or g.cls
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
