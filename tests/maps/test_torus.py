"""Five unit balls above eps*: every eps exits, on certified cells (verify.maps.torus), checked by the test's own
checker (tests/cells_check.py: its own period, projectors checked as identities, its own runs on its own numbers)."""

from __future__ import annotations

import itertools
from fractions import Fraction as F

import pytest
import sympy as sp

from tests.cells_check import Refused, check_cells, period_data, prepare
from tests.helpers import shared
from tests.maps.test_cautious import POINTS, _drawn, _first_decided, _normals, _unit_balls
from tests.sweeps import MAP, cells_of, replayed
from tests.sweeps import load as load_sweeps
from verify.errors import BadNumber
from verify.maps.boundary import Pattern
from verify.maps.cradle import cradle_map
from verify.maps.line import undecided_length
from verify.maps.meanvalue import cell, working_precision
from verify.maps.torus import exit_cells, exits_on_cells, torus_period
from verify.maps.watch import Watch
from verify.models.cradle import cradle_system
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.symbolic import EPS, Piece
from verify.numbers.format import format_exact

NORMALS = [[-1, 1, 0, 0, 0], [0, -1, 1, 0, 0], [0, 0, -1, 1, 0], [0, 0, 0, -1, 1]]
SETS = [(0, 2), (1, 3)]
VELOCITY = ["1", "0", "0", "0", "0"]
#: eps* = 0.25961618368..., a root of x^4 - 44 x^3 + 166 x^2 - 44 x + 1
STAR = sp.CRootOf(sp.Poly([1, -44, 166, -44, 1], sp.Symbol("x")), 1)


def _build(K):
    return cradle_system(EPS, 5, backend=K)


def _period(lo: F, hi: F):
    return torus_period(_build, Piece.closed(lo, hi), Pattern(2, tuple(SETS)))


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def data():
    return prepare([1] * 5, NORMALS, SETS)


def test_the_checker_finds_two_turning_pairs_above_eps_star(data) -> None:
    """The premise, from the checker's own period: two quadratics over Q(sqrt(5)) with roots of product eps^2,
    complex just above eps* and beyond (|tau| < 2 eps), one pair real just below it."""
    assert data["root"] == sp.sqrt(5)
    for above in (STAR + sp.Rational(1, 10**7), sp.Rational(27, 100), sp.Rational(1, 2)):
        assert all(sp.N((t / (2 * EPS)).subs(EPS, above) ** 2, 50) < 1 for t in data["taus"])
    below = STAR - sp.Rational(1, 10**7)
    assert any(sp.N((t / (2 * EPS)).subs(EPS, below) ** 2, 50) > 1 for t in data["taus"])


@pytest.mark.parametrize(("lo", "width"), [("0.26", "0.0002"), ("0.2596171837", "0.00000001"), ("0.3", "0.05")])
def test_cells_above_eps_star_exit_and_the_checker_agrees(lo: str, width: str, data) -> None:
    """Every cell of a sweep exits (the library), and the checker proves each cell on its own. The second interval
    lies 1e-6 above eps*, where a run follows the period for about 1,000 periods before it leaves."""
    a, b = F(lo), F(lo) + F(width)
    found = exit_cells(_period(a, b), VELOCITY, a, b)
    assert found.undecided == [] and found.decided == b - a
    assert found.cells[0][0] == a and found.cells[-1][1] == b
    assert all(x[1] == y[0] for x, y in zip(found.cells, found.cells[1:]))
    assert check_cells([[str(x), str(y)] for x, y in found.cells], [1] * 5, NORMALS, [1, 0, 0, 0, 0], SETS,
                       data=data) == []  # fmt: skip
    if lo == "0.2596171837":
        assert found.deepest > 900


def test_the_checker_refuses_cells_where_eps_never_exits(data) -> None:
    """Below eps* every eps never exits (the growth certificate of the map): cells there are refused, as is a
    cell that reaches over eps*."""
    below = check_cells([[str(F(1, 4)), str(F(1, 4) + F(1, 10**6))]], [1] * 5, NORMALS, [1, 0, 0, 0, 0], SETS,
                        halvings=1, data=data)  # fmt: skip
    assert below and "real" in below[0]
    assert check_cells([["0.2596", "0.2597"]], [1] * 5, NORMALS, [1, 0, 0, 0, 0], SETS, halvings=1, data=data)


