"""Figures, written with matplotlib (imported inside each function; optional dependency).

Every figure is deterministic: fixed size and fonts, no timestamps in the file (metadata
stripped), so regenerating gives the same bytes.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any

from verify.core.format import counted

METADATA = {"Software": None}


def _pyplot() -> Any:
    from verify.errors import require

    matplotlib = require("matplotlib", "a figure")

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 9, "svg.hashsalt": "verify", "path.simplify": False})
    return plt


def _x(a: Any) -> float:
    """A plotting coordinate for an exact endpoint (display only: the map itself is exact)."""
    from verify.core.format import format_decimal

    return float(format_decimal(a, 17))


def _unexplored_kind(part: Any) -> str:
    """``"exits_later"`` when every eps of an unexplored part is proved to exit after the bound, else
    ``"undecided"``."""
    return "exits_later" if part.exits_beyond_bound else "undecided"


#: how each kind of part is drawn (the staircase's legend shows the same styles)
_UNEXPLORED_STYLE: dict[str, dict[str, Any]] = {
    "exits_later": {"facecolor": "0.6", "alpha": 0.3, "hatch": "//"},
    "undecided": {"facecolor": "0.85", "alpha": 0.6, "hatch": "xx"},
}


def _staircase_band(part: Any) -> dict[str, Any]:
    """The band of a staircase part that does not exit: red where it never exits, grey where unexplored."""
    if part.stop == "non_terminating":
        return {"color": "C3", "alpha": 0.18}
    return _UNEXPLORED_STYLE[_unexplored_kind(part)]


def staircase_legend(cmap: Any) -> list[tuple[str, str]]:
    """The legend of :func:`cradle_staircase`: ``(kind, label)`` for each kind of thing drawn, and only those.

    Kinds: ``exit`` (the pieces), ``non_terminating`` (proved never to exit), ``exits_later``
    (unexplored, every eps proved to exit after the bound), ``undecided`` (unexplored, not
    decided: the label gives the map's reason), ``boundary`` and ``threshold_3_4``.

    >>> from verify.maps.cradle import cradle_map
    >>> staircase_legend(cradle_map(upper="1/20", max_impulses=2))
    [('non_terminating', 'never exits (proved)')]
    >>> dict(staircase_legend(cradle_map(balls=4, max_impulses=3)))["undecided"]
    'undecided: still impacting after 3 impulses\\n(no invariant cone found for the whole interval)'
    """
    from verify.maps.cradle import termination_boundaries, threshold_between

    out = []
    if cmap.pieces:
        out.append(("exit", "exits after n impulses (exact pieces)"))
    if cmap.non_terminating:
        out.append(("non_terminating", "never exits (proved)"))
    kinds = [_unexplored_kind(p) for p in cmap.unexplored]
    if "exits_later" in kinds:
        out.append(("exits_later", f"exits after more than {counted(cmap.max_impulses, 'impulse')}"))
    if "undecided" in kinds:
        reasons = []
        for part in cmap.unexplored:
            why = part.reason.split("; ", 1)[-1]  # the map's reason: "still impacting after N impulses; WHY"
            if _unexplored_kind(part) == "undecided" and why != "not decided" and why not in reasons:
                reasons.append(why)
        label = f"undecided: still impacting after {counted(cmap.max_impulses, 'impulse')}"
        out.append(("undecided", label + "".join(f"\n({why})" for why in reasons)))
    boundaries = termination_boundaries(cmap)
    if boundaries:
        out.append(("boundary", f"termination boundary {boundaries[0]}"))
    t34 = threshold_between(cmap, 4, 3)
    if t34 is not None:
        out.append(("threshold_3_4", f"3 -> 4 impulses at {t34}"))
    return out


def cradle_staircase(cmap: Any, path: str | Path) -> Path:
    """Iteration count against eps for a cradle map: the staircase, the thresholds and the
    termination boundary. Left: the whole range. Right (when there is a termination
    boundary): the same steps against the distance to the boundary, on a log scale.
    The legend (:func:`staircase_legend`) names only what is drawn; unexplored parts are
    marked as proved to exit later or as undecided, with the map's reason."""
    return _save(staircase_figure(cmap), path)


def staircase_figure(cmap: Any) -> Any:
    """The matplotlib figure of :func:`cradle_staircase`, not saved (close it with ``plt.close``)."""
    plt = _pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from verify.maps.cradle import termination_boundaries, threshold_between

    boundaries = termination_boundaries(cmap)
    t34 = threshold_between(cmap, 4, 3)
    fig, axes = plt.subplots(
        1, 2 if boundaries else 1, figsize=(10 if boundaries else 5.5, 4), constrained_layout=True, squeeze=False
    )
    ax = axes[0][0]
    for part in cmap.parts:
        a, b = _x(part.piece.lower), _x(part.piece.upper)
        _part_on_axes(ax, part, a, b, lw=1.6, band=_staircase_band)
    for x in boundaries:
        ax.axvline(_x(x), color="C3", ls="--", lw=1)
    if t34 is not None:
        ax.axvline(_x(t34), color="C2", ls=":", lw=1)
    ax.set_xlim(_x(cmap.domain.lower), _x(cmap.domain.upper))
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel("coefficient of restitution eps")
    ax.set_ylabel("impulses until exit")
    masses = "" if all(m == 1 for m in cmap.masses) else f" (masses {', '.join(str(m) for m in cmap.masses)})"
    ax.set_title(f"Newton's cradle, {cmap.balls} balls{masses}, eps in [{cmap.domain.lower}, {cmap.domain.upper}]")
    ax.grid(alpha=0.3)
    style = {
        "exit": lambda label: Line2D([], [], color="C0", lw=1.6, label=label),
        "non_terminating": lambda label: Patch(color="C3", alpha=0.18, label=label),
        "exits_later": lambda label: Patch(**_UNEXPLORED_STYLE["exits_later"], label=label),
        "undecided": lambda label: Patch(**_UNEXPLORED_STYLE["undecided"], label=label),
        "boundary": lambda label: Line2D([], [], color="C3", ls="--", label=label),
        "threshold_3_4": lambda label: Line2D([], [], color="C2", ls=":", label=label),
    }
    handles = [style[kind](label) for kind, label in staircase_legend(cmap)]
    ax.legend(handles=handles, loc="upper right", fontsize=8)
    if boundaries:
        _distance_panel(axes[0][1], cmap, boundaries[0])
    return fig


def _distance_panel(ax: Any, cmap: Any, boundary: Any) -> None:
    """The steps against eps - boundary on a log scale: they grow like (eps - boundary)^(-1/2)."""
    b = _x(boundary)
    smallest = None
    for part in cmap.parts:
        lo, hi = _x(part.piece.lower) - b, _x(part.piece.upper) - b
        if hi <= 0:
            continue
        if part.stop == "exit" and not part.piece.is_point and lo > 0:
            ax.hlines(part.iterations, lo, hi, color="C0", lw=1.6)
            smallest = lo if smallest is None else min(smallest, lo)
        elif part.stop == "max_iterations":
            ax.axvspan(max(lo, 1e-12), hi, lw=0, **_UNEXPLORED_STYLE[_unexplored_kind(part)])
    left = (smallest or 1e-3) / 5
    ax.set_xscale("log")
    ax.set_xlim(left, _x(cmap.domain.upper) - b)
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel(f"eps - ({boundary})   (log scale)")
    ax.set_ylabel("impulses until exit")
    ax.set_title("near the termination boundary")
    ax.grid(alpha=0.3, which="both")


# -- the disk in the corner -------------------------------------------------------------------


def _corner_runs(
    cases: list[dict[str, Any]], executor: Any = None, workers: int | None = None, runner: Any = None
) -> list[dict[str, Any]]:
    from verify.checks.sweep import sweep

    return sweep(cases, executor=executor, workers=workers, progress=False, runner=runner)


def _angle_cases(alpha: str, phis: list[str], pairs: list[tuple[str, str]]) -> list[dict[str, Any]]:
    return [
        {
            "id": f"{e1}-{e2}-{p}",
            "alpha": alpha,
            "phi": p,
            "eps1": e1,
            "eps2": e2,
            "max_iterations": 2000,
            "backend": "interval",
        }
        for e1, e2 in pairs
        for p in phis
    ]


def corner_exit_vs_entrance(
    path: str | Path, *, executor: Any = None, workers: int | None = None, runner: Any = None
) -> Path:
    """Exit velocity against entrance direction (alpha = pi/6, v0 = 100), as in the paper's appendix:
    exit speed and exit direction for three pairs of CORs (certified interval runs)."""
    import math

    plt = _pyplot()
    pairs = [("0.999", "0.001"), ("1/2", "1/2"), ("1", "1")]
    n = 181
    phis = [f"({2 * j - 181})*pi/360" for j in range(n)]  # -90.5 .. 89.5 degrees, off the walls' directions
    results = _corner_runs(_angle_cases("pi/6", phis, pairs), executor, workers, runner)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, (e1, e2) in enumerate(pairs):
        rows = results[i * n : (i + 1) * n]
        xs, speed, direction = [], [], []
        for j, r in enumerate(rows):
            if r["stop"] != "exit":
                continue
            vx, vy = (float(v) for v in r["exit_velocity"])  # display only
            xs.append(j - 90.5)
            speed.append(math.hypot(vx, vy))
            direction.append(math.degrees(math.atan2(vy, vx)))
        ax1.plot(xs, speed, lw=1.3, label=f"eps1 = {e1}, eps2 = {e2}")
        ax2.plot(xs, direction, ".", ms=2.5, label=f"eps1 = {e1}, eps2 = {e2}")
    ax1.set_xlabel("entrance direction phi (degrees)")
    ax1.set_ylabel("exit speed (entrance speed 100)")
    ax2.set_xlabel("entrance direction phi (degrees)")
    ax2.set_ylabel("exit direction (degrees)")
    for ax in (ax1, ax2):
        ax.axvline(-30, color="0.5", ls=":", lw=1)
        ax.axvline(30, color="0.5", ls=":", lw=1)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax1.set_title("disk in a corner, alpha = pi/6: exit speed")
    ax2.set_title("exit direction (dotted: the walls' directions, +-alpha)")
    return _save(fig, path)


def _save(fig: Any, path: str | Path) -> Path:
    """Write ``fig`` as PNG to ``path`` whole or not at all (drawn in memory, then written as
    :func:`verify.records.files.write_atomic` does), and close it."""
    import io

    from verify.records.files import write_atomic

    plt = _pyplot()
    path = Path(path)
    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=120, metadata=METADATA)
    finally:
        plt.close(fig)
    write_atomic(path, buffer.getvalue())
    return path


