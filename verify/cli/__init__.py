"""The ``verify`` command line: a thin layer over the library.

Each subcommand parses its arguments, makes one library call, prints text (or JSON with
``--json``) and returns an exit code: 0 success, 1 a check found a mismatch, 2 bad
input or usage. Bad input prints one line on stderr, never a traceback. Python callers
should use the library (:mod:`verify`) directly.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import sys
from collections.abc import Iterator, Sequence
from fractions import Fraction
from typing import Any

from verify.errors import InvalidInput, Undecided, VerifyError

PROG = "verify"
#: The property profiles (the keys of verify.checks.properties.verdicts.PROFILES, which is not imported here:
#: it loads Hypothesis and SymPy, and every command would start slower). A test checks both agree.
PROFILE_NAMES = ("dev", "ci", "thorough")


class UsageError(VerifyError):
    """Command-line usage that argparse rejects (reported in one line, exit code 2)."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, no usage block
        import re

        # "argument --dps: must be ..." -> "--dps must be ..."; "argument --x: invalid ..." -> "--x: invalid ..."
        found = re.match(r"argument (\S+): (.*)", message, re.DOTALL)
        if found:
            name, rest = found.groups()
            message = f"{name} {rest}" if rest.startswith("must ") else f"{name}: {rest}"
        raise UsageError(f"{self.prog}: {message}")


def _formatter(prog: str) -> argparse.HelpFormatter:
    return argparse.RawDescriptionHelpFormatter(prog, max_help_position=32)


def _list(text: str) -> list[str]:
    from verify.core.numbers import split_list

    parts = split_list(text)
    if any(p == "" for p in parts):
        raise UsageError(f"empty entry in the list {text!r}")
    return parts


# -- option types: every numeric and output-path option is checked when it is parsed ----------------
#
# Each is an argparse ``type=``: a bad value ends the parse with one line naming the option and the
# value (``--dps must be an integer >= 5, got '0'``), before anything is computed or written.
# tests/test_cli_options.py walks the parser and feeds every option of these types bad values.

#: the library's lower limit on decimal digits (verify.core.backends) and a ceiling on absurd requests
MIN_DPS, MAX_DPS = 5, 100_000
MAX_COUNT = 10**9  # caps on impulses, bits
MAX_SECONDS = 10**7  # about 16 weeks
MAX_BALLS = 1000
MAX_CASES = 10**7
MAX_SEED = 2**63 - 1
MAX_WORKERS = 1024
MAX_IMPULSES_MAP = 100_000  # cradle-map --max-impulses
MAX_APPROACH = 20  # cradle-map --approach: eps = boundary + 10^-k, k up to this


class BoundedInt:
    """An integer option in ``[lo, hi]`` (decimal digits only: no ``1e3``, no ``0x10``).

    >>> BoundedInt(1, 8)("3")
    3
    >>> BoundedInt(1, 8)("0")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be an integer >= 1, got '0'
    """

    def __init__(self, lo: int, hi: int):
        self.lo, self.hi = lo, hi

    def __call__(self, text: str) -> int:
        import re

        stripped = text.strip()
        if not re.fullmatch(r"[+-]?[0-9]+", stripped):
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}")
        if len(stripped.lstrip("+-").lstrip("0")) > 30:  # past every bound here (and not read as an int)
            value = self.lo - 1 if stripped.startswith("-") else self.hi + 1
        else:
            value = int(stripped)
        if value < self.lo:
            below = f">= {self.lo}" if self.lo <= 0 else f"an integer >= {self.lo}"
            raise argparse.ArgumentTypeError(f"must be {below}, got {text!r}")
        if value > self.hi:
            raise argparse.ArgumentTypeError(f"must be <= {self.hi}, got {text!r}")
        return value

    def __repr__(self) -> str:  # argparse names the type in some messages
        return f"integer in [{self.lo}, {self.hi}]"


