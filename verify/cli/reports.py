"""``verify report``, ``verify all``, ``verify bench``, ``verify bounds``: the reports, the main job, the
throughput figures, the bounds of the algorithms."""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Callable
from typing import Any

from verify.cli.common import (
    CASES,
    OutputDir,
    OutputFile,
    cluster_options,
    quiet_option,
    task_runner,
    write_output,
    writing,
)
from verify.properties.profiles import PROFILES


def report_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify report``."""
    p.add_argument("--out", default="reports", type=OutputDir(), help="the folder to write (default reports)")
    p.add_argument("--profile", default="ci", choices=tuple(PROFILES), help="property profile (default ci)")
    cluster_options(p, "local processes (default: every core)")
    quiet_option(p, "no progress lines on stderr")


def bench_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify bench``."""
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    p.add_argument("--quick", action="store_true", help="a smoke run: small batches, one round, no Table 1 or GP")
    p.add_argument("--size", type=CASES, default=None, help="cases in the corner batch (default 10000)")
    p.add_argument("--save", default=None, metavar="FILE", type=OutputFile(), help="also write the JSON record to FILE")
    quiet_option(p, "no progress lines on stderr")


def bounds_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify bounds``."""
    p.add_argument("logs", nargs="*", metavar="FILE", help="files written under VERIFY_BOUNDS=FILE by earlier commands")
    quiet_option(p, "no progress on stderr (this command prints none; every subcommand takes --quiet)")


def all_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify all``."""
    p.add_argument("--out", default="reports", type=OutputDir(), help="the folder for the reports (default reports)")
    cluster_options(p, "local processes (default: every core)")
    quiet_option(p, "no progress lines, only the summary")


def cmd_report(args: argparse.Namespace) -> int:
    """``verify report``: write the reports."""
    from verify.report.pages import write_reports

    with task_runner(args, {"command": "report", "profile": args.profile}) as runner, writing(args.out, "--out"):
        progress = None if args.quiet else lambda line: print(line, file=sys.stderr, flush=True)
        write_reports(args.out, profile=args.profile, runner=runner, progress=progress)
    print(f"reports written to {args.out}/")
    return 0


#: the clock of :class:`StepClock` (seconds; a test replaces it)
_clock = time.monotonic


class StepClock:
    """The progress lines of ``verify all``: a step's line (one ending in ``...``) says when it
    started, counted from the start of the run, and when the step ends (the next line comes, or
    :meth:`finish`) a line gives the step's own time.

    >>> ticks = iter([0, 5, 65, 70])
    >>> clock = StepClock(print, clock=lambda: next(ticks))
    >>> clock("[report 1/2] Table 1 ...")
    [report 1/2] Table 1 ... (at 5 s)
    >>> clock("[report 2/2] Performance ...")
    [report 1/2] done in 60 s
    [report 2/2] Performance ... (at 65 s)
    >>> clock.finish()
    [report 2/2] done in 5 s
    """

    def __init__(self, write: Callable[[str], Any], *, clock: Callable[[], float] | None = None) -> None:
        self.write, self.clock = write, clock or _clock
        self.start = self.clock()
        self.step: tuple[str, float] | None = None  # the running step's label and start

    def elapsed(self) -> float:
        """Seconds since the start of the run."""
        return self.clock() - self.start

    def __call__(self, line: str) -> None:
        now = self.clock()
        self.finish(now)
        self.write(f"{line} (at {now - self.start:.0f} s)")
        if line.endswith("..."):
            self.step = (line.split("]", 1)[0] + "]" if line.startswith("[") else line, now)

    def finish(self, now: float | None = None) -> None:
        """End the running step, if any: print its own time."""
        if self.step is not None:
            label, began = self.step
            self.write(f"{label} done in {(self.clock() if now is None else now) - began:.0f} s")
            self.step = None


def cmd_all(args: argparse.Namespace) -> int:
    """``verify all``: write the reports (ci profile), then summarise; exit code 1 if the program contradicts itself."""
    from verify.errors import require
    from verify.report.pages import write_reports
    from verify.report.summary import all_summary

    require("matplotlib", "the reports' figures")  # before anything is printed or computed
    progress = StepClock((lambda line: None) if args.quiet else (lambda line: print(line, flush=True)))
    print("verify all: reproducing Pasquero (2021), then writing the reports", flush=True)
    refresh_engines(args.out, progress)
    with task_runner(args, {"command": "all", "profile": "ci"}) as runner, writing(args.out, "--out"):
        found = write_reports(args.out, profile="ci", runner=runner, progress=progress)
    progress.finish()
    summary, failed = all_summary(found.table1, found.cradle_map.cmap, found.corner_example, found.corner.claims,
                                  profile=found.profile, found=found.verdicts,
                                  oracle_ok=found.oracle.self_check.ok)  # fmt: skip
    sys.stdout.write(summary)
    print(f"reports written to {args.out}/ in {progress.elapsed():.0f} s")
    return 1 if failed else 0


def refresh_engines(out: str, progress: Any) -> None:
    """Run the physics engines again into ``out/engines.json`` when every one is installed (the
    ``engines`` extra); otherwise the engines page is rendered from the record as it is."""
    from verify.engines import ENGINES
    from verify.engines.run import engines_record, installed
    from verify.records.files import write_atomic
    from verify.records.results import dumps

    missing = sorted(set(ENGINES) - set(installed()))
    if missing:
        progress(f"[engines] not all installed ({', '.join(missing)} missing): the engines page shows the saved record")
        return
    progress("[engines] running every engine (verify engines) ...")
    record = engines_record()
    with writing(out, "--out"):
        os.makedirs(out, exist_ok=True)
        write_atomic(os.path.join(out, "engines.json"), dumps(record))


def cmd_bench(args: argparse.Namespace) -> int:
    """``verify bench``: time the engines against their baselines; print (and ``--save``) the record."""
    from verify.bench.throughput import QUICK, bench, bench_json, bench_text
    from verify.records.results import dumps

    options: dict[str, Any] = dict(QUICK) if args.quick else {}
    if args.size is not None:
        options["size"] = args.size
    figures = bench(**options, progress=None if args.quiet else lambda line: print(line, file=sys.stderr, flush=True))
    record = bench_json(figures, quick=args.quick)
    if args.save:
        write_output(args.save, dumps(record), "--save")
    sys.stdout.write(dumps(record) if args.json else bench_text(record))
    return 0


def cmd_bounds(args: argparse.Namespace) -> int:
    """``verify bounds``: the bounds of the algorithms, and what the commands run under VERIFY_BOUNDS used."""
    from verify.cli.common import UsageError
    from verify.report.bounds import summary, table

    if not args.logs:
        print(table())
        return 0
    lines: list[str] = []
    for path in args.logs:
        try:
            with open(path, encoding="utf-8") as f:
                part = f.read().splitlines()
            summary(part)
        except (OSError, UnicodeDecodeError) as exc:
            raise UsageError(f"cannot read {path}: {exc.strerror if isinstance(exc, OSError) else exc}") from None
        except ValueError as exc:
            raise UsageError(f"{path}: {exc}") from None
        lines += part
    print(table(summary(lines)))
    return 0


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("report", "bench", "bounds", "all")
