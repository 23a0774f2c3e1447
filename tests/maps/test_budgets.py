"""Maps bounded and visible (verify.maps.line.Watch): a wall-clock and a size budget, progress, and on a budget
or Ctrl-C the map decided so far, whole: every value of the interval in one part, the rest unexplored, saying why."""

from __future__ import annotations

import itertools
import json
import os
import signal
import subprocess
import sys
import time
from fractions import Fraction as F

import pytest
from hypothesis import given
from hypothesis import strategies as st

from verify.cli import main
from verify.maps import line
from verify.maps.cradle import cradle_map, map_json
from verify.maps.line import Watch
from verify.numbers.algebraic import RealAlgebraic


def _covers_once(parts) -> bool:
    return all(a.piece.upper == b.piece.lower and a.piece.upper_closed != b.piece.lower_closed
               for a, b in itertools.pairwise(parts))  # fmt: skip


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def full():
    return cradle_map(4, max_impulses=12)


@pytest.mark.parametrize("budget", [0, 1, 3, 6])
def test_a_size_budget_stops_the_map_and_what_was_decided_is_the_full_maps(full, budget) -> None:
    m = cradle_map(4, max_impulses=12, watch=Watch(max_parts=budget))
    assert m.stopped == f"the size budget of {budget} parts was reached"
    assert _covers_once(m.parts) and m.parts[0].piece.lower == full.parts[0].piece.lower
    assert m.parts[-1].piece.upper == full.parts[-1].piece.upper
    left = [p for p in m.parts if p.stopped_by]
    assert left and all(p.reason == f"not explored: {m.stopped}" and p.stop == "max_iterations" for p in left)
    for part in m.parts:
        if part.stopped_by:
            continue
        inside = part.piece.lower if part.piece.is_point else RealAlgebraic.rational(part.piece.sample())
        same = full.locate(inside)
        assert (same.stop, same.iterations, same.impact_sets) == (part.stop, part.iterations, part.impact_sets)
    assert map_json(m)["stopped"] == m.stopped and "stopped" not in map_json(full)


def test_a_budget_that_is_not_reached_changes_nothing(full) -> None:
    m = cradle_map(4, max_impulses=12, watch=Watch(seconds=3600.0, max_parts=10**6))
    assert m.stopped == "" and json.dumps(map_json(m)) == json.dumps(map_json(full))


def test_a_spent_wall_clock_budget_leaves_the_whole_interval_unexplored() -> None:
    m = cradle_map(4, max_impulses=12, watch=Watch(seconds=0.0))
    assert m.stopped == "the wall-clock budget of 0 s ran out"
    assert [(str(p.piece), p.stop) for p in m.parts] == [("[0, 1]", "max_iterations")]


def test_progress_counts_the_parts_the_length_decided_and_the_deepest_impulse(full) -> None:
    seen: list[str] = []
    cradle_map(4, max_impulses=12, watch=Watch(progress=seen.append))
    counts = [int(s.split()[1]) for s in seen]
    assert counts == list(range(1, len(seen) + 1)) and len(seen) >= len(full.parts)
    deepest = max(p.iterations for p in full.parts)
    assert seen[-1].startswith(f"map: {len(seen)} parts, decided a length of ")
    assert f"deepest impulse {deepest}," in seen[-1]
    decided = F(seen[-1].split("length of ")[1].split(",")[0])
    exact = sum(_length(p.piece) for p in full.parts if p.stop != "max_iterations")
    assert abs(decided - exact) < F(1, 10**5)


def _interrupt_after(monkeypatch: pytest.MonkeyPatch, calls: int) -> None:
    real, count = line.solve, [0]

    def solve(*args, **kwargs):
        count[0] += 1
        if count[0] > calls:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(line, "solve", solve)


def test_without_a_watch_ctrl_c_is_not_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    _interrupt_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        cradle_map(4, max_impulses=12)


@pytest.mark.parametrize("argv", [["cradle-map", "--balls", "4", "--max-impulses", "12"],
                                  ["map", "docs/examples/corner-map.json", "--lines", "2"]])  # fmt: skip
def test_ctrl_c_prints_the_map_so_far_and_exits_130(monkeypatch, capsys, argv) -> None:
    _interrupt_after(monkeypatch, 3)
    assert main([*argv, "--json"]) == 130
    out = json.loads(capsys.readouterr().out)
    assert out["stopped"] == "interrupted (Ctrl-C)"
    _interrupt_after(monkeypatch, 3)
    assert main(argv) == 130
    assert "Stopped early: interrupted (Ctrl-C)." in capsys.readouterr().out


