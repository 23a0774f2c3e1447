"""Table 1: reproduction, paper mode, the AEEV identification, backend agreement."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from verify.checks.paper.table1 import check_entry, load_table1, parse_printed_iterations, round_to, table1
from verify.core.backends import IntervalBackend, get_backend
from verify.models.cradle import run_cradle
from verify.models.paper import (
    MAX_PAIR_READING,
    MAX_PAIR_SIGMA_RELATIVE,
    PAPER_READING,
    PAPER_SIGMA_RELATIVE,
    PAPER_SIGMA_STATED,
)

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
    from verify.checks.paper.table1 import sqrt_decimal

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
