"""The ``verify`` command line: a thin layer over the library.

Each subcommand parses its arguments, makes one library call, prints text (or JSON with
``--json``) and returns an exit code: 0 success, 1 a check found a mismatch, 2 bad
input or usage. Bad input prints one line on stderr, never a traceback. Python callers
should use the library (:mod:`verify`) directly.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput, Undecided, VerifyError

PROG = "verify"
#: The property profiles (the keys of verify.verdicts.PROFILES, which is not imported here:
#: it loads Hypothesis and SymPy, and every command would start slower). A test checks both agree.
PROFILE_NAMES = ("dev", "ci", "thorough")


class UsageError(VerifyError):
    """Command-line usage that argparse rejects (reported in one line, exit code 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, no usage block
        raise UsageError(f"{self.prog}: {message}")


def _formatter(prog: str) -> argparse.HelpFormatter:
    return argparse.RawDescriptionHelpFormatter(prog, max_help_position=32)


def _list(text: str) -> list[str]:
    from verify.numbers import split_list

    parts = split_list(text)
    if any(p == "" for p in parts):
        raise UsageError(f"empty entry in the list {text!r}")
    return parts


# -- cradle -----------------------------------------------------------------------------------


def _cmd_cradle(args: argparse.Namespace) -> int:
    from verify.cradle import run_cradle
    from verify.records import dumps, result_record
    from verify.render import cradle_text

    eps = _list(args.eps)
    masses = _list(args.masses) if args.masses else None
    velocity = _list(args.velocity) if args.velocity else None
    balls = args.balls
    inferred = {len(x) for x in (masses, velocity) if x is not None}
    if balls is None:
        balls = inferred.pop() if len(inferred) == 1 else 3
    for name, values in (("--masses", masses), ("--velocity", velocity)):
        if values is not None and len(values) != balls:
            raise UsageError(f"{PROG} cradle: {name} has {len(values)} entries but there are {balls} balls")
    result = run_cradle(
        eps if len(eps) > 1 else eps[0],
        v0=args.v0,
        balls=balls,
        masses=masses,
        velocity=velocity,
        mode=args.mode,
        backend=args.backend,
        dps=args.dps,
        max_iterations=args.max_iterations,
    )
    if args.json:
        sys.stdout.write(dumps(result_record(result, "cradle")))
    else:
        sys.stdout.write(cradle_text(result, eps=eps, mode=args.mode, full_trace=args.trace))
    return 0


def _cmd_solve(args: argparse.Namespace) -> int:
    from verify.records import dumps, load_cases, result_record
    from verify.render import solve_text
    from verify.rule import solve

    cases = load_cases(args.cases, backend=args.backend, dps=args.dps)  # every case validated first
    results = [(c, solve(c.system, c.velocity_source, rule=args.rule, max_iterations=c.max_iterations)) for c in cases]
    if args.json:
        sys.stdout.write(dumps({"results": [result_record(r, c.id) for c, r in results]}))
    else:
        sys.stdout.write("".join(solve_text(c.id, r) for c, r in results))
    return 0


def _cmd_cradle_map(args: argparse.Namespace) -> int:
    from verify.cradle_map import aeev_rows_explained, approach_counts, cradle_map, map_json, termination_boundaries
    from verify.records import dumps
    from verify.render import cradle_map_text

    masses = _list(args.masses) if args.masses else None
    velocity = _list(args.velocity) if args.velocity else None
    balls = args.balls if args.balls is not None else len(masses or velocity or [0, 0, 0])
    interval = _list(args.interval)
    if len(interval) != 2:
        raise UsageError(f"{PROG} cradle-map: --interval takes two numbers LO,HI, got {args.interval!r}")
    cmap = cradle_map(
        balls, masses, velocity, v0=args.v0, lower=interval[0], upper=interval[1], max_impulses=args.max_impulses
    )
    if args.json:
        sys.stdout.write(dumps(map_json(cmap)))
    else:
        default = balls == 3 and masses is None and velocity is None
        rows = aeev_rows_explained(cmap) if default and interval == ["0", "1"] else []
        bounds = termination_boundaries(cmap)
        approach = approach_counts(bounds[0], range(2, args.approach + 1)) if bounds and args.approach >= 2 else []
        sys.stdout.write(cradle_map_text(cmap, aeev_rows=rows, approach=approach))
    if args.figure:
        from verify.figures import cradle_staircase

        cradle_staircase(cmap, args.figure)
        print(f"figure written to {args.figure}", file=sys.stderr)
    return 0


def _cmd_corner(args: argparse.Namespace) -> int:
    from verify.corner import run_corner
    from verify.records import dumps, result_record
    from verify.render import corner_text

    run = run_corner(
        alpha=args.alpha,
        slope=args.slope,
        phi=args.phi,
        eps1=args.eps1,
        eps2=args.eps2,
        v0=args.v0,
        backend=args.backend,
        dps=args.dps,
        max_iterations=args.max_iterations,
    )
    if args.json:
        record = result_record(run.result, "corner")
        record["zones"] = run.zones
        record["repeated_multiple_impacts"] = run.repeated_multiple_impacts
        if run.notes:
            record["notes"] = run.notes
        sys.stdout.write(dumps(record))
    else:
        sys.stdout.write(corner_text(run, args))
    return 0


def _cmd_corner_claims(args: argparse.Namespace) -> int:
    from verify.corner_claims import corner_findings
    from verify.records import dumps
    from verify.render import corner_claims_json, corner_claims_text

    if args.cases < 1:
        raise UsageError(f"{PROG} corner-claims: --cases must be >= 1, got {args.cases}")
    data = corner_findings(args.cases, seed=args.seed, workers=args.workers)
    claims = data[0]
    sys.stdout.write(dumps(corner_claims_json(*data)) if args.json else corner_claims_text(*data))
    if args.figures:
        from pathlib import Path

        from verify import figures

        out = Path(args.figures)
        for name, draw in (
            ("corner-exit-vs-entrance.png", figures.corner_exit_vs_entrance),
            ("corner-iterations.png", figures.corner_iterations_map),
            ("corner-multiple-impacts.png", figures.corner_multiple_impacts_map),
            ("wedge-boundary.png", figures.wedge_boundary),
        ):
            draw(out / name, workers=args.workers)
            print(f"figure written to {out / name}", file=sys.stderr)
    return 1 if any(c.verdict == "refuted" for c in claims) else 0


def _cmd_sweep(args: argparse.Namespace) -> int:
    import time
    from collections import Counter

    from verify.records import dumps
    from verify.sweep import random_corner_cases, sweep

    if args.cases < 1:
        raise UsageError(f"{PROG} sweep: --cases must be >= 1, got {args.cases}")
    cases = random_corner_cases(args.cases, seed=args.seed, max_iterations=args.max_iterations)
    start = time.perf_counter()
    results = sweep(cases, workers=args.workers)
    seconds = time.perf_counter() - start
    stops = Counter(r["stop"] for r in results)
    repeated = sum(1 for r in results if r["multiple_impacts"] > 1)
    if args.json:
        sys.stdout.write(
            dumps(
                {
                    "cases": len(cases),
                    "seconds": round(seconds, 3),
                    "stops": dict(stops),
                    "repeated_multiple_impacts": repeated,
                    "results": results,
                }
            )
        )
    else:
        print(f"{len(cases)} random rational corner cases (seed {args.seed}), exact, in {seconds:.1f} s")
        for stop, count in sorted(stops.items()):
            print(f"  {stop}: {count}")
        print(f"  with repeated multiple impacts: {repeated}")
    return 0


def _cmd_table1(args: argparse.Namespace) -> int:
    from verify.records import dumps
    from verify.render import table1_json, table1_text
    from verify.table1 import table1

    table = table1(exact_cap=args.exact_cap)
    sys.stdout.write(dumps(table1_json(table)) if args.json else table1_text(table))
    return 0


def _cmd_all(args: argparse.Namespace) -> int:
    import time

    from verify.render import all_summary
    from verify.report import write_reports

    start = time.monotonic()
    print("verify all: reproducing Pasquero (2021), then writing the reports", flush=True)

    def progress(line: str) -> None:
        print(f"{line} ({time.monotonic() - start:.0f} s)", flush=True)

    ctx = write_reports(args.out, profile="ci", workers=args.workers, progress=progress)
    summary, failed = all_summary(ctx)
    sys.stdout.write(summary)
    print(f"reports written to {args.out}/ in {time.monotonic() - start:.0f} s")
    return 1 if failed else 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from verify.bench import QUICK, bench, bench_json, bench_text
    from verify.records import dumps

    if args.save and os.path.isdir(args.save):
        raise UsageError(f"{PROG} bench: --save {args.save!r} is a directory")
    options = dict(QUICK) if args.quick else {}
    if args.size is not None:
        if args.size < 1:
            raise UsageError(f"{PROG} bench: --size must be >= 1, got {args.size}")
        options["size"] = args.size
    figures = bench(**options, progress=lambda line: print(line, file=sys.stderr, flush=True))
    record = bench_json(figures, quick=args.quick)
    if args.save:
        tmp = args.save + ".tmp"
        with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(dumps(record))
        os.replace(tmp, args.save)
    sys.stdout.write(dumps(record) if args.json else bench_text(record))
    return 0


def _cmd_report(args: argparse.Namespace) -> int:
    from verify.report import write_reports

    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise UsageError(f"{PROG} report: --out {args.out!r} is not a directory")
    write_reports(args.out, profile=args.profile, workers=args.workers,
                  progress=lambda line: print(line, file=sys.stderr, flush=True))  # fmt: skip
    print(f"reports written to {args.out}/")
    return 0


def _cmd_properties(args: argparse.Namespace) -> int:
    import json
    import os

    from verify.records import dumps
    from verify.render import properties_text
    from verify.verdicts import report, rows, verdicts

    if args.list:
        for prop in dict.fromkeys(p for p, _, _ in rows()):
            print(f"{prop.name}  [rules: {', '.join(prop.rules)}; families: {', '.join(prop.families)}]")
        return 0
    if args.counterexamples and os.path.exists(args.counterexamples) and not os.path.isdir(args.counterexamples):
        raise UsageError(f"{PROG} properties: --counterexamples {args.counterexamples!r} is not a directory")
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
        _write_counterexamples(args.counterexamples, found)
    sys.stdout.write(dumps(report(args.profile, found)) if args.json else properties_text(args.profile, found))
    return 1 if any(v.verdict == "refuted" for v in found) else 0


def _write_counterexamples(folder: str, found: list) -> None:
    """One case file per refuted row (written whole, then renamed into place)."""
    import os

    from verify.records import dumps

    os.makedirs(folder, exist_ok=True)
    for v in found:
        if v.counterexample is None:
            continue
        path = os.path.join(folder, v.counterexample["id"] + ".json")
        with open(path + ".tmp", "w", encoding="utf-8") as fh:
            fh.write(dumps({"cases": [v.counterexample]}))
        os.replace(path + ".tmp", path)


def _cmd_oracle(args: argparse.Namespace) -> int:
    from verify import oracle

    if args.action == "export":
        if os.path.exists(args.folder) and not os.path.isdir(args.folder):
            raise UsageError(f"{PROG} oracle export: {args.folder!r} is not a directory")
        for path in oracle.export(args.folder):
            print(f"wrote {path}")
        return 0
    return _oracle_check(args)


def _oracle_check(args: argparse.Namespace) -> int:
    from verify import oracle
    from verify.numbers import parse_number, to_number
    from verify.records import dumps, load_cases
    from verify.render import oracle_text

    if (args.results is None) == (args.impl is None):
        raise UsageError(f"{PROG} oracle check: give either RESULTS.json or --impl COMMAND")
    tolerances = {}
    for name in ("rtol", "atol"):
        value = to_number(parse_number(getattr(args, name), where=f"--{name}"), where=f"--{name}")
        if not isinstance(value, Fraction) or value < 0:
            raise UsageError(
                f"{PROG} oracle check: --{name} must be a non-negative rational, got {getattr(args, name)!r}"
            )
        tolerances[name] = value
    load_cases(args.cases)  # validates the file: schema, then every number
    with open(args.cases, encoding="utf-8") as fh:
        case_text = fh.read()
    records = json.loads(case_text)["cases"]
    if args.impl is not None:
        text = oracle.run_implementation(args.impl, case_text, args.timeout)
        source = f"the output of {args.impl!r}"
    else:
        try:
            with open(args.results, encoding="utf-8") as fh:
                text = fh.read()
        except OSError as exc:
            raise UsageError(f"{args.results}: cannot read ({exc.strerror})") from None
        source = args.results
    got = oracle.load_results(text, source)
    expected = oracle.golden_results(records)
    comparison = oracle.compare(records, expected, got, **tolerances)
    if args.json:
        sys.stdout.write(dumps(oracle.comparison_json(comparison)))
    else:
        sys.stdout.write(oracle_text(comparison))
    return 0 if comparison.ok else 1


# -- the parser ----------------------------------------------------------------------------------


def _backend_options(p: argparse.ArgumentParser) -> None:
    from verify.backends import BACKENDS

    p.add_argument(
        "--backend",
        default="exact",
        choices=BACKENDS,
        help="arithmetic: exact (default), mp, interval (certified), float (not rigorous)",
    )
    p.add_argument("--dps", type=int, default=None, help="decimal digits for mp and interval (default 50)")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``verify`` (subcommands as in the contracts)."""
    from verify.rule import RULES

    parser = _Parser(
        prog=PROG,
        formatter_class=_formatter,
        description="Exact verification of the multiple-impact rule of Pasquero (2021).",
        epilog="examples:\n  verify all\n  verify table1\n  verify cradle --eps 0.5\n",
    )
    from verify import __version__

    parser.add_argument("--version", action="version", version=f"verify {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    p = sub.add_parser(
        "cradle",
        help="Newton's cradle (Sect. 4.1)",
        formatter_class=_formatter,
        description="Run Newton's cradle: N balls on a line, one COR for all contacts or one per contact.",
        epilog=(
            "examples:\n  verify cradle --eps 0.5\n  verify cradle --eps 0.0743 --mode paper\n"
            "  verify cradle --eps 1/2,1 --masses 1,2,1 --velocity 1,0,-1 --json\n"
        ),
    )
    p.add_argument("--eps", required=True, help="COR for all contacts, or one per contact: 0.5 or 0.5,0.9")
    p.add_argument("--v0", default="100", help="velocity of ball 1, the others at rest (default 100)")
    p.add_argument("--balls", type=int, default=None, help="number of balls N >= 2 (default 3)")
    p.add_argument("--masses", help="masses m1,m2,...,mN (default all 1)")
    p.add_argument("--velocity", help="the whole left velocity v1,...,vN (instead of --v0)")
    p.add_argument(
        "--mode",
        default="exact",
        choices=("exact", "paper"),
        help="exact: stop at exit; paper: the paper's 10^4 cap and AEEV stop",
    )
    p.add_argument("--max-iterations", type=int, default=None, help="cap on impulses (default 10000)")
    p.add_argument("--trace", action="store_true", help="print every impulse, however many")
    p.add_argument("--json", action="store_true", help="print the result record (JSON)")
    _backend_options(p)
    p.set_defaults(func=_cmd_cradle)

    p = sub.add_parser(
        "solve",
        help="run the general rule on a case file",
        formatter_class=_formatter,
        description="Run the rule (eq. 8) on every case of a case file (format: shared/docs/contracts.md).",
        epilog="examples:\n  verify solve cases.json\n  verify solve cases.json --backend interval --json\n",
    )
    p.add_argument("cases", metavar="CASES.json", help='a case file {"cases": [...]}')
    p.add_argument(
        "--rule",
        default="general",
        choices=RULES,
        help="general (eq. 8, default), ideal (5), symmetric (6) or asymmetric (7)",
    )
    p.add_argument("--json", action="store_true", help='print {"results": [...]}')
    _backend_options(p)
    p.set_defaults(func=_cmd_solve)

    p = sub.add_parser(
        "corner",
        help="the disk in a corner (Sect. 4.2)",
        formatter_class=_formatter,
        description=(
            "A disk in a corner of angle 2*alpha, walls kx - y = 0 (S1, COR eps1) and kx + y = 0 (S2, COR eps2), "
            "entrance velocity v0 (cos phi, sin phi). Exact when every input is algebraic, certified intervals "
            "otherwise."
        ),
        epilog=(
            "examples:\n  verify corner --alpha pi/6 --phi pi/12 --eps1 0.999 --eps2 0.001\n"
            "  verify corner --slope 1/2 --phi 1/10 --eps1 0 --eps2 0 --json\n"
            "  verify corner --alpha 3/10 --phi 0 --eps1 0.5 --eps2 0.5 --backend mp --dps 40\n"
        ),
    )
    angle = p.add_mutually_exclusive_group(required=True)
    angle.add_argument("--alpha", help="half the corner angle, in (0, pi/2): pi/6, 3/10 (radians)")
    angle.add_argument("--slope", help="k = tan(alpha) > 0 instead of alpha: 1/2, sqrt(3)/3")
    p.add_argument("--phi", required=True, help="direction of the entrance velocity: pi/12, 0, -1/5")
    p.add_argument("--eps1", required=True, help="COR of wall S1 (kx - y = 0), in [0, 1]")
    p.add_argument("--eps2", required=True, help="COR of wall S2 (kx + y = 0), in [0, 1]")
    p.add_argument("--v0", default="100", help="speed of the entrance velocity (default 100)")
    p.add_argument("--max-iterations", type=int, default=10_000, help="cap on impulses (default 10000)")
    p.add_argument("--json", action="store_true", help="print the result record with the zones (JSON)")
    _backend_options(p)
    p.set_defaults(func=_cmd_corner)

    p = sub.add_parser(
        "corner-claims",
        help="the paper's claims about the corner, checked exactly; termination in the wedge; float vs exact",
        formatter_class=_formatter,
        description=(
            "Check the claims of Sect. 4.2 on samples of exact rational corner cases (in parallel), derive the "
            "symmetric termination boundary, show the rebounds as the corner narrows, and count where a plain "
            "float implementation takes another branch. Exit code 1 if a claim is refuted."
        ),
        epilog="examples:\n  verify corner-claims\n  verify corner-claims --cases 10000 --json\n",
    )
    p.add_argument("--cases", type=int, default=2000, help="cases per sample (default 2000)")
    p.add_argument("--seed", type=int, default=0, help="seed of the deterministic samples (default 0)")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: every core)")
    p.add_argument("--figures", metavar="DIR", help="also draw the corner's figures (PNG) into DIR")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_cmd_corner_claims)

    p = sub.add_parser(
        "sweep",
        help="run many random rational corner cases exactly, in parallel",
        formatter_class=_formatter,
        description=(
            "A deterministic batch of corner cases with rational inputs (slope in (1/10, 10), both walls hit at the "
            "start, CORs in [0, 1] with 0 and 1 often), run exactly on every core; prints the stops and the time."
        ),
        epilog="examples:\n  verify sweep --cases 10000\n  verify sweep --cases 200 --seed 3 --json\n",
    )
    p.add_argument("--cases", type=int, default=10_000, help="number of cases (default 10000)")
    p.add_argument("--seed", type=int, default=0, help="seed of the deterministic batch (default 0)")
    p.add_argument("--workers", type=int, default=None, help="local processes (default: every core)")
    p.add_argument("--max-iterations", type=int, default=100, help="cap on impulses per case (default 100)")
    p.add_argument("--json", action="store_true", help="print the results as JSON")
    p.set_defaults(func=_cmd_sweep)

    p = sub.add_parser(
        "cradle-map",
        help="the cradle for every eps at once: pieces, thresholds, termination",
        formatter_class=_formatter,
        description=(
            "The exact eps-map of Newton's cradle: a partition of the eps interval into pieces with a fixed impact "
            "sequence (exact endpoints, exit velocity as a function of eps), intervals proved never to exit "
            "(with certificates), and what lies beyond the bound on impulses."
        ),
        epilog=(
            "examples:\n  verify cradle-map\n  verify cradle-map --max-impulses 60 --json\n"
            "  verify cradle-map --balls 4 --max-impulses 20\n  verify cradle-map --masses 1,2,1 --figure map.png\n"
        ),
    )
    p.add_argument("--balls", type=int, default=None, help="number of balls N >= 2 (default 3)")
    p.add_argument("--masses", help="masses m1,...,mN (default all 1)")
    p.add_argument("--velocity", help="the left velocity v1,...,vN (default v0 on ball 1)")
    p.add_argument("--v0", default="1", help="velocity of ball 1 (default 1)")
    p.add_argument("--interval", default="0,1", help="the eps interval LO,HI inside [0, 1] (default 0,1)")
    p.add_argument("--max-impulses", type=int, default=40, help="bound on the exploration (default 40)")
    p.add_argument(
        "--approach",
        type=int,
        default=6,
        help="show impulse counts at eps = boundary + 10^-k for k = 2..K (default 6; 0 to skip)",
    )
    p.add_argument("--figure", help="also write the staircase figure (PNG) to this path")
    p.add_argument("--json", action="store_true", help="print the map as JSON (contracts)")
    p.set_defaults(func=_cmd_cradle_map)

    p = sub.add_parser(
        "table1",
        help="the paper's Table 1, recomputed and checked",
        formatter_class=_formatter,
        description="Table 1 of the paper: exact and paper-mode results, every printed entry checked.",
        epilog="examples:\n  verify table1\n  verify table1 --json\n",
    )
    p.add_argument(
        "--exact-cap",
        type=int,
        default=10_000,
        help="impulses after which an exact run that has neither exited nor been proved never to exit "
        "is reported as such (default 10000)",
    )
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_cmd_table1)

    p = sub.add_parser(
        "properties",
        help="the property suite: what the rule promises, proved, holding or refuted",
        formatter_class=_formatter,
        description=(
            "Check every property x rule x family (kinetic energy, the printed formulas, reductions, symmetries, "
            "frame independence, termination, momentum, backends) on exact cases drawn by Hypothesis. Verdicts: "
            "proved (SymPy identity; the cases still test the code), holds (N cases, none failing), refuted (a shrunk "
            "exact counterexample that verify solve reproduces). Exit code 1 if a property is refuted."
        ),
        epilog=(
            "examples:\n  verify properties\n  verify properties --profile dev --json\n"
            "  verify properties --property 'kinetic energy' --rule asymmetric --counterexamples found/\n"
            "  verify properties --profile thorough --workers 2\n  verify properties --list\n"
        ),
    )
    p.add_argument(
        "--profile",
        default="ci",
        choices=PROFILE_NAMES,
        help="cases per row: dev 25, ci 100 (default), thorough 100000 per property",
    )
    p.add_argument("--property", action="append", help="only this property (name or prefix; repeatable)")
    p.add_argument(
        "--rule",
        action="append",
        choices=RULES,
        help="only this rule (repeatable)",
    )
    p.add_argument(
        "--family", action="append", choices=("general", "cradle", "corner"), help="only this family (repeatable)"
    )
    p.add_argument("--workers", type=int, default=None, help="processes (default: every core)")
    p.add_argument("--counterexamples", metavar="DIR", help="write each counterexample as a case file into DIR")
    p.add_argument("--list", action="store_true", help="list the properties and exit")
    p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    p.add_argument("--json", action="store_true", help="print the verdicts as JSON (contracts)")
    p.set_defaults(func=_cmd_properties)

    p = sub.add_parser(
        "oracle",
        help="the reference oracle: export the golden dataset, check another implementation",
        formatter_class=_formatter,
        description=(
            "export DIR writes the golden dataset (cases.json, results.json, README.md) from its generator; "
            "check compares another implementation's results with the exact ones: stop, iteration count, impact "
            "sets, exit velocity within atol + rtol * |v_in|. Every mismatch is listed; exit code 1 if any."
        ),
        epilog=(
            "examples:\n  verify oracle export golden\n"
            "  verify oracle check golden/cases.json my_results.json --rtol 1e-9\n"
            "  verify oracle check golden/cases.json --impl 'python3 examples/float_impl.py'\n"
        ),
    )
    oracle_sub = p.add_subparsers(dest="action", metavar="ACTION", parser_class=_Parser, required=True)
    q = oracle_sub.add_parser("export", help="write the golden dataset into DIR", formatter_class=_formatter,
                              epilog="example:\n  verify oracle export golden\n")  # fmt: skip
    q.add_argument("folder", metavar="DIR")
    q.set_defaults(func=_cmd_oracle)
    q = oracle_sub.add_parser(
        "check",
        help="check RESULTS.json (or the output of --impl COMMAND) against the exact results of CASES.json",
        formatter_class=_formatter,
        epilog=(
            "examples:\n  verify oracle check golden/cases.json my_results.json\n"
            "  verify oracle check golden/cases.json --impl './my_solver --json' --timeout 60\n"
        ),
    )
    q.add_argument("cases", metavar="CASES.json")
    q.add_argument("results", metavar="RESULTS.json", nargs="?", help="the other implementation's result file")
    q.add_argument("--impl", metavar="COMMAND", help="run COMMAND: case file on stdin, result file on stdout")
    q.add_argument("--timeout", type=float, default=600.0, help="seconds allowed to --impl (default 600)")
    q.add_argument("--rtol", default="1e-9", help="relative tolerance on the exit velocity (default 1e-9)")
    q.add_argument("--atol", default="0", help="absolute tolerance on the exit velocity (default 0)")
    q.add_argument("--json", action="store_true", help="print the comparison as JSON")
    q.set_defaults(func=_cmd_oracle)

    p = sub.add_parser(
        "report",
        help="regenerate the reports (reports/: one page per topic, figures)",
        formatter_class=_formatter,
        description="Write reports/README.md and one page per topic, every number from the library.",
        epilog="examples:\n  verify report\n  verify report --out /tmp/reports --profile dev\n",
    )
    p.add_argument("--out", default="reports", help="the folder to write (default reports)")
    p.add_argument("--profile", default="ci", choices=PROFILE_NAMES, help="property profile (default ci)")
    p.add_argument("--workers", type=int, default=None, help="processes (default: every core)")
    p.set_defaults(func=_cmd_report)

    p = sub.add_parser(
        "bench",
        help="throughput figures, each beside a baseline measured in the same run",
        formatter_class=_formatter,
        description=(
            "Time the exact engine and the float path on a fixed batch of 10,000 corner cases against plain "
            "Fraction and float loops, Table 1 against pure-Python rationals, the cost of one impulse on the exact "
            "and interval backends at 10 to 10,000 impulses, and peak memory. Ratios are against baselines timed "
            "alternately in the same run (best of 3). --save FILE keeps the JSON record (the report's performance "
            "page reads reports/bench.json)."
        ),
        epilog="examples:\n  verify bench\n  verify bench --quick --json\n  verify bench --save reports/bench.json\n",
    )
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    p.add_argument("--quick", action="store_true", help="a smoke run: 500 cases, one round, up to 100 impulses")
    p.add_argument("--size", type=int, default=None, help="cases in the corner batch (default 10000)")
    p.add_argument("--save", default=None, metavar="FILE", help="also write the JSON record to FILE")
    p.set_defaults(func=_cmd_bench)

    p = sub.add_parser(
        "all",
        help="the main job: reproduce the paper, check the properties and the oracle, write the reports",
        formatter_class=_formatter,
        description=(
            "Reproduce the paper (Table 1, the threshold, the corner example), run the cradle map, the corner claims, "
            "the properties (ci profile) and the oracle self-check, write the reports, and summarise what was "
            "reproduced, what disagrees with the paper and what was refuted. Exit code 1 only if the program "
            "contradicts itself: a proved property refuted, or the oracle failing its self-check."
        ),
        epilog="examples:\n  verify all\n  verify all --out /tmp/reports\n",
    )
    p.add_argument("--out", default="reports", help="the folder for the reports (default reports)")
    p.add_argument("--workers", type=int, default=None, help="processes (default: every core)")
    p.set_defaults(func=_cmd_all)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 1 mismatch, 2 bad input)."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help()
            return 2
        for name in ("max_iterations", "exact_cap", "dps", "max_impulses", "workers"):
            value = getattr(args, name, None)
            if value is not None and value < 0:
                raise UsageError(f"{PROG} {args.command}: --{name.replace('_', '-')} must be >= 0, got {value}")
        return int(args.func(args))
    except (UsageError, InvalidInput, Undecided) as exc:
        print(f"{PROG}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # pragma: no cover - e.g. piped into head
        return 0


def _one_line(exc: Any) -> str:
    return " ".join(str(exc).split())
