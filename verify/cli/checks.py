"""``verify properties``, ``verify oracle``: the property suite and the reference oracle."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
import time
from collections.abc import Iterator, Sequence
from fractions import Fraction
from typing import Any

from verify.cli.common import (
    PROG,
    BoundedInt,
    IntList,
    NonNegativeRational,
    OutputDir,
    OutputFile,
    Parser,
    RationalList,
    Seconds,
    StatusLine,
    UsageError,
    budget_options,
    cluster_options,
    command,
    law_choice,
    law_options,
    one_line,
    quiet_option,
    renamed,
    run_budget,
    task_runner,
    write_output,
    writing,
)
from verify.errors import InvalidInput, Undecided
from verify.numbers.format import plural
from verify.oracle.impl import IMPL_NOTE
from verify.properties.profiles import PROFILES
from verify.records.files import STDIO, display_name, read_text
from verify.records.versions import stamped


class JunitAs:
    """``--junit-as CLASS=KIND,...``: how each class is reported in the JUnit XML
    (:func:`verify.oracle.junit.parse_report_as`), checked when parsed.

    >>> JunitAs()("gave_up=skipped")["gave_up"]
    'skipped'
    """

    def __call__(self, text: str) -> dict[str, str]:
        from verify.oracle.junit import parse_report_as

        try:
            return parse_report_as(text)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    def __repr__(self) -> str:
        return "CLASS=KIND list"


def properties_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify properties``."""
    from verify.laws.rule import RULES

    p.add_argument(
        "--profile",
        default="ci",
        choices=tuple(PROFILES),
        help="cases per row: dev 25, ci 100 (default), thorough 100000 per property",
    )
    p.add_argument(
        "--property",
        action="append",
        help="only this property (its name, its start, or a part of one name only; repeatable)",
    )
    p.add_argument("--rule", action="append", choices=RULES,
                   help="only this rule, or for the simultaneous law these CORs (repeatable)")  # fmt: skip
    law_options(p, append=True, help="only this law: rule (the paper's), simultaneous or sequential (repeatable; "
                "default all three)")  # fmt: skip
    p.add_argument(
        "--family", action="append", choices=("general", "cradle", "corner"), help="only this family (repeatable)"
    )
    cluster_options(p, "processes (default: every core); one row a task")
    p.add_argument("--counterexamples", metavar="DIR", type=OutputDir(),
                   help="write each counterexample as a case file into DIR")  # fmt: skip
    p.add_argument("--list", action="store_true", help="list the properties and exit")
    p.add_argument("--quiet", action="store_true", help="no progress and no refutations on stderr, only a final line")
    p.add_argument("--json", action="store_true", help="print the verdicts as JSON (contracts)")


def implementation_options(q: argparse.ArgumentParser) -> None:
    """CASES.json and the other implementation's answers: RESULTS.json, or ``--impl COMMAND`` (with
    ``--impl-time-limit``)."""
    q.add_argument("cases", metavar="CASES.json", help="the case file (- reads it from stdin)")
    q.add_argument("results", metavar="RESULTS.json", nargs="?",
                   help="the other implementation's result file (- reads it from stdin)")  # fmt: skip
    q.add_argument("--impl", metavar="COMMAND",
                   help="run COMMAND: case file on stdin, result file on stdout; " + IMPL_NOTE)  # fmt: skip
    renamed(q, "--impl-time-limit", "--timeout", type=Seconds(), default=600.0, metavar="SECONDS",
            help="seconds allowed to --impl (default 600)")  # fmt: skip


