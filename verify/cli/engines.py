"""``verify engines``: physics engines through the oracle, against both laws."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from verify.cli.common import WORKERS, OutputDir, UsageError, writing


def engines_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify engines``."""
    from verify.engines import ENGINES

    p.add_argument("--engine", action="append", choices=tuple(ENGINES), default=None, metavar="NAME",
                   help=f"run only this engine (repeatable): {', '.join(ENGINES)}")  # fmt: skip
    p.add_argument("--report", action="store_true",
                   help="write engines.json, engines.md and engines-cradle.png into --out")  # fmt: skip
    p.add_argument("--out", default="reports", type=OutputDir(), help="the folder of --report (default reports)")
    p.add_argument("--workers", type=WORKERS, default=None, help="engines run at once (default 2)")
    p.add_argument("--python", action="append", default=[], metavar="NAME=PYTHON", type=_interpreter,
                   help="run engine NAME's adapter with another Python (an environment of its own, with verify and "
                        "the engine installed), e.g. nimblephysics=venv-nimble/bin/python (repeatable)")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    p.add_argument("--from", dest="record", default=None, metavar="RECORD",
                   help="read this record (engines.json of --report, or --json's output) instead of running the "
                        "engines, e.g. reports/engines.json")  # fmt: skip
    p.add_argument("--explain", action="store_true",
                   help="with --from: explain the saved answers again by the exact models of the engines' "
                        "algorithms (no engine runs); --report then writes the record anew")  # fmt: skip
    p.add_argument("--cases", action="store_true",
                   help="also print each engine's answer on every case, beside both laws' exact answers")  # fmt: skip
    p.add_argument("--json", action="store_true", help="print the record (JSON)")


def _interpreter(text: str) -> tuple[str, str]:
    """``NAME=PYTHON``: a known engine and an executable file."""
    import os

    from verify.engines import ENGINES

    name, sep, path = text.partition("=")
    if not sep or name not in ENGINES:
        raise argparse.ArgumentTypeError(f"expected NAME=PYTHON with NAME one of {', '.join(ENGINES)}, got {text!r}")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise argparse.ArgumentTypeError(f"{path!r} is not an executable file")
    return name, path


def cmd_engines(args: argparse.Namespace) -> int:
    """``verify engines``: run every installed engine's adapter; print the findings (or the record)."""
    from verify.engines.run import engines_record, findings
    from verify.records.results import dumps

    def progress(line: str) -> None:
        if not args.quiet:
            print(f"verify engines: {line}", file=sys.stderr, flush=True)

    if args.explain and args.record is None:
        raise UsageError("--explain explains a saved record again: it goes with --from")
    if args.explain and args.report and args.engine:
        raise UsageError("--explain --report writes the whole record anew: --engine cannot go with it")
    if args.record is not None:
        ran = [flag for flag, given in (("--report", args.report and not args.explain), ("--python", args.python),
                                        ("--workers", args.workers)) if given]  # fmt: skip
        if ran:  # they run engines or write a new record: a saved record is only read
            raise UsageError(f"--from reads a saved record and runs no engine: {', '.join(ran)} cannot go with it")
        record = read_record(args.record, args.engine)
        if args.explain:
            from verify.engines.run import explain_again

            explain_again(record, progress)
    else:
        record = engines_record(args.engine, progress=progress, workers=args.workers or 2, pythons=dict(args.python))
    if args.report:
        write_engines_report(args.out, record)
    if args.json:
        sys.stdout.write(dumps(record))
        return 0
    lines = [f"{e['name']} {e['version']}: {len(e['cases'])} cases" for e in record["engines"]]
    lines += [f"{s['name']}: skipped ({s['reason']})" for s in record["skipped"]]
    lines += ["", *[f"- {line}" for line in findings(record)]]
    if args.cases:
        from verify.engines.pages import case_tables

        lines += ["", *case_tables(record)]
    if args.report:
        lines += ["", f"wrote {args.out}/engines.md, engines.json and engines-cradle.png"]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def read_record(path: str, names: list[str] | None) -> dict[str, Any]:
    """A saved engines record (``--from``), narrowed to the engines ``names`` (all when None); a file that is
    not such a record is a usage error."""
    import json
    from pathlib import Path

    try:
        record: dict[str, Any] = json.loads(Path(path).read_text(encoding="utf-8"))
        if not (isinstance(record, dict) and {"cases", "engines", "skipped"} <= record.keys()):
            raise ValueError("it has no cases, engines and skipped")
    except (OSError, ValueError) as exc:
        raise UsageError(f"--from {path}: not an engines record ({exc})") from None
    if names:
        record = dict(record, engines=[e for e in record["engines"] if e["name"] in names])
    return record


def write_engines_report(out: str, record: dict[Any, Any]) -> None:
    """``engines.json`` (the record), then the page and its figure, into ``out``."""
    from pathlib import Path

    from verify.engines.pages import engines_page
    from verify.records.files import write_atomic
    from verify.records.results import dumps

    with writing(out, "--out"):
        folder = Path(out)
        folder.mkdir(parents=True, exist_ok=True)
        write_atomic(folder / "engines.json", dumps(record))
        write_atomic(folder / "engines.md", engines_page(folder))


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("engines",)
