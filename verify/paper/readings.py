"""The family of readings of the paper's AEEV stop, searched exhaustively against Table 1.

A reading (:class:`verify.models.paper.Reading`) fixes what "the differences of the
velocities" measure, which norm sigma is relative to, and when the test is made; the stop
fires when ``measure < sigma`` (strictly), ``sigma = c * norm``. For every reading,
:func:`search_readings` computes from the exact runs of every row of Table 1

- the window of ``c`` that reproduces EVERY printed iteration count: with ``r_w`` the
  ratio measure / norm at the state after w impulses, a row printed "AEEV / k" needs the
  test to fire at state k (``r_k < c``) and at no earlier tested state (``c <= r_w``), and a
  row printed "k" needs ``c <= r_w`` at every tested state before it exits. So the window
  is ``(lower, upper]``, open below and closed above, with ``lower`` the largest ``r_k`` of
  the AEEV rows and ``upper`` the smallest ``r_w`` of the states that must not fire. Both
  are kept as exact rationals ``lower^2``, ``upper^2`` (no square root is taken);
- whether the printed ``c = 10^-9`` lies in it, and the counts that 10^-9 gives on every
  row (paper-mode runs), with the first row whose count differs.

"Tested states": ``before`` tests states 0 .. k-1 of a row that exits after k impulses, and
0 .. k of an AEEV row (state k must still have an impact); ``after`` tests states 1 .. k.

>>> s = search_readings()
>>> [w.reading.name for w in s.windows if w.stated_reproduces]
['l2_pair/v/before']
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from fractions import Fraction
from importlib import resources
from typing import Any

from verify.models.cradle import run_cradle
from verify.models.paper import PAPER_SIGMA_STATED, Reading, all_readings, ratio_squared
from verify.numbers.format import counted
from verify.numbers.parse import to_number


@dataclass(frozen=True)
class RowRun:
    """One printed row and the exact states of its run (enough of them for every test)."""

    eps: str
    stop: str  # "exit" or "aeev", as printed
    count: int
    states: list[list[Fraction]]
    exit_state: int | None  # the state at which the exact run exits, if within the states


@dataclass(frozen=True)
class Window:
    """A reading's window of c (``lower < c <= upper``, as squares) and what 10^-9 gives."""

    reading: Reading
    lower_sq: Fraction  # c must be > sqrt(lower_sq)
    upper_sq: Fraction | None  # c must be <= sqrt(upper_sq); None: no upper bound
    impossible: str | None  # why no c can work, if a row cannot be reproduced at all
    stated_counts: dict[str, str]  # eps -> the count 10^-9 gives (as printed: "17", "AEEV / 30")
    first_difference: tuple[str, str, str] | None  # (eps, printed, obtained) with 10^-9

    @property
    def consistent(self) -> bool:
        return self.impossible is None and (self.upper_sq is None or self.lower_sq < self.upper_sq)

    def contains(self, c: Fraction) -> bool:
        """Whether ``c > 0`` reproduces every printed count (decided exactly, on squares)."""
        return self.contains_squared(c * c)

    def contains_squared(self, c_squared: Fraction) -> bool:
        """Whether the ``c > 0`` with ``c^2 = c_squared`` reproduces every printed count."""
        upper = self.upper_sq
        return self.impossible is None and self.lower_sq < c_squared and (upper is None or c_squared <= upper)

    @property
    def stated_inside(self) -> bool:
        return self.contains(PAPER_SIGMA_STATED)

    @property
    def stated_reproduces(self) -> bool:
        return self.first_difference is None


@dataclass(frozen=True)
class Search:
    """Every reading's window, in the order of :func:`verify.models.paper.all_readings`."""

    windows: list[Window]
    sensitive: list[str]  #: the rows whose count depends on the reading (:func:`sensitive_rows`)

    def by_name(self, name: str) -> Window:
        return next(w for w in self.windows if w.reading.name == name)

    @property
    def reproducing(self) -> list[Window]:
        """The readings under which the printed 10^-9 reproduces every printed count."""
        return [w for w in self.windows if w.stated_reproduces]


def load_table1() -> dict[str, Any]:
    """The printed Table 1 (strings as printed) with its source."""
    text = resources.files("verify").joinpath("data/paper/table1.json").read_text(encoding="utf-8")
    table: dict[str, Any] = json.loads(text)
    return table


def parse_printed_iterations(text: str) -> tuple[str, int]:
    """``"3"`` -> ``("exit", 3)``; ``"AEEV / 17"`` -> ``("aeev", 17)``.

    >>> parse_printed_iterations("AEEV / 30")
    ('aeev', 30)
    """
    if "/" in text:
        label, _, count = text.partition("/")
        return label.strip().lower(), int(count)
    return "exit", int(text)