def corner_iterations_map(
    path: str | Path, *, executor: Any = None, workers: int | None = None, runner: Any = None, n: int = 30
) -> Path:
    """Impulses until exit over (alpha, phi), for a symmetric and an asymmetric pair of CORs;
    runs proved never to exit are marked. The grid's slopes and directions are rationals
    (tan alpha and tan phi to 6 digits), so every run is exact and fast."""
    plt = _pyplot()  # first: without matplotlib (and its numpy), a clear message
    import numpy as np
    from mpmath import mp

    def rational_tan(degrees: float) -> str:  # grid construction only; the runs are exact on these rationals
        return mp.nstr(mp.tan(mp.radians(degrees)), 6, min_fixed=-10, max_fixed=10)

    alphas = [(i + 0.5) * 90 / (2 * n) for i in range(2 * n)]
    phis = [-89 + 178 * j / (2 * n) for j in range(2 * n + 1)]
    pairs = [("1/2", "1/2"), ("0.999", "0.001")]
    cases = [
        {
            "id": f"{a}-{p}-{e1}",
            "slope": rational_tan(a),
            "velocity": ["1", rational_tan(p)],
            "eps1": e1,
            "eps2": e2,
            "max_iterations": 500,
        }
        for e1, e2 in pairs
        for a in alphas
        for p in phis
    ]
    results = _corner_runs(cases, executor, workers, runner)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    size = len(alphas) * len(phis)
    for ax, (e1, e2), part in zip(axes, pairs, (results[:size], results[size:])):
        grid = np.full((len(phis), len(alphas)), np.nan)
        never = np.full_like(grid, np.nan)
        for idx, r in enumerate(part):
            i, j = divmod(idx, len(phis))
            if r["stop"] == "exit":
                grid[j, i] = max(r["iterations"], 0.5)
            elif r["stop"] == "non_terminating":
                never[j, i] = 1.0
        extent = (0, 90, -90, 90)
        im = ax.imshow(
            grid,
            origin="lower",
            extent=extent,
            aspect="auto",
            cmap="viridis",
            norm=_log_norm(),
            interpolation="nearest",
        )
        ax.imshow(
            never, origin="lower", extent=extent, aspect="auto", cmap="Reds", vmin=0, vmax=1.2, interpolation="nearest"
        )
        ax.set_xlabel("half corner angle alpha (degrees)")
        ax.set_ylabel("entrance direction phi (degrees)")
        ax.set_title(f"eps1 = {e1}, eps2 = {e2} (red: never exits, proved)", fontsize=9)
        fig.colorbar(im, ax=ax, label="impulses until exit (log scale)")
    return _save(fig, path)


