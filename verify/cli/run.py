"""``verify cradle``, ``verify solve``, ``verify corner``: one run (or one case file) of the rule."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from verify.cli.common import (
    BALLS,
    BALLS_DEFAULT,
    MAX_BALLS,
    NUMBER,
    PROG,
    StatusLine,
    UsageError,
    backend_choice,
    backend_options,
    budget_options,
    case_progress,
    law_choice,
    law_options,
    max_impulses_option,
    one_line,
    quiet_option,
    run_budget,
    split_option,
)
from verify.errors import InvalidInput, InvalidSystem, Undecided


def cradle_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify cradle``."""
    p.add_argument("--eps", required=True, help="COR for all contacts, or one per contact: 0.5 or 0.5,0.9")
    p.add_argument("--v0", default="100", type=NUMBER, help="velocity of ball 1, the others at rest (default 100)")
    p.add_argument("--balls", type=BALLS, default=None, help=f"number of balls N, 2 to {MAX_BALLS} ({BALLS_DEFAULT})")
    p.add_argument("--masses", help="masses m1,m2,...,mN (default all 1; their number sets N)")
    p.add_argument("--velocity", help="the whole left velocity v1,...,vN (instead of --v0; its length sets N)")
    p.add_argument(
        "--mode",
        default="exact",
        choices=("exact", "paper"),
        help="exact: stop at exit; paper: the paper's 10^4 cap and AEEV stop",
    )
    p.add_argument(
        "--aeev",
        metavar="READING",
        default=None,
        help="with --mode paper: the reading of the AEEV stop, measure/norm/when "
        "(default l2_pair/v/before; the earlier one: max_pair/v0/before; verify table1 lists all)",
    )
    law_options(p)
    max_impulses_option(p, default=None, help="cap on impulses (default 10000)")
    p.add_argument("--trace", action="store_true", help="print every impulse, however many")
    p.add_argument("--json", action="store_true", help="print the result record (JSON)")
    quiet_option(p, "no progress on stderr (this command prints none; every subcommand takes --quiet)")
    backend_options(p)


def solve_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify solve``."""
    from verify.laws.rule import RULES

    p.add_argument("cases", metavar="CASES.json", help='a case file {"cases": [...]}')
    p.add_argument(
        "--rule",
        default="general",
        choices=RULES,
        help="general (eq. 8, default), ideal (5), symmetric (6) or asymmetric (7); also for --law simultaneous",
    )
    law_options(p)
    budget_options(p, "per case")
    quiet_option(p)
    p.add_argument("--json", action="store_true", help='print {"results": [...]}')
    p.add_argument("--trace", action="store_true",
                   help="also print every impulse (every sweep under the sequential law) of each case")  # fmt: skip
    backend_options(p)


def corner_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify corner``."""
    angle = p.add_mutually_exclusive_group(required=True)
    angle.add_argument("--alpha", type=NUMBER, help="half the corner angle, in (0, pi/2): pi/6, 3/10 (radians)")
    angle.add_argument("--slope", type=NUMBER, help="k = tan(alpha) > 0 instead of alpha: 1/2, sqrt(3)/3")
    p.add_argument("--phi", required=True, type=NUMBER, help="direction of the entrance velocity: pi/12, 0, -1/5")
    p.add_argument("--eps1", required=True, type=NUMBER, help="COR of wall S1 (kx - y = 0), in [0, 1]")
    p.add_argument("--eps2", required=True, type=NUMBER, help="COR of wall S2 (kx + y = 0), in [0, 1]")
    p.add_argument("--v0", default="100", type=NUMBER, help="speed of the entrance velocity (default 100)")
    law_options(p)
    max_impulses_option(p, default=10_000, help="cap on impulses (default 10000)")
    p.add_argument("--json", action="store_true", help="print the result record with the zones (JSON)")
    quiet_option(p, "no progress on stderr (this command prints none; every subcommand takes --quiet)")
    backend_options(p)