def oracle_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify oracle``."""
    oracle_sub = p.add_subparsers(dest="action", metavar="ACTION", parser_class=Parser, required=True)
    q = command(oracle_sub, "oracle export", cmd_oracle)
    q.add_argument("folder", metavar="DIR", type=OutputDir(), nargs="?", default=None,
                   help="the folder to write (created if needed), or --out DIR")  # fmt: skip
    q.add_argument("--out", metavar="DIR", type=OutputDir(), default=None, help="the folder to write, as DIR")
    quiet_option(q, "no progress on stderr (this command prints none; every subcommand takes --quiet)")
    q = command(oracle_sub, "oracle check", cmd_oracle)
    implementation_options(q)
    q.add_argument("--rtol", default="1e-8", type=NonNegativeRational(),
                   help="tolerance on each exit-velocity component, relative to the exact exit speed "
                        "max|v_exit| (default 1e-8)")  # fmt: skip
    q.add_argument("--atol", default="0", type=NonNegativeRational(),
                   help="absolute tolerance added to it (default 0)")  # fmt: skip
    q.add_argument("--floor", default="1e-12", type=NonNegativeRational(),
                   help="a component whose exact value is 0 also passes within FLOOR times the entrance speed "
                        "max|v_in| (default 1e-12)")  # fmt: skip
    law_options(q, help="the law of the exact results: the paper's rule (default), the simultaneous law, or the "
                "sequential law (with its settings below)")  # fmt: skip
    q.add_argument("--junit", metavar="FILE", type=OutputFile(stdout=True), default=None,
                   help="also write the graded verdicts as JUnit XML, one test case per case (- for stdout: "
                        "the report then goes to stderr)")  # fmt: skip
    q.add_argument("--junit-as", metavar="CLASS=KIND,...", type=JunitAs(), default=None,
                   help="how --junit reports a class: failure, skipped or passed (default: exact and "
                        "within_tolerance pass, skipped is skipped, every other class is a failure), "
                        "e.g. gave_up=skipped,limited=passed")  # fmt: skip
    q.add_argument("--tolerances", metavar="FILE", default=None,
                   help="tolerance budgets per case (in exit speeds or binary64 ulps): docs/oracle.md")  # fmt: skip
    budget_options(q, "per case, for the exact results")
    q.add_argument("--quiet", action="store_true", help="no status line on stderr")
    q.add_argument("--json", action="store_true", help="print the comparison as JSON")
    q = command(oracle_sub, "oracle explain", cmd_oracle)
    implementation_options(q)
    q.add_argument("--sweeps", type=IntList(1, 1000), default=None, metavar="K,...",
                   help="the sequential law's sweeps to try: 1-20,25,30 (default 1-20,25,30,40,50,100)")  # fmt: skip
    q.add_argument("--thresholds", type=RationalList(), default=None, metavar="T,...",
                   help="the restitution thresholds to try (speeds; default 0,1/100,1/10,1/4,1/2,1,2)")  # fmt: skip
    q.add_argument("--tolerance", type=NonNegativeRational(), default="1e-9", metavar="TOL",
                   help="a model explains an answer within TOL times the entrance speed (default 1e-9, float64; "
                        "1e-5 for float32)")  # fmt: skip
    q.add_argument("--junit", metavar="FILE", type=OutputFile(stdout=True), default=None,
                   help="also write one test case per case: passed when a model explains it (- for stdout: the "
                        "report then goes to stderr)")  # fmt: skip
    q.add_argument("--quiet", action="store_true", help="no status line on stderr")
    q.add_argument("--json", action="store_true", help="print the explanation as JSON")
    q = command(oracle_sub, "oracle generate", cmd_oracle)
    q.add_argument("--level", type=BoundedInt(1, 3), default=1, help="1 (small, for CI), 2 or 3 (larger)")
    q.add_argument("--seed", type=BoundedInt(0, 2**63 - 1), default=0, help="the seed of the random cases (default 0)")
    q.add_argument("--law", default="rule", choices=("rule", "simultaneous", "sequential"),
                   help="also the cases where this law branches: restitution thresholds, order ties and badly "
                        "scaled contacts (sequential), the active set's boundary (simultaneous); each sequential "
                        "case carries its own law_settings")  # fmt: skip
    renamed(q, "--save", "--out", metavar="FILE", type=OutputFile(stdout=True), default=None,
            help="write the case file to FILE (default, or -: stdout)")  # fmt: skip
    quiet_option(q, "no progress on stderr (this command prints none; every subcommand takes --quiet)")
    q = command(oracle_sub, "oracle table", cmd_oracle)
    q.add_argument("cases", metavar="CASES.json", help="the case file (- reads it from stdin)")
    q.add_argument("results", metavar="RESULTS.json", nargs="+",
                   help="result files, each NAME=FILE or FILE (named by its file name; one of the files may be -, "
                        "stdin)")  # fmt: skip
    law_options(q, help="the law of the exact results (the sequential law with its settings below)")
    q.add_argument("--rtol", default="1e-8", type=NonNegativeRational(),
                   help="tolerance relative to the exact exit speed (default 1e-8)")  # fmt: skip
    quiet_option(q, "no progress on stderr (this command prints none; every subcommand takes --quiet)")
    q.add_argument("--json", action="store_true", help="print the table as JSON")


def cmd_properties(args: argparse.Namespace) -> int:
    """``verify properties``: every row's verdict (or the list of properties); exit code 1 if one is refuted,
    2 (3 for a bug in verify) if a row could not be run (its task failed twice: the others are still run,
    checkpointed and shown)."""
    import time

    from verify.properties.text import properties_text
    from verify.properties.verdicts import checkpoint_options, report, rows, run_verdicts
    from verify.records.results import dumps

    if args.list:
        list_properties(rows())
        return 0
    status = StatusLine.for_args(args)
    start = time.monotonic()

    def progress(done: int, total: int, v: Any) -> None:
        if v.verdict == "refuted" and not args.quiet:  # shown at once: a long run may be stopped before its table
            status.close()
            print(f"  refuted: {v.property} | {v.law} | {v.rule} | {v.family}\n      {v.note}\n"
                  f"      {json.dumps(v.counterexample, sort_keys=True)}", file=sys.stderr, flush=True)  # fmt: skip
        width = 30
        bar = "#" * (width * done // max(total, 1))
        status.show(f"[{bar:{width}}] {done}/{total} tasks  {time.monotonic() - start:.0f} s", now=done == total)

    laws = law_choice(args, "properties")
    chosen = {"properties": args.property, "families": args.family, "rules": args.rule, "laws": laws}
    with task_runner(args, checkpoint_options(args.profile, **chosen)) as runner:
        run = run_verdicts(args.profile, **chosen, progress=progress, runner=runner)
    status.close()
    found = [v for v in run.results if v is not None]
    counts = ", ".join(
        f"{n} {kind}" for kind in ("proved", "holds", "refuted") if (n := sum(v.verdict == kind for v in found))
    )
    print(f"{PROG} properties: {len(found)} of {len(run.results)} rows ({counts or 'none'}) in "
          f"{time.monotonic() - start:.0f} s", file=sys.stderr, flush=True)  # fmt: skip
    for f in run.failures:
        print(f"{PROG}: error: row {f.label} failed twice: {f.error}", file=sys.stderr)
    if args.counterexamples:
        write_counterexamples(args.counterexamples, found)
    sys.stdout.write(dumps(report(args.profile, found)) if args.json else properties_text(args.profile, found))
    if run.failures:  # 3 when a row failed with a bug in verify, 2 with bad input
        return 3 if any(f.internal for f in run.failures) else 2
    return 1 if any(v.verdict == "refuted" for v in found) else 0


def list_properties(table: Sequence[tuple[Any, str, str, Any]]) -> None:
    """``verify properties --list``: each property with the rules of each law, and its families.

    >>> from verify.properties.verdicts import rows
    >>> table = rows(["the exit velocity"], ["corner"], ["ideal", "asymmetric"])
    >>> list_properties(table)  # doctest: +NORMALIZE_WHITESPACE
    the exit velocity is outgoing  [rule: ideal, asymmetric; simultaneous: ideal; sequential: ideal;
    families: general, cradle, corner]
    """
    for prop in dict.fromkeys(p for p, _, _, _ in table):
        laws = "; ".join(
            f"{law}: " + ", ".join(dict.fromkeys(r for p, _, r, x in table if p is prop and x == law))
            for law in prop.laws
        )
        print(f"{prop.name}  [{laws}; families: {', '.join(prop.families)}]")


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


def export_folder(args: argparse.Namespace) -> str:
    """The folder of ``verify oracle export``: DIR or ``--out DIR`` (one of them)."""
    if args.folder is None and args.out is None:
        raise UsageError(f"{PROG} oracle export: give the folder to write, as DIR or as --out DIR")
    if args.folder is not None and args.out is not None:
        raise UsageError(f"{PROG} oracle export: give the folder once, as DIR or as --out DIR")
    return str(args.folder if args.folder is not None else args.out)


def cmd_oracle(args: argparse.Namespace) -> int:
    """``verify oracle export|check``."""
    from verify.oracle import reference as oracle

    if args.action == "generate":
        from verify.oracle.hardcases import generate_file_text

        text = generate_file_text(args.level, args.seed, args.law)
        if args.save and args.save != STDIO:
            write_output(args.save, text, "--save")
        else:
            sys.stdout.write(text)
        return 0
    if args.action == "table":
        return oracle_table(args)
    if args.action == "explain":
        return oracle_explain(args)
    if args.action == "export":
        folder = export_folder(args)
        with writing(folder, "DIR"):
            paths = oracle.export(folder)
        for path in paths:
            print(f"wrote {path}")
        return 0
    return oracle_check(args)


def oracle_check(args: argparse.Namespace) -> int:
    """``verify oracle check``: another implementation's results against the exact ones; exit code 1 on a mismatch."""
    if args.junit_as is not None and not args.junit:
        raise UsageError(f"{PROG} oracle check: --junit-as needs --junit FILE")
    both_stdout(args, "oracle check")
    with junit_on_error(args, f"verify oracle check {args.cases}"):
        return _oracle_check(args, time.monotonic())


