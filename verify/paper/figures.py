"""The figures of the paper's examples: the corner's exits, iterations and multiple impacts, the wedge's
termination boundary, the three disks after the impact (like the paper's Fig. 1)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

from verify.dynamics.policy import JSONObject
from verify.laws.outcome import Result
from verify.numbers.format import counted
from verify.views.figures import load_pyplot, save_figure, to_float

if TYPE_CHECKING:
    from verify.runner.tasks import TaskRunner


def _corner_runs(
    cases: list[dict[str, Any]],
    executor: Executor | None = None,
    workers: int | None = None,
    runner: TaskRunner | None = None,
) -> list[dict[str, Any]]:
    from verify.paper.sweep import sweep

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


EXIT_PAIRS = [("0.999", "0.001"), ("1/2", "1/2"), ("1", "1")]  #: the CORs of the exit figure's curves
EXIT_DIRECTIONS = 181  #: entrance directions of each curve: -90.5 .. 89.5 degrees, off the walls' directions


def exit_vs_entrance_cases() -> list[dict[str, Any]]:
    """The corner cases of :func:`draw_exit_vs_entrance` (alpha = pi/6, v0 = 100, certified intervals)."""
    phis = [f"({2 * j - 181})*pi/360" for j in range(EXIT_DIRECTIONS)]
    return _angle_cases("pi/6", phis, EXIT_PAIRS)


def draw_exit_vs_entrance(cases: list[dict[str, Any]], results: list[dict[str, Any]], path: str | Path) -> Path:
    """Draw the runs of :func:`exit_vs_entrance_cases` (``results``, in order) into ``path``."""
    import math

    plt = load_pyplot()
    pairs, n = EXIT_PAIRS, EXIT_DIRECTIONS
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.4), constrained_layout=True)
    for i, (e1, e2) in enumerate(pairs):
        rows = results[i * n : (i + 1) * n]
        xs, speed, direction = [], [], []
        for j, r in enumerate(rows):
            if r["stop"] != "exit":
                continue
            vx, vy = (float(v) for v in r["exit_velocity"])  # display only
            xs.append(j - 90.5)
            speed.append(math.hypot(vx, vy))
            direction.append(math.degrees(math.atan2(vy, vx)) % 360)  # in [0, 360): the disk leaves backwards
        ax1.plot(xs, speed, lw=1.3, label=f"eps1 = {e1}, eps2 = {e2}")
        ax2.plot(xs, direction, "-", lw=1.3, label=f"eps1 = {e1}, eps2 = {e2}")
    ax1.set_xlabel("entrance direction phi (degrees)")
    ax1.set_ylabel("exit speed (entrance speed 100)")
    ax2.set_xlabel("entrance direction phi (degrees)")
    ax2.set_ylabel("exit direction (degrees, 180 = straight back)")
    for ax in (ax1, ax2):
        ax.axvline(-30, color="0.5", ls=":", lw=1)
        ax.axvline(30, color="0.5", ls=":", lw=1)
        ax.grid(alpha=0.3)
    fig.legend(*ax1.get_legend_handles_labels(), loc="outside lower center", ncol=3, fontsize=8, frameon=False)
    ax1.set_title("disk in a corner, alpha = pi/6: exit speed")
    ax2.set_title("exit direction (dotted: the walls' directions, +-alpha)")
    return save_figure(fig, path)


def iterations_cases(n: int = 30) -> Cases:
    """The corner cases of :func:`draw_iterations`: ``2n`` half angles by ``2n + 1`` directions, for a symmetric
    and an asymmetric pair of CORs. The grid's slopes and directions are rationals (tan alpha and tan phi to 6
    digits), so every run is exact and fast."""
    from mpmath import mp

    def rational_tan(degrees: float) -> str:  # grid construction only; the runs are exact on these rationals
        return str(mp.nstr(mp.tan(mp.radians(degrees)), 6, min_fixed=-10, max_fixed=10))

    alphas = [(i + 0.5) * 90 / (2 * n) for i in range(2 * n)]
    phis = [-89 + 178 * j / (2 * n) for j in range(2 * n + 1)]
    return [
        {
            "id": f"{a}-{p}-{e1}",
            "slope": rational_tan(a),
            "velocity": ["1", rational_tan(p)],
            "eps1": e1,
            "eps2": e2,
            "max_iterations": 500,
        }
        for e1, e2 in ITERATION_PAIRS
        for a in alphas
        for p in phis
    ]


#: the CORs of the two panels of :func:`draw_iterations`
ITERATION_PAIRS = [("1/2", "1/2"), ("0.999", "0.001")]


def draw_iterations(cases: Cases, results: Cases, path: str | Path) -> Path:
    """Impulses until exit over (alpha, phi), for a symmetric and an asymmetric pair of CORs; runs proved never to
    exit are marked (the runs of :func:`iterations_cases`)."""
    import math

    plt = load_pyplot()  # first: without matplotlib (and its numpy), a clear message
    import numpy as np

    m = (math.isqrt(1 + 2 * len(cases)) - 1) // 2  # 2n half angles: 2n (2n + 1) cases per pair
    alphas, phis, pairs = range(m), range(m + 1), ITERATION_PAIRS
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
    return save_figure(fig, path)


def _log_norm() -> Any:
    from matplotlib.colors import LogNorm

    return LogNorm(vmin=0.5, vmax=500)


#: the zoomed panel of :func:`draw_multiple_impacts`: where the paper's example and the repeated multiple impacts lie
ZOOM_EPS1, ZOOM_EPS2 = (Fraction(3, 4), Fraction(1)), (Fraction(0), Fraction(1, 20))


def _corner_case(case_id: str, a: str, b: str) -> dict[str, Any]:
    return {"id": case_id, "alpha": "pi/6", "phi": "pi/12", "eps1": a, "eps2": b, "max_iterations": 2000,
            "backend": "interval"}  # fmt: skip


def multiple_impacts_cases(n: int = 20) -> list[dict[str, Any]]:
    """The corner cases of :func:`draw_multiple_impacts`: a grid of ``n + 1`` CORs on each wall, then a grid of
    ``n + 1`` by ``n // 2 + 1`` over the corner of the square zoomed (:data:`ZOOM_EPS1` x :data:`ZOOM_EPS2`)."""
    cors = [f"{j}/{n}" for j in range(n + 1)]
    (a0, a1), (b0, b1), m = ZOOM_EPS1, ZOOM_EPS2, n // 2
    zoom1 = [str(a0 + (a1 - a0) * j / n) for j in range(n + 1)]
    zoom2 = [str(b0 + (b1 - b0) * k / m) for k in range(m + 1)]
    return [_corner_case(f"{a}-{b}", a, b) for a in cors for b in cors] + [
        _corner_case(f"zoom-{a}-{b}", a, b) for a in zoom1 for b in zoom2
    ]


