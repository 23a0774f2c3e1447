"""The sweeps of certified cells of the five-ball map, recorded once and checked instead of found again.

``cradle_map(balls=5, max_impulses=20, leaving=True)`` proves that every eps above eps* exits by sweeping the
interval with cells of eps (``verify.maps.torus.exit_cells``): about 15,000 cells, three minutes of search. The
slow tests of ``tests/maps/test_torus.py`` prove the same fact without that search: they run the map with each
sweep replaced by its recorded cells (:func:`replayed`: a sweep of another interval or pattern is an error that
says how to record them again), and ``tests/cells_check.py`` proves every recorded cell on its own. The sweep
itself is tested where it runs, on intervals of the same map (the other tests of that file).

Record the sweeps again after a change to the map or the cells (a few minutes)::

    python3 -m tests.sweeps
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from fractions import Fraction
from pathlib import Path
from typing import Any

from verify.maps import torus
from verify.numbers.format import format_exact

#: the recorded sweeps of the five-ball map
RECORDED = Path(__file__).resolve().parent / "data" / "five-balls-sweeps.json"
#: the map whose sweeps are recorded
MAP = {"balls": 5, "max_impulses": 20, "leaving": True}
COMMAND = "python3 -m tests.sweeps"


def _key(period: Any, lower: Fraction, upper: Fraction) -> str:
    return f"{period.pattern.start} {period.pattern} [{format_exact(lower)}, {format_exact(upper)}]"


def _runs(cells: list[tuple[Fraction, Fraction]], lower: Fraction, upper: Fraction) -> list[list[Any]]:
    """Adjacent cells as runs: a run is its first cut, then each cell's width as an exponent j (the width
    (upper - lower)/8 * 2^j, the widths the sweep tries) or, for a cell the sweep cut short, its end."""
    unit, runs = (upper - lower) / 8, []
    for a, b in cells:
        if not runs or runs[-1][1] != a:
            runs.append([[format_exact(a)], a])
        j = (b - a) / unit
        exponent = j.numerator.bit_length() - 1 if j.denominator == 1 else 1 - j.denominator.bit_length()
        exact = j == Fraction(2) ** exponent
        runs[-1][0].append(exponent if exact else format_exact(b))
        runs[-1][1] = b
    return [run for run, _ in runs]


def cells_of(sweep: dict[str, Any]) -> list[tuple[Fraction, Fraction]]:
    """The cells of a recorded sweep, in order."""
    unit = (Fraction(sweep["upper"]) - Fraction(sweep["lower"])) / 8
    out = []
    for run in sweep["cells"]:
        a = Fraction(run[0])
        for token in run[1:]:
            b = a + unit * Fraction(2) ** token if isinstance(token, int) else Fraction(token)
            out.append((a, b))
            a = b
    return out


def load(path: Path = RECORDED) -> dict[str, dict[str, Any]]:
    """The recorded sweeps by key (pattern and interval)."""
    return {s["key"]: s for s in json.loads(path.read_text(encoding="utf-8"))["sweeps"]}


@contextmanager
def replayed(path: Path = RECORDED) -> Iterator[list[tuple[str, Any, list[Fraction], Fraction, Fraction]]]:
    """Within the block, ``exit_cells`` gives the recorded cells of the sweeps it is asked for (the block gets what
    each was asked, in order: the key, the period, the velocity and the interval); a sweep that was not recorded
    raises AssertionError."""
    sweeps, asked = load(path), []
    original = torus.exit_cells

    def recorded(period: Any, velocity: Any, lower: Fraction, upper: Fraction, **_: Any) -> torus.Cells:
        key = _key(period, lower, upper)
        assert key in sweeps, f"the sweep {key} was not recorded: record the sweeps again ({COMMAND})"
        s = sweeps[key]
        assert s["velocity"] == [format_exact(Fraction(x)) for x in velocity], f"{key}: another velocity"
        asked.append((key, period, [Fraction(x) for x in velocity], lower, upper))
        undecided = [(Fraction(a), Fraction(b)) for a, b in s["undecided"]]
        return torus.Cells(lower, upper, cells_of(s), undecided, s["deepest"])

    torus.exit_cells = recorded  # type: ignore[assignment]
    try:
        yield asked
    finally:
        torus.exit_cells = original  # type: ignore[assignment]


def record(path: Path = RECORDED) -> None:
    """Run the map, recording every sweep of cells it makes, and write them to ``path``."""
    from verify.maps.cradle import cradle_map

    original, sweeps = torus.exit_cells, []

    def recording(period: Any, velocity: Any, lower: Fraction, upper: Fraction, **kw: Any) -> torus.Cells:
        found = original(period, velocity, lower, upper, **kw)
        sweeps.append({"key": _key(period, lower, upper), "lower": format_exact(lower), "upper": format_exact(upper),
                       "velocity": [format_exact(Fraction(x)) for x in velocity], "deepest": found.deepest,
                       "undecided": [[format_exact(a), format_exact(b)] for a, b in found.undecided],
                       "cells": _runs(found.cells, lower, upper)})  # fmt: skip
        assert cells_of(sweeps[-1]) == found.cells  # the record gives the cells back
        return found

    torus.exit_cells = recording  # type: ignore[assignment]
    try:
        cradle_map(**MAP)  # type: ignore[arg-type]
    finally:
        torus.exit_cells = original  # type: ignore[assignment]
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = [json.dumps({k: v for k, v in sweep.items() if k != "cells"})[:-1] + ', "cells": [' for sweep in sweeps]
    body = ",\n".join(head + "\n" + ",\n".join(json.dumps(run) for run in sweep["cells"]) + "]}"
                       for head, sweep in zip(lines, sweeps))  # fmt: skip
    text = f'{{"map": {json.dumps(MAP)}, "command": "{COMMAND}", "sweeps": [\n{body}]}}\n'
    json.loads(text)  # one run a line, and valid JSON
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path}: {len(sweeps)} sweeps, {sum(len(cells_of(s)) for s in sweeps)} cells", file=sys.stderr)


if __name__ == "__main__":
    record()
