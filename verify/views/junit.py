"""The oracle's graded verdicts as JUnit XML, so that another project's CI shows each case as a test.

One ``<testcase>`` per case of the case file (``classname`` is the grade's class, ``name`` the
case id); a case whose class does not pass has a ``<failure>`` with the class and what shows it,
a skipped case a ``<skipped>``. Written with :mod:`xml.etree.ElementTree`, so every text is
escaped.

>>> from verify.checks.grading import Grade
>>> xml = junit_xml([Grade("a", "exact"), Grade("b", "wrong_stop", "expected exit")], "oracle")
>>> import xml.etree.ElementTree as ET
>>> suite = ET.fromstring(xml)
>>> suite.get("tests"), suite.get("failures"), [c.get("name") for c in suite]
('2', '1', ['a', 'b'])
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from typing import Any


def junit_xml(grades: Sequence[Any], suite: str) -> str:
    """The JUnit XML text of the grades (one test suite named ``suite``)."""
    from verify.checks.grading import PASSING

    failing = [g for g in grades if g.cls not in PASSING and g.cls != "skipped"]
    root = ET.Element(
        "testsuite",
        {
            "name": suite,
            "tests": str(len(grades)),
            "failures": str(len(failing)),
            "errors": "0",
            "skipped": str(sum(g.cls == "skipped" for g in grades)),
        },
    )
    for g in grades:
        case = ET.SubElement(root, "testcase", {"classname": f"oracle.{g.cls}", "name": g.case_id})
        if g.cls == "skipped":
            ET.SubElement(case, "skipped", {"message": g.detail or "skipped by the implementation"})
        elif g.cls not in PASSING:
            failure = ET.SubElement(case, "failure", {"message": g.cls, "type": g.cls})
            failure.text = g.detail or g.cls
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