def cmd_cradle(args: argparse.Namespace) -> int:
    """``verify cradle``: run the cradle, print the run (or its result record)."""
    from verify.models.cradle import cradle_balls, run_cradle
    from verify.models.paper import default_sigma
    from verify.records.results import dumps, result_record
    from verify.records.text import cradle_text

    eps = split_option(args.eps)
    masses, velocity = (split_option(x) if x else None for x in (args.masses, args.velocity))
    try:
        balls = cradle_balls(args.balls, masses, velocity)
    except InvalidSystem as exc:  # a list of another length than the balls: name the option
        raise UsageError(f"{PROG} cradle: --{exc}") from None
    aeev = _aeev_reading(args)
    law = law_choice(args, "cradle")
    if args.law != "rule" and args.mode == "paper":
        raise UsageError(f"{PROG} cradle: --mode paper is the paper's rule; --law {args.law} has no AEEV stop")
    result = run_cradle(
        eps if len(eps) > 1 else eps[0],
        aeev=aeev,
        v0=args.v0,
        balls=balls,
        masses=masses,
        velocity=velocity,
        mode=args.mode,
        law=law,
        max_iterations=args.max_impulses,
        **backend_choice(args),
    )
    if args.json:
        sys.stdout.write(dumps(result_record(result, "cradle")))
    else:
        mode = f"paper (AEEV stop {aeev.name}, c = {default_sigma(aeev)})" if args.mode == "paper" else args.mode
        sys.stdout.write(cradle_text(result, eps=eps, mode=mode, full_trace=args.trace))
    return 0


def _aeev_reading(args: argparse.Namespace) -> Any:
    """The reading of ``--aeev`` (the default reading without it)."""
    from verify.models.paper import PAPER_READING, Reading

    if args.aeev is None:
        return PAPER_READING
    if args.mode != "paper":
        raise UsageError(f"{PROG} cradle: --aeev needs --mode paper")
    try:
        return Reading.parse(args.aeev)
    except ValueError as exc:
        raise UsageError(f"{PROG} cradle: --aeev: {exc}") from None


def cmd_solve(args: argparse.Namespace) -> int:
    """``verify solve``: run every case of a case file, in order, and print one result per case."""
    from verify.laws.rule import solve
    from verify.laws.sequential import law_for_case
    from verify.records.results import dumps, load_cases, result_record
    from verify.records.text import solve_text

    law = law_choice(args, "solve")
    cases = load_cases(args.cases, **backend_choice(args))  # every case validated first
    budget = run_budget(args)
    status = StatusLine.for_args(args)
    results = []
    try:
        for k, c in enumerate(cases, 1):
            cap = c.max_iterations if args.max_impulses is None else args.max_impulses
            progress = case_progress(status, f"verify solve: case {k}/{len(cases)} {c.id}")
            try:
                case_law = law_for_case(law, c.law_settings, c.system.r)
                r = solve(c.system, c.velocity_source, rule=args.rule, law=case_law,
                          max_iterations=cap, trace=args.trace, budget=budget, progress=progress)  # fmt: skip
            except (InvalidInput, Undecided) as exc:  # name the case; nothing is printed for the others
                raise type(exc)(f"{PROG} solve: case {c.id!r} (cases[{k - 1}]): {one_line(exc)}") from None
            results.append((c, r))
    finally:
        status.close()
    if args.json:
        sys.stdout.write(dumps({"results": [result_record(r, c.id) for c, r in results]}))
    else:
        sys.stdout.write("".join(solve_text(c.id, r, args.trace) for c, r in results))
    return 0


def cmd_corner(args: argparse.Namespace) -> int:
    """``verify corner``: run the disk in a corner, print the run (or its record with the zones)."""
    from verify.models.corner import run_corner
    from verify.records.results import corner_record, dumps
    from verify.records.text import corner_text

    law = law_choice(args, "corner")
    run = run_corner(
        alpha=args.alpha,
        slope=args.slope,
        phi=args.phi,
        eps1=args.eps1,
        eps2=args.eps2,
        v0=args.v0,
        law=law,
        max_iterations=args.max_impulses,
        **backend_choice(args),
    )
    if args.json:
        sys.stdout.write(dumps(corner_record(run)))
    else:
        given = {"alpha": args.alpha, "slope": args.slope, "phi": args.phi, "v0": args.v0}
        sys.stdout.write(corner_text(run, **given, eps1=args.eps1, eps2=args.eps2))
    return 0


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("cradle", "solve", "corner")
