"""``verify table1``: the paper's Table 1, recomputed and checked."""

from __future__ import annotations

import argparse
import sys

from verify.cli.common import COUNT


def table1_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify table1``."""
    p.add_argument(
        "--exact-cap",
        type=COUNT,
        default=10_000,
        help="impulses after which an exact run that has neither exited nor been proved never to exit "
        "is reported as such (default 10000)",
    )
    p.add_argument("--json", action="store_true", help="print JSON")


def cmd_table1(args: argparse.Namespace) -> int:
    """``verify table1``: print the table (or its JSON)."""
    from verify.checks.paper.table1 import table1
    from verify.records.results import dumps
    from verify.views.text import table1_json, table1_text

    table = table1(exact_cap=args.exact_cap)
    sys.stdout.write(dumps(table1_json(table)) if args.json else table1_text(table))
    return 0


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("table1",)
