"""``verify properties``, ``verify oracle``: the property suite and the reference oracle."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from verify.checks.properties.profiles import PROFILES
from verify.cli.common import (
    PROG,
    WORKERS,
    NonNegativeRational,
    OutputDir,
    Parser,
    Seconds,
    StatusLine,
    UsageError,
    budget_options,
    command,
    run_budget,
    write_output,
    writing,
)


def properties_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify properties``."""
    from verify.core.rule import RULES

    p.add_argument(
        "--profile",
        default="ci",
        choices=tuple(PROFILES),
        help="cases per row: dev 25, ci 100 (default), thorough 100000 per property",
    )
    p.add_argument("--property", action="append", help="only this property (name or prefix; repeatable)")
    p.add_argument("--rule", action="append", choices=RULES, help="only this rule (repeatable)")
    p.add_argument(
        "--family", action="append", choices=("general", "cradle", "corner"), help="only this family (repeatable)"
    )
    p.add_argument("--workers", type=WORKERS, default=None, help="processes (default: every core)")
    p.add_argument("--counterexamples", metavar="DIR", type=OutputDir(),
                   help="write each counterexample as a case file into DIR")  # fmt: skip
    p.add_argument("--list", action="store_true", help="list the properties and exit")
    p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    p.add_argument("--json", action="store_true", help="print the verdicts as JSON (contracts)")


def oracle_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify oracle``."""
    oracle_sub = p.add_subparsers(dest="action", metavar="ACTION", parser_class=Parser, required=True)
    q = command(oracle_sub, "oracle export", cmd_oracle)
    q.add_argument("folder", metavar="DIR", type=OutputDir(), help="the folder to write (created if needed)")
    q = command(oracle_sub, "oracle check", cmd_oracle)
    q.add_argument("cases", metavar="CASES.json")
    q.add_argument("results", metavar="RESULTS.json", nargs="?", help="the other implementation's result file")
    q.add_argument("--impl", metavar="COMMAND", help="run COMMAND: case file on stdin, result file on stdout")
    q.add_argument("--timeout", type=Seconds(), default=600.0, metavar="SECONDS",
                   help="seconds allowed to --impl (default 600)")  # fmt: skip
    q.add_argument("--rtol", default="1e-9", type=NonNegativeRational(),
                   help="relative tolerance on the exit velocity (default 1e-9)")  # fmt: skip
    q.add_argument("--atol", default="0", type=NonNegativeRational(),
                   help="absolute tolerance on the exit velocity (default 0)")  # fmt: skip
    budget_options(q, "per case, for the exact results")
    q.add_argument("--quiet", action="store_true", help="no status line on stderr")
    q.add_argument("--json", action="store_true", help="print the comparison as JSON")


def cmd_properties(args: argparse.Namespace) -> int:
    """``verify properties``: every row's verdict (or the list of properties); exit code 1 if one is refuted."""
    import os

    from verify.checks.properties.verdicts import report, rows, verdicts
    from verify.records.results import dumps
    from verify.views.text import properties_text

    if args.list:
        for prop in dict.fromkeys(p for p, _, _ in rows()):
            print(f"{prop.name}  [rules: {', '.join(prop.rules)}; families: {', '.join(prop.families)}]")
        return 0
    workers = args.workers if args.workers is not None else (os.cpu_count() or 1)

    def progress(done: int, total: int, v: Any) -> None:
        line = f"  [{done}/{total}] {v.verdict:8} {v.cases:6} cases  {v.property} | {v.rule} | {v.family}"
        if v.verdict == "refuted":  # shown at once: a long run may be stopped before its table
            line += f"\n      {v.note}\n      {json.dumps(v.counterexample, sort_keys=True)}"
        print(line, file=sys.stderr, flush=True)

    found = verdicts(
        args.profile,
        properties=args.property,
        families=args.family,
        rules=args.rule,
        workers=workers,
        progress=None if args.quiet else progress,
    )
    if args.counterexamples:
        write_counterexamples(args.counterexamples, found)
    sys.stdout.write(dumps(report(args.profile, found)) if args.json else properties_text(args.profile, found))
    return 1 if any(v.verdict == "refuted" for v in found) else 0


def write_counterexamples(folder: str, found: list[Any]) -> None:
    """One case file per refuted row, each written whole (``--counterexamples DIR``)."""
    import os

    from verify.records.results import dumps

    with writing(folder, "--counterexamples"):
        os.makedirs(folder, exist_ok=True)
    for v in found:
        if v.counterexample is None:
            continue
        write_output(os.path.join(folder, v.counterexample["id"] + ".json"), dumps({"cases": [v.counterexample]}),
                     "--counterexamples")  # fmt: skip


def cmd_oracle(args: argparse.Namespace) -> int:
    """``verify oracle export|check``."""
    from verify.checks import oracle

    if args.action == "export":
        with writing(args.folder, "DIR"):
            paths = oracle.export(args.folder)
        for path in paths:
            print(f"wrote {path}")
        return 0
    return oracle_check(args)


def oracle_check(args: argparse.Namespace) -> int:
    """``verify oracle check``: another implementation's results against the exact ones; exit code 1 on a mismatch."""
    from verify.checks import oracle
    from verify.records.results import dumps, load_cases
    from verify.views.text import oracle_text

    if (args.results is None) == (args.impl is None):
        raise UsageError(f"{PROG} oracle check: give either RESULTS.json or --impl COMMAND")
    load_cases(args.cases)  # validates the file: schema, then every number
    with open(args.cases, encoding="utf-8") as fh:
        case_text = fh.read()
    records = json.loads(case_text)["cases"]
    if args.max_iterations is not None:  # the cases as if each had this cap: for the exact runs and --impl
        records = [dict(r, max_iterations=args.max_iterations) for r in records]
        case_text = dumps({"cases": records})
    status = StatusLine.for_args(args)
    got = oracle.load_results(*other_results(args, case_text, status))

    def progress(k: int, case_id: str, impulses: int) -> None:
        status.show(f"verify oracle check: exact results, case {k}/{len(records)} {case_id}: {impulses} impulses",
                    now=impulses == 0)  # fmt: skip

    try:
        expected = oracle.golden_results(records, budget=run_budget(args),
                                         progress=progress if status.enabled else None)  # fmt: skip
    finally:
        status.close()
    comparison = oracle.compare(records, expected, got, rtol=args.rtol, atol=args.atol)  # Fractions
    if args.json:
        sys.stdout.write(dumps(oracle.comparison_json(comparison)))
    else:
        sys.stdout.write(oracle_text(comparison))
        if comparison.limited:
            print(f"note: {len(comparison.limited)} cases checked only on the impulses the exact run made before "
                  f"reaching --max-bits or --case-timeout: {', '.join(comparison.limited)}")  # fmt: skip
    return 0 if comparison.ok else 1


def other_results(args: argparse.Namespace, case_text: str, status: StatusLine) -> tuple[str, str]:
    """The other implementation's result file as text (the output of ``--impl``, or RESULTS.json), and
    its name for messages."""
    from verify.checks import oracle

    if args.impl is not None:
        status.show(f"verify oracle check: running {args.impl}", now=True)
        try:
            return oracle.run_implementation(args.impl, case_text, args.timeout), f"the output of {args.impl!r}"
        finally:
            status.close()
    try:
        with open(args.results, encoding="utf-8") as fh:
            return fh.read(), args.results
    except OSError as exc:
        raise UsageError(f"{args.results}: cannot read ({exc.strerror})") from None


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("properties", "oracle")