class Seconds:
    """A positive, finite duration in seconds up to ``hi``, read exactly (``90``, ``0.5``,
    ``1/4``; not ``nan``, ``inf``, ``1e400``), returned as a float for the clock.

    >>> Seconds()("1/4")
    0.25
    >>> Seconds()("nan")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a number of seconds > 0, got 'nan'
    """

    def __init__(self, hi: int = MAX_SECONDS):
        self.hi = hi

    def __call__(self, text: str) -> float:
        value = _rational(text)
        if value is None or value <= 0:
            raise argparse.ArgumentTypeError(f"must be a number of seconds > 0, got {text!r}")
        if value > self.hi:
            raise argparse.ArgumentTypeError(f"must be <= {self.hi} seconds, got {text!r}")
        return float(value)

    def __repr__(self) -> str:
        return "seconds"


class NonNegativeRational:
    """A rational number >= 0, read exactly (``1e-9`` is 1/10^9), returned as a Fraction.

    >>> NonNegativeRational()("1e-9")
    Fraction(1, 1000000000)
    """

    def __call__(self, text: str) -> Fraction:
        value = _rational(text)
        if value is None or value < 0:
            raise argparse.ArgumentTypeError(f"must be a non-negative rational, got {text!r}")
        return value

    def __repr__(self) -> str:
        return "non-negative rational"


class ExactNumber:
    """A real number in the restricted syntax of :mod:`verify.core.numbers` (``0.5``, ``pi/6``,
    ``3 - 2*sqrt(2)``), checked when parsed and returned as the text (the library reads it).

    >>> ExactNumber()("pi/6")
    'pi/6'
    """

    def __call__(self, text: str) -> str:
        from verify.core.numbers import parse_number
        from verify.errors import InvalidInput

        try:
            parse_number(text)
        except InvalidInput as exc:
            raise argparse.ArgumentTypeError(_one_line(exc)) from None
        return text

    def __repr__(self) -> str:
        return "number"


def _rational(text: str) -> Fraction | None:
    """``text`` as a Fraction through the restricted parser, or None if it is not a rational."""
    from verify.core.numbers import parse_number, to_number
    from verify.errors import InvalidInput

    try:
        value = to_number(parse_number(text))
    except InvalidInput:
        return None
    return value if isinstance(value, Fraction) else None


class OutputDir:
    """A folder to write into: it is a folder, or it can be created (its nearest existing
    ancestor is a folder in which a file can be created). Nothing is left behind by the
    check: a probe file is created and removed at once. Returns the text.

    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> OutputDir()(folder + "/new/reports") == folder + "/new/reports"
    True
    >>> open(folder + "/file", "w").close()
    >>> OutputDir()(folder + "/file/reports")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a folder that can be written, got '.../file/reports' (.../file is a file)
    >>> import shutil; shutil.rmtree(folder)
    """

    what = "a folder that can be written"

    def __call__(self, text: str) -> str:
        if not text:
            raise argparse.ArgumentTypeError(f"must be {self.what}, got ''")
        path = os.path.abspath(text)
        if os.path.exists(path) and not os.path.isdir(path):
            raise argparse.ArgumentTypeError(f"must be {self.what}, got {text!r} (a file is there)")
        _check_writable(path, self.what, text)
        return text

    def __repr__(self) -> str:
        return "folder"


class OutputFile:
    """A file to write: not a folder, with one of ``suffixes`` (when given), in a folder
    that exists or can be created (checked as :class:`OutputDir` does). Returns the text.

    >>> OutputFile((".png",))("map.svg")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a file name ending in .png, got 'map.svg'
    """

    def __init__(self, suffixes: tuple[str, ...] = ()):
        self.suffixes = suffixes

    def __call__(self, text: str) -> str:
        what = "a file that can be written"
        if self.suffixes and not text.lower().endswith(self.suffixes):
            endings = " or ".join(self.suffixes)
            raise argparse.ArgumentTypeError(f"must be a file name ending in {endings}, got {text!r}")
        if not text or text.endswith(("/", os.sep)) or os.path.isdir(text):
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r} (a folder)")
        _check_writable(os.path.dirname(os.path.abspath(text)), what, text)
        return text

    def __repr__(self) -> str:
        return "file"