def _oracle_check(args: argparse.Namespace, started: float) -> int:
    from verify.oracle import reference as oracle
    from verify.oracle.text import oracle_text
    from verify.records.results import dumps

    budgets = None  # the options are read before the cases, so that a bad one is told at once
    if args.tolerances:
        from verify.oracle.grading import Budgets, Tolerance

        budgets = Budgets.load(args.tolerances, Tolerance(rtol=args.rtol, atol=args.atol, floor=args.floor))
    case_text, records, dataset = checked_cases(args, "oracle check")
    if args.max_impulses is not None:  # the cases as if each had this cap: for the exact runs and --impl
        records = [dict(r, max_iterations=args.max_impulses) for r in records]
        case_text = dumps(stamped({"cases": records}, dataset))
    status = StatusLine.for_args(args)
    got, skipped = oracle.load_result_file(*other_results(args, case_text, status), dataset)
    clock = CaseClock()

    def progress(k: int, case_id: str, impulses: int) -> None:
        clock.start(case_id, impulses)
        if status.enabled:
            status.show(f"verify oracle check: exact results, case {k}/{len(records)} {case_id}: {impulses} "
                        "impulses", now=impulses == 0)  # fmt: skip

    try:
        expected = oracle.golden_results(records, budget=run_budget(args), law=law_choice(args, "oracle check"),
                                         progress=progress)  # fmt: skip
    except InvalidInput as exc:  # a law setting that does not fit a case: name the file too
        raise InvalidInput(f"{display_name(args.cases)}: {exc}") from None
    finally:
        status.close()
    clock.start("", 0)
    comparison = oracle.compare(records, expected, got, rtol=args.rtol, atol=args.atol, floor=args.floor,
                                skipped=skipped, budgets=budgets)  # fmt: skip
    report = sys.stderr if args.junit == STDIO else sys.stdout  # stdout holds one document
    if args.json:
        report.write(dumps(stamped(oracle.comparison_json(comparison), dataset, report=True)))
    else:
        report.write(oracle_text(comparison, args.junit_as))
        if comparison.limited:
            print(f"note: {len(comparison.limited)} {plural(len(comparison.limited), 'case')} checked only on the "
                  "impulses the exact run made before reaching --max-bits or --case-time-limit: "
                  f"{', '.join(comparison.limited)}", file=report)  # fmt: skip
        other = other_law(got, args.law)
        if other:
            print(f"note: the results name the {other} law and were graded under the {args.law} (--law "
                  f"{args.law}); --law {other} grades them under their own", file=report)  # fmt: skip
    if args.junit:
        from verify.oracle.junit import junit_xml

        checks: dict[str, list[str]] = {}
        for m in sorted(comparison.mismatches, key=lambda m: not m.field.startswith("exit_velocity")):
            checks.setdefault(m.case_id, []).append(f"{m.field}: {m.detail}")
        xml = junit_xml(comparison.grades, f"verify oracle check {args.cases}", args.junit_as,
                        group=junit_group(args.cases), checks=checks, times=clock.seconds,
                        total=time.monotonic() - started)  # fmt: skip
        write_output(args.junit, xml, "--junit")
    return 0 if comparison.ok else 1


