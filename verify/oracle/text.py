"""The text of the oracle's check (``verify oracle check``): mismatches, graded classes, error tables."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from verify.numbers.format import counted, format_decimal

if TYPE_CHECKING:
    from collections.abc import Mapping

    from verify.oracle.grading import TableRow
    from verify.oracle.reference import Comparison


def graded_lines(comparison: Comparison) -> list[str]:
    """The graded verdicts: one line per case that does not pass, the count per class, and the
    cases that need the largest tolerance (:mod:`verify.oracle.grading`)."""
    from verify.numbers.format import format_decimal
    from verify.oracle.grading import PASSING, hardest

    lines = [f"{g.cls.upper()} {g.case_id}: {g.detail}" for g in comparison.grades if g.cls not in PASSING]
    lines += [f"WITHIN_TOLERANCE {g.case_id}: {g.detail}" for g in comparison.grades
              if g.cls == "within_tolerance" and g.detail]  # fmt: skip
    lines += ["", "  class                count"] if lines else ["  class                count"]
    lines += [f"  {cls:20} {n}" for cls, n in comparison.classes().items()]
    worst = hardest(comparison.grades, 3)
    if worst:
        lines += ["", "largest tolerance needed (relative to the exit speed; binary64 ulps of the exact value):"]
        lines += [f"  {g.case_id}: {format_decimal(g.needed_speed or 0, 3)} ({g.needed_ulps} ulps)" for g in worst]
    return [*lines, ""]


def ulps_text(n: int) -> str:
    """A count of ulps: all its digits below a million, else its first three digits (truncated).

    >>> ulps_text(4049), ulps_text(938012345678901234567890123456)
    ('4049', '9.38e+29')
    """
    digits = str(n)
    if n < 10**6:
        return digits
    return f"{digits[0]}.{digits[1:3]}e+{len(digits) - 1}"


def error_table_text(rows: Sequence[TableRow]) -> str:
    """``verify oracle table``: one row per implementation, the count per class and the worst errors."""
    from verify.oracle.grading import CLASSES

    used = [c for c in CLASSES if any(c in r.counts for r in rows)]
    width = max([len(r.name) for r in rows] + [14])
    head = f"  {'implementation':{width}}  {'law':12}" + "".join(f"  {c:>{max(len(c), 5)}}" for c in used)
    lines = [head + "  worst relative error (case)"]
    for r in rows:
        counts = "".join(f"  {r.counts.get(c, 0):>{max(len(c), 5)}}" for c in used)
        worst = "-" if r.worst_speed is None else f"{format_decimal(r.worst_speed[0], 3)} ({r.worst_speed[1]})"
        ulp_text = "" if r.worst_ulps is None else f"; {ulps_text(r.worst_ulps[0])} ulps ({r.worst_ulps[1]})"
        lines.append(f"  {r.name:{width}}  {r.law:12}{counts}  {worst}{ulp_text}")
    return "\n".join(lines) + "\n"


def oracle_text(comparison: Comparison, report: Mapping[str, str] | None = None) -> str:
    """Every mismatch of ``verify oracle check``, then a summary table; the last lines count the cases as
    ``--junit`` reports them (``report``: its ``--junit-as``)."""
    from verify.oracle.grading import PASSING
    from verify.oracle.junit import junit_counts

    said = {(g.case_id, g.detail) for g in comparison.grades if g.cls not in PASSING}
    # a mismatch that its grade's line below says (class, case, detail) is not said twice
    lines = [f"MISMATCH {m.case_id}: {m.field}: {m.detail}" for m in comparison.mismatches
             if (m.case_id, m.detail) not in said]  # fmt: skip
    fields: dict[str, int] = {}
    for m in comparison.mismatches:
        key = m.field.split("[")[0]
        fields[key] = fields.get(key, 0) + 1
    lines += [*([""] if lines else []), "  what                 count", f"  cases checked        {comparison.checked}",
              f"  cases agreeing       {comparison.agreeing}"]  # fmt: skip
    lines += [f"  {k:20} {v}" for k, v in sorted(fields.items())]
    if comparison.skipped:
        lines.append(f"  skipped by the implementation: {len(comparison.skipped)}")
    lines.append("")
    for name, lacking in comparison.unchecked.items():
        lines.append(f"not checked: {name} (left out of {counted(lacking, 'result')}: velocity-only)")
    if comparison.unchecked:
        lines.append("")
    for cid, reason in comparison.skipped.items():
        lines.append(f"SKIPPED {cid}: {reason}")
    lines += graded_lines(comparison)
    if comparison.tolerance:
        lines += [f"tolerance: {comparison.tolerance}", ""]
    counts = junit_counts(comparison.grades, report)
    graded = {g.case_id for g in comparison.grades}
    if any(m.case_id not in graded for m in comparison.mismatches):  # results of no case: a test of their own
        counts = dict(counts, tests=counts["tests"] + 1, failures=counts["failures"] + 1)
    lines.append(f"as tests (--junit): {counts['passed']} passed, {counts['failures']} failed, "
                 f"{counts['skipped']} skipped of {counts['tests']}")  # fmt: skip
    agree = "every case agrees" if not comparison.skipped else "every case that the implementation ran agrees"
    if comparison.limited:
        agree += (f" as far as the exact runs went ({len(comparison.limited)} limited by the budget: --junit counts "
                  "them as failures unless --junit-as limited=passed)")  # fmt: skip
    lines.append(f"OK: {agree}" if comparison.ok else counted(len(comparison.mismatches), "mismatch"))
    return "\n".join(lines) + "\n"