@contextlib.contextmanager
def _writing(path: str, option: str) -> Iterator[None]:
    """Report an OSError on ``path`` or inside it (a full disk, a folder removed since the option was
    checked) as one line naming the option; other errors pass through."""
    try:
        yield
    except OSError as exc:
        name = exc.filename if isinstance(exc.filename, str) else None
        if name is None or not os.path.abspath(name).startswith(os.path.abspath(path)):
            raise
        raise UsageError(f"{option} {path!r}: cannot write {name} ({exc.strerror or exc})") from None


def _write_file(path: str, text: str, option: str) -> None:
    """Write ``text`` whole to a temporary name beside ``path``, then rename it into place: a
    failed write leaves neither a partial file nor the temporary one."""
    tmp = path + ".tmp"
    with _writing(path, option):
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        opened = False
        try:
            with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
                opened = True
                fh.write(text)
            os.replace(tmp, path)
        except BaseException:
            if opened and os.path.isfile(tmp):
                os.remove(tmp)
            raise


def _check_writable(path: str, what: str, text: str) -> None:
    """Check that ``path`` is, or can be created as, a folder one can write into."""
    import tempfile

    ancestor = path
    while not os.path.exists(ancestor) and os.path.dirname(ancestor) != ancestor:
        ancestor = os.path.dirname(ancestor)
    if not os.path.isdir(ancestor):
        raise argparse.ArgumentTypeError(f"must be {what}, got {text!r} ({ancestor} is a file)")
    try:
        fd, probe = tempfile.mkstemp(prefix=".verify-probe-", dir=ancestor)
        os.close(fd)
        os.remove(probe)
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise argparse.ArgumentTypeError(
            f"must be {what}, got {text!r} (cannot write in {ancestor}: {reason})"
        ) from None


# -- cradle -----------------------------------------------------------------------------------


def _cmd_cradle(args: argparse.Namespace) -> int:
    from verify.models.cradle import run_cradle
    from verify.records.results import dumps, result_record
    from verify.views.text import cradle_text

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


class StatusLine:
    """A live status line on stderr, on a terminal only (never in a pipe or a log file): rewritten
    in place at most ten times a second, cut to the terminal's width, and erased by :meth:`close`.

    >>> line = StatusLine(enabled=False)  # stderr is not a terminal, or --quiet: shows nothing
    >>> line.show("case 1/3", now=True); line.close()
    """

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.shown = False
        self.last = 0.0
        self.width = 80
        if enabled:
            with contextlib.suppress(OSError, ValueError, AttributeError):
                self.width = os.get_terminal_size(sys.stderr.fileno()).columns or 80  # 0: size unknown

    @classmethod
    def for_args(cls, args: argparse.Namespace) -> StatusLine:
        """Enabled when stderr is a terminal and ``--quiet`` was not given."""
        tty = getattr(sys.stderr, "isatty", lambda: False)()
        return cls(enabled=tty and not getattr(args, "quiet", False) and os.environ.get("TERM") != "dumb")

    def show(self, text: str, *, now: bool = False) -> None:
        """Replace the line by ``text`` (unless it was rewritten less than 0.1 s ago and not ``now``)."""
        if not self.enabled:
            return
        import time

        t = time.monotonic()
        if not now and t - self.last < 0.1:
            return
        self.last = t
        sys.stderr.write("\r\x1b[K" + text[: max(self.width - 1, 10)])
        sys.stderr.flush()
        self.shown = True

    def close(self) -> None:
        """Erase the line."""
        if self.shown:
            sys.stderr.write("\r\x1b[K")
            sys.stderr.flush()
            self.shown = False


def _budget(args: argparse.Namespace) -> Any:
    """The per-case :class:`verify.core.rule.Budget` of ``--max-bits`` and ``--case-timeout`` (None if neither)."""
    from verify.core.rule import Budget

    if args.max_bits is None and args.case_timeout is None:
        return None
    return Budget(bits=args.max_bits, seconds=args.case_timeout)


def _case_progress(status: StatusLine, label: str) -> Any:
    """A ``progress`` callback for :func:`verify.core.rule.solve` that shows ``label``, the impulses so far
    and the time (None when the status line is off: no cost at all)."""
    if not status.enabled:
        return None
    import time

    start = time.monotonic()
    status.show(f"{label}: starting", now=True)
    return lambda count: status.show(f"{label}: {count} impulses, {time.monotonic() - start:.0f} s")