def draw_multiple_impacts(cases: list[dict[str, Any]], results: list[dict[str, Any]], path: str | Path) -> Path:
    """Draw the runs of :func:`multiple_impacts_cases` (``results``, in order) into ``path``: the whole square of
    CORs, and its corner where the repeated multiple impacts are, zoomed."""
    plt = load_pyplot()
    import numpy as np

    whole = [k for k, c in enumerate(cases) if not c["id"].startswith("zoom-")]
    zoom = [k for k, c in enumerate(cases) if c["id"].startswith("zoom-")]
    most = max(1, *(r["multiple_impacts"] for r in results))  # the colour bar fitted to the data
    fig, axes = plt.subplots(1, 2 if zoom else 1, figsize=(10.5 if zoom else 5.8, 4.6), squeeze=False,
                             constrained_layout=True)  # fmt: skip
    panels = [(whole, (Fraction(0), Fraction(1)), (Fraction(0), Fraction(1)), "the whole square of CORs")]
    if zoom:
        panels.append((zoom, ZOOM_EPS1, ZOOM_EPS2, "zoomed: where the CORs are very different"))
    im = None
    for ax, (indices, (a0, a1), (b0, b1), title) in zip(axes[0], panels):
        columns = len({cases[k]["eps1"] for k in indices})
        rows = len(indices) // columns
        grid, forever = np.zeros((rows, columns)), np.full((rows, columns), np.nan)
        for idx, k in enumerate(indices):
            i, j = divmod(idx, rows)
            grid[j, i] = results[k]["multiple_impacts"]
            if results[k]["stop"] == "non_terminating":
                forever[j, i] = 1.0
        dx, dy = to_float(a1 - a0) / (columns - 1) / 2, to_float(b1 - b0) / (rows - 1) / 2
        extent = (to_float(a0) - dx, to_float(a1) + dx, to_float(b0) - dy, to_float(b1) + dy)
        im = ax.imshow(grid, origin="lower", extent=extent, cmap="magma_r", interpolation="nearest", vmin=0,
                       vmax=most, aspect="auto")  # fmt: skip
        ax.imshow(forever, origin="lower", extent=extent, cmap="Blues", vmin=0, vmax=1.3, interpolation="nearest",
                  alpha=0.6, aspect="auto")  # fmt: skip
        ax.plot([0.999], [0.001], "c*", ms=10, label="the paper's example (0.999, 0.001)")
        ax.set_xlabel("eps1 (wall S1)")
        ax.set_ylabel("eps2 (wall S2)")
        ax.set_title(title, fontsize=9)
    axes[0][0].legend(loc="upper right", fontsize=8)
    fig.suptitle("Multiple impacts in the corner alpha = pi/6, phi = pi/12 (blue: never exits, proved)", fontsize=10)
    fig.colorbar(im, ax=axes[0].tolist(), label="number of multiple impacts", ticks=list(range(most + 1)))
    return save_figure(fig, path)


def wedge_cases(n: int = 30) -> list[dict[str, Any]]:
    """The corner cases of :func:`draw_wedge`: ``(n - 1)^2`` half angles in (0, pi/4) and equal CORs."""
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
    return cases


