"""Table 1: reproduction, paper mode, the AEEV identification, backend agreement."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from verify.models.cradle import run_cradle
from verify.models.paper import (
    MAX_PAIR_READING,
    MAX_PAIR_SIGMA_RELATIVE,
    PAPER_READING,
    PAPER_SIGMA_RELATIVE,
    PAPER_SIGMA_STATED,
)
from verify.numbers.backends import IntervalBackend, get_backend
from verify.paper.table1 import check_entry, load_table1, parse_printed_iterations, round_to, table1

DATA = load_table1()
ROWS = DATA["rows"]
TERMINATING = [row for row in ROWS if parse_printed_iterations(row[4])[0] == "exit"]


@pytest.fixture(scope="module")
def table():
    return table1()


def test_the_data_is_the_printed_table():
    assert len(ROWS) == 17
    assert [r[0] for r in ROWS][:3] == ["1", "0.99", "0.9"]
    assert "Table 1" in DATA["source"]


@pytest.mark.parametrize("row", TERMINATING, ids=[r[0] for r in TERMINATING])
def test_every_terminating_row_is_reproduced_exactly(row):
    eps, *printed, iterations = row
    r = run_cradle(eps, v0=DATA["v0"])  # exact backend, stop only at exit
    K = r.backend
    assert r.stop == "exit"
    assert r.iterations == int(iterations)
    for text, x in zip(printed, r.exit_velocity, strict=True):
        digits = len(text.partition(".")[2])
        assert round_to(K.to_number(x), digits) == F(text)


def test_paper_mode_reproduces_every_printed_count(table):
    for row in table.rows:
        stop, count = parse_printed_iterations(row.printed[3])
        assert (row.paper.stop, row.paper.iterations) == (stop, count), row.eps


def test_which_entries_disagree_and_why(table):
    bad = {(row.eps, c.column): c for row in table.rows for c in row.checks if not c.agrees}
    assert set(bad) == {("0.0743", "v_D2"), ("0", "v_D1"), ("0", "v_D2"), ("0", "v_D3")}
    assert "1 unit of the 7th decimal" in bad["0.0743", "v_D2"].reason
    notes = {row.eps: row.row_notes for row in table.rows}
    assert any("conserves total momentum" in n for n in notes["0"])
    assert not any("conserves total momentum" in n for n in notes["0.0743"])


def _labels(**paper):
    out = []
    for eps, *_ in ROWS:
        r = run_cradle(eps, mode="paper", trace=False, **paper)
        out.append(f"AEEV / {r.iterations}" if r.stop == "aeev" else str(r.iterations))
    return out


PRINTED = [row[4] for row in ROWS]


def test_the_default_reading_is_the_one_the_search_finds(table):
    search = table.identification
    assert [w.reading for w in search.reproducing] == [PAPER_READING]
    assert PAPER_SIGMA_RELATIVE == PAPER_SIGMA_STATED  # paper mode uses the printed constant
    for w in search.windows:  # the exact window and the paper-mode runs agree on 10^-9
        assert w.stated_inside == w.stated_reproduces, w.reading.name
        assert w.stated_counts == dict(zip([r[0] for r in ROWS], _labels(aeev=w.reading, sigma_relative=F(1, 10**9))))


def test_the_earlier_reading_stays_selectable():
    assert _labels(aeev=MAX_PAIR_READING) == PRINTED  # with its own constant, 4e-10
    assert _labels(aeev="max_pair/v0/before", sigma_relative=MAX_PAIR_SIGMA_RELATIVE) == PRINTED
    assert _labels(aeev=MAX_PAIR_READING, sigma_relative=PAPER_SIGMA_STATED) != PRINTED


def _independent_measure(v, measure):
    """The square of the measure (or of the sum of squares), written out again here."""
    n = len(v)
    pairs = [(v[i] - v[j]) ** 2 for i in range(n) for j in range(i + 1, n)]
    adjacent = [(v[i] - v[i + 1]) ** 2 for i in range(n - 1)]
    mean = sum(v) / n
    to_mean = [(x - mean) ** 2 for x in v]
    return {"max_pair": max(pairs), "l2_pair": sum(pairs), "max_adjacent": max(adjacent),
            "l2_adjacent": sum(adjacent), "max_mean": max(to_mean), "l2_mean": sum(to_mean),
            "sumsq_pair": sum(pairs) ** 2}[measure]  # fmt: skip


def _independent_count(eps, reading, c):
    """The count of ``reading`` with constant ``c``, walked over the exact states of the run."""
    run = run_cradle(eps, max_iterations=60, certify=False)
    K = run.backend
    states = [[K.to_number(x) for x in run.velocity_in]] + [[K.to_number(x) for x in s.velocity] for s in run.steps]
    last = run.iterations
    for w, v in enumerate(states):
        if (reading.when == "before" and w == last and run.stop == "exit") or (reading.when == "after" and w == 0):
            continue
        norm_sq = sum(x * x for x in (v if reading.norm in ("v", "v^2") else states[0]))
        norm_sq = norm_sq**2 if reading.norm.endswith("^2") else norm_sq
        if _independent_measure(v, reading.measure) < c * c * norm_sq:
            return f"AEEV / {w}"
    assert run.stop == "exit"
    return str(last)


def test_every_readings_counts_with_the_printed_constant(table):
    search = table.identification
    assert search.sensitive == [r[0] for r in ROWS[-4:]]  # the rows the reading can change
    for w in search.windows:
        for eps in search.sensitive:
            assert w.stated_counts[eps] == _independent_count(eps, w.reading, F(1, 10**9)), (w.reading.name, eps)
    good = search.by_name(PAPER_READING.name)
    assert [good.stated_counts[e] for e in search.sensitive] == ["17", "AEEV / 17", "AEEV / 30", "AEEV / 32"]
    assert [good.stated_counts[e] for e in search.sensitive] == PRINTED[-4:]


@pytest.mark.parametrize("reading", [PAPER_READING, MAX_PAIR_READING], ids=lambda r: r.name)
def test_the_window_ends(table, reading):
    """Open below, closed above (the stop is strict): tested at each end, just inside and just outside."""
    w = table.identification.by_name(reading.name)
    lo, hi = w.lower_sq, w.upper_sq
    assert w.consistent and lo < hi
    delta = (hi - lo) / 10**6
    reproduces = {
        "at the lower end": False,
        "just inside the lower end": True,
        "just outside the lower end": False,
        "at the upper end": True,
        "just inside the upper end": True,
        "just outside the upper end": False,
    }
    squares = [lo, lo + delta, lo - delta, hi, hi - delta, hi + delta]
    for (what, expected), sq in zip(reproduces.items(), squares, strict=True):
        assert (_labels(aeev=reading, sigma_squared=sq) == PRINTED) == expected, what
        assert w.contains_squared(sq) == expected, what
    from verify.paper.table1 import sqrt_decimal

    for c in (F(sqrt_decimal(lo, 12)), F(sqrt_decimal(hi, 12, up=True))):  # rational c just outside
        assert _labels(aeev=reading, sigma_relative=c) != PRINTED


def test_exact_run_of_the_aeev_rows(table):
    by_eps = {row.eps: row for row in table.rows}
    assert (by_eps["0.0743"].exact.stop, by_eps["0.0743"].exact.iterations) == ("exit", 18)
    assert by_eps["0.01"].exact.stop == "non_terminating"
    assert by_eps["0"].exact.stop == "non_terminating"
    assert by_eps["0.01"].exact.certificate["kind"] == "alternating invariant cone"


def test_check_entry_reasons():
    assert check_entry("v", "1.25", F(5, 4)).agrees
    assert check_entry("v", "1.2", F(5, 4)).agrees  # half to even
    assert check_entry("v", "1.24", F(1249, 1000)).reason == "agrees if the printed digits were truncated, not rounded"


@pytest.mark.parametrize("row", ROWS, ids=[r[0] for r in ROWS])
def test_exact_interval_and_mp_agree_on_every_row(row):
    eps = row[0]
    cap = 40
    exact = run_cradle(eps, max_iterations=cap)
    interval = run_cradle(eps, max_iterations=cap, backend=get_backend("interval", dps=60))
    mp = run_cradle(eps, max_iterations=cap, backend=get_backend("mp", dps=60))
    assert exact.impact_sets == interval.impact_sets == mp.impact_sets
    assert exact.stop == interval.stop == mp.stop
    K, KI, KM = exact.backend, interval.backend, mp.backend
    assert isinstance(KI, IntervalBackend)
    for x, xi, xm in zip(exact.exit_velocity, interval.exit_velocity, mp.exit_velocity, strict=True):
        value = K.to_number(x)
        assert KI.contains(xi, value)
        assert abs(F(KM.to_decimal(xm, 55)) - value) <= F(1, 10**50)


def test_the_reading_on_the_command_line(capsys):
    import json

    from verify.cli import main

    for extra in ([], ["--aeev", "max_pair/v0/before"]):
        assert main(["cradle", "--eps", "0.01", "--mode", "paper", "--json", *extra]) == 0
        rec = json.loads(capsys.readouterr().out)
        assert (rec["stop"], rec["iterations"]) == ("aeev", 30)  # the printed AEEV / 30, under both readings
    assert main(["table1", "--json"]) == 0
    ident = json.loads(capsys.readouterr().out)["aeev_identification"]
    assert ident["reproducing_with_stated_c"] == [PAPER_READING.name]
    assert len(ident["readings"]) == 56


# --- the rounding readings and the paper's 38-digit binary arithmetic (issue 16, item 2) ---

from decimal import ROUND_DOWN, ROUND_HALF_EVEN, ROUND_HALF_UP, Context, Decimal  # noqa: E402

from verify.paper.table1 import (  # noqa: E402
    ARITHMETICS,
    PARI_PREC,
    READINGS,
    reading_range,
)

_CTX = Context(prec=400)


def _dec(q):
    return _CTX.divide(Decimal(q.numerator), Decimal(q.denominator))


def _printed_as(reading, q, text):
    """Whether ``reading`` prints the rational ``q`` as ``text``, recomputed with the decimal module."""
    places = Decimal(1).scaleb(-len(text.partition(".")[2]))
    d = _dec(q)
    ten = Context(prec=10, rounding=ROUND_HALF_EVEN).plus(d)
    got = {
        "round": lambda: d.quantize(places, ROUND_HALF_EVEN, _CTX),
        "round_half_up": lambda: d.quantize(places, ROUND_HALF_UP, _CTX),
        "truncate": lambda: d.quantize(places, ROUND_DOWN, _CTX),
        "sig10": lambda: ten,
        "sig10_then_printed": lambda: ten.quantize(places, ROUND_HALF_EVEN, _CTX),
    }[reading]()
    return got == Decimal(text)


def _mpf_exact(x):
    """An mpf as a rational from its mantissa and exponent (no float)."""
    return F(int(x.man) * 2 ** int(x.exp)) if x.exp >= 0 else F(int(x.man), 2 ** int(-x.exp))


def test_pari_precision_is_two_64_bit_words():
    K = get_backend("mp", prec=PARI_PREC)
    assert PARI_PREC == 128 and K.ctx.prec == 128 and K.dps == 38
    assert -(-38 * 3321928 // 1000000) == 127  # ceil(38 log2 10) bits, rounded up to 2 words of 64


def test_which_reading_and_arithmetic_explains_each_entry(table):
    """Every (arithmetic, reading) that explains an entry at the final state, recomputed here
    from the two paper-mode runs with the decimal module."""
    for row in table.rows:
        exact = run_cradle(row.eps, mode="paper", trace=False)
        binary = run_cradle(row.eps, mode="paper", trace=False, backend=get_backend("mp", prec=128))
        assert (binary.stop, binary.iterations) == (exact.stop, exact.iterations), row.eps
        finals = {
            "exact": [exact.backend.to_number(x) for x in exact.exit_velocity],
            "binary128": [_mpf_exact(x) for x in binary.exit_velocity],
        }
        for i, c in enumerate(row.checks[:3]):
            expected = {(a, r) for a in ARITHMETICS for r in READINGS if _printed_as(r, finals[a][i], c.printed)}
            assert {(e.arithmetic, e.reading) for e in c.explained_by if e.state is None} == expected, (row.eps, i)
            assert all(e.state is None for e in c.explained_by)  # no other state explains a whole row
    some = {(row.eps, c.column): c for row in table.rows for c in row.checks if c.only_some}
    assert len(some) == 21
    # truncation is refuted by entries of the exact run, e.g. 0.0744, v_D2: 33.3333333352 printed 33.33333334
    assert not any(e.reading == "truncate" for e in some["0.0744", "v_D2"].explained_by)
    # the eps = 0.0743 row has 9 significant digits: not "10 significant digits" as printed
    assert {e.reading for e in some["0.0743", "v_D1"].explained_by} == {
        "round", "round_half_up", "truncate", "sig10_then_printed"}  # fmt: skip


def test_the_inconsistent_entries_under_every_reading_and_arithmetic(table):
    bad = {(row.eps, c.column) for row in table.rows for c in row.checks if not c.explained}
    assert bad == {("0.0743", "v_D2"), ("0", "v_D1"), ("0", "v_D2"), ("0", "v_D3")}
    for row in table.rows:
        for c in row.checks[:3]:
            assert len(c.tried) == len(ARITHMETICS)
    notes = {row.eps: row.row_notes for row in table.rows}
    assert any("no state of the run (after 0 to 36 impulses)" in n and n.startswith("binary128") for n in notes["0"])
    assert any("no state of the run (after 0 to 18 impulses)" in n and n.startswith("exact") for n in notes["0.0743"])


@pytest.mark.parametrize("reading", list(READINGS))
def test_reading_ranges_against_the_decimal_module(reading):
    """Just inside each end of the range the reading prints the entry so; just outside it does not."""
    tiny = F(1, 10**15)
    for text in ("33.3333335", "33.33333330", "33.3333333", "34.316164", "0.4975125", "100", "9.9"):
        lo, hi = reading_range(reading, text)
        assert _printed_as(reading, lo + tiny, text) and _printed_as(reading, hi - tiny, text), text
        assert not _printed_as(reading, lo - tiny, text) and not _printed_as(reading, hi + tiny, text), text


def test_the_zero_row_momentum_range_under_every_reading(table):
    row = next(r for r in table.rows if r.eps == "0")
    got = {r: (str(float(lo)), str(float(hi))) for r, (lo, hi) in row.momentum_ranges.items()}
    expected = {
        "round": (F("100.000000195"), F("100.000000405")),
        "round_half_up": (F("100.000000195"), F("100.000000405")),
        "truncate": (F("100.0000003"), F("100.00000051")),
        "sig10": (F("100.000000285"), F("100.000000315")),
        "sig10_then_printed": (F("100.000000205"), F("100.000000395")),
    }
    assert row.momentum_ranges == expected, got
    assert all(lo > 100 for lo, _ in expected.values())  # the momentum argument holds under every reading
    assert any("cannot be a state of the rule under any reading" in n for n in row.row_notes)
    other = next(r for r in table.rows if r.eps == "0.0743")
    assert all(lo <= 100 <= hi for lo, hi in other.momentum_ranges.values())
