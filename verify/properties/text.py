"""The text of the property verdicts (``verify properties``): the verdict table and the termination census."""

from __future__ import annotations

from typing import TYPE_CHECKING

from verify.numbers.format import counted

if TYPE_CHECKING:
    from collections.abc import Sequence

    from verify.properties.verdicts import Verdict


def properties_text(profile: str, found: Sequence[Verdict]) -> str:
    """The verdict table of ``verify properties`` (a row per property, law, rule and family; for
    the simultaneous law the rule column names the CORs), then every refutation with its case.

    >>> from types import SimpleNamespace as Row
    >>> print(properties_text("dev", [Row(property="p", law="simultaneous", rule="ideal", family="corner",
    ...                                   verdict="holds", cases=25)]), end="")
    Property suite, profile dev: 1 row (property x law x rule x family)
    <BLANKLINE>
      property  law           rule        family   verdict   cases
      p         simultaneous  ideal       corner   holds     25
    <BLANKLINE>
      0 proved, 1 holds, 0 refuted
    """
    import json

    lines = [f"Property suite, profile {profile}: {counted(len(found), 'row')} (property x law x rule x family)", ""]
    width = max((len(v.property) for v in found), default=10)
    lines.append(f"  {'property':{width}}  {'law':12}  {'rule':10}  {'family':7}  {'verdict':8}  cases")
    for v in found:
        lines.append(f"  {v.property:{width}}  {v.law:12}  {v.rule:10}  {v.family:7}  {v.verdict:8}  {v.cases}")
    from verify.properties.verdicts import verdict_counts

    counts = verdict_counts(found)
    lines += ["", "  " + ", ".join(f"{n} {k}" for k, n in counts.items())]
    lines += census_lines(found)
    for v in found:
        if v.verdict != "refuted":
            continue
        which = f"{v.rule} rule" if v.law == "rule" else f"{v.law} law, {v.rule} CORs"
        lines += [
            "",
            f"REFUTED: {v.property} ({which}, {v.family})",
            f"  {v.note}",
            "  counterexample (case file):",
        ]
        lines.append("    " + json.dumps({"cases": [v.counterexample]}, sort_keys=True))
    return "\n".join(lines) + "\n"


def census_lines(found: Sequence[Verdict]) -> list[str]:
    """The census of the termination rows: how each row's runs end (empty without such rows).

    >>> from types import SimpleNamespace as Row
    >>> row = Row(property="t", law="rule", rule="ideal", family="corner", cases=3,
    ...           census=lambda: {"exit": 2, "non_terminating": 1, "max_iterations": 0, "budget": 0})
    >>> for line in census_lines([row]):
    ...     print(line)
    <BLANKLINE>
    Census: how the runs of each termination row end (a refuted row's census is a separate sample)
    <BLANKLINE>
      law           rule        family   cases  exit  non_terminating  max_iterations  budget
      rule          ideal       corner       3     2                1               0       0
    """
    rows = [(v, c) for v in found if (c := getattr(v, "census", lambda: None)()) is not None]
    if not rows:
        return []
    stops = list(dict.fromkeys(k for _, c in rows for k in c))
    lines = ["", "Census: how the runs of each termination row end (a refuted row's census is a separate sample)", ""]
    lines.append(f"  {'law':12}  {'rule':10}  {'family':7}  {'cases':>5}  " + "  ".join(stops))
    for v, c in rows:
        counts = "  ".join(f"{c.get(k, 0):>{len(k)}}" for k in stops)
        lines.append(f"  {v.law:12}  {v.rule:10}  {v.family:7}  {v.cases:>5}  {counts}")
    return lines
