"""``verify oracle explain`` as text and as JUnit XML (:mod:`verify.oracle.explain`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from verify.numbers.format import counted, format_decimal

if TYPE_CHECKING:
    from verify.oracle.explain import Explanation


def explanation_text(result: Explanation) -> str:
    """The settings that explain the most cases first, then one line per case that no model explains, then a
    line per case with the models that explain it.

    >>> from fractions import Fraction
    >>> from verify.oracle.explain import Explanation, Row, Settings
    >>> s = Settings("sequential", 10, "as given", Fraction(1, 2))
    >>> print(explanation_text(Explanation([Row("a", [s.label()], [s], s.label(), Fraction(0))], [(1, [s])],
    ...                                    Fraction(1, 10**9))), end="")
    Explained: 1 of 1 cases by the sequential law, 10 sweeps, order as given, threshold 1/2
      (verify oracle check --law sequential --iterations 10 --threshold 1/2)
    <BLANKLINE>
    settings that explain the most cases:
      1 of 1  the sequential law, 10 sweeps, order as given, threshold 1/2
    <BLANKLINE>
      a: the sequential law, 10 sweeps, order as given, threshold 1/2
    <BLANKLINE>
    tolerance: a model explains an answer within 1e-9 of the entrance speed (max_i |got_i - model_i| / max_i |v_in_i|)
    """
    from verify.oracle.explain import describe_settings
    from verify.oracle.grading import short_number

    n = len(result.rows)
    lines = []
    if result.best:
        count = result.ranking[0][0]
        lines.append(f"Explained: {count} of {n} cases by {'; '.join(describe_settings(result.best))}")
        if result.best[0].flags():
            lines.append(f"  (verify oracle check {result.best[0].flags()})")
        if len(result.best) > 1:
            lines.append(f"  {len(result.best)} settings explain exactly these cases: the cases cannot tell them apart")
    else:
        lines.append(f"Explained: no model explains any of the {n} cases")
    if result.own_settings:
        own = len(result.own_settings)
        carry = "carries its" if own == 1 else "carry their"
        lines.append(f"  {counted(own, 'case')} {carry} own law_settings, which the grid replaces "
                     f"(verify oracle check honours them): {', '.join(result.own_settings[:5])}"
                     + (", ..." if len(result.own_settings) > 5 else ""))  # fmt: skip
    lines += ["", "settings that explain the most cases:"]
    for count, group in result.ranking[:5]:
        lines.append(f"  {count} of {n}  {'; '.join(describe_settings(group))}")
    lines.append("")
    for r in result.rows:
        if r.settings:
            lines.append(f"  {r.case_id}: {'; '.join(r.explained_by)}")
        else:
            near = f"nearest {r.nearest} at {format_decimal(r.distance, 3)}" if r.distance is not None else ""
            lines.append(f"UNEXPLAINED {r.case_id}: " + "; ".join(x for x in (r.note, near) if x))
    lines += ["", f"tolerance: a model explains an answer within {short_number(result.tolerance)} of the entrance "
              "speed (max_i |got_i - model_i| / max_i |v_in_i|)"]  # fmt: skip
    return "\n".join(lines) + "\n"


def explanation_junit(result: Explanation, suite: str, group: str = "cases") -> str:
    """One test case per case (classname ``explain.GROUP``, the case file's name): a failure names the nearest
    model and its distance."""
    from verify.oracle.grading import Grade
    from verify.oracle.junit import junit_xml

    grades = []
    for r in result.rows:
        if r.settings:
            grades.append(Grade(r.case_id, "explained", "; ".join(r.explained_by)))
        else:
            near = f"nearest {r.nearest} at {format_decimal(r.distance, 3)}" if r.distance is not None else ""
            grades.append(Grade(r.case_id, "unexplained", "; ".join(x for x in (r.note, near) if x)))
    return junit_xml(grades, suite, {"explained": "passed", "unexplained": "failure"}, prefix="explain", group=group)