def _log_norm() -> Any:
    from matplotlib.colors import LogNorm

    return LogNorm(vmin=0.5, vmax=500)


def corner_multiple_impacts_map(
    path: str | Path, *, executor: Any = None, workers: int | None = None, runner: Any = None, n: int = 20
) -> Path:
    """How many multiple impacts, over (eps1, eps2), for alpha = pi/6 and phi = pi/12 (the paper's
    example): repeated multiple impacts need very different CORs (certified interval runs)."""
    plt = _pyplot()
    import numpy as np

    cors = [f"{j}/{n}" for j in range(n + 1)]
    cases = [
        {
            "id": f"{a}-{b}",
            "alpha": "pi/6",
            "phi": "pi/12",
            "eps1": a,
            "eps2": b,
            "max_iterations": 2000,
            "backend": "interval",
        }
        for a in cors
        for b in cors
    ]
    results = _corner_runs(cases, executor, workers, runner)
    grid = np.zeros((n + 1, n + 1))
    forever = np.full((n + 1, n + 1), np.nan)
    for idx, r in enumerate(results):
        i, j = divmod(idx, n + 1)
        grid[j, i] = min(r["multiple_impacts"], 4)
        if r["stop"] == "non_terminating":
            forever[j, i] = 1.0
    fig, ax = plt.subplots(figsize=(5.8, 4.6), constrained_layout=True)
    half = 0.5 / n
    extent = (-half, 1 + half, -half, 1 + half)
    im = ax.imshow(grid, origin="lower", extent=extent, cmap="magma_r", interpolation="nearest", vmin=0, vmax=4)
    ax.imshow(
        forever, origin="lower", extent=extent, cmap="Blues", vmin=0, vmax=1.3, interpolation="nearest", alpha=0.6
    )
    ax.plot([0.999], [0.001], "c*", ms=10, label="the paper's example (0.999, 0.001)")
    ax.set_xlabel("eps1 (wall S1)")
    ax.set_ylabel("eps2 (wall S2)")
    ax.set_title("multiple impacts, alpha = pi/6, phi = pi/12 (blue: never exits, proved)")
    ax.legend(loc="upper right", fontsize=8)
    bar = fig.colorbar(im, ax=ax, label="number of multiple impacts", ticks=[0, 1, 2, 3, 4])
    bar.ax.set_yticklabels(["0", "1", "2", "3", ">= 4"])
    return _save(fig, path)


