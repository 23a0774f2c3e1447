"""``verify table1``: the paper's Table 1, recomputed and checked."""

from __future__ import annotations

import argparse
import sys

from verify.cli.common import max_impulses_option, quiet_option


def table1_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify table1``."""
    max_impulses_option(
        p,
        default=10_000,
        old=("--exact-cap",),
        help="impulses after which an exact run that has neither exited nor been proved never to exit "
        "is reported as such (default 10000)",
    )
    p.add_argument("--json", action="store_true", help="print JSON")
    quiet_option(p, "no progress on stderr (this command prints none; every subcommand takes --quiet)")


def cmd_table1(args: argparse.Namespace) -> int:
    """``verify table1``: print the table (or its JSON)."""
    from verify.paper.table1 import table1
    from verify.paper.text import table1_json, table1_text
    from verify.records.results import dumps

    table = table1(exact_cap=args.max_impulses)
    sys.stdout.write(dumps(table1_json(table)) if args.json else table1_text(table))
    return 0


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("table1",)
