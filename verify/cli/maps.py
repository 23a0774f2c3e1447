"""``verify corner-claims``, ``verify sweep``, ``verify cradle-map``: many runs at once."""

from __future__ import annotations

import argparse
import sys
from typing import Any

from verify.cli.common import (
    BALLS,
    BALLS_DEFAULT,
    CASES,
    MAX_APPROACH,
    MAX_BALLS,
    MAX_IMPULSES_MAP,
    NUMBER,
    PROG,
    SEED,
    BoundedInt,
    OutputDir,
    OutputFile,
    Seconds,
    StatusLine,
    UsageError,
    cluster_options,
    max_impulses_option,
    split_option,
    task_runner,
    writing,
)
from verify.errors import require


def batch_options(p: argparse.ArgumentParser, *, cases: int, what: str, batch: str) -> None:
    """``--cases`` and ``--seed``: a deterministic ``batch`` of random cases (``cases`` by default), run as
    tasks of 100 cases where :func:`verify.cli.common.cluster_options` says."""
    p.add_argument("--cases", type=CASES, default=cases, help=f"{what} (default {cases})")
    p.add_argument("--seed", type=SEED, default=0, help=f"seed of the deterministic {batch}, >= 0 (default 0)")
    cluster_options(p, "local processes (default: every core); 100 cases a task")
    p.add_argument("--quiet", action="store_true", help="no progress bar on stderr")


def bar_wanted(args: argparse.Namespace) -> bool:
    """A progress bar on stderr: on a terminal, without ``--quiet``."""
    return StatusLine.for_args(args).enabled


def corner_claims_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify corner-claims``."""
    batch_options(p, cases=2000, what="cases per sample", batch="samples")
    p.add_argument("--figures", metavar="DIR", type=OutputDir(), help="also draw the corner's figures (PNG) into DIR")
    p.add_argument("--json", action="store_true", help="print JSON")


def sweep_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify sweep``."""
    batch_options(p, cases=10_000, what="number of cases", batch="batch")
    max_impulses_option(p, default=100, help="cap on impulses per case (default 100)")
    p.add_argument("--json", action="store_true", help="print the results as JSON")


#: the most parts a map may be asked to decide (--max-parts)
MAX_PARTS = 10**7
#: the exit code of a map stopped by Ctrl-C (the map decided so far is printed first)
INTERRUPTED = 130


def map_budget_options(p: argparse.ArgumentParser) -> None:
    """The budgets of ``verify map`` and ``verify cradle-map`` (their progress line goes with them)."""
    p.add_argument("--time-limit", type=Seconds(), default=None, metavar="SECONDS",
                   help="stop after this wall-clock time and print the map decided so far (default: none)")  # fmt: skip
    p.add_argument("--max-parts", type=BoundedInt(0, MAX_PARTS), default=None, metavar="N",
                   help="stop after deciding N parts (all lines together) and print the map so far")  # fmt: skip
    from verify.maps import DEFAULT_WIDEN, MAX_WIDEN

    p.add_argument("--widen", type=BoundedInt(0, MAX_WIDEN), default=DEFAULT_WIDEN, metavar="N",
                   help="try up to N rational points of each unexplored interval: where the run at a point is "
                        "proved never to exit by a cone, the cone is checked for the widest interval around "
                        f"the point (default {DEFAULT_WIDEN}; 0: none)")  # fmt: skip
    from verify.maps import DEFAULT_HALVINGS, MAX_HALVINGS

    p.add_argument("--halvings", type=BoundedInt(0, MAX_HALVINGS), default=DEFAULT_HALVINGS, metavar="N",
                   help="below a boundary where only cones that the period turns into themselves can hold, halve "
                        f"a piece on which none closes at most N times (default {DEFAULT_HALVINGS}): more takes "
                        "them nearer the boundary, and longer")  # fmt: skip
    p.add_argument("--leaving", action=argparse.BooleanOptionalAction, default=None,
                   help="where the runs repeat a period whose eigenvalues all have modulus eps (above a boundary of "
                        "never-exits), prove that every eps exits: the rates leave the period, and exit where they "
                        "leave it (exact cells of eps and a slope), or, for a period of two turning pairs (five "
                        "unit balls), the rule run on certified cells of eps. Default: cradle-map tries it on the "
                        "parts it leaves undecided without it (seconds for four balls); map does not")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress line on stderr")