def wedge_boundary(
    path: str | Path, *, executor: Any = None, workers: int | None = None, runner: Any = None, n: int = 30
) -> Path:
    """The symmetric termination boundary alpha*(eps) = pi/4 - atan(sqrt(eps)) with exact runs
    around it (entrance direction phi = alpha/2, as in the paper's example)."""
    import math

    import sympy as sp

    from verify.models.wedge import symmetric_boundary

    plt = _pyplot()
    _, alpha_star = symmetric_boundary()
    eps = sp.Symbol("eps", positive=True)
    curve = sp.lambdify(eps, alpha_star, "math")
    cases: list[dict[str, Any]] = []
    for i in range(1, n):
        for j in range(1, n):
            a = f"{j}*pi/{4 * n}"  # (0, pi/4)
            e = f"{i}/{n}"
            cases.append(
                {
                    "id": f"{a}-{e}",
                    "alpha": a,
                    "phi": f"{j}*pi/{8 * n}",
                    "eps1": e,
                    "eps2": e,
                    "max_iterations": 3000,
                    "backend": "interval",
                }
            )
    results = _corner_runs(cases, executor, workers, runner)
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    style = {
        "exit": ("o", "C0", "exits"),
        "non_terminating": ("s", "C3", "never exits (proved)"),
        "max_iterations": ("x", "0.4", "undecided within 3000 impulses"),
    }
    shown = set()
    for case, r in zip(cases, results):
        m, color, label = style[r["stop"]]
        i = int(case["eps1"].split("/")[0])
        j = int(case["alpha"].split("*")[0])
        ax.plot(
            i / n,
            math.degrees(j * math.pi / (4 * n)),
            m,
            color=color,
            ms=3,
            label=None if r["stop"] in shown else label,
        )
        shown.add(r["stop"])
    xs = [k / 400 for k in range(1, 400)]
    ax.plot(xs, [math.degrees(curve(x)) for x in xs], "k-", lw=1.5, label=f"alpha* = {alpha_star}")
    ax.set_xlabel("eps (both walls)")
    ax.set_ylabel("half corner angle alpha (degrees)")
    ax.set_title("termination in the wedge, entrance phi = alpha/2")
    ax.legend(fontsize=8, loc="upper right")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def cradle_motion(path: str | Path, eps_values: tuple[str, ...] = ("0.9", "0.5", "0.1")) -> Path:
    """Like the paper's Fig. 1: the three disks after the impact, one panel per eps.

    Disk D1 hits D2 and D3 (at rest, touching) with v0 = 1; each panel shows the centres
    x_i(t) = x_i(0) + v_i t of the three unit-radius disks for t in [0, 4] with their exact
    exit velocities (decimals only for drawing), and the disks drawn at t = 0 and t = 4.
    """
    plt = _pyplot()
    from matplotlib.patches import Circle

    from verify.models.cradle import run_cradle

    fig, axes = plt.subplots(len(eps_values), 1, figsize=(7.0, 2.0 * len(eps_values)), sharex=True)
    colours = ("tab:blue", "tab:orange", "tab:green")
    t_end = 4.0
    for ax, eps in zip(axes, eps_values):
        r = run_cradle(eps, v0="1")
        K = r.backend
        v = [float(K.to_decimal(x, 17)) for x in r.exit_velocity]
        for i, (vi, colour) in enumerate(zip(v, colours)):
            x0 = 2.0 * i
            ax.add_patch(Circle((x0, 0.0), 1.0, fill=False, ec=colour, ls=":", lw=1))
            ax.add_patch(Circle((x0 + vi * t_end, 0.0), 1.0, fill=False, ec=colour, lw=1.5))
            ax.annotate("", xy=(x0 + vi * t_end, 0.0), xytext=(x0, 0.0),
                        arrowprops={"arrowstyle": "->", "color": colour})  # fmt: skip
            ax.text(x0 + vi * t_end, -1.45, f"D{i + 1}: v = {K.to_decimal(r.exit_velocity[i], 4)}",
                    ha="center", fontsize=8, color=colour)  # fmt: skip
        ax.set_title(
            f"eps = {eps}: {counted(r.iterations, 'impulse')}, disks at t = 0 (dotted) and t = {t_end:g} (solid)"
        )
        ax.set_aspect("equal")
        ax.set_ylim(-1.9, 1.3)
        ax.set_yticks([])
    axes[-1].set_xlim(-1.5, 9.5)
    axes[-1].set_xlabel("position along the line of centres (disk radii; v0 = 1 radius per unit time)")
    fig.tight_layout()
    return _save(fig, path)


