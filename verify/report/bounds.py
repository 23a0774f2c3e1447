"""The catalogue of the bounds inside the algorithms (``verify bounds``): each one's constant, read where it lives,
what it bounds and what a run does when it is reached; the table of their values and of how much of each the
commands used (the uses are recorded by :mod:`verify.bounds`, below every layer).

>>> print(table().splitlines()[0])
bound                   value  constant                                         bounds
"""

from __future__ import annotations

import json
from dataclasses import dataclass


@dataclass(frozen=True)
class Bound:
    """A bound of an algorithm: the constant that holds it (``module:NAME``), what it bounds, and
    what a run does when it is reached."""

    constant: str
    bounds: str
    reached: str

    @property
    def value(self) -> int:
        """The constant's value, read where it lives."""
        import importlib

        module, name = self.constant.split(":")
        return int(getattr(importlib.import_module(module), name))


#: every bound, by the name under which its use is recorded. "Found" uses are those of a search that found
#: its certificate: the amount a bound must allow for the tests and the ci census to pass.
BOUNDS: dict[str, Bound] = {
    "pivots": Bound(
        "verify.proofs.cones.period:MAX_PIVOTS",
        "pivots of exact linear programming in one cone search that found its cone",
        "the search gives up (no certificate; the run goes on)",
    ),
    "pivots_failed": Bound(
        "verify.proofs.cones.period:MAX_PIVOTS",
        "pivots of a cone search that found nothing within its budget or gave up on another bound",
        "the search gives up (no certificate; the run goes on)",
    ),
    "crossings": Bound(
        "verify.proofs.cones.period:MAX_CROSSINGS",
        "pairs of edges of a carried cone on either side of one hyperplane x_f = 0",
        "the cone is too wide to carry: the search gives up",
    ),
    "carried": Bound(
        "verify.proofs.cones.period:MAX_CARRIED",
        "vectors carried through one impulse of a period (boxes: but the last)",
        "the search gives up",
    ),
    "generators": Bound(
        "verify.proofs.cones.period:MAX_GENERATORS",
        "generators a cone gained beyond its seeds while it was closed",
        "the search gives up",
    ),
    "rounds": Bound(
        "verify.proofs.cones.period:MAX_ROUNDS",
        "rounds of closing a cone around the limit direction",
        "the search gives up",
    ),
    "hull_rays": Bound(
        "verify.proofs.cones.hull:MAX_HULL_RAYS",
        "extreme rays of a cone around a run's own points, pushed out by a slack (runs that switch between impact "
        "sets in no period)",
        "the cone is not grown: the pushed cone of the run's points alone is closed, or that slack given up",
    ),
    "hull_rounds": Bound(
        "verify.proofs.cones.hull:HULL_ROUNDS",
        "rounds of growing a pushed cone by the points its period carries outside it",
        "the pushed cone of the run's points alone is closed instead",
    ),
    "beta_vectors": Bound(
        "verify.proofs.cones.period:MAX_BETA_VECTORS",
        "vectors whose beta is bounded at a multiple impact of a period",
        "the search gives up",
    ),
    "polar_vectors": Bound(
        "verify.proofs.cones.polar:MAX_VECTORS",
        "vectors whose polar values are taken at once",
        "the search gives up",
    ),
    "period": Bound(
        "verify.proofs.termination:MAX_PERIOD",
        "impulses in the period of a cone certificate",
        "longer periods are not looked for",
    ),
    "parametric_impulses": Bound(
        "verify.proofs.termination:PARAMETRIC_IMPULSES",
        "impulses after which a run on a parameter backend looks for a cone",
        "no cone is looked for after it",
    ),
    "cone_bits": Bound(
        "verify.proofs.cones.period:MAX_BITS",
        "bits of the exact rates a cone is searched from",
        "the cone is searched around a box of 64-bit rationals that holds the rates",
    ),
    "field_bits": Bound(
        "verify.proofs.termination:MAX_BITS",
        "bits of exact rates in a field of algebraic numbers a cone is looked for from",
        "no cone is looked for from them",
    ),
    "turning_halvings": Bound(
        "verify.maps:DEFAULT_HALVINGS",
        "halvings of a piece below a boundary on which no turning cone closes (``--halvings``)",
        "the search for turning cones ends there, and what lies above is left unexplored",
    ),
    "cell_tail": Bound(
        "verify.maps.torus:TAIL",
        "impulses a branch of a cell of eps takes after it leaves the period, before it exits",
        "the cell is halved (below 1e-14, left undecided)",
    ),
    "cell_entries": Bound(
        "verify.maps.torus:ENTRIES",
        "times a branch of a cell of eps comes back to the period",
        "the cell is halved (below 1e-14, left undecided)",
    ),
    "cell_branches": Bound(
        "verify.maps.torus:NODES",
        "impulses followed over all branches of one cell of eps",
        "the cell is halved (below 1e-14, left undecided)",
    ),
    "cell_periods": Bound(
        "verify.maps.torus:MAX_PERIODS",
        "periods a branch of a cell of eps follows in one stay in the period",
        "the cell is halved (below 1e-14, left undecided)",
    ),
    "cell_undecided": Bound(
        "verify.maps.torus:MAX_UNDECIDED",
        "cells narrower than 1e-14 left undecided by one sweep of an interval",
        "the sweep gives up: the interval stays unexplored",
    ),
    "run_bits": Bound(
        "verify.properties.verdicts:CENSUS_BITS",
        "bits of the exact numbers of a run under a size budget (the verdicts' and the census': this one)",
        "the run is decided again on certified intervals",
    ),
    "run_digits": Bound(
        "verify.properties.verdicts:CENSUS_DIGITS",
        "digits of the certified intervals that decide a run past its size budget (the census': this one)",
        "the run ends with stop budget (a sign its intervals cannot decide)",
    ),
}


