"""Table 1 of the paper, recomputed exactly and checked entry by entry.

The printed table lives in ``verify/data/paper/table1.json`` (the strings as printed,
with their source). For every row :func:`table1` computes

- the exact result: the rule run over the rationals until the velocity exits, or until a
  cap on the number of impulses (``exact_cap``) without exit;
- the paper-mode result: the paper's own termination, 10^4 impulses at most and the
  almost-equal-exit-velocities (AEEV) stop of :mod:`verify.models.paper`;

and checks every printed entry against the paper-mode result to the digits printed. An
entry that disagrees gets a reason computed here: whether truncation instead of rounding
explains it, by how many units of the last printed digit it is off, whether another
state of the run matches, and whether the printed row can be a state of the rule at all
(every impulse of the cradle conserves total momentum exactly).

:func:`verify.checks.paper.readings.search_readings` works out which readings of the AEEV
stop reproduce the printed iteration counts and for which thresholds sigma: the paper's
text leaves the test loosely described.

>>> rows = table1().rows
>>> rows[0].eps, rows[0].exact.iterations, rows[0].exact.stop
('1', 2, 'exit')
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from verify.checks.paper.readings import Search, load_table1, parse_printed_iterations, search_readings
from verify.core.format import format_decimal, ilog10, int_to_str
from verify.core.parse import to_number
from verify.core.rule import Result
from verify.models.cradle import run_cradle
from verify.models.paper import PAPER_READING, Reading

DEFAULT_EXACT_CAP = 10_000


def decimals_of(printed: str) -> int:
    """The number of digits after the decimal point in a printed entry."""
    return len(printed.partition(".")[2])


def round_to(value: Fraction, decimals: int, *, truncate: bool = False) -> Fraction:
    """``value`` rounded half to even (or truncated toward zero) to ``decimals`` places."""
    scale = 10**decimals
    scaled = value * scale
    if truncate:
        q = scaled.numerator // scaled.denominator if scaled >= 0 else -((-scaled.numerator) // scaled.denominator)
    else:
        q = round(scaled)
    return Fraction(q, scale)


@dataclass
class EntryCheck:
    """One printed entry against the computation."""

    column: str
    printed: str
    computed: str
    agrees: bool
    reason: str = ""


@dataclass
class Row:
    """One row of Table 1: the printed strings, both runs, and the entry checks."""

    eps: str
    printed: list[str]
    exact: Result
    paper: Result
    checks: list[EntryCheck] = field(default_factory=list)
    row_notes: list[str] = field(default_factory=list)

    @property
    def agrees(self) -> bool:
        return all(c.agrees for c in self.checks)


@dataclass
class Table1:
    """The whole table: source, rows, and the identification of the AEEV test."""

    source: str
    v0: Fraction
    exact_cap: int
    rows: list[Row]
    identification: Search


def _velocities(result: Result) -> list[Fraction]:
    K = result.backend
    return [K.to_number(x) for x in result.exit_velocity]


def _states(result: Result) -> list[list[Fraction]]:
    K = result.backend
    return [[K.to_number(x) for x in result.velocity_in]] + [[K.to_number(x) for x in s.velocity] for s in result.steps]


def check_entry(column: str, printed: str, value: Fraction) -> EntryCheck:
    """Whether ``value`` rounds to the printed string; if not, why not.

    >>> check_entry("v", "0.4975125", Fraction(4975125, 10**7)).agrees
    True
    >>> check_entry("v", "33.3333334", Fraction(100, 3)).reason
    'off by 1 unit of the 7th decimal (the computation rounds to 33.3333333)'
    """
    k = decimals_of(printed)
    p = to_number(printed)
    computed = format_decimal(value, 30)
    if round_to(value, k) == p:
        return EntryCheck(column, printed, computed, True)
    if round_to(value, k, truncate=True) == p:
        return EntryCheck(column, printed, computed, False, "agrees if the printed digits were truncated, not rounded")
    units = (p - round_to(value, k)) * 10**k
    unit_word = "unit" if abs(units) == 1 else "units"
    place = f"{k}th decimal" if k > 3 else {0: "units digit", 1: "1st decimal", 2: "2nd decimal", 3: "3rd decimal"}[k]
    return EntryCheck(
        column,
        printed,
        computed,
        False,
        f"off by {int_to_str(abs(units.numerator))} {unit_word} of the {place} "
        f"(the computation rounds to {_fixed(round_to(value, k), k)})",
    )


def _fixed(q: Fraction, decimals: int) -> str:
    scaled = q * 10**decimals
    n = scaled.numerator // scaled.denominator
    s = int_to_str(abs(n)).rjust(decimals + 1, "0")
    body = s[:-decimals] + "." + s[-decimals:] if decimals else s
    return ("-" if n < 0 else "") + body


def _row_diagnosis(printed: list[str], states: list[list[Fraction]], momentum: Fraction) -> list[str]:
    """Row-level reasons for a row whose velocities disagree."""
    notes = []
    lows, highs = [], []
    for s in printed:
        k = decimals_of(s)
        half = Fraction(1, 2 * 10**k)
        lows.append(to_number(s) - half)
        highs.append(to_number(s) + half)
    if not sum(lows) <= momentum <= sum(highs):
        notes.append(
            f"the printed velocities cannot be a state of the rule: every impulse conserves total momentum "
            f"{format_decimal(momentum)}, but any values that round to the printed ones sum to between "
            f"{format_decimal(sum(lows))} and {format_decimal(sum(highs))}"
        )
    matches = [
        w for w, v in enumerate(states) if all(round_to(x, decimals_of(s)) == to_number(s) for x, s in zip(v, printed))
    ]
    if matches:
        notes.append(f"the printed velocities match the state after {', '.join(map(str, matches))} impulses")
    else:
        notes.append(f"no state of the run (after 0 to {len(states) - 1} impulses) rounds to the printed velocities")
    return notes


def table1(
    *, exact_cap: int = DEFAULT_EXACT_CAP, sigma_relative: Fraction | None = None, aeev: Reading = PAPER_READING
) -> Table1:
    """Recompute Table 1: exact and paper-mode results, and every printed entry checked.

    Paper mode uses the AEEV reading ``aeev`` with constant ``sigma_relative`` (default: the
    paper mode of :mod:`verify.models.paper`); ``identification`` searches every reading
    (:func:`verify.checks.paper.readings.search_readings`).
    """
    data = load_table1()
    v0 = to_number(data["v0"])
    rows = []
    for eps, *vel, iters in data["rows"]:
        exact = run_cradle(eps, v0=data["v0"], mode="exact", max_iterations=exact_cap, trace=False)
        paper = run_cradle(eps, v0=data["v0"], mode="paper", sigma_relative=sigma_relative, aeev=aeev)
        row = Row(eps, [*vel, iters], exact, paper)
        computed = _velocities(paper)
        for i, (printed, value) in enumerate(zip(vel, computed)):
            row.checks.append(check_entry(f"v_D{i + 1}", printed, value))
        stop, count = parse_printed_iterations(iters)
        shown = f"{'AEEV / ' if paper.stop == 'aeev' else ''}{paper.iterations}"
        agrees = (stop, count) == (paper.stop, paper.iterations)
        why = "" if agrees else f"paper mode stops with {paper.stop} after {paper.iterations}"
        row.checks.append(EntryCheck("iterations", iters, shown, agrees, why))
        if not all(c.agrees for c in row.checks[:-1]):
            follow = run_cradle(eps, v0=data["v0"], max_iterations=paper.iterations + 4, certify=False)
            states = _states(follow)
            row.row_notes = _row_diagnosis(vel, states, v0)
        rows.append(row)
    return Table1(data["source"], v0, exact_cap, rows, search_readings(data))


def _stop_label(result: Result) -> str:
    return f"AEEV / {result.iterations}" if result.stop == "aeev" else str(result.iterations)


def below_three_minus_two_sqrt2(q: Fraction) -> bool:
    """Whether ``q < 3 - 2*sqrt(2)``, decided exactly: for q < 3 it is ``(3 - q)^2 > 8``.

    >>> below_three_minus_two_sqrt2(Fraction(1715, 10000)), below_three_minus_two_sqrt2(Fraction(1716, 10000))
    (True, False)
    """
    return q < 3 and (3 - q) ** 2 > 8


def threshold_brackets(table: Table1) -> list[tuple[str, str, bool]]:
    """Neighbouring rows where the exact count goes from 3 to 4, and whether the paper's
    threshold 3 - 2*sqrt(2) lies between their CORs (exactly)."""
    out = []
    for a, b in zip(table.rows, table.rows[1:]):
        if a.exact.iterations == 3 and b.exact.iterations == 4:
            hi, lo = to_number(a.eps), to_number(b.eps)
            out.append((a.eps, b.eps, below_three_minus_two_sqrt2(lo) and not below_three_minus_two_sqrt2(hi)))
    return out


def sqrt_decimal(q: Fraction, digits: int = 4, *, up: bool = False) -> str:
    """sqrt(q) to ``digits`` significant digits, rounded down (or up), exactly.

    >>> sqrt_decimal(Fraction(2), 5), sqrt_decimal(Fraction(2), 5, up=True)
    ('1.4142', '1.4143')
    """
    import math

    if q <= 0:
        return "0"
    k = digits - 1 - ilog10(q.numerator, q.denominator) // 2
    s = q * Fraction(10) ** (2 * k)
    r = math.isqrt(s.numerator // s.denominator)
    if up and Fraction(r * r) != s:
        r += 1
    return format_decimal(Fraction(r) / Fraction(10) ** k, digits + 1)