def engines_cradle(record: dict[str, Any], path: str | Path) -> Path:
    """The three-ball cradle (v0 = 100) against eps: each ball's exit velocity under the paper's
    rule and the simultaneous law (exact, from the engines record; the rule only where it exits)
    and under each engine's default settings (markers). Decimals only for drawing."""
    plt = _pyplot()
    from verify.checks.engines import GRID, grid_rows

    rule, sim, engines = grid_rows(record)
    fig, axes = plt.subplots(1, 3, figsize=(10.0, 3.4), sharey=True)
    markers = ("o", "s", "^", "D", "v", "P", "X")
    eps = [_x(e) for e in GRID]
    for ball, ax in enumerate(axes):
        ax.plot(eps, [_x(v[ball]) for v in sim], "-", color="black", lw=1.5, label="simultaneous law (exact)")
        pts = [(e, v) for e, v in zip(eps, rule) if v is not None]
        ax.plot([e for e, _ in pts], [_x(v[ball]) for _, v in pts], "--", color="tab:red", lw=1.2,
                label="paper's rule (exact, where it exits)")  # fmt: skip
        for k, (name, values) in enumerate(engines.items()):
            pts = [(e, v) for e, v in zip(eps, values) if v is not None]
            ax.plot([e for e, _ in pts], [_x(v[ball]) for _, v in pts], markers[k % len(markers)], ms=4,
                    fillstyle="none", label=name)  # fmt: skip
        ax.set_title(f"ball {ball + 1}")
        ax.set_xlabel("eps (both contacts)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("exit velocity (v0 = 100)")
    axes[-1].legend(fontsize=7, loc="best")
    fig.tight_layout()
    return _save(fig, path)


def eps_map_figure(m: Any, path: str | Path) -> Path:
    """A map of :func:`verify.maps.general.eps_map` drawn (:func:`eps_map_plot`) and written to
    ``path`` (PNG) whole or not at all."""
    return _save(eps_map_plot(m), path)


def eps_map_legend(m: Any) -> list[tuple[str, str]]:
    """The legend of :func:`eps_map_plot`: ``(kind, label)`` for each kind of part drawn, and only those.

    Kinds: ``exit`` (one parameter: the impulses to exit; two or more: the colour bar says them),
    ``non_terminating`` (proved never to exit) and ``unexplored`` (still impacting at the bound).

    >>> from verify.maps.general import eps_map
    >>> from verify.models.cradle import cradle_system
    >>> eps_map_legend(eps_map(cradle_system("1", 3), ["1", "0", "0"], max_impulses=4))
    [('non_terminating', 'never exits (proved)'),
     ('unexplored', 'unexplored: still impacting after 4 impulses'),
     ('exit', 'exit after k impulses')]
    """
    drawn = {p.stop for line in _drawn_lines(m) for p in line.parts}
    labels = {
        "non_terminating": "never exits (proved)",
        "max_iterations": f"unexplored: still impacting after {counted(m.max_impulses, 'impulse')}",
        "exit": "exit after k impulses",
    }
    kinds = {"non_terminating": "non_terminating", "max_iterations": "unexplored", "exit": "exit"}
    return [
        (kinds[stop], label)
        for stop, label in labels.items()
        if stop in drawn and (stop != "exit" or len(m.parameters) == 1)
    ]


def _drawn_lines(m: Any) -> list[Any]:
    """The lines a map's figure draws: all of them, but with three parameters or more only those where
    the third and later take their lowest value."""
    names = list(m.parameters)
    lowest = {n: lo for n, (lo, _) in m.parameters.items() if n not in names[:2]}
    return [line for line in m.lines if all(v == lowest[n] for n, v in line.fixed.items() if n in lowest)]


#: how :func:`eps_map_plot` draws the parts that do not exit: bands for one parameter, coloured lines for two
_MAP_STYLE: dict[str, dict[str, Any]] = {
    "non_terminating": {"color": "C3", "alpha": 0.25},
    "unexplored": {"facecolor": "0.7", "alpha": 0.5, "hatch": "xx"},
}
_GRID_COLOUR = {"non_terminating": "C3", "max_iterations": "0.6", "unexplored": "0.6"}


def eps_map_plot(m: Any) -> Any:
    """The matplotlib figure of a map, not saved (close it with ``plt.close``). One parameter: the
    impulses to exit against it, as the cradle's staircase, with the parts that never exit and the
    unexplored ones as shaded bands; two: each line of the grid in the plane of the first two parameters,
    coloured by its impulses, red where the rule never exits, grey where unexplored (a third parameter and
    more: the lines where they take their lowest value). The legend (:func:`eps_map_legend`) names what is
    drawn; the title gives each contact's COR by the contact's name."""
    plt = _pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    names = list(m.parameters)
    fig, ax = plt.subplots(figsize=(5.5, 4.5), constrained_layout=True)
    top = max([p.iterations for line in m.lines for p in line.parts if p.stop == "exit"], default=1)
    cmap = plt.get_cmap("viridis")
    one = len(names) == 1
    for line in _drawn_lines(m):
        for part in line.parts:
            a, b = _x(part.piece.lower), _x(part.piece.upper)
            if one:
                _part_on_axes(ax, part, a, b, lw=2, band=_map_band)
                continue
            color = cmap(part.iterations / top) if part.stop == "exit" else _GRID_COLOUR[part.stop]
            if line.free == names[0]:
                ax.hlines(_x(line.fixed[names[1]]), a, b, color=color, lw=3)
            elif line.free == names[1]:
                ax.vlines(_x(line.fixed[names[0]]), a, b, color=color, lw=3)
    ax.set_xlabel(names[0])
    ax.set_ylabel("impulses until exit" if one else names[1])
    if one:
        ax.set_xlim(_x(m.lines[0].domain.lower), _x(m.lines[0].domain.upper))
        ax.set_ylim(0, top + 1)
    else:
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0, top))
        fig.colorbar(sm, ax=ax, label="impulses to exit")
    handles = [
        Line2D([], [], color="C0", lw=2, label=label)
        if kind == "exit"
        else Patch(**_MAP_STYLE[kind], label=label)
        if one
        else Line2D([], [], color=_GRID_COLOUR[kind], lw=3, label=label)
        for kind, label in eps_map_legend(m)
    ]
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8)
    cors = ", ".join(f"{name} = {cor}" for name, cor in zip(m.system.names, m.restitution))
    where = f"the exact map on {len(m.lines)} lines" if not one else "the exact map"
    ax.set_title(f"{where}\nCORs: {cors}", fontsize=9)
    return fig