def test_the_library_leaves_undecided_what_it_cannot_prove() -> None:
    """A sweep that reaches below eps* proves nothing there: its cells stop short of eps*, the rest undecided."""
    a, b = F("0.25961618"), F("0.25961619")
    found = exit_cells(_period(a, b), VELOCITY, a, b, min_width=F(1, 10**9))
    assert found.undecided and found.undecided[0][0] == a
    assert all(x > STAR for c in found.cells for x in c)


def test_no_float_enters_the_cells() -> None:
    """Velocities are read exactly (a binary float is refused) and the numbers of a cell are balls, not floats."""
    a, b = F("0.27"), F("0.2701")
    with pytest.raises(BadNumber):
        exit_cells(_period(a, b), [1.0, 0, 0, 0, 0], a, b)
    with working_precision():
        e = cell(a, b)
        assert type(e.point).__name__ == "arb" and type(e.slope).__name__ == "arb"

    class Poisoned(F):
        def __float__(self) -> float:
            raise AssertionError("a float was taken")

    found = exit_cells(_period(a, b), [Poisoned(1), Poisoned(0), 0, 0, 0], a, b)
    assert found.decided == b - a


def test_the_projectors_are_identities(data) -> None:
    """E1 + E2 = 1 splits the period: checked exactly by the checker (it raises otherwise)."""
    _G, P, _root, _taus, E1 = period_data([1] * 5, NORMALS, SETS)
    assert sp.simplify((P * E1 - E1 * P)[0, 0]) == 0
    with pytest.raises(Refused):
        period_data([1] * 5, NORMALS, [(0, 1), (2, 3)])


def _cells_of(certificate: dict) -> list[list[str]]:
    cuts = certificate["cuts"]
    return [[a, b] for a, b in itertools.pairwise(cuts)]


@pytest.mark.slow(seconds=17)
def test_the_map_above_eps_star_proves_every_piece_and_the_checker_agrees(data) -> None:
    """``cradle_map(..., leaving=True)`` on an interval above eps*: the pieces whose runs end on the period at the
    bound and those that left it before (and had not exited yet) are each proved to exit, cell by cell, and the
    checker proves every cell of every certificate."""
    m = cradle_map(balls=5, lower="0.2685", upper="0.2715", max_impulses=20, leaving=True)
    proved = [p for p in m.unexplored if p.exits_beyond_bound]
    assert len(proved) >= 3 and all(p.certificate["kind"] == "exits on cells" for p in proved)
    assert all(p.piece.is_point for p in m.unexplored if not p.exits_beyond_bound)
    assert undecided_length(m.parts)[1] < F(1, 10**15)  # the points between pieces (measure 0)
    for p in proved:
        cells = _cells_of(p.certificate)
        assert p.piece.lower.cmp(RealAlgebraic.rational(F(cells[0][0]))) >= 0
        assert p.piece.upper.cmp(RealAlgebraic.rational(F(cells[-1][1]))) <= 0
        assert check_cells(cells, [1] * 5, NORMALS, [1, 0, 0, 0, 0], SETS, data=data) == []


def test_just_above_eps_star_a_gap_of_5e_minus_7_stays_undecided() -> None:
    """The cells start 5e-7 above eps* (within 1e-15): a piece that starts at eps* keeps that gap undecided."""
    piece = Piece(RealAlgebraic.from_number(STAR), RealAlgebraic.from_number(STAR + sp.Rational(52, 10**8)),
                  False, True)  # fmt: skip
    found = exits_on_cells(_build, VELOCITY, piece, Pattern(2, tuple(SETS)), above_boundary=True)
    assert found is not None and found.undecided == []
    assert F(0) < found.lower - sp.Rational(5, 10**7) - STAR < F(1, 10**14)
    assert piece.upper.cmp(RealAlgebraic.rational(found.cells[-1][1])) <= 0


@pytest.fixture(scope="session")
def five_balls(tmp_path_factory):
    """The whole map of five unit balls with ``leaving``, its sweeps of cells replayed from their record
    (tests/sweeps.py: the cells found once, each proved by the checker in the tests below), computed once for
    both test processes; with the sweeps the map asked for (key, pattern, velocity, interval)."""

    def compute():
        with replayed() as asked:
            m = cradle_map(**MAP)
        return m, [(key, period.pattern, velocity, lower, upper) for key, period, velocity, lower, upper in asked]

    return shared(tmp_path_factory, "five-balls-map", compute)


