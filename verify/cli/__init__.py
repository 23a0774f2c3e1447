"""The ``verify`` command line: a thin layer over the library.

Each subcommand parses its arguments, makes one library call, prints text (or JSON with
``--json``) and returns an exit code: 0 success, 1 a check found a mismatch, 2 bad
input or usage. Bad input prints one line on stderr, never a traceback. Python callers
should use the library (:mod:`verify`) directly.

The subcommands live in groups, each module with its parsers and their handlers:
:mod:`~verify.cli.run` (cradle, solve, corner), :mod:`~verify.cli.maps` (corner-claims, sweep,
cradle-map), :mod:`~verify.cli.paper` (table1), :mod:`~verify.cli.checks` (properties, oracle),
:mod:`~verify.cli.engines` (engines) and :mod:`~verify.cli.reports` (report, bench, all); what
they share is in :mod:`~verify.cli.common`.
Each group lists its subcommands in ``COMMANDS``; a subcommand ``N`` has its options declared by
``N_options(parser)`` (``-`` read as ``_``) and is run by ``cmd_N(args)``; the texts of every ``--help``
are in ``verify/cli/commands.toml``.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from collections.abc import Sequence

from verify.cli import checks, engines, maps, paper, reports, run
from verify.cli.common import PROG, Parser, UsageError, command, formatter, one_line
from verify.cli.signals import Terminated, finish, stop_on_signals
from verify.errors import InvalidInput, Undecided
from verify.runner.tasks import TasksFailed


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``verify`` (subcommands as in the contracts).

    >>> build_parser().parse_args(["solve", "cases.json", "--max-bits", "5000"]).max_bits
    5000
    """
    from verify import __version__

    parser = Parser(
        prog=PROG,
        formatter_class=formatter,
        description="Exact verification of the multiple-impact rule of Pasquero (2021).",
        epilog=(
            "examples:\n  verify all\n  verify table1\n  verify cradle --eps 0.5\n\n"
            "Formats and commands: docs/ in the source repository (docs/README.md).\n"
        ),
    )
    parser.add_argument("--version", action="version", version=f"verify {__version__}")
    debug_help = f"on an internal error (exit code 3), print its traceback (also {DEBUG_VARIABLE}=1)"
    parser.add_argument("--debug", action="store_true", help=debug_help)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    for group in (run, maps, paper, checks, engines, reports):  # the order of the subcommands in --help
        for name in group.COMMANDS:  # found when the parser is built: the handlers are the module's then
            stem = name.replace("-", "_")
            getattr(group, f"{stem}_options")(command(sub, name, getattr(group, f"cmd_{stem}")))
    return parser


#: the exit code of an internal error (a bug in verify, not in its input)
INTERNAL_ERROR = 3
#: set (to anything but "" or "0") to see the traceback of an internal error, as ``--debug`` does
DEBUG_VARIABLE = "VERIFY_DEBUG"


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code: 0 ok, 1 mismatch, 2 bad input or usage, 3 an internal
    error (:data:`INTERNAL_ERROR`), 128 + n when stopped by signal n (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP)."""
    parser = build_parser()
    limit = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)  # exact outputs are printed whole, however many digits they have
    debug = os.environ.get(DEBUG_VARIABLE, "") not in ("", "0")
    args = None
    try:
        args = parser.parse_args(argv)
        debug = debug or args.debug
        if args.command is None:
            parser.print_help()
            return 2
        with stop_on_signals():
            return int(args.func(args))  # every numeric and output-path option was checked by its type
    except (UsageError, InvalidInput, Undecided) as exc:
        print(f"{PROG}: error: {one_line(exc)}", file=sys.stderr)
        if args is None:  # refused while the options were read: a --junit file says so
            checks.junit_after_usage_error(list(sys.argv[1:] if argv is None else argv), one_line(exc))
        return 2
    except TasksFailed as exc:  # the other tasks finished (and are in the checkpoint, if any)
        for f in exc.failures:
            print(f"{PROG}: error: {f.label} failed twice: {f.error}", file=sys.stderr)
        return INTERNAL_ERROR if any(f.internal for f in exc.failures) else 2
    except Terminated as stop:  # SIGTERM or SIGHUP: cleaned up as for Ctrl-C
        print(f"{PROG}: terminated ({stop.name})", file=sys.stderr)
        sys.set_int_max_str_digits(limit)
        finish(stop)  # exits now (the interpreter's shutdown could wait on a pool's threads)
        return stop.exit_code
    except KeyboardInterrupt:  # Ctrl-C on a long run: one line, the shell's code for SIGINT
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # pragma: no cover - e.g. piped into head
        return 0
    except Exception as exc:  # a bug in verify: one line and its own exit code (the traceback when asked for)
        if debug:
            traceback.print_exc()
        hint = "" if debug else f"; verify --debug COMMAND ... (or {DEBUG_VARIABLE}=1) shows the traceback"
        what = f"{type(exc).__name__}: {one_line(exc)}"
        print(f"{PROG}: internal error ({what}): a bug in verify, please report it{hint}", file=sys.stderr)
        return INTERNAL_ERROR
    finally:
        sys.set_int_max_str_digits(limit)