def test_a_real_ctrl_c_gives_the_map_decided_so_far() -> None:
    import pty
    import select

    master, slave = pty.openpty()  # stderr on a terminal: the status line shows when the map is under way
    proc = subprocess.Popen(
        [sys.executable, "-m", "verify", "cradle-map", "--balls", "5", "--max-impulses", "30", "--json"],
        stdout=subprocess.PIPE, stderr=slave, text=True, env={**os.environ, "TERM": "xterm"},
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # noqa: PLW1509 (a test's own child)
    )  # fmt: skip
    os.close(slave)
    seen, deadline = b"", time.monotonic() + 120
    while b"parts" not in seen and time.monotonic() < deadline and proc.poll() is None:
        if select.select([master], [], [], 0.5)[0]:
            seen += os.read(master, 4096)
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=120)
    while select.select([master], [], [], 0.2)[0]:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the child is gone: its end of the terminal is closed
            break
        if not chunk:
            break
        seen += chunk
    os.close(master)
    assert b"cradle-map: map: " in seen  # the progress line: parts, the length decided, the deepest impulse
    assert proc.returncode == 130 and b"Traceback" not in seen
    data = json.loads(out)
    assert data["stopped"] == "interrupted (Ctrl-C)" and data["unexplored"]


BAD = [("--time-limit", "0"), ("--time-limit", "nan"), ("--time-limit", "-1"), ("--max-parts", "-1")]
BAD += [("--max-parts", "x"), ("--halvings", "-1"), ("--halvings", "41"), ("--halvings", "1.5")]


@pytest.mark.parametrize(("option", "value"), BAD)
@pytest.mark.parametrize("command", [["cradle-map"], ["map", "docs/examples/corner-map.json"]])
def test_bad_budgets_are_refused_with_exit_code_2(capsys, command, option, value) -> None:
    assert main([*command, option, value]) == 2
    out = capsys.readouterr()
    assert option in out.err and "Traceback" not in out.err and out.out == ""


@given(st.lists(st.fractions(min_value=0, max_value=1, max_denominator=9), max_size=6), st.data())
def test_what_is_left_uncovered_is_exactly_what_no_part_holds(cuts, data) -> None:
    from verify.maps.line import uncovered
    from verify.numbers.backends.symbolic import Piece

    domain = Piece.closed(0, 1)
    parts = domain.cut([RealAlgebraic.rational(c) for c in cuts])
    kept = [p for p in parts if data.draw(st.booleans())]
    left = uncovered(domain, kept)
    whole = sorted(kept + left, key=lambda p: (p.lower, not p.is_point))
    assert _covers_once_pieces(whole) and whole[0].lower == domain.lower and whole[-1].upper == domain.upper
    assert whole[0].lower_closed and whole[-1].upper_closed
    for p in parts:
        if p not in kept:
            inside = p.lower if p.is_point else RealAlgebraic.rational(p.sample())
            assert any(q.contains(inside) for q in left)
            assert not any(q.contains(inside) for q in kept)


def _covers_once_pieces(pieces) -> bool:
    return all(a.upper == b.lower and a.upper_closed != b.lower_closed for a, b in itertools.pairwise(pieces))


def test_ctrl_c_while_a_piece_is_cut_still_gives_a_whole_map(monkeypatch: pytest.MonkeyPatch) -> None:
    from verify.numbers.backends.symbolic import Piece

    real, count = Piece.cut, [0]

    def cut(self, points):
        count[0] += 1
        if count[0] == 3:
            raise KeyboardInterrupt
        return real(self, points)

    monkeypatch.setattr(Piece, "cut", cut)
    watch = Watch()
    m = cradle_map(4, max_impulses=12, watch=watch)
    assert watch.interrupted and m.stopped == "interrupted (Ctrl-C)"
    assert _covers_once(m.parts) and m.parts[0].piece.lower_closed and m.parts[-1].piece.upper_closed
    assert any(p.stopped_by for p in m.parts)


def _length(piece) -> F:
    """A piece's length within 1e-12, from its ends refined on copies (the map's own are left as they are)."""
    ends = []
    for x in (piece.lower, piece.upper):
        y = RealAlgebraic(x.poly, x.lo, x.hi)
        while y.hi - y.lo > F(1, 10**13):
            y.refine()
        ends.append(y.lo)
    return ends[1] - ends[0]


class _StopsAt(Watch):
    """A watch whose budget runs out at its ``calls``-th check: a stop at a chosen place, whatever the machine's
    speed."""

    def __init__(self, calls: int) -> None:
        super().__init__()
        self.calls = calls

    def check(self) -> bool:
        self.calls -= 1
        if self.calls <= 0 and not self.stopped:
            self.stopped = "the test's budget ran out"
        return bool(self.stopped)


