"""The report page of the reference oracle: the golden dataset, its self-check, the error tables."""

from __future__ import annotations

from verify.oracle.reference import Comparison
from verify.oracle.selfcheck import OracleFindings
from verify.views.pages import block


def oracle_page(found: OracleFindings) -> str:
    """The page of the reference oracle."""
    from verify.oracle import reference as oracle
    from verify.oracle.text import oracle_text

    lines = [
        "# The reference oracle\n",
        *_found_lines(found),
        "The golden dataset (`golden/`, written by `verify oracle export golden`): what it contains.\n",
        oracle.dataset_description(found.cases, found.results, found.skipped).split("\n", 1)[1],  # not its banner
        "Self-check: the exact results compared with themselves at zero tolerance "
        "(`verify oracle check golden/cases.json golden/results.json --rtol 0 --floor 0`):\n",
        block(oracle_text(found.self_check)),
    ]
    if found.example is not None:
        lines += [
            "\nAn independent float implementation (`examples/float_impl.py`) checked against it "
            '(`verify oracle check golden/cases.json --impl "python3 examples/float_impl.py"`):\n',
            block(oracle_text(found.example)),
        ]
    else:
        lines.append("\n(The worked example `examples/float_impl.py` is in the source checkout; run from its root.)\n")
    return "\n".join(lines + error_tables(found))


def _found_lines(found: OracleFindings) -> list[str]:
    """The page's opening: the golden dataset, its self-check, and how the float example and the engines fare."""
    from verify.views.pages import wrapped

    def classes(c: Comparison) -> str:
        return ", ".join(f"{n} {cls.replace('_', ' ')}" for cls, n in c.classes().items())

    never = sum(r["stop"] == "non_terminating" for r in found.results)
    text = [
        f"**What was found.** The golden dataset holds {len(found.cases)} cases with their exact results under the "
        f"paper's rule ({never} of them never exit, with a certificate); compared with themselves at zero tolerance "
        + ("they agree on every case." if found.self_check.ok else "they do NOT agree.")
    ]
    if found.example is not None:
        endless = {c["id"] for c, r in zip(found.cases, found.results) if r["stop"] == "non_terminating"}
        wrong = {g.case_id for g in found.example.grades if g.cls == "wrong_stop"}
        text.append(
            "An independent implementation in binary floating point (`examples/float_impl.py`, the paper's rule in "
            f"Python floats) grades as: {classes(found.example)} on the golden cases"
            + ("" if found.hard is None else f"; {classes(found.hard)} on the hard cases of level 1")
            + (
                ". Its wrong stops on the golden cases are the runs that never exit, which it ends after finitely "
                "many impulses."
                if wrong and wrong <= endless
                else "."
            )
        )
    if found.engine_rows:
        text.append(f"The {len(found.engine_rows)} physics engines of the engines page are graded on the same cases "
                    "against the simultaneous law in the last table.")  # fmt: skip
    return [line for paragraph in text for line in [*wrapped(paragraph), ""]]


def error_tables(found: OracleFindings) -> list[str]:
    """The error tables of the oracle page: the float example on the hard cases of level 1, and the
    float example and every engine of the engines record on the golden cases."""
    from verify.oracle.grading import table_row
    from verify.oracle.text import error_table_text

    lines = ["\n## Error tables\n"]
    if found.hard is not None:
        lines += [
            "The hard cases of `verify oracle generate --level 1 --seed 0` (cases near the exact breakpoints, the",
            "corner's boundaries, grazing contacts, runs that never exit), graded against the paper's rule",
            "(`verify oracle table hard.json floats=RESULTS.json`):\n",
            block(error_table_text([table_row("float example", "rule", found.hard)])),
        ]
    rows = [table_row("float example", "rule", found.example)] if found.example is not None else []
    rows += found.engine_rows
    if rows:
        lines += [
            "\nThe golden cases: the float example against the rule, and each physics engine of",
            "[engines.md](engines.md) against the simultaneous law (the law engines implement; the cases an engine",
            "cannot build count as skipped):\n",
            block(error_table_text(rows)),
        ]
    return lines
