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

Every velocity entry is then tried under each rounding reading of :data:`READINGS` and
each arithmetic of :data:`ARITHMETICS` (the exact run, and the run in the binary floating
point of the paper's PARI/GP code, :data:`PARI_PREC` bits), at the final state of the
paper-mode run and at every state of the run (:func:`explain_entries`). An entry is
inconsistent only when none explains it.

:func:`verify.paper.readings.search_readings` works out which readings of the AEEV
stop reproduce the printed iteration counts and for which thresholds sigma: the paper's
text leaves the test loosely described.

>>> rows = table1().rows
>>> rows[0].eps, rows[0].exact.iterations, rows[0].exact.stop
('1', 2, 'exit')
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

from verify.laws.outcome import Result
from verify.models.cradle import run_cradle, run_cradle_many
from verify.models.paper import PAPER_READING, Reading
from verify.numbers.backends import Backend, get_backend
from verify.numbers.format import counted, format_decimal, ilog10, int_to_str
from verify.numbers.numeric import mpf_to_fraction
from verify.numbers.parse import to_number
from verify.paper.readings import Search, load_table1, parse_printed_iterations, search_readings

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


#: Binary precision (bits of mantissa) of the paper's arithmetic. The paper's PARI/GP code
#: ran at ``realprecision 38``; 38 decimal digits need ceil(38 log2 10) = 127 bits, and
#: 64-bit PARI rounds the mantissa of a t_REAL up to whole 64-bit words: two words, 128
#: bits. The run uses mpmath at that width (correctly rounded to nearest); PARI's own
#: last-bit rounding may differ, which moves values at the 38th digit, far below the
#: 10 digits printed.
PARI_PREC = 128

#: the arithmetics an entry is checked against
ARITHMETICS = {
    "exact": "exact (rationals)",
    "binary128": f"binary floating point, {PARI_PREC}-bit mantissa (PARI/GP realprecision 38 on 64 bits)",
}

SIGNIFICANT = 10  #: "the last rows rounded to the tenth significant digit" (Sect. 4.1)

#: the rounding readings of a printed entry, in the order tried
READINGS = {
    "round": "rounded half to even to the printed digits",
    "round_half_up": "rounded half away from zero to the printed digits",
    "truncate": "truncated toward zero to the printed digits",
    "sig10": f"rounded half to even to {SIGNIFICANT} significant digits (printed without trailing zeros)",
    "sig10_then_printed": f"rounded to {SIGNIFICANT} significant digits, then to the printed digits",
}


def sig_decimals(value: Fraction, digits: int = SIGNIFICANT) -> int:
    """The number of decimals that leaves ``digits`` significant digits in ``value`` (not 0).

    >>> sig_decimals(Fraction(100, 3)), sig_decimals(Fraction(1, 2))
    (8, 10)
    """
    return digits - 1 - ilog10(abs(value.numerator), value.denominator)


def round_half_up(value: Fraction, decimals: int) -> Fraction:
    """``value`` rounded half away from zero to ``decimals`` places."""
    scaled = abs(value) * 10**decimals
    q = (scaled + Fraction(1, 2)).__floor__()
    return Fraction(q if value >= 0 else -q, 10**decimals)


def read_as(reading: str, value: Fraction, decimals: int) -> Fraction:
    """``value`` as it would be printed with ``decimals`` places under ``reading`` (:data:`READINGS`).

    >>> x = Fraction(33333333348855, 10**12)
    >>> [str(read_as(r, x, 7)) for r in READINGS]
    ['333333333/10000000', '333333333/10000000', '333333333/10000000', '666666667/20000000', '166666667/5000000']
    """
    if reading == "round":
        return round_to(value, decimals)
    if reading == "round_half_up":
        return round_half_up(value, decimals)
    if reading == "truncate":
        return round_to(value, decimals, truncate=True)
    if reading not in ("sig10", "sig10_then_printed"):
        raise ValueError(f"unknown reading {reading!r} (choose from {', '.join(READINGS)})")
    ten = value if value == 0 else round_to(value, sig_decimals(value))
    return ten if reading == "sig10" else round_to(ten, decimals)


def reading_range(reading: str, printed: str) -> tuple[Fraction, Fraction] | None:
    """The least interval holding every value that ``reading`` prints as ``printed`` (its
    ends may or may not belong to the set); None when no value is printed so.

    >>> [tuple(map(format_decimal, reading_range(r, "33.3333335"))) for r in ("round", "truncate")]
    [('33.33333345', '33.33333355'), ('33.3333335', '33.3333336')]
    >>> tuple(map(format_decimal, reading_range("sig10", "33.3333335")))
    ('33.333333495', '33.333333505')
    """
    k = decimals_of(printed)
    p = to_number(printed)
    unit = Fraction(1, 10**k)
    if reading in ("round", "round_half_up"):
        return p - unit / 2, p + unit / 2
    if reading == "truncate":
        return (p, p + unit) if p > 0 else (p - unit, p) if p < 0 else (-unit, unit)
    if p == 0:
        return p, p
    d = sig_decimals(p)
    if read_as("sig10", p, d) != p:  # more than 10 significant digits: never the result
        return None
    power_of_ten = abs(p.numerator) == 1 or (p.denominator == 1 and int_to_str(abs(p.numerator)).strip("0") == "1")
    below, above = Fraction(1, 2 * 10 ** (d + 1 if power_of_ten else d)), Fraction(1, 2 * 10**d)
    lo, hi = (p - below, p + above) if p > 0 else (p - above, p + below)
    if reading == "sig10":
        return lo, hi
    if d <= k:  # the second rounding changes nothing
        return lo, hi
    # the 10-digit values y that round (half to even) to p lie within half a unit of p,
    # the ends included only when p's last digit is even; x lies within half a 10th digit of y
    step = Fraction(1, 10**d)
    if (p * 10**k).numerator % 2 == 0:
        return lo - unit / 2, hi + unit / 2
    return lo - unit / 2 + step, hi + unit / 2 - step


@dataclass(frozen=True)
class Explanation:
    """An arithmetic, a rounding reading and a state of the run under which an entry is printed so."""

    arithmetic: str
    reading: str
    state: int | None = None  #: None: the final state of the paper-mode run; else impulses made

    def describe(self) -> str:
        where = "final state" if self.state is None else f"state after {counted(self.state, 'impulse')}"
        return f"{self.arithmetic}, {self.reading}, {where}"


@dataclass
class EntryCheck:
    """One printed entry against the computation.

    ``agrees``: under the exact run, rounded to the printed digits, at the final state.
    ``explained_by``: every (arithmetic, reading, state) under which the entry is printed so
    (:func:`explain_entries`); ``tried`` names every reading and arithmetic tried.
    """

    column: str
    printed: str
    computed: str
    agrees: bool
    reason: str = ""
    explained_by: list[Explanation] = field(default_factory=list)
    tried: list[str] = field(default_factory=list)

    @property
    def explained(self) -> bool:
        return self.agrees or bool(self.explained_by)

    @property
    def only_some(self) -> bool:
        """Explained, but not at the final state under every reading and arithmetic."""
        finals = {(e.arithmetic, e.reading) for e in self.explained_by if e.state is None}
        return self.explained and bool(self.tried) and len(finals) < len(ARITHMETICS) * len(READINGS)


@dataclass
class Row:
    """One row of Table 1: the printed strings, both runs, and the entry checks."""

    eps: str
    printed: list[str]
    exact: Result
    paper: Result
    checks: list[EntryCheck] = field(default_factory=list)
    row_notes: list[str] = field(default_factory=list)
    binary: Result | None = None  #: the paper-mode run in binary floating point (:data:`PARI_PREC`)
    momentum_ranges: dict[str, tuple[Fraction, Fraction] | None] = field(default_factory=dict)

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

    def disagreeing(self) -> list[tuple[str, str]]:
        """(eps, column) of every printed entry that disagrees with the exact run."""
        return [(row.eps, c.column) for row in self.rows for c in row.checks if not c.agrees]


def off_limit(printed: Sequence[str], result: Result) -> Fraction | None:
    """How far printed velocities (strings, read exactly) are from the limit velocity a run that never exits is
    proved to tend to: the largest difference of a component (None when no limit is proved). The limit's
    components are read through the run's backend, whatever rationals it holds.

    >>> from verify.models.cradle import run_cradle
    >>> off_limit(["33.3333335", "33.3333335", "33.33333330"], run_cradle("0"))
    Fraction(1, 6000000)
    """
    limit = result.limit
    if limit is None:
        return None
    K = result.backend
    return max(abs(Fraction(to_number(p)) - _value(K, x)) for p, x in zip(printed, limit.velocity))


def _velocities(result: Result) -> list[Fraction]:
    K = result.backend
    return [K.to_number(x) for x in result.exit_velocity]


def _value(K: Backend, x: object) -> Fraction:
    """The exact value of a backend element: a rational, or an mpf read exactly (never via float)."""
    if K.name == "mp":
        return mpf_to_fraction(x)
    value = K.to_number(x)
    assert isinstance(value, Fraction)
    return value


def _states(result: Result) -> list[list[Fraction]]:
    K = result.backend
    return [[_value(K, x) for x in result.velocity_in]] + [[_value(K, x) for x in s.velocity] for s in result.steps]


def binary_backend() -> Backend:
    """The ``mp`` backend at the paper's binary precision, :data:`PARI_PREC` bits."""
    return get_backend("mp", prec=PARI_PREC)


def sum_fractions(values: Iterable[Fraction]) -> Fraction:
    """The sum of rationals, as a rational (0 for none)."""
    return sum(values, Fraction(0))


def momentum_ranges(printed: list[str]) -> dict[str, tuple[Fraction, Fraction] | None]:
    """Per reading, the range of the sum of any values that the reading prints as ``printed``
    (None when some entry cannot be printed so under the reading)."""
    out: dict[str, tuple[Fraction, Fraction] | None] = {}
    for reading in READINGS:
        ranges = [reading_range(reading, s) for s in printed]
        spans = [r for r in ranges if r is not None]
        out[reading] = None if len(spans) < len(ranges) else (sum_fractions(r[0] for r in spans),
                                                              sum_fractions(r[1] for r in spans))  # fmt: skip
    return out


def explain_entries(printed: list[str], finals: dict[str, list[Fraction]],
                    runs: dict[str, list[list[Fraction]]]) -> list[list[Explanation]]:  # fmt: skip
    """For each printed velocity, the (arithmetic, reading, state) that print it so.

    ``finals[a]`` is the final state of the paper-mode run in arithmetic ``a``; ``runs[a]``
    the states of the run (after 0, 1, ... impulses), tried only when the final state does
    not explain every entry under the reading. A state other than the final one explains
    an entry only when it explains the whole printed row (the row is one state).
    """
    out: list[list[Explanation]] = [[] for _ in printed]
    for arithmetic in ARITHMETICS:
        for reading in READINGS:
            reads = [read_as(reading, x, decimals_of(s)) == to_number(s) for x, s in zip(finals[arithmetic], printed)]
            for i, ok in enumerate(reads):
                if ok:
                    out[i].append(Explanation(arithmetic, reading))
            if all(reads):
                continue
            for w, state in enumerate(runs.get(arithmetic, [])):
                if all(read_as(reading, x, decimals_of(s)) == to_number(s) for x, s in zip(state, printed)):
                    for i, ok in enumerate(reads):
                        if not ok:
                            out[i].append(Explanation(arithmetic, reading, w))
    return out


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


def _row_diagnosis(
    printed: list[str], runs: dict[str, list[list[Fraction]]], momentum: Fraction
) -> tuple[list[str], dict[str, tuple[Fraction, Fraction] | None]]:
    """Row-level reasons for a row whose velocities disagree, and the momentum range per reading.

    The momentum argument (every impulse conserves total momentum, so a printed row whose
    every reading sums away from it is no state of the rule) is made only when it holds
    under every reading of :data:`READINGS`; the binary run's drift from the momentum is
    stated with it.
    """
    notes = []
    ranges = momentum_ranges(printed)
    possible = [r for r, span in ranges.items() if span is not None and span[0] <= momentum <= span[1]]
    spans = "; ".join(
        f"{r}: {'no values' if span is None else f'{format_decimal(span[0])} to {format_decimal(span[1])}'}"
        for r, span in ranges.items()
    )
    if not possible:
        drift = max((abs(sum(v) - momentum) for v in runs.get("binary128", [])), default=Fraction(0))
        notes.append(
            f"the printed velocities cannot be a state of the rule under any reading: every impulse conserves "
            f"total momentum {format_decimal(momentum)} (the binary run's states sum to it "
            f"{'exactly' if drift == 0 else 'within ' + format_decimal(drift, 3)}), "
            f"but any values that read as the printed ones sum to between ({spans})"
        )
    else:
        notes.append(f"the momentum {format_decimal(momentum)} is within reach under {', '.join(possible)} ({spans})")
    for arithmetic, states in runs.items():
        matches = {
            r: [w for w, v in enumerate(states)
                if all(read_as(r, x, decimals_of(s)) == to_number(s) for x, s in zip(v, printed))]
            for r in READINGS
        }  # fmt: skip
        found = {r: ws for r, ws in matches.items() if ws}
        if found:
            where = "; ".join(f"{', '.join(map(str, ws))} impulses ({r})" for r, ws in found.items())
            notes.append(f"{arithmetic}: the printed velocities match the state after {where}")
        else:
            notes.append(f"{arithmetic}: no state of the run (after 0 to {len(states) - 1} impulses) reads as "
                         "the printed velocities under any reading")  # fmt: skip
    return notes, ranges


def table1(
    *, exact_cap: int = DEFAULT_EXACT_CAP, sigma_relative: Fraction | None = None, aeev: Reading = PAPER_READING
) -> Table1:
    """Recompute Table 1: exact and paper-mode results, and every printed entry checked.

    Paper mode uses the AEEV reading ``aeev`` with constant ``sigma_relative`` (default: the
    paper mode of :mod:`verify.models.paper`); ``identification`` searches every reading
    (:func:`verify.paper.readings.search_readings`).
    """
    data = load_table1()
    v0 = to_number(data["v0"])
    rows = []
    for eps, *vel, iters in data["rows"]:
        exact = run_cradle(eps, v0=data["v0"], mode="exact", max_iterations=exact_cap, trace=False)
        paper = run_cradle(eps, v0=data["v0"], mode="paper", sigma_relative=sigma_relative, aeev=aeev)
        binary = run_cradle(eps, v0=data["v0"], mode="paper", sigma_relative=sigma_relative, aeev=aeev,
                            backend=binary_backend(), trace=False)  # fmt: skip
        row = Row(eps, [*vel, iters], exact, paper, binary=binary)
        computed = _velocities(paper)
        finals = {"exact": computed, "binary128": [_value(binary.backend, x) for x in binary.exit_velocity]}
        for i, (printed, value) in enumerate(zip(vel, computed)):
            row.checks.append(check_entry(f"v_D{i + 1}", printed, value))
        need_states = not all(len(e) == len(ARITHMETICS) * len(READINGS)
                              for e in explain_entries(vel, finals, {}))  # fmt: skip
        runs: dict[str, list[list[Fraction]]] = {}
        if need_states:
            for name, K, result in (("exact", "exact", paper), ("binary128", binary_backend(), binary)):
                follow = run_cradle(eps, v0=data["v0"], max_iterations=result.iterations + 4, certify=False,
                                    backend=K)  # fmt: skip
                runs[name] = _states(follow)
        tried = [f"{a} x {', '.join(READINGS)}" for a in ARITHMETICS]
        for c, found in zip(row.checks, explain_entries(vel, finals, runs)):
            c.explained_by = found
            c.tried = tried
        stop, count = parse_printed_iterations(iters)
        shown = f"{'AEEV / ' if paper.stop == 'aeev' else ''}{paper.iterations}"
        agrees = (stop, count) == (paper.stop, paper.iterations)
        why = "" if agrees else f"paper mode stops with {paper.stop} after {paper.iterations}"
        row.checks.append(EntryCheck("iterations", iters, shown, agrees, why))
        if not all(c.agrees for c in row.checks[:-1]):
            row.row_notes, row.momentum_ranges = _row_diagnosis(vel, runs, v0)
        rows.append(row)
    return Table1(data["source"], v0, exact_cap, rows, search_readings(data))


def table1_runs(
    *, exact_cap: int = DEFAULT_EXACT_CAP, sigma_relative: Fraction | None = None, aeev: Reading = PAPER_READING
) -> list[tuple[Result, Result]]:
    """Table 1's runs alone, without the audit of :func:`table1`: per row, the exact run (exit,
    or a proof that it never exits, within ``exact_cap`` impulses) and the paper-mode run, each
    over one cradle whose geometry every row shares (:func:`verify.models.cradle.run_cradle_many`).
    What ``verify bench`` times against the paper's loop in PARI/GP.

    >>> [(e.stop, p.stop, p.iterations) for e, p in table1_runs()][-1]
    ('non_terminating', 'aeev', 32)
    """
    data = load_table1()
    eps = [row[0] for row in data["rows"]]
    exact = run_cradle_many(eps, v0=data["v0"], mode="exact", max_iterations=exact_cap, trace=False)
    paper = run_cradle_many(eps, v0=data["v0"], mode="paper", sigma_relative=sigma_relative, aeev=aeev, trace=False)
    return list(zip(exact, paper))


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