@pytest.mark.slow(seconds=13)
@pytest.mark.parametrize("calls", [2, 20])
def test_a_budget_stops_the_search_for_turning_cones_and_keeps_what_it_proved(calls, monkeypatch) -> None:
    """Five unit balls below their boundary eps* (verify.maps.turning): the search for cones checks the map's budget
    before each piece. Stopped at its first piece, the whole interval is left, saying so; stopped later, the cones
    found are kept (each certificate the search would give), and only what lies between them and eps* is left. The
    map proves this interval with the growth argument (verify.maps.growth) before any cone is searched: here it
    is switched off, as it is off for a system where it does not hold."""
    monkeypatch.setattr(line, "grown_below", lambda *args, **kwargs: None)
    m = cradle_map(balls=5, lower="0.23", upper="0.2597", max_impulses=20, watch=_StopsAt(calls))
    assert m.stopped == "the test's budget ran out" and _covers_once(m.parts)
    left = [p for p in m.parts if p.stopped_by]
    assert left and all(p.reason.endswith("the search for cones stopped: the test's budget ran out") for p in left)
    proved = m.non_terminating
    if calls == 2:
        assert not proved and len(m.parts) == 1
        return
    assert proved and proved[0].piece.lower == RealAlgebraic.rational(F(23, 100))
    assert all(p.certificate["boundary"]["reached"] is False for p in proved)
    star = proved[0].certificate["boundary"]["eps"]
    assert left[0].piece.lower == proved[-1].piece.upper and str(left[0].piece.upper) == star
    assert [p.reason.split("; ")[1].split(" the boundary")[0] for p in m.parts[-2:]] == ["at", "above"]


def _jumping_clock(monkeypatch: pytest.MonkeyPatch) -> list[float]:
    """The clock of the maps of cells and of their watch, ahead of the real one by ``jump[0]`` seconds (the list
    returned: a test sets it to jump past a budget)."""
    from verify.maps import plane
    from verify.maps import watch as watch_module

    jump = [0.0]

    class Clock:
        @staticmethod
        def monotonic() -> float:
            return time.monotonic() + jump[0]

    monkeypatch.setattr(plane, "time", Clock)
    monkeypatch.setattr(watch_module, "time", Clock)
    return jump


def test_a_wall_clock_budget_that_runs_out_while_a_cell_is_cut_stops_there(monkeypatch: pytest.MonkeyPatch) -> None:
    """A map of cells (verify.maps.plane) checks its wall-clock budget while it cuts a cell too (between projections,
    and inside long resultants), not only between signs: a clock that jumps past the budget at the third cut stops
    the map there. That cell is left whole and unexplored, saying why; the cells decided before are the full map's;
    the cells still cover the box."""
    from verify.maps import plane
    from verify.maps.general import case_map

    case = "docs/examples/corner-map.json"
    full = case_map(case, cells=True, max_impulses=4)
    jump = _jumping_clock(monkeypatch)
    cuts = []
    real_refine = plane.refine

    def refine(*args, **kwargs):
        cuts.append(1)
        if len(cuts) == 3:
            jump[0] = 10.0**6
        return real_refine(*args, **kwargs)

    monkeypatch.setattr(plane, "refine", refine)
    m = case_map(case, cells=True, max_impulses=4, watch=Watch(seconds=3600))
    assert len(cuts) == 3 and m.stopped == "the wall-clock budget of 3600 s ran out"
    parts = m.plane.parts
    left = [p for p in parts if p.reason == f"not explored: {m.stopped}"]
    assert left and len(parts) < len(full.plane.parts)
    for p in parts:
        if p.stop == "exit":
            twin = full.at(dict(zip(full.plane.names, p.cell.sample)))[0]
            assert (twin.stop, twin.impact_sets) == (p.stop, p.impact_sets)
    low, high = sum(p.cell.area[0] for p in parts), sum(p.cell.area[1] for p in parts)
    assert low <= 1 <= high


@pytest.mark.parametrize("how", ["clock", "ctrl-c"])
def test_a_budget_or_ctrl_c_stops_the_proof_that_every_eps_above_the_boundary_exits(monkeypatch, how) -> None:
    """``--leaving`` checks its proof on exact cells of (eps, t) (verify.maps.leaving): the map's wall-clock budget and
    Ctrl-C stop those cells too. A clock that jumps past the budget (or a Ctrl-C) at the first cut of a cell of the
    proof stops the map there: the part above the boundary is left unexplored, saying that the proof stopped and why,
    with no certificate; the parts decided before are kept and the interval is still covered once."""
    from verify.maps import plane

    jump = _jumping_clock(monkeypatch)
    cuts = []

    def refine(*args, **kwargs):
        cuts.append(1)
        if how == "ctrl-c":
            raise KeyboardInterrupt
        jump[0] = 10.0**6
        raise plane.OutOfTime("the clock jumped")

    monkeypatch.setattr(plane, "refine", refine)
    watch = Watch(seconds=3600)
    m = cradle_map(4, lower="0.1715", upper="0.1729", max_impulses=40, widen=0, leaving=True, watch=watch)
    stopped = "interrupted (Ctrl-C)" if how == "ctrl-c" else "the wall-clock budget of 3600 s ran out"
    assert cuts == [1] and m.stopped == stopped and watch.interrupted == (how == "ctrl-c")
    assert _covers_once(m.parts) and m.non_terminating
    left = [p for p in m.parts if p.stopped_by]
    assert left and all(p.reason.endswith(f"the proof that it exits stopped: {stopped}") for p in left)
    assert not any((p.certificate or {}).get("kind") == "leaves and exits" for p in m.parts)