def _cmd_solve(args: argparse.Namespace) -> int:
    from verify.core.rule import solve
    from verify.records.results import dumps, load_cases, result_record
    from verify.views.text import solve_text

    cases = load_cases(args.cases, backend=args.backend, dps=args.dps)  # every case validated first
    budget = _budget(args)
    status = StatusLine.for_args(args)
    results = []
    try:
        for k, c in enumerate(cases, 1):
            cap = c.max_iterations if args.max_iterations is None else args.max_iterations
            progress = _case_progress(status, f"verify solve: case {k}/{len(cases)} {c.id}")
            try:
                r = solve(c.system, c.velocity_source, rule=args.rule, max_iterations=cap, trace=False,
                          budget=budget, progress=progress)  # fmt: skip
            except (InvalidInput, Undecided) as exc:  # name the case; nothing is printed for the others
                raise type(exc)(f"{PROG} solve: case {c.id!r} (cases[{k - 1}]): {_one_line(exc)}") from None
            results.append((c, r))
    finally:
        status.close()
    if args.json:
        sys.stdout.write(dumps({"results": [result_record(r, c.id) for c, r in results]}))
    else:
        sys.stdout.write("".join(solve_text(c.id, r) for c, r in results))
    return 0


def _cmd_cradle_map(args: argparse.Namespace) -> int:
    from verify.checks.paper.cradle_map import (
        aeev_rows_explained,
        approach_counts,
        cradle_map,
        map_json,
        termination_boundaries,
    )
    from verify.records.results import dumps
    from verify.views.text import cradle_map_text

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
        approach = []
        if bounds and args.approach >= 2:  # runs of this map's cradle (its balls, masses and velocity)
            approach = approach_counts(bounds[0], range(2, args.approach + 1), cmap)
        sys.stdout.write(cradle_map_text(cmap, aeev_rows=rows, approach=approach))
    if args.figure:
        from verify.views.figures import cradle_staircase

        with _writing(args.figure, "--figure"):
            cradle_staircase(cmap, args.figure)
        print(f"figure written to {args.figure}", file=sys.stderr)
    return 0


def _cmd_corner(args: argparse.Namespace) -> int:
    from verify.models.corner import run_corner
    from verify.records.results import dumps, result_record
    from verify.views.text import corner_text

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
    from verify.checks.paper.corner_claims import corner_findings
    from verify.records.results import dumps
    from verify.views.text import corner_claims_json, corner_claims_text

    data = corner_findings(args.cases, seed=args.seed, workers=args.workers)
    claims = data[0]
    sys.stdout.write(dumps(corner_claims_json(*data)) if args.json else corner_claims_text(*data))
    if args.figures:
        from pathlib import Path

        from verify.views import figures

        out = Path(args.figures)
        for name, draw in (
            ("corner-exit-vs-entrance.png", figures.corner_exit_vs_entrance),
            ("corner-iterations.png", figures.corner_iterations_map),
            ("corner-multiple-impacts.png", figures.corner_multiple_impacts_map),
            ("wedge-boundary.png", figures.wedge_boundary),
        ):
            with _writing(args.figures, "--figures"):
                draw(out / name, workers=args.workers)
            print(f"figure written to {out / name}", file=sys.stderr)
    return 1 if any(c.verdict == "refuted" for c in claims) else 0


def _cmd_sweep(args: argparse.Namespace) -> int:
    import time
    from collections import Counter

    from verify.checks.sweep import random_corner_cases, sweep
    from verify.records.results import dumps

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
    from verify.checks.paper.table1 import table1
    from verify.records.results import dumps
    from verify.views.text import table1_json, table1_text

    table = table1(exact_cap=args.exact_cap)
    sys.stdout.write(dumps(table1_json(table)) if args.json else table1_text(table))
    return 0