def draw_wedge(cases: list[dict[str, Any]], results: list[dict[str, Any]], path: str | Path) -> Path:
    """Draw the runs of :func:`wedge_cases` (``results``, in order) around the boundary into ``path``."""
    import math

    import sympy as sp

    from verify.models.wedge import symmetric_boundary

    plt = load_pyplot()
    _, alpha_star = symmetric_boundary()
    eps = sp.Symbol("eps", positive=True)
    curve = sp.lambdify(eps, alpha_star, "math")
    n = math.isqrt(len(cases)) + 1  # the grid's side, from the number of cases
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
    return save_figure(fig, path)


FIG1_EPS = ("0.9", "0.5", "0.1")  #: the eps of the three panels of :func:`cradle_motion`


def cradle_motion_runs(eps_values: tuple[str, ...] = FIG1_EPS) -> list[Result]:
    """The exact runs that :func:`draw_cradle_motion` draws: D1 hits D2 and D3 with v0 = 1, one run per eps."""
    from verify.models.cradle import run_cradle

    return [run_cradle(eps, v0="1") for eps in eps_values]


def cradle_motion(path: str | Path, eps_values: tuple[str, ...] = FIG1_EPS) -> Path:
    """Like the paper's Fig. 1: the three disks after the impact, one panel per eps (the runs of
    :func:`cradle_motion_runs`, drawn by :func:`draw_cradle_motion`)."""
    return draw_cradle_motion(eps_values, cradle_motion_runs(eps_values), path)


def draw_cradle_motion(eps_values: tuple[str, ...], runs: list[Result], path: str | Path) -> Path:
    """Draw the runs of :func:`cradle_motion_runs`: one panel per eps.

    Disk D1 hits D2 and D3 (at rest, touching) with v0 = 1; each panel shows the centres
    x_i(t) = x_i(0) + v_i t of the three unit-radius disks for t in [0, 4] with their exact
    exit velocities (decimals only for drawing), and the disks drawn at t = 0 and t = 4.
    """
    plt = load_pyplot()
    from matplotlib.patches import Circle

    fig, axes = plt.subplots(len(eps_values), 1, figsize=(7.0, 2.0 * len(eps_values)), sharex=True)
    colours = ("tab:blue", "tab:orange", "tab:green")
    t_end = 4.0
    for ax, eps, r in zip(axes, eps_values, runs):
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
    return save_figure(fig, path)


Cases = list[dict[str, Any]]  #: corner case dictionaries (:func:`verify.paper.sweep.sweep`'s input and output)


@dataclass(frozen=True)
class CornerFigure:
    """A figure of the corner: its file, its caption, the corner cases it runs (``cases(**size)``), how it is drawn.

    :meth:`make` runs its cases and draws them; the report computes the runs first and draws them
    (:func:`run_corner_figures`)."""

    file: str
    caption: str
    cases: Callable[..., Cases]
    draw: Callable[[Cases, Cases, str | Path], Path]

    def make(
        self, path: str | Path, *, runner: TaskRunner | None = None, workers: int | None = None, **size: int
    ) -> Path:
        """Run the cases (on ``runner``, else ``workers`` local processes) and draw them into ``path``."""
        cases = self.cases(**size)
        return self.draw(cases, _corner_runs(cases, workers=workers, runner=runner), path)


EXIT_VS_ENTRANCE = CornerFigure("corner-exit-vs-entrance.png", "exit speed and direction against entrance",
                                exit_vs_entrance_cases, draw_exit_vs_entrance)  # fmt: skip
ITERATIONS = CornerFigure("corner-iterations.png", "impulses until exit over the corner's angle and the entrance",
                          iterations_cases, draw_iterations)  # fmt: skip
MULTIPLE_IMPACTS = CornerFigure("corner-multiple-impacts.png", "where repeated multiple impacts occur",
                                multiple_impacts_cases, draw_multiple_impacts)  # fmt: skip
WEDGE = CornerFigure("wedge-boundary.png", "the symmetric termination boundary", wedge_cases, draw_wedge)
#: the figures of the corner's report page, in order, and those of ``verify corner-claims --figures``
CORNER_FIGURES = (EXIT_VS_ENTRANCE, MULTIPLE_IMPACTS, WEDGE)
CLAIMS_FIGURES = (EXIT_VS_ENTRANCE, ITERATIONS, MULTIPLE_IMPACTS, WEDGE)


@dataclass(frozen=True)
class FigureRuns:
    """A corner figure with its cases and their runs: what the page draws, computed before."""

    figure: CornerFigure
    cases: list[JSONObject]
    results: list[JSONObject]


def run_corner_figures(runner: TaskRunner | None = None) -> list[FigureRuns]:
    """The runs of every figure of the corner's page (on ``runner``, a :class:`verify.runner.tasks.TaskRunner`)."""
    out = []
    for figure in CORNER_FIGURES:
        cases = figure.cases()
        out.append(FigureRuns(figure, cases, _corner_runs(cases, runner=runner)))
    return out
