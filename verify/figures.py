"""Figures, written with matplotlib (imported inside each function; optional dependency).

Every figure is deterministic: fixed size and fonts, no timestamps in the file (metadata
stripped), so regenerating gives the same bytes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

METADATA = {"Software": None}


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 9, "svg.hashsalt": "verify", "path.simplify": False})
    return plt


def _x(a: Any) -> float:
    """A plotting coordinate for an exact endpoint (display only: the map itself is exact)."""
    return float(a.decimal(17))


def cradle_staircase(cmap: Any, path: str | Path) -> Path:
    """Iteration count against eps for a cradle map: the staircase, the thresholds and the
    termination boundary. Left: the whole range. Right (when there is a termination
    boundary): the same steps against the distance to the boundary, on a log scale."""
    plt = _pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from verify.cradle_map import termination_boundaries, threshold_between

    boundaries = termination_boundaries(cmap)
    t34 = threshold_between(cmap, 4, 3)
    fig, axes = plt.subplots(
        1, 2 if boundaries else 1, figsize=(10 if boundaries else 5.5, 4), constrained_layout=True, squeeze=False
    )
    ax = axes[0][0]
    for part in cmap.parts:
        a, b = _x(part.piece.lower), _x(part.piece.upper)
        if part.stop == "exit":
            if part.piece.is_point:
                ax.plot([a], [part.iterations], "o", color="C0", ms=3)
            else:
                ax.hlines(part.iterations, a, b, color="C0", lw=1.6)
        elif part.stop == "non_terminating":
            ax.axvspan(a, b, color="C3", alpha=0.18, lw=0)
        else:
            ax.axvspan(a, b, facecolor="0.6", alpha=0.3, lw=0, hatch="//")
    for x in boundaries:
        ax.axvline(_x(x), color="C3", ls="--", lw=1)
    if t34 is not None:
        ax.axvline(_x(t34), color="C2", ls=":", lw=1)
    ax.set_xlim(_x(cmap.domain.lower), _x(cmap.domain.upper))
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel("coefficient of restitution eps")
    ax.set_ylabel("impulses until exit")
    ax.set_title(f"Newton's cradle, {cmap.balls} balls, eps in [{cmap.domain.lower}, {cmap.domain.upper}]")
    ax.grid(alpha=0.3)
    handles = [
        Line2D([], [], color="C0", lw=1.6, label="exits after n impulses (exact pieces)"),
        Patch(color="C3", alpha=0.18, label="never exits (proved)"),
        Patch(facecolor="0.6", alpha=0.3, hatch="//", label=f"exits after more than {cmap.max_impulses} impulses"),
    ]
    if boundaries:
        handles.append(Line2D([], [], color="C3", ls="--", label=f"termination boundary {boundaries[0]}"))
    if t34 is not None:
        handles.append(Line2D([], [], color="C2", ls=":", label=f"3 -> 4 impulses at {t34}"))
    ax.legend(handles=handles, loc="upper right", fontsize=8)
    if boundaries:
        _distance_panel(axes[0][1], cmap, boundaries[0])
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120, metadata=METADATA)
    plt.close(fig)
    return path


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
            ax.axvspan(max(lo, 1e-12), hi, facecolor="0.6", alpha=0.3, lw=0, hatch="//")
    left = (smallest or 1e-3) / 5
    ax.set_xscale("log")
    ax.set_xlim(left, _x(cmap.domain.upper) - b)
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel(f"eps - ({boundary})   (log scale)")
    ax.set_ylabel("impulses until exit")
    ax.set_title("near the termination boundary")
    ax.grid(alpha=0.3, which="both")
