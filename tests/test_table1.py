"""Table 1: reproduction, paper mode, the AEEV identification, backend agreement."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from verify.checks.paper.table1 import check_entry, load_table1, parse_printed_iterations, round_to, table1
from verify.core.backends import IntervalBackend, get_backend
from verify.models.cradle import run_cradle
from verify.models.paper import PAPER_SIGMA_RELATIVE, PAPER_SIGMA_STATED

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


def test_the_aeev_identification(table):
    ident = table.identification["measures"]["all"]
    assert ident["consistent"]
    assert ident["lower_sq"] < PAPER_SIGMA_RELATIVE**2 <= ident["upper_sq"]  # paper mode is inside the window
    assert not ident["stated_inside"]  # the stated sigma is not
    assert not ident["lower_sq"] < PAPER_SIGMA_STATED**2 <= ident["upper_sq"]
    counts = table.identification["stated_counts"]
    assert counts["0.0744"] == "AEEV / 16"  # what the stated sigma would have printed


def test_the_window_is_tight_at_both_ends():
    # sigma at either end of the window changes one printed count: the window is exact
    ident = table1().identification["measures"]["all"]
    lo, hi = ident["lower_sq"], ident["upper_sq"]
    from verify.checks.paper.table1 import sqrt_decimal

    just_below = F(sqrt_decimal(lo, 12))  # < sqrt(lo): outside the window
    just_above = F(sqrt_decimal(hi, 12, up=True))  # > sqrt(hi): outside the window
    for sigma in (just_below, just_above):
        labels = []
        for eps, *_ in ROWS:
            r = run_cradle(eps, mode="paper", sigma_relative=sigma)
            labels.append(f"AEEV / {r.iterations}" if r.stop == "aeev" else str(r.iterations))
        assert labels != [row[4] for row in ROWS]


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