def _map_band(part: Any) -> dict[str, Any]:
    """The band of a one-parameter map's part that does not exit: never exits, or unexplored."""
    return _MAP_STYLE["non_terminating" if part.stop == "non_terminating" else "unexplored"]


def _part_on_axes(ax: Any, part: Any, a: float, b: float, *, lw: float, band: Any) -> None:
    """One part of a map against its parameter (the cradle's staircase, a one-parameter map): a step at
    its impulses when it exits (a dot for a point), else a band over [a, b] in the style ``band(part)``."""
    if part.stop == "exit":
        if part.piece.is_point:
            ax.plot([a], [part.iterations], "o", color="C0", ms=3)
        else:
            ax.hlines(part.iterations, a, b, color="C0", lw=lw)
    else:
        ax.axvspan(a, b, lw=0, **band(part))


#: rational x per open cell where its sides are computed for the drawing
DRAW_STEPS = 48


def _named_sequence(sets: list[tuple[int, ...]], names: list[str]) -> str:
    return "".join("(" + ",".join(names[j] for j in J) + ")" for J in sets)


def plane_legend(m: Any) -> list[tuple[tuple, str]]:
    """``(behaviour, label)`` for each behaviour drawn, the largest area first; a behaviour is (stop,
    impulses, impact sets).

    >>> from verify.maps.general import case_map
    >>> m = case_map("docs/examples/corner-map.json", cells=True, max_impulses=4)
    >>> [label for _, label in plane_legend(m)]
    ['exit after 2: (S1,S2)(S2), area 0.758-0.767', 'exit after 1: (S1,S2), area 0.155-0.169',
     'exit after 2: (S1,S2)(S1), area 0.0733-0.0782']
    """
    plane, names = m.plane, list(m.system.names)
    kinds: dict[tuple, list[Any]] = {}
    for p in plane.parts:
        if p.stop != "not_run":
            kinds.setdefault((p.stop, p.iterations, tuple(p.impact_sets)), []).append(p)
    total = plane.area("exit")[1] + 1  # an upper bound of any area, for the order only
    out = []
    for key, parts in sorted(kinds.items(), key=lambda kv: total - sum(p.cell.area[0] for p in kv[1])):
        low, high = plane.bounds_of(parts)
        stop, n, sets = key
        so_far = f", {_named_sequence(list(sets), names)} so far" if sets else ""
        what = {"exit": f"exit after {n}: {_named_sequence(list(sets), names)}",
                "non_terminating": f"never exits (proved) after {counted(n, 'impulse')}{so_far}"}.get(
            stop, f"unexplored: still impacting after {counted(n, 'impulse')}{so_far}")  # fmt: skip
        out.append((key, f"{what}, area {_x(low):.3g}-{_x(high):.3g}"))
    return out