def _cmd_all(args: argparse.Namespace) -> int:
    import time

    from verify.views.pages import write_reports
    from verify.views.text import all_summary

    start = time.monotonic()
    print("verify all: reproducing Pasquero (2021), then writing the reports", flush=True)

    def progress(line: str) -> None:
        print(f"{line} ({time.monotonic() - start:.0f} s)", flush=True)

    with _writing(args.out, "--out"):
        ctx = write_reports(args.out, profile="ci", workers=args.workers, progress=progress)
    summary, failed = all_summary(ctx)
    sys.stdout.write(summary)
    print(f"reports written to {args.out}/ in {time.monotonic() - start:.0f} s")
    return 1 if failed else 0


def _cmd_bench(args: argparse.Namespace) -> int:
    from verify.checks.bench import QUICK, bench, bench_json, bench_text
    from verify.records.results import dumps

    options = dict(QUICK) if args.quick else {}
    if args.size is not None:
        options["size"] = args.size
    figures = bench(**options, progress=lambda line: print(line, file=sys.stderr, flush=True))
    record = bench_json(figures, quick=args.quick)
    if args.save:
        _write_file(args.save, dumps(record), "--save")
    sys.stdout.write(dumps(record) if args.json else bench_text(record))
    return 0


def _cmd_report(args: argparse.Namespace) -> int:
    from verify.views.pages import write_reports

    with _writing(args.out, "--out"):
        write_reports(args.out, profile=args.profile, workers=args.workers,
                      progress=lambda line: print(line, file=sys.stderr, flush=True))  # fmt: skip
    print(f"reports written to {args.out}/")
    return 0


def _cmd_properties(args: argparse.Namespace) -> int:
    import json
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
        with _writing(args.counterexamples, "--counterexamples"):
            _write_counterexamples(args.counterexamples, found)
    sys.stdout.write(dumps(report(args.profile, found)) if args.json else properties_text(args.profile, found))
    return 1 if any(v.verdict == "refuted" for v in found) else 0


def _write_counterexamples(folder: str, found: list) -> None:
    """One case file per refuted row (written whole, then renamed into place)."""
    import os

    from verify.records.results import dumps

    os.makedirs(folder, exist_ok=True)
    for v in found:
        if v.counterexample is None:
            continue
        _write_file(os.path.join(folder, v.counterexample["id"] + ".json"), dumps({"cases": [v.counterexample]}),
                    "--counterexamples")  # fmt: skip


def _cmd_oracle(args: argparse.Namespace) -> int:
    from verify.checks import oracle

    if args.action == "export":
        with _writing(args.folder, "DIR"):
            paths = oracle.export(args.folder)
        for path in paths:
            print(f"wrote {path}")
        return 0
    return _oracle_check(args)


def _oracle_check(args: argparse.Namespace) -> int:
    from verify.checks import oracle
    from verify.records.results import dumps, load_cases
    from verify.views.text import oracle_text

    if (args.results is None) == (args.impl is None):
        raise UsageError(f"{PROG} oracle check: give either RESULTS.json or --impl COMMAND")
    tolerances = {"rtol": args.rtol, "atol": args.atol}  # Fractions (NonNegativeRational)
    load_cases(args.cases)  # validates the file: schema, then every number
    with open(args.cases, encoding="utf-8") as fh:
        case_text = fh.read()
    records = json.loads(case_text)["cases"]
    if args.max_iterations is not None:  # the cases as if each had this cap: for the exact runs and --impl
        records = [dict(r, max_iterations=args.max_iterations) for r in records]
        case_text = dumps({"cases": records})
    status = StatusLine.for_args(args)
    if args.impl is not None:
        status.show(f"verify oracle check: running {args.impl}", now=True)
        try:
            text = oracle.run_implementation(args.impl, case_text, args.timeout)
        finally:
            status.close()
        source = f"the output of {args.impl!r}"
    else:
        try:
            with open(args.results, encoding="utf-8") as fh:
                text = fh.read()
        except OSError as exc:
            raise UsageError(f"{args.results}: cannot read ({exc.strerror})") from None
        source = args.results
    got = oracle.load_results(text, source)

    def progress(k: int, case_id: str, impulses: int) -> None:
        status.show(f"verify oracle check: exact results, case {k}/{len(records)} {case_id}: {impulses} impulses",
                    now=impulses == 0)  # fmt: skip

    try:
        expected = oracle.golden_results(records, budget=_budget(args), progress=progress if status.enabled else None)
    finally:
        status.close()
    comparison = oracle.compare(records, expected, got, **tolerances)
    if args.json:
        sys.stdout.write(dumps(oracle.comparison_json(comparison)))
    else:
        sys.stdout.write(oracle_text(comparison))
        if comparison.limited:
            print(f"note: {len(comparison.limited)} cases checked only on the impulses the exact run made before "
                  f"reaching --max-bits or --case-timeout: {', '.join(comparison.limited)}")  # fmt: skip
    return 0 if comparison.ok else 1