class CaseClock:
    """The seconds of each case's exact run, from the progress calls (impulses 0: a case starts, and the
    last one ends)."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}
        self._running: tuple[str, float] | None = None

    def start(self, case_id: str, impulses: int) -> None:
        """Case ``case_id`` starts (when ``impulses`` is 0): the running one ends now."""
        if impulses:
            return
        now = time.monotonic()
        if self._running is not None:
            done, began = self._running
            self.seconds[done] = self.seconds.get(done, 0.0) + now - began
        self._running = (case_id, now) if case_id else None


def other_law(results: list[Any], law: str) -> str | None:
    """The law the results name (their ``law`` fields) when it is not ``law``, the one they are graded under.

    >>> other_law([{"id": "a", "law": "simultaneous"}], "rule"), other_law([{"id": "a"}], "rule")
    ('simultaneous', None)
    """
    named = sorted({r["law"] for r in results if isinstance(r, dict) and isinstance(r.get("law"), str)})
    return named[0] if len(named) == 1 and named[0] != law else None


def junit_group(cases: str) -> str:
    """The ``classname`` part that names the case file (its name without ``.json``; ``stdin`` for ``-``).

    >>> junit_group("golden/cases.json"), junit_group("-")
    ('cases', 'stdin')
    """
    return "stdin" if cases == STDIO else os.path.splitext(os.path.basename(cases))[0] or "cases"


def both_stdout(args: argparse.Namespace, command_name: str) -> None:
    """``--junit -`` and ``--json`` would both write to stdout: a usage error."""
    if getattr(args, "junit", None) == STDIO and getattr(args, "json", False):
        raise UsageError(f"{PROG} {command_name}: --junit - and --json both write to stdout: give --junit a file")


@contextlib.contextmanager
def junit_on_error(args: argparse.Namespace, suite: str, prefix: str = "oracle") -> Iterator[None]:
    """With ``--junit``, a run that ends without grades (bad input, an internal error, Ctrl-C, SIGTERM) writes a
    JUnit file saying what went wrong (:func:`verify.oracle.junit.error_xml`) in place of the last run's."""
    try:
        yield
    except BaseException as exc:
        if args.junit:
            _write_error_junit(args.junit, suite, _why(exc), prefix, junit_group(args.cases))
        raise


