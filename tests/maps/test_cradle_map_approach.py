"""The cradle map's approach table, staircase legend and interval check (issue 14, item 6)."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from tests import certificate_check
from verify.cli import main
from verify.errors import InvalidInput, NoConvergence
from verify.maps.cradle import approach_counts, cradle_map, termination_boundaries
from verify.models.cradle import run_cradle

MASSES = ["1", "2", "3"]


@pytest.fixture(scope="module")
def map123():
    return cradle_map(masses=MASSES, max_impulses=4)


def _table_rows(text: str) -> list[tuple[F, str]]:
    """(eps, rest of the line) for each row of the approach table in the command's text."""
    lines = text.splitlines()
    start = lines.index("Impulses until exit just above the boundary (certified interval runs):") + 2
    rows = []
    for line in lines[start:]:
        if line.startswith("  (each row"):
            break
        eps, rest = line.split(maxsplit=1)
        rows.append((F(eps), rest))
    return rows


def test_approach_counts_are_runs_of_the_maps_own_cradle(map123):
    (b,) = termination_boundaries(map123)
    rows = approach_counts(b, range(2, 4), map123)
    assert len(rows) == 2
    for eps, n in rows:
        r = run_cradle(eps, masses=MASSES, v0="1", trace=False)  # a direct exact run, same masses
        assert r.stop == "exit"
        assert n == r.iterations


def test_cli_approach_table_matches_direct_runs(capsys):
    assert main(["cradle-map", "--masses", "1,2,3", "--max-impulses", "4", "--approach", "3"]) == 0
    rows = _table_rows(capsys.readouterr().out)
    assert len(rows) == 2
    previous = None
    for eps, rest in rows:
        r = run_cradle(eps, masses=MASSES, v0="1", trace=False)
        assert r.stop == "exit"
        count, *ratio = rest.split()
        assert int(count) == r.iterations
        if previous is not None:  # the ratio is the one of the direct counts
            assert F(ratio[0]) == F(round(F(r.iterations, previous), 4))
        previous = r.iterations


def test_a_run_beyond_the_budget_is_said_in_words_with_no_ratio(map123):
    (b,) = termination_boundaries(map123)
    rows = approach_counts(b, range(2, 4), map123, max_impulses=10)
    direct = [run_cradle(eps, masses=MASSES, v0="1", trace=False, max_iterations=10) for eps, _ in rows]
    assert [r.stop for r in direct] == ["exit", "max_iterations"]
    assert rows[0][1] == direct[0].iterations
    assert rows[1][1] == f"> {direct[1].iterations} (budget)"
    from verify.maps.text import approach_table

    lines = approach_table(rows)
    eps, *words = lines[-2].split()  # the last row, before the footnote
    assert (F(eps), " ".join(words)) == rows[1]
    assert not any("-1" in line.split() for line in lines)


def test_no_ratio_to_or_from_a_row_without_a_count():
    from verify.maps.text import approach_table

    lines = approach_table([(F(1, 10), 8), (F(1, 100), "> 10 (budget)"), (F(1, 1000), 78)])
    row = {line.split()[0]: line.split()[1:] for line in lines[3:-1]}
    assert row == {"0.1": ["8"], "0.01": [">", "10", "(budget)"], "0.001": ["78"]}


def test_precision_running_out_is_said_in_words(map123, monkeypatch):
    (b,) = termination_boundaries(map123)

    def out_of_precision(*args, **kwargs):
        raise NoConvergence("a sign stayed undecided at the largest precision")

    monkeypatch.setattr("verify.models.cradle.run_cradle", out_of_precision)
    assert approach_counts(b, [2], map123)[0][1] == "undecided at the precision limit"


def test_staircase_legend_shows_only_what_is_drawn():
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from verify.maps.figures import staircase_figure, staircase_legend

    for m in (cradle_map(4, ["1", "2", "3", "4"], max_impulses=6), cradle_map(max_impulses=2)):
        labels = [label for _, label in staircase_legend(m)]
        fig = staircase_figure(m)
        try:
            drawn = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        finally:
            plt.close(fig)
        assert drawn == labels
        assert any("exits after n impulses" in x for x in labels) == bool(m.pieces)
        assert ("never exits (proved)" in labels) == bool(m.non_terminating)
        proved_later = [p for p in m.unexplored if p.exits_beyond_bound]
        undecided = [p for p in m.unexplored if not p.exits_beyond_bound]
        assert any(x.startswith("exits after more than") for x in labels) == bool(proved_later)
        assert any(x.startswith("undecided") for x in labels) == bool(undecided)
        for part in undecided:  # labelled with its reason, never as known to exit
            assert part.reason.split("; ", 1)[1] in "".join(labels)


def test_four_balls_staircase_claims_only_what_is_proved(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    from verify.maps.figures import cradle_staircase

    saved = []
    real_savefig = Figure.savefig

    def keep(fig, *args, **kwargs):  # the legend of the figure cradle_staircase writes
        saved.append([t.get_text() for t in fig.axes[0].get_legend().get_texts()])
        return real_savefig(fig, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", keep)
    m = cradle_map(4, ["1", "2", "3", "4"], max_impulses=6)
    # what is proved never to exit carries a certificate (a cone of a period); nothing claims an exit beyond
    kinds = [p.certificate["kind"] for p in m.non_terminating]
    assert m.unexplored and set(kinds) <= {"invariant cone of a period", "repeating direction"}
    normals = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]
    for p in m.non_terminating:  # eps = 0 is decided as verify solve decides it: its certificate checked here
        if p.certificate["kind"] == "repeating direction":
            assert p.piece.is_point
            assert certificate_check.check_repeating(p.certificate, ["1", "2", "3", "4"], normals) == []
    assert not any(p.exits_beyond_bound for p in m.unexplored)
    assert cradle_staircase(m, tmp_path / "s.png").read_bytes()[:4] == b"\x89PNG"
    (labels,) = saved
    assert not any("exits after more than" in x for x in labels)
    assert ("never exits (proved)" in labels) == bool(m.non_terminating)
    assert any("undecided" in x and "no invariant cone found" in x for x in labels)


def test_reversed_interval():
    with pytest.raises(InvalidInput, match=r"the eps interval is reversed: lower = 0\.5 > upper = 0\.2"):
        cradle_map(lower="0.5", upper="0.2")
    with pytest.raises(InvalidInput, match=r"reversed: lower = 1/2 > upper = 1/5"):
        cradle_map(lower=F(1, 2), upper=F(1, 5))


def test_cli_reversed_interval(capsys):
    assert main(["cradle-map", "--interval", "0.5,0.2"]) == 2
    err = capsys.readouterr().err
    assert "the eps interval is reversed: lower = 0.5 > upper = 0.2" in err and err.count("\n") == 1
    assert "must lie in" not in err
