"""Figures, written with matplotlib (imported inside each function; optional dependency).

Every figure is deterministic: fixed size and fonts, no timestamps in the file (metadata
stripped), so regenerating gives the same bytes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

METADATA = {"Software": None}


def load_pyplot() -> Any:
    from verify.errors import require

    matplotlib = require("matplotlib", "a figure")

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update({"font.size": 9, "svg.hashsalt": "verify", "path.simplify": False})
    return plt


def to_float(a: Any) -> float:
    """A plotting coordinate for an exact endpoint (display only: the map itself is exact)."""
    from verify.numbers.format import format_decimal

    return float(format_decimal(a, 17))


def save_figure(fig: Any, path: str | Path) -> Path:
    """Write ``fig`` as PNG to ``path`` whole or not at all (drawn in memory, then written as
    :func:`verify.records.files.write_atomic` does), and close it."""
    import io

    from verify.records.files import write_atomic

    plt = load_pyplot()
    path = Path(path)
    buffer = io.BytesIO()
    try:
        fig.savefig(buffer, format="png", dpi=120, metadata=METADATA)
    finally:
        plt.close(fig)
    write_atomic(path, buffer.getvalue())
    return path
