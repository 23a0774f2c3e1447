"""The oracle's graded verdicts as JUnit XML, so that another project's CI shows each case as a test.

One ``<testcase>`` per case of the case file (``classname`` names the case file, the same in every
run; ``name`` is the case id; ``time`` its seconds). How each class is reported is the user's choice
(:func:`parse_report_as`, ``verify oracle check --junit-as``): as a ``<failure>`` with the class and what shows it, as
``<skipped>``, or as passed (no child). By default (:func:`default_report`) the passing classes
pass, ``skipped`` is skipped and every other class fails. Written with
:mod:`xml.etree.ElementTree`, so every text is escaped.

>>> from verify.oracle.grading import Grade
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
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from verify.oracle.grading import Grade

#: how a class can be reported
KINDS = ("failure", "skipped", "passed")


def default_report() -> dict[str, str]:
    """How each class is reported unless the user says otherwise: the passing classes
    (:data:`verify.oracle.grading.PASSING`) pass, ``skipped`` is skipped, every other class fails.

    >>> r = default_report()
    >>> r["exact"], r["within_tolerance"], r["skipped"], r["gave_up"], r["limited"]
    ('passed', 'passed', 'skipped', 'failure', 'failure')
    """
    from verify.oracle.grading import CLASSES, PASSING

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
    from verify.oracle.grading import CLASSES

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


def junit_counts(grades: Sequence[Grade], report: Mapping[str, str] | None = None) -> dict[str, int]:
    """How many grades ``--junit`` reports as passed, failures and skipped (the summary prints the same).

    >>> from verify.oracle.grading import Grade
    >>> junit_counts([Grade("a", "exact"), Grade("b", "gave_up"), Grade("c", "skipped")])
    {'tests': 3, 'passed': 1, 'failures': 1, 'skipped': 1}
    """
    kinds = {**default_report(), **(report or {})}
    failures = sum(kinds[g.cls] == "failure" for g in grades)
    skipped = sum(kinds[g.cls] == "skipped" for g in grades)
    return {"tests": len(grades), "passed": len(grades) - failures - skipped, "failures": failures, "skipped": skipped}


def junit_xml(
    grades: Sequence[Grade],
    suite: str,
    report: Mapping[str, str] | None = None,
    prefix: str = "oracle",
    *,
    group: str = "cases",
    checks: Mapping[str, Sequence[str]] | None = None,
    times: Mapping[str, float] | None = None,
    total: float | None = None,
) -> str:
    """The JUnit XML text of the grades (one test suite named ``suite``), each class reported as
    ``report`` says (class -> ``failure``, ``skipped`` or ``passed``; default :func:`default_report`).

    A test's ``classname`` is ``prefix.group`` (the case file's name: the same for a case in every run,
    whatever its grade) and its ``name`` the case id. A failure's text is its class and what shows it,
    then each line of ``checks[case_id]`` (every check the case failed, with both numbers). ``time``
    attributes give each case's seconds (``times``; 0 when not measured) and the suite's (``total``, else
    their sum): they are the only bytes that change between two runs."""
    kinds = {**default_report(), **(report or {})}
    counts = junit_counts(grades, report)
    seconds = {g.case_id: (times or {}).get(g.case_id, 0.0) for g in grades}
    ids = set(seconds)
    unmatched = [line for cid, lines in (checks or {}).items() if cid not in ids for line in lines]
    if unmatched:  # results that belong to no case (an unknown or repeated id): one failing test of their own
        counts = dict(counts, tests=counts["tests"] + 1, failures=counts["failures"] + 1)
    root = ET.Element(
        "testsuite",
        {
            "name": suite,
            "tests": str(counts["tests"]),
            "failures": str(counts["failures"]),
            "errors": "0",
            "skipped": str(counts["skipped"]),
            "time": f"{sum(seconds.values()) if total is None else total:.3f}",
        },
    )
    for g in grades:
        case = ET.SubElement(
            root, "testcase", {"classname": f"{prefix}.{group}", "name": g.case_id, "time": f"{seconds[g.case_id]:.3f}"}
        )
        if kinds[g.cls] == "skipped":
            if g.cls == "skipped":
                message = g.detail or "skipped by the implementation"
            else:  # another class reported as skipped (--junit-as): the class says why
                message = f"{g.cls}: {g.detail}" if g.detail else g.cls
            ET.SubElement(case, "skipped", {"message": message})
        elif kinds[g.cls] == "failure":
            failure = ET.SubElement(case, "failure", {"message": g.cls, "type": g.cls})
            failure.text = "\n".join(_failure_lines(g, (checks or {}).get(g.case_id, ())))
    if unmatched:
        case = ET.SubElement(root, "testcase", {"classname": f"{prefix}.{group}", "name": "the result file",
                                                "time": "0.000"})  # fmt: skip
        failure = ET.SubElement(case, "failure", {"message": "results of no case", "type": "result_file"})
        failure.text = "\n".join(unmatched)
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _failure_lines(g: Any, checks: Sequence[str]) -> list[str]:
    """A failure's text: every check the case failed with both numbers, the velocity's first, and the class with
    what shows it (on the line of the check it names, which is not repeated).

    >>> from verify.oracle.grading import Grade
    >>> _failure_lines(Grade("a", "wrong_stop", "expected 3, got 4"), ["iterations: expected 3, got 4"])
    ['wrong_stop: iterations: expected 3, got 4']
    >>> _failure_lines(Grade("a", "momentum_drift", "drift 0.1"), ["stop: x", "exit_velocity[0]: expected 1, got 2"])
    ['exit_velocity[0]: expected 1, got 2', 'momentum_drift: drift 0.1', 'stop: x']
    >>> _failure_lines(Grade("a", "out_of_tolerance", "exit_velocity[0]: expected 1, got 2"),
    ...                ["exit_velocity[0]: expected 1, got 2"])
    ['out_of_tolerance: exit_velocity[0]: expected 1, got 2']
    """
    head, rest = f"{g.cls}: {g.detail}" if g.detail else g.cls, []
    for check in sorted(checks, key=lambda c: not c.startswith("exit_velocity")):  # the velocity's first
        field, _, text = check.partition(": ")
        if g.detail and check == g.detail:  # the class's detail is this check, field and all
            continue
        if g.detail and head.startswith(f"{g.cls}: ") and text and g.detail.startswith(text):
            head = f"{g.cls}: {field}: {g.detail}"  # the check the class names: on the class's line
            continue
        rest.append(check)
    velocity = [c for c in rest if c.startswith("exit_velocity")]
    first = [head] if head.startswith(f"{g.cls}: exit_velocity") else []
    return [*first, *velocity, *([] if first else [head]), *(c for c in rest if not c.startswith("exit_velocity"))]


def error_xml(suite: str, message: str, prefix: str = "oracle", group: str = "cases") -> str:
    """A JUnit file for a run that could not grade (exit code 2): one test in error, saying what went wrong,
    so that a CI dashboard shows the reason rather than the last run's results.

    >>> print(error_xml("verify oracle check x.json", "x.json: cannot read (No such file or directory)"))
    <?xml version="1.0" encoding="utf-8"?>
    <testsuite name="verify oracle check x.json" tests="1" failures="0" errors="1" skipped="0" time="0.000">
      <testcase classname="oracle.cases" name="verify" time="0.000">
        <error message="x.json: cannot read (No such file or directory)" type="error" />
      </testcase>
    </testsuite>
    <BLANKLINE>
    """
    root = ET.Element("testsuite", {"name": suite, "tests": "1", "failures": "0", "errors": "1", "skipped": "0",
                                    "time": "0.000"})  # fmt: skip
    case = ET.SubElement(root, "testcase", {"classname": f"{prefix}.{group}", "name": "verify", "time": "0.000"})
    ET.SubElement(case, "error", {"message": message, "type": "error"})
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