def label(stop: str, count: int) -> str:
    """A count as Table 1 prints it."""
    return f"AEEV / {count}" if stop == "aeev" else str(count)


def row_runs(data: dict[str, Any]) -> list[RowRun]:
    """The exact states of every printed row, up to one past its printed count."""
    out = []
    for eps, *_, iters in data["rows"]:
        stop, count = parse_printed_iterations(iters)
        run = run_cradle(eps, v0=data["v0"], mode="exact", max_iterations=count + 1, certify=False)
        K = run.backend
        states = [[K.to_number(x) for x in run.velocity_in]] + [[K.to_number(x) for x in s.velocity] for s in run.steps]
        exit_state = run.iterations if run.stop == "exit" else None
        out.append(RowRun(eps, stop, count, states, exit_state))
    return out


def _tested(row: RowRun, when: str) -> tuple[list[int], int | None, str | None]:
    """(states that must not fire, the state that must fire, why impossible)."""
    k, e = row.count, row.exit_state
    if row.stop == "exit":
        if e != k:
            return [], None, f"the exact run of eps = {row.eps} does not exit after {counted(k, 'impulse')}"
        return (list(range(k)) if when == "before" else list(range(1, k + 1))), None, None
    if e is not None and (e < k or (e == k and when == "before")):
        return [], None, f"the exact run of eps = {row.eps} exits after {counted(e, 'impulse')}, before a test at {k}"
    if when == "after" and k == 0:
        return [], None, f"eps = {row.eps}: no test is made before the first impulse"
    return (list(range(k)) if when == "before" else list(range(1, k))), k, None


def window_of(reading: Reading, rows: list[RowRun], v0: list[Fraction]) -> tuple[Fraction, Fraction | None, str | None]:
    """``(lower^2, upper^2, why impossible)`` for one reading, exactly."""
    lower, upper = Fraction(0), None
    for row in rows:
        quiet, fire, why = _tested(row, reading.when)
        if why:
            return lower, upper, why
        for w in quiet:
            r = ratio_squared(row.states[w], v0, reading)
            if r is not None:
                upper = r if upper is None else min(upper, r)
        if fire is not None:
            r = ratio_squared(row.states[fire], v0, reading)
            if r is None:
                return lower, upper, f"eps = {row.eps}: the norm is 0 where the stop must fire"
            lower = max(lower, r)
    return lower, upper, None


def stated_counts(reading: Reading, data: dict[str, Any], c: Fraction = PAPER_SIGMA_STATED) -> dict[str, str]:
    """The count of every row in paper mode under ``reading`` with constant ``c`` (paper-mode runs)."""
    out = {}
    for eps, *_ in data["rows"]:
        r = run_cradle(eps, v0=data["v0"], mode="paper", aeev=reading, sigma_relative=c, trace=False)
        out[eps] = label(r.stop, r.iterations) if r.stop in ("aeev", "exit") else f"{r.stop} {r.iterations}"
    return out


def search_readings(data: dict[str, Any] | None = None) -> Search:
    """Every reading of the family against Table 1: windows and the counts 10^-9 gives."""
    data = data or load_table1()
    v0 = [to_number(data["v0"]), Fraction(0), Fraction(0)]
    rows = row_runs(data)
    windows = []
    for reading in all_readings():
        lower, upper, why = window_of(reading, rows, v0)
        counts = stated_counts(reading, data)
        first = next(((eps, iters, counts[eps]) for eps, *_, iters in data["rows"] if counts[eps] != iters), None)
        windows.append(Window(reading, lower, upper, why, counts, first))
    return Search(windows, sensitive_rows(windows, data))


def closed_form(q: Fraction) -> str:
    """``sqrt(q)`` exactly: a rational when ``q`` is the square of one, else ``sqrt(q)``.

    >>> closed_form(Fraction(4, 9)), closed_form(Fraction(1, 2))
    ('2/3', 'sqrt(1/2)')
    """
    import math

    a, b = math.isqrt(q.numerator), math.isqrt(q.denominator)
    if a * a == q.numerator and b * b == q.denominator:
        return str(Fraction(a, b))
    return f"sqrt({q})"


def sensitive_rows(windows: list[Window], data: dict[str, Any]) -> list[str]:
    """The rows whose count depends on the reading: printed AEEV, or changed by some reading with 10^-9."""
    return [
        eps for eps, *_, iters in data["rows"] if "AEEV" in iters or any(w.stated_counts[eps] != iters for w in windows)
    ]
