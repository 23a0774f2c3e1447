"""The figure of the engines page: the three-ball cradle against eps, each engine beside the exact laws."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from verify.views.figures import load_pyplot, save_figure, to_float


def engines_cradle(record: dict[str, Any], path: str | Path) -> Path:
    """The three-ball cradle (v0 = 100) against eps: each ball's exit velocity under the paper's
    rule and the simultaneous law (exact, from the engines record; the rule only where it exits)
    and under each engine's default settings (markers). Decimals only for drawing."""
    plt = load_pyplot()
    from verify.engines.run import GRID, grid_rows

    rule, sim, engines = grid_rows(record)
    fig, axes = plt.subplots(1, 3, figsize=(10.0, 4.2), sharey=True)
    markers = ("o", "s", "^", "D", "v", "P", "X")
    eps = [to_float(e) for e in GRID]
    for ball, ax in enumerate(axes):
        ax.plot(eps, [to_float(v[ball]) for v in sim], "-", color="black", lw=1.5, label="simultaneous law (exact)")
        pts = [(e, v) for e, v in zip(eps, rule) if v is not None]
        ax.plot([e for e, _ in pts], [to_float(v[ball]) for _, v in pts], "--", color="tab:red", lw=1.2,
                label="paper's rule (exact, where it exits)")  # fmt: skip
        for k, (name, values) in enumerate(engines.items()):
            pts = [(e, v) for e, v in zip(eps, values) if v is not None]
            ax.plot([e for e, _ in pts], [to_float(v[ball]) for _, v in pts], markers[k % len(markers)], ms=4,
                    fillstyle="none", label=name)  # fmt: skip
        ax.set_title(f"ball {ball + 1}")
        ax.set_xlabel("eps (both contacts)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("exit velocity (v0 = 100)")
    handles, labels = axes[-1].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=4, frameon=False)  # below the panels, off the data
    fig.tight_layout(rect=(0, 0.16, 1, 1))
    return save_figure(fig, path)