def _xs(cell: Any) -> list[Fraction]:
    """Rational x inside an open cell, from near its left end to near its right end."""
    from verify.maps.cells import inside

    lo, hi, _, _ = inside(cell.x_lo, cell.x_hi)
    return [lo + (hi - lo) * k / DRAW_STEPS for k in range(DRAW_STEPS + 1)]


def plane_plot(m: Any) -> Any:
    """The matplotlib figure of a map of two parameters as cells (``verify map --cells --figure FILE``), not
    saved: each open cell filled with the colour of its behaviour (stop and impact sequence; the legend names
    each, with its area bounds), the unexplored cells hatched in the colour of their impact sequence so far;
    the curves between cells drawn from their exact description (each side's y computed exactly at rational
    x, rounded for the drawing only), the cells that are points as dots."""
    plt = _pyplot()
    from matplotlib.patches import Patch

    from verify.maps.cells import Roots, bound_at

    plane, (xname, yname) = m.plane, m.plane.names
    cache = Roots()
    legend = plane_legend(m)
    colours = {key: plt.get_cmap("tab10")(k % 10) for k, (key, _) in enumerate(legend)}
    fig, ax = plt.subplots(figsize=(6.2, 5.0), constrained_layout=True)
    for part in plane.parts:
        cell = part.cell
        if part.stop == "not_run":
            continue
        key = (part.stop, part.iterations, tuple(part.impact_sets))
        colour = colours[key]
        if cell.dim == 2:
            xs = _xs(cell)
            low = [_x(bound_at(plane.P, cell.y_lo, x, plane.box, cache)) for x in xs]
            high = [_x(bound_at(plane.P, cell.y_hi, x, plane.box, cache)) for x in xs]
            style = _plane_style(part.stop, colour)
            ax.fill_between([_x(x) for x in xs], low, high, lw=0, **style)
        elif cell.dim == 1 and not cell.on_line:
            xs = _xs(cell)
            ax.plot([_x(x) for x in xs], [_x(bound_at(plane.P, cell.y_lo, x, plane.box, cache)) for x in xs],
                    color="black", lw=0.8)  # fmt: skip
    for part in plane.parts:  # the points last, above the curves
        if part.cell.dim == 0 and part.cell.sample is not None:
            ax.plot([_x(part.cell.sample[0])], [_x(part.cell.sample[1])], "o", color="black", ms=2)
    a, b, c, d = plane.box
    ax.set_xlim(_x(a), _x(b))
    ax.set_ylim(_x(c), _x(d))
    ax.set_xlabel(xname)
    ax.set_ylabel(yname)
    cors = ", ".join(f"{n} = {c}" for n, c in zip(m.system.names, m.restitution))
    ax.set_title(f"{len(plane.parts)} exact cells; CORs {cors}", fontsize=9)
    handles = [Patch(label=label, **_plane_style(key[0], colours[key])) for key, label in legend]
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
    return fig


def _plane_style(stop: str, colour: Any) -> dict[str, Any]:
    """How a cell of this stop is filled: exits in their colour, never-exits dotted in theirs, unexplored cells hatched
    in the colour of their impact sequence so far."""
    if stop == "exit":
        return {"color": colour}
    if stop == "non_terminating":
        return {"hatch": "..", "facecolor": colour, "edgecolor": "black", "alpha": 0.6}
    return {"hatch": "xx", "facecolor": "0.85", "edgecolor": colour}


def plane_figure(m: Any, path: str | Path) -> Path:
    """:func:`plane_plot` written to ``path`` (PNG) whole or not at all."""
    return _save(plane_plot(m), path)