def summary(lines: list[str]) -> dict[str, tuple[int | None, int]]:
    """``{name: (largest use, times reached)}`` from the lines of ``VERIFY_BOUNDS`` files, for every bound
    of :data:`BOUNDS` (None: never used). A line that is not a record of this module raises ValueError.

    >>> summary(['{"bound": "pivots", "peak": 7}', '{"bound": "pivots", "peak": 9}'])["pivots"]
    (9, 0)
    """
    peaks: dict[str, int] = {}
    counts: dict[str, int] = {}
    for n, line in enumerate(lines, 1):
        if not line.strip():
            continue
        try:
            record = json.loads(line)
            name = record["bound"]
            if name not in BOUNDS or not set(record) < {"bound", "peak", "reached"} or len(record) != 2:
                raise ValueError
            if "peak" in record:
                peaks[name] = max(peaks.get(name, 0), int(record["peak"]))
            else:
                counts[name] = counts.get(name, 0) + int(record["reached"])
        except (ValueError, KeyError, TypeError, AttributeError):
            raise ValueError(f"line {n} is not a record of VERIFY_BOUNDS: {line.strip()[:80]!r}") from None
    return {name: (peaks.get(name), counts.get(name, 0)) for name in BOUNDS}


def table(measured: dict[str, tuple[int | None, int]] | None = None) -> str:
    """The bounds as a text table: name, value, constant, what it bounds; with ``measured``
    (:func:`summary`), the largest use and the times reached.

    >>> print(table().splitlines()[0])
    bound                   value  constant                                         bounds
    """
    value = max(len("value"), *(len(str(b.value)) for b in BOUNDS.values()))
    constant = max(len(b.constant) for b in BOUNDS.values())
    head = f"{'bound':<20}  {'value':>{value}}  "
    if measured is not None:
        head += f"{'largest used':>12}  {'reached':>7}  "
    rows = [head + f"{'constant':<{constant}}  bounds"]
    for name, b in BOUNDS.items():
        row = f"{name:<20}  {b.value:>{value}}  "
        if measured is not None:
            peak, count = measured[name]
            row += f"{'-' if peak is None else f'{peak:,}':>12}  {count:>7}  "
        rows.append(row + f"{b.constant:<{constant}}  {b.bounds}")
    return "\n".join(rows)