def map_watch(args: argparse.Namespace, label: str) -> tuple[Any, StatusLine]:
    """The :class:`~verify.maps.line.Watch` of the budget options, with a status line on a terminal."""
    from verify.maps.watch import Watch

    status = StatusLine.for_args(args)
    progress = (lambda line: status.show(f"{label} {line}")) if status.enabled else None
    watch = Watch(seconds=args.time_limit, max_parts=args.max_parts, progress=progress, halvings=args.halvings)
    return watch, status


def cradle_map_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify cradle-map``."""
    p.add_argument("--balls", type=BALLS, default=None, help=f"number of balls N, 2 to {MAX_BALLS} ({BALLS_DEFAULT})")
    p.add_argument("--masses", help="masses m1,...,mN (default all 1)")
    p.add_argument("--velocity", help="the left velocity v1,...,vN (default v0 on ball 1)")
    p.add_argument("--v0", default="1", type=NUMBER, help="velocity of ball 1 (default 1)")
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
    map_budget_options(p)


def cmd_corner_claims(args: argparse.Namespace) -> int:
    """``verify corner-claims``: the paper's claims about the corner checked; exit code 1 if one is refuted."""
    from verify.paper.corner_claims import corner_findings
    from verify.paper.text import corner_claims_json, corner_claims_text
    from verify.records.results import dumps

    if args.figures:
        require("matplotlib", "--figures")  # before the claims are computed
    options = {"command": "corner-claims", "cases": args.cases, "seed": args.seed}
    with task_runner(args, options) as runner:
        data = corner_findings(args.cases, seed=args.seed, runner=runner, progress=bar_wanted(args))
        claims = data.claims
        sys.stdout.write(dumps(corner_claims_json(data)) if args.json else corner_claims_text(data))
        if args.figures:
            draw_corner_figures(args.figures, runner)
    return 1 if any(c.verdict == "refuted" for c in claims) else 0


def draw_corner_figures(folder: str, runner: Any) -> None:
    """``verify corner-claims --figures DIR``: the corner's four figures, their runs on ``runner``."""
    from pathlib import Path

    from verify.paper.figures import CLAIMS_FIGURES

    out = Path(folder)
    for figure in CLAIMS_FIGURES:
        with writing(folder, "--figures"):
            figure.make(out / figure.file, runner=runner)
        print(f"figure written to {out / figure.file}", file=sys.stderr)


def cmd_sweep(args: argparse.Namespace) -> int:
    """``verify sweep``: random rational corner cases run exactly; the stops and the time."""
    from verify.paper.sweep import random_sweep
    from verify.records.results import dumps

    options = {"command": "sweep", "cases": args.cases, "seed": args.seed, "max_iterations": args.max_impulses}
    with task_runner(args, options) as runner:
        found = random_sweep(
            args.cases, seed=args.seed, max_iterations=args.max_impulses, runner=runner, progress=bar_wanted(args)
        )
    if args.json:
        sys.stdout.write(dumps(dict(found, seconds=round(found["seconds"], 3))))
    else:
        print(f"{found['cases']} random rational corner cases (seed {args.seed}), exact, in {found['seconds']:.1f} s")
        for stop, count in sorted(found["stops"].items()):
            print(f"  {stop}: {count}")
        print(f"  with repeated multiple impacts: {found['repeated_multiple_impacts']}")
    return 0


def cmd_cradle_map(args: argparse.Namespace) -> int:
    """``verify cradle-map``: the cradle for every eps of an interval (and its staircase figure)."""
    from verify.maps.cradle import cradle_map, map_json
    from verify.maps.text import cradle_map_text
    from verify.paper.cradle_map import map_report
    from verify.records.results import dumps

    if args.figure:
        require("matplotlib", "--figure")  # before the map is computed
    interval = split_option(args.interval)
    if len(interval) != 2:
        raise UsageError(f"{PROG} cradle-map: --interval takes two numbers LO,HI, got {args.interval!r}")
    masses, velocity = (split_option(x) if x else None for x in (args.masses, args.velocity))
    watch, status = map_watch(args, "cradle-map:")
    try:
        cmap = cradle_map(args.balls, masses, velocity, v0=args.v0, lower=interval[0], upper=interval[1],
                          max_impulses=args.max_impulses, watch=watch, widen=args.widen,
                          leaving=args.leaving)  # fmt: skip
    finally:
        status.close()
    if args.json:
        sys.stdout.write(dumps(map_json(cmap)))
    else:  # the paper's AEEV rows beside the paper's own cradle
        paper = args.balls in (None, 3) and masses is None and velocity is None and interval == ["0", "1"]
        report = map_report(cmap, approach=args.approach, paper=paper)
        sys.stdout.write(cradle_map_text(cmap, aeev_rows=report.aeev_rows, approach=report.approach, exact_in="--json"))
    if args.figure:
        from verify.maps.figures import cradle_staircase

        with writing(args.figure, "--figure"):
            cradle_staircase(cmap, args.figure)
        print(f"figure written to {args.figure}", file=sys.stderr)
    return INTERRUPTED if watch.interrupted else 0