def _why(exc: BaseException) -> str:
    """What ended a run, in one line."""
    from verify.cli.signals import Terminated

    if isinstance(exc, (UsageError, InvalidInput, Undecided)):
        return one_line(exc)
    if isinstance(exc, Terminated):
        return f"terminated ({exc.name})"
    if isinstance(exc, KeyboardInterrupt):
        return "interrupted"
    return f"internal error ({type(exc).__name__}: {one_line(exc)})"


def _write_error_junit(path: str, suite: str, message: str, prefix: str, group: str) -> None:
    """Write the JUnit file of a run that could not grade; a failure to write it leaves the first error to tell."""
    from verify.oracle.junit import error_xml

    with contextlib.suppress(Exception):
        write_output(path, error_xml(suite, message, prefix, group), "--junit")


def junit_after_usage_error(argv: list[str], message: str) -> None:
    """``verify oracle check|explain ... --junit FILE`` refused while its options were read (exit code 2): the
    JUnit file says so, in place of the last run's (FILE is written only where it could be)."""
    if len(argv) < 3 or argv[0] != "oracle" or argv[1] not in ("check", "explain"):
        return
    path = next((argv[i + 1] for i, a in enumerate(argv[:-1]) if a == "--junit"), None)
    path = next((a.split("=", 1)[1] for a in argv if a.startswith("--junit=")), path)
    if not path or path == STDIO or os.path.isdir(path) or not os.path.isdir(os.path.dirname(os.path.abspath(path))):
        return
    cases = argv[2] if not argv[2].startswith("-") else "cases"
    prefix = "oracle" if argv[1] == "check" else "explain"
    _write_error_junit(path, f"verify oracle {argv[1]} {cases}", message, prefix, junit_group(cases))