# -- the parser ----------------------------------------------------------------------------------


def _budget_options(p: argparse.ArgumentParser, scope: str) -> None:
    p.add_argument(
        "--max-iterations",
        type=BoundedInt(0, MAX_COUNT),
        default=None,
        metavar="N",
        help="cap on impulses, replacing each case's max_iterations (default: the case's own, else 10000)",
    )
    p.add_argument(
        "--max-bits",
        type=BoundedInt(1, MAX_COUNT),
        default=None,
        metavar="BITS",
        help=f"stop a run (stop budget) once its exact numbers pass BITS bits, {scope}: numerator plus "
        "denominator of the largest velocity component; the same on every machine; exact backend only",
    )
    p.add_argument(
        "--case-timeout",
        type=Seconds(),
        default=None,
        metavar="SECONDS",
        help=f"stop a run (stop budget) after SECONDS of wall time, {scope}: depends on the machine, so "
        "prefer --max-bits where results must be reproducible",
    )


def _backend_options(p: argparse.ArgumentParser) -> None:
    from verify.core.backends import BACKENDS

    p.add_argument(
        "--backend",
        default="exact",
        choices=BACKENDS,
        help="arithmetic: exact (default), mp, interval (certified), float (not rigorous)",
    )
    p.add_argument(
        "--dps",
        type=BoundedInt(MIN_DPS, MAX_DPS),
        default=None,
        help=f"decimal digits for mp and interval, {MIN_DPS} to {MAX_DPS} (default 50)",
    )


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``verify`` (subcommands as in the contracts).

    >>> build_parser().parse_args(["solve", "cases.json", "--max-bits", "5000"]).max_bits
    5000
    """
    from verify.core.rule import RULES

    # the types of the numeric options (each checks its range when parsed: one line, exit code 2)
    count = BoundedInt(0, MAX_COUNT)  # caps on impulses
    balls = BoundedInt(2, MAX_BALLS)
    cases = BoundedInt(1, MAX_CASES)
    seed = BoundedInt(0, MAX_SEED)
    workers = BoundedInt(1, MAX_WORKERS)
    number = ExactNumber()

    parser = _Parser(
        prog=PROG,
        formatter_class=_formatter,
        description="Exact verification of the multiple-impact rule of Pasquero (2021).",
        epilog=(
            "examples:\n  verify all\n  verify table1\n  verify cradle --eps 0.5\n\n"
            "Formats and commands: docs/ in the source repository (docs/README.md).\n"
        ),
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
    p.add_argument("--v0", default="100", type=number, help="velocity of ball 1, the others at rest (default 100)")
    p.add_argument("--balls", type=balls, default=None, help=f"number of balls N, 2 to {MAX_BALLS} (default 3)")
    p.add_argument("--masses", help="masses m1,m2,...,mN (default all 1)")
    p.add_argument("--velocity", help="the whole left velocity v1,...,vN (instead of --v0)")
    p.add_argument(
        "--mode",
        default="exact",
        choices=("exact", "paper"),
        help="exact: stop at exit; paper: the paper's 10^4 cap and AEEV stop",
    )
    p.add_argument("--max-iterations", type=count, default=None, help="cap on impulses (default 10000)")
    p.add_argument("--trace", action="store_true", help="print every impulse, however many")
    p.add_argument("--json", action="store_true", help="print the result record (JSON)")
    _backend_options(p)
    p.set_defaults(func=_cmd_cradle)

    p = sub.add_parser(
        "solve",
        help="run the general rule on a case file",
        formatter_class=_formatter,
        description=(
            "Run the rule (eq. 8) on every case of a case file (format: docs/records.md in the source repository), "
            "in order, and print one result per case. A run stops at its exit, at its cap on impulses (stop "
            "max_iterations), when proved never to exit (non_terminating), or at the budget of --max-bits or "
            "--case-timeout (stop budget). On a terminal, a status line on stderr shows the case and the impulses "
            "so far (--quiet: none). A case that cannot be run (a rule that does not apply to it, or a sign the "
            "interval backend cannot decide even at its largest precision) ends the command with one line naming "
            "the case and exit code 2, and nothing on stdout: a result file only holds the stops of the format. "
            "Rerun such a case with --backend exact, or leave it out."
        ),
        epilog=(
            "examples:\n  verify solve cases.json\n  verify solve cases.json --backend interval --json\n"
            "  verify solve cases.json --max-iterations 2000 --max-bits 100000 --case-timeout 60\n"
        ),
    )
    p.add_argument("cases", metavar="CASES.json", help='a case file {"cases": [...]}')
    p.add_argument(
        "--rule",
        default="general",
        choices=RULES,
        help="general (eq. 8, default), ideal (5), symmetric (6) or asymmetric (7)",
    )
    _budget_options(p, "per case")
    p.add_argument("--quiet", action="store_true", help="no status line on stderr")
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
    angle.add_argument("--alpha", type=number, help="half the corner angle, in (0, pi/2): pi/6, 3/10 (radians)")
    angle.add_argument("--slope", type=number, help="k = tan(alpha) > 0 instead of alpha: 1/2, sqrt(3)/3")
    p.add_argument("--phi", required=True, type=number, help="direction of the entrance velocity: pi/12, 0, -1/5")
    p.add_argument("--eps1", required=True, type=number, help="COR of wall S1 (kx - y = 0), in [0, 1]")
    p.add_argument("--eps2", required=True, type=number, help="COR of wall S2 (kx + y = 0), in [0, 1]")
    p.add_argument("--v0", default="100", type=number, help="speed of the entrance velocity (default 100)")
    p.add_argument("--max-iterations", type=count, default=10_000, help="cap on impulses (default 10000)")
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
    p.add_argument("--cases", type=cases, default=2000, help="cases per sample (default 2000)")
    p.add_argument("--seed", type=seed, default=0, help="seed of the deterministic samples, >= 0 (default 0)")
    p.add_argument("--workers", type=workers, default=None, help="local processes (default: every core)")
    p.add_argument("--figures", metavar="DIR", type=OutputDir(), help="also draw the corner's figures (PNG) into DIR")
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
    p.add_argument("--cases", type=cases, default=10_000, help="number of cases (default 10000)")
    p.add_argument("--seed", type=seed, default=0, help="seed of the deterministic batch, >= 0 (default 0)")
    p.add_argument("--workers", type=workers, default=None, help="local processes (default: every core)")
    p.add_argument("--max-iterations", type=count, default=100, help="cap on impulses per case (default 100)")
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
    p.add_argument("--balls", type=balls, default=None, help=f"number of balls N, 2 to {MAX_BALLS} (default 3)")
    p.add_argument("--masses", help="masses m1,...,mN (default all 1)")
    p.add_argument("--velocity", help="the left velocity v1,...,vN (default v0 on ball 1)")
    p.add_argument("--v0", default="1", type=number, help="velocity of ball 1 (default 1)")
    p.add_argument("--interval", default="0,1", help="the eps interval LO,HI inside [0, 1] (default 0,1)")
    p.add_argument("--max-impulses", type=BoundedInt(0, MAX_IMPULSES_MAP), default=40,
                   help="bound on the exploration (default 40)")  # fmt: skip
    p.add_argument(
        "--approach",
        type=BoundedInt(0, MAX_APPROACH),
        default=6,
        help="show impulse counts at eps = boundary + 10^-k for k = 2..K (default 6; 0 to skip)",
    )
    p.add_argument("--figure", type=OutputFile((".png",)), help="also write the staircase figure (PNG) to this path")
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
        type=count,
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
    p.add_argument("--workers", type=workers, default=None, help="processes (default: every core)")
    p.add_argument("--counterexamples", metavar="DIR", type=OutputDir(),
                   help="write each counterexample as a case file into DIR")  # fmt: skip
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
    q.add_argument("folder", metavar="DIR", type=OutputDir(), help="the folder to write (created if needed)")
    q.set_defaults(func=_cmd_oracle)
    q = oracle_sub.add_parser(
        "check",
        help="check RESULTS.json (or the output of --impl COMMAND) against the exact results of CASES.json",
        formatter_class=_formatter,
        description=(
            "Compare another implementation's results with the exact results of CASES.json, computed here. "
            "--max-iterations replaces every case's cap, for the exact runs and in the case file given to --impl "
            "(a RESULTS.json file should then be made with the same cap). --max-bits and --case-timeout bound "
            "each exact run: a case whose run reaches them is checked only on the impulses it made (the other "
            "implementation must not stop before them), and is named in a note."
        ),
        epilog=(
            "examples:\n  verify oracle check golden/cases.json my_results.json\n"
            "  verify oracle check golden/cases.json --impl './my_solver --json' --timeout 60\n"
            "  verify oracle check my_cases.json --impl './my_solver' --max-bits 100000 --case-timeout 30\n"
        ),
    )
    q.add_argument("cases", metavar="CASES.json")
    q.add_argument("results", metavar="RESULTS.json", nargs="?", help="the other implementation's result file")
    q.add_argument("--impl", metavar="COMMAND", help="run COMMAND: case file on stdin, result file on stdout")
    q.add_argument("--timeout", type=Seconds(), default=600.0, metavar="SECONDS",
                   help="seconds allowed to --impl (default 600)")  # fmt: skip
    q.add_argument("--rtol", default="1e-9", type=NonNegativeRational(),
                   help="relative tolerance on the exit velocity (default 1e-9)")  # fmt: skip
    q.add_argument("--atol", default="0", type=NonNegativeRational(),
                   help="absolute tolerance on the exit velocity (default 0)")  # fmt: skip
    _budget_options(q, "per case, for the exact results")
    q.add_argument("--quiet", action="store_true", help="no status line on stderr")
    q.add_argument("--json", action="store_true", help="print the comparison as JSON")
    q.set_defaults(func=_cmd_oracle)

    p = sub.add_parser(
        "report",
        help="regenerate the reports (reports/: one page per topic, figures)",
        formatter_class=_formatter,
        description="Write reports/README.md and one page per topic, every number from the library.",
        epilog="examples:\n  verify report\n  verify report --out /tmp/reports --profile dev\n",
    )
    p.add_argument("--out", default="reports", type=OutputDir(), help="the folder to write (default reports)")
    p.add_argument("--profile", default="ci", choices=PROFILE_NAMES, help="property profile (default ci)")
    p.add_argument("--workers", type=workers, default=None, help="processes (default: every core)")
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
    p.add_argument("--size", type=cases, default=None, help="cases in the corner batch (default 10000)")
    p.add_argument("--save", default=None, metavar="FILE", type=OutputFile(), help="also write the JSON record to FILE")
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
    p.add_argument("--out", default="reports", type=OutputDir(), help="the folder for the reports (default reports)")
    p.add_argument("--workers", type=workers, default=None, help="processes (default: every core)")
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
        return int(args.func(args))  # every numeric and output-path option was checked by its type
    except (UsageError, InvalidInput, Undecided) as exc:
        print(f"{PROG}: error: {_one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # Ctrl-C on a long run: one line, the shell's code for SIGINT
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # pragma: no cover - e.g. piped into head
        return 0


#: library parameters that error messages name, and the command line's flags for them
_PARAMETER_FLAGS = {'backend="interval"': "--backend interval", 'backend="mp"': "--backend mp"}


def _one_line(exc: Any) -> str:
    text = " ".join(str(exc).split())
    for parameter, flag in _PARAMETER_FLAGS.items():  # the library's terms, in the command line's
        text = text.replace(parameter, flag)
    return text