def map_options(p: argparse.ArgumentParser) -> None:
    """The options of ``verify map``."""
    from verify.maps import DEFAULT_LINES, MAX_LINES

    p.add_argument("case", metavar="CASE.json", help='a case file {"cases": [...]} whose CORs name parameters')
    p.add_argument("--case", dest="case_id", metavar="ID", help="the case to map (needed when the file has several)")
    p.add_argument(
        "--parameter",
        action="append",
        default=[],
        metavar="NAME=LO,HI",
        help="the interval of a parameter (default 0,1 for each); repeat for several",
    )
    p.add_argument("--lines", type=BoundedInt(2, MAX_LINES), default=None,
                   help=f"with two or more parameters: a grid of lines, this many values per parameter (default "
                        f"{DEFAULT_LINES} with three or more parameters, or with --grid)")  # fmt: skip
    p.add_argument("--grid", action="store_true",
                   help="with two parameters: a grid of lines instead of the default exact cells")  # fmt: skip
    p.add_argument("--cells", action="store_true",
                   help="with two parameters: cut the whole box into exact cells, every rational point mapped (the "
                        "default with two parameters; kept for scripts that name it)")  # fmt: skip
    p.add_argument("--cell-cones", action="store_true",
                   help="with --cells, for three or more contacts: try a boundary cone on each cell still "
                        "impacting at the bound, proved on the whole cell (slow: minutes)")  # fmt: skip
    p.add_argument("--max-impulses", type=BoundedInt(0, MAX_IMPULSES_MAP), default=40,
                   help="bound on the exploration (default 40)")  # fmt: skip
    p.add_argument("--figure", type=OutputFile((".png",)), help="also draw the map (PNG) to this path")
    p.add_argument("--json", action="store_true", help="print the map as JSON")
    map_budget_options(p)


def _parameters(args: argparse.Namespace) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for text in args.parameter:
        name, sep, ends = text.partition("=")
        values = split_option(ends) if sep else []
        if not name.strip() or len(values) != 2:
            raise UsageError(f"{PROG} map: --parameter takes NAME=LO,HI, got {text!r}")
        if name.strip() in out:
            raise UsageError(f"{PROG} map: --parameter {name.strip()} is given twice")
        out[name.strip()] = values
    return out


def cmd_map(args: argparse.Namespace) -> int:
    """``verify map``: a case's CORs as parameters, mapped exactly (one interval, or a grid of lines)."""
    from verify.maps import DEFAULT_LINES
    from verify.maps.general import case_map, eps_map_json
    from verify.maps.text import eps_map_text
    from verify.records.results import dumps

    grid = args.grid or args.lines is not None
    if args.cells and grid:
        raise UsageError(f"{PROG} map: --cells and --grid (or --lines) ask for two different maps: give one")
    if args.cell_cones and grid:
        raise UsageError(f"{PROG} map: --cell-cones is for a map of cells, not a grid of lines")
    if args.figure:
        require("matplotlib", "--figure")  # before the map is computed
    watch, status = map_watch(args, "map:")
    try:
        m = case_map(args.case, args.case_id, _parameters(args), lines=args.lines or (DEFAULT_LINES if grid else None),
                     max_impulses=args.max_impulses, watch=watch, widen=args.widen,
                     cells=True if args.cells else False if grid else None, leaving=bool(args.leaving),
                     cell_cones=args.cell_cones)  # fmt: skip
    finally:
        status.close()
    sys.stdout.write(dumps(eps_map_json(m)) if args.json else eps_map_text(m, exact_in="--json"))
    if args.figure:
        from verify.maps.figures import eps_map_figure, plane_figure

        with writing(args.figure, "--figure"):
            (plane_figure if m.plane is not None else eps_map_figure)(m, args.figure)
        print(f"figure written to {args.figure}", file=sys.stderr)
    return INTERRUPTED if watch.interrupted else 0


#: this group's subcommands, in the order of ``verify --help`` (each N has ``N_options`` and ``cmd_N``)
COMMANDS = ("corner-claims", "sweep", "cradle-map", "map")