def checked_cases(args: argparse.Namespace, command_name: str) -> tuple[str, list[dict[Any, Any]], str | None]:
    """The case file's text, records and dataset (None when it names none), validated (one line and exit code 2
    for a bad file), with RESULTS.json or --impl given, not both."""
    from verify.records.results import load_cases

    if (args.results is None) == (args.impl is None):
        raise UsageError(f"{PROG} {command_name}: give either RESULTS.json or --impl COMMAND")
    if args.cases == STDIO and args.results == STDIO:
        raise UsageError(f"{PROG} {command_name}: CASES.json and RESULTS.json cannot both be - (stdin)")
    load_cases(args.cases)  # validates the file: schema, ids, then every number
    case_text = read_text(args.cases)
    data = json.loads(case_text)
    return case_text, data["cases"], data.get("dataset")


def oracle_explain(args: argparse.Namespace) -> int:
    """``verify oracle explain``: which exact model explains each answer of another implementation; exit code 1
    when a case is explained by none."""
    from verify.oracle import reference as oracle
    from verify.oracle.explain import DEFAULT_SWEEPS, DEFAULT_THRESHOLDS, Grid, explain
    from verify.oracle.explanation import explanation_junit, explanation_text
    from verify.records.results import dumps

    both_stdout(args, "oracle explain")
    with junit_on_error(args, f"verify oracle explain {args.cases}", "explain"):
        case_text, records, dataset = checked_cases(args, "oracle explain")
        status = StatusLine.for_args(args)
        got, _ = oracle.load_result_file(*other_results(args, case_text, status), dataset)
    from verify.engines.explain import engine_velocities

    grid = Grid(tuple(args.sweeps or DEFAULT_SWEEPS), tuple(args.thresholds or DEFAULT_THRESHOLDS),
                tolerance=args.tolerance, more=(engine_velocities,))  # fmt: skip
    status.show("verify oracle explain: running the exact models", now=True)
    try:
        result = explain(records, got, grid)
    finally:
        status.close()
    report = sys.stderr if args.junit == STDIO else sys.stdout  # stdout holds one document
    report.write(dumps(stamped(result.to_json(), dataset, report=True)) if args.json else explanation_text(result))
    if args.junit:
        write_output(args.junit, explanation_junit(result, f"verify oracle explain {args.cases}",
                                                   junit_group(args.cases)), "--junit")  # fmt: skip
    return 0 if all(r.settings for r in result.rows) else 1


def oracle_table(args: argparse.Namespace) -> int:
    """``verify oracle table``: several implementations' result files graded side by side."""
    from verify.oracle import reference as oracle
    from verify.oracle.grading import table_row
    from verify.oracle.text import error_table_text
    from verify.records.results import dumps, load_cases

    if sum(x == STDIO or x.partition("=")[2] == STDIO for x in [args.cases, *args.results]) > 1:
        raise UsageError(f"{PROG} oracle table: only one of the files can be - (stdin)")
    load_cases(args.cases)
    data = json.loads(read_text(args.cases))
    records, dataset = data["cases"], data.get("dataset")
    expected = oracle.golden_results(records, law=law_choice(args, "oracle table"))
    rows = []
    failed = False
    for spec in args.results:
        name, sep, path = spec.partition("=")
        name, path = (name, path) if sep else (os.path.basename(spec) if spec != STDIO else "stdin", spec)
        got, skipped = oracle.load_result_file(read_text(path), display_name(path), dataset)
        comparison = oracle.compare(records, expected, got, rtol=args.rtol, atol=Fraction(0), skipped=skipped)
        failed = failed or not comparison.ok
        rows.append(table_row(name, args.law, comparison))
    table = stamped({"table": [r.to_json() for r in rows]}, dataset, report=True)
    sys.stdout.write(dumps(table) if args.json else error_table_text(rows))
    return 1 if failed else 0


def other_results(args: argparse.Namespace, case_text: str, status: StatusLine) -> tuple[str, str]:
    """The other implementation's result file as text (the output of ``--impl``, or RESULTS.json), and
    its name for messages."""
    from verify.oracle import reference as oracle

    if args.impl is not None:
        status.show(f"verify oracle check: running {args.impl}", now=True)
        try:
            return oracle.run_implementation(args.impl, case_text, args.impl_time_limit), f"the output of {args.impl!r}"
        finally:
            status.close()
    return read_text(args.results), display_name(args.results)


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("properties", "oracle")