@pytest.mark.slow(seconds=18)
def test_five_unit_balls_every_eps_above_eps_star_exits_but_less_than_1e_minus_6(five_balls) -> None:
    """The whole map of five unit balls with ``leaving``: up to and at eps* never exits, and above it every eps
    exits but a set of length below 1e-6 (the gap of 5e-7 above eps* and cells narrower than 1e-14). Its cells are
    the recorded sweeps', every one of which the checker proves (the next test); the map asks for each recorded
    sweep, and its certificates list exactly their cells."""
    m, asked = five_balls
    recorded = load_sweeps()
    assert sorted(key for key, *_ in asked) == sorted(recorded)
    assert undecided_length(m.parts)[1] < F(1, 10**6)
    star = RealAlgebraic.from_number(STAR)
    assert all(p.piece.lower.cmp(star) >= 0 for p in m.unexplored)
    proved = [p for p in m.unexplored if p.exits_beyond_bound]
    listed = sorted((F(a), F(b)) for p in proved for a, b in _cells_of(p.certificate))
    assert len(listed) > 1000
    assert listed == sorted(cell for sweep in recorded.values() for cell in cells_of(sweep))


class _Cells(Watch):
    """A watch that stops a sweep after its first ``count`` steps (a step tries one cell)."""

    def __init__(self, count: int) -> None:
        super().__init__()
        self.count = count

    def check(self) -> bool:
        self.count -= 1
        return self.count < 0


#: the steps of the long sweep made again by the library (its first ones)
AGAIN = 400


def test_the_recorded_sweeps_are_what_the_sweep_finds_now(five_balls) -> None:
    """The record is not stale: the short sweeps the map asks for are found again, cell for cell, and the
    long one's cells found in its first steps (a sweep's cells depend only on those before them), so a change
    to the sweep that moves a cell fails here (record them again: ``python3 -m tests.sweeps``)."""
    _, asked = five_balls
    recorded = load_sweeps()
    for key, pattern, velocity, lower, upper in asked:
        period = _period(lower, upper)  # as the map makes it for the sweep of [lower, upper]
        assert period.pattern == pattern, key
        mine = cells_of(recorded[key])
        short = len(mine) <= AGAIN
        found = exit_cells(period, velocity, lower, upper, watch=None if short else _Cells(AGAIN))
        assert found.cells == (mine if short else mine[: len(found.cells)]), key
        if short:  # and what the replay gives besides the cells
            s = recorded[key]
            undecided = [[format_exact(a), format_exact(b)] for a, b in found.undecided]
            assert undecided == s["undecided"] and found.deepest == s["deepest"], key
        assert short or len(found.cells) > AGAIN // 4


#: the recorded cells are checked in this many tests, each a share of every sweep (so both test processes share them)
CHECKS = 4


@pytest.mark.slow(seconds=26)
@pytest.mark.parametrize("share", range(CHECKS))
def test_every_recorded_cell_of_the_five_ball_map_exits_by_the_checker(share: int, data) -> None:
    """The checker proves every cell of the recorded sweeps on its own (its own period, runs and numbers)."""
    cells = [cell for sweep in load_sweeps().values() for cell in cells_of(sweep)][share::CHECKS]
    assert cells
    assert check_cells([[str(a), str(b)] for a, b in cells], [1] * 5, NORMALS, [1, 0, 0, 0, 0], SETS, data=data) == []


@pytest.mark.slow(seconds=40)
def test_no_eps_the_five_ball_cells_leave_is_decided_by_a_single_run(five_balls) -> None:
    """Never more cautious than a single run: what the cells leave (the gap above eps*, the cells left undecided)
    is not decided by verify solve with the map's cap of 20, at 100 rational points drawn in it."""
    m, _ = five_balls
    points = _drawn([p for p in m.parts if not p.exits_beyond_bound], POINTS, seed=36)
    assert len(points) == POINTS
    assert _first_decided(_unit_balls(5), _normals(5), points, 20) is None


def test_any_phase_of_the_period_gives_the_same_cells(data) -> None:
    """The period taken from its other phase, (S2,S4)(S1,S3) from impulse 3 on: the run looks for it from there,
    and the cells prove the same interval (checked by the checker with that phase)."""
    a, b = F("0.27"), F("0.2705")
    phase = Pattern(3, ((1, 3), (0, 2)))
    found = exit_cells(torus_period(_build, Piece.closed(a, b), phase), VELOCITY, a, b)
    assert found.undecided == [] and found.decided == b - a
    cells = [[str(x), str(y)] for x, y in found.cells]
    assert check_cells(cells, [1] * 5, NORMALS, [1, 0, 0, 0, 0], [(1, 3), (0, 2)]) == []
