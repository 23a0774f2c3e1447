"""The exact eps-map of Newton's cradle (issue: thresholds and termination)."""

from __future__ import annotations

import itertools
import json
from fractions import Fraction as F

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from tests import certificate_check
from verify.cli import main
from verify.errors import InvalidInput, InvalidSystem
from verify.maps.cradle import (
    approach_counts,
    cradle_map,
    map_json,
    termination_boundaries,
    threshold_between,
    undecided_measure,
)
from verify.models.cradle import run_cradle
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.symbolic import EPS
from verify.paper.cradle_map import aeev_rows_explained

BOUND = 40


@pytest.fixture(scope="module")
def cmap():
    return cradle_map(max_impulses=BOUND)


def inner_rational(part, t: F) -> F:
    """A rational strictly inside a part's interval, at fraction t in (0, 1) of an inner box."""
    lo, hi = part.piece.lower, part.piece.upper
    a = lo.lo if lo.is_rational else lo.hi
    b = hi.hi if hi.is_rational else hi.lo
    while not a < b:  # refine the ends until an inner box exists
        lo.refine()
        hi.refine()
        a = lo.lo if lo.is_rational else lo.hi
        b = hi.hi if hi.is_rational else hi.lo
    return a + t * (b - a)


def test_the_map_covers_the_interval_exactly_once(cmap):
    parts = cmap.parts
    assert parts[0].piece.lower == RealAlgebraic.rational(F(0)) and parts[0].piece.lower_closed
    assert parts[-1].piece.upper == RealAlgebraic.rational(F(1)) and parts[-1].piece.upper_closed
    for a, b in itertools.pairwise(parts):
        assert a.piece.upper == b.piece.lower
        assert a.piece.upper_closed != b.piece.lower_closed  # the endpoint belongs to exactly one part


@given(st.data())
@settings(max_examples=40, deadline=None)
def test_pieces_agree_with_exact_rational_runs(cmap, data):
    part = data.draw(st.sampled_from([p for p in cmap.pieces if not p.piece.is_point]), label="piece")
    t = data.draw(st.fractions(min_value=F(1, 100), max_value=F(99, 100), max_denominator=100), label="t")
    eps = inner_rational(part, t)
    r = run_cradle(eps, v0="1")
    K = r.backend
    assert r.stop == "exit"
    assert r.iterations == part.iterations
    assert r.impact_sets == part.impact_sets
    value = sp.Rational(eps.numerator, eps.denominator)
    for x, formula in zip(r.exit_velocity, part.exit_velocity, strict=True):
        assert K.to_number(x) == F(str(formula.subs(EPS, value)))


@given(st.fractions(min_value=F(1, 1000), max_value=F(999, 1000), max_denominator=1000))
def test_rational_points_of_non_terminating_intervals_are_proved(cmap, t):
    part = cmap.non_terminating[0]
    eps = inner_rational(part, t)
    r = run_cradle(eps, v0="1")
    assert r.stop == "non_terminating"
    failures = certificate_check.check(r.certificate, ["1", "1", "1"], [["-1", "1", "0"], ["0", "-1", "1"]])
    assert failures == []


def test_unexplored_points_exit_after_more_than_the_bound(cmap):
    part = cmap.unexplored[0]
    for t in (F(1, 2), F(9, 10)):
        r = run_cradle(inner_rational(part, t), v0="1")
        assert r.stop == "exit" and r.iterations > BOUND


def test_endpoints_are_roots_of_the_rates_that_change_sign(cmap):
    """Each threshold between exit pieces is a root of the rate that decides the extra impulse.

    The rates are recomputed here by a direct simulation in SymPy (alternating impacts of
    unit balls), independent of the engine: after k impulses the rate of the contact hit
    next on the lower side vanishes at the threshold."""
    v = [sp.Integer(1), sp.Integer(0), sp.Integer(0)]
    rates_after = []
    for k in range(BOUND + 1):
        b = [sp.expand(v[1] - v[0]), sp.expand(v[2] - v[1])]
        rates_after.append(b)
        j = k % 2  # impacts alternate (0), (1), (0), ...
        c = (1 + EPS) * b[j] / 2
        v[j], v[j + 1] = sp.expand(v[j] + c), sp.expand(v[j + 1] - c)
    checked = 0
    for a, b in zip(cmap.parts, cmap.parts[1:]):
        if a.stop == b.stop == "exit" and a.iterations == b.iterations + 1 and not b.piece.is_point:
            x = b.piece.lower
            k = b.iterations
            rate = rates_after[k][k % 2]
            point = certificate_check.read(str(x))
            m = sp.minimal_polynomial(point, sp.Symbol("y"))
            assert sp.rem(sp.Poly(rate, EPS), sp.Poly(m.subs(sp.Symbol("y"), EPS), EPS)).is_zero
            checked += 1
    assert checked >= 30


def test_the_threshold_3_minus_2_sqrt2_is_derived_and_agrees_with_an_algebraic_run(cmap):
    t = threshold_between(cmap, 4, 3)
    assert str(t) == "3 - 2*sqrt(2)"
    part = cmap.locate(t)
    run = run_cradle("3 - 2*sqrt(2)", v0="1")  # exact algebraic numbers, not the map's machinery
    assert run.backend.describe().startswith("exact (number field")
    assert (
        (run.stop, run.iterations, run.impact_sets)
        == ("exit", part.iterations, part.impact_sets)
        == ("exit", 3, [(0,), (1,), (0,)])
    )
    for x, formula in zip(run.exit_velocity, part.exit_velocity, strict=True):
        assert sp.simplify(run.backend.to_number(x) - formula.subs(EPS, 3 - 2 * sp.sqrt(2))) == 0


def test_the_termination_boundary_is_exact(cmap):
    (b,) = termination_boundaries(cmap)
    assert b == RealAlgebraic.from_number(certificate_check.read("7 - 4*sqrt(3)"))
    nt = cmap.non_terminating[0]
    assert nt.piece.lower_closed and nt.piece.upper_closed  # 7 - 4 sqrt(3) itself never exits
    failures = certificate_check.check(
        nt.certificate,
        ["1", "1", "1"],
        [["-1", "1", "0"], ["0", "-1", "1"]],
        interval=(str(nt.piece.lower), str(nt.piece.upper)),
    )
    assert failures == []


def test_the_checker_rejects_wrong_certificates(cmap):
    nt = cmap.non_terminating[0]
    system = (["1", "1", "1"], [["-1", "1", "0"], ["0", "-1", "1"]])
    too_wide = certificate_check.check(nt.certificate, *system, interval=("0", "1/10"))
    assert too_wide  # the cones are not invariant beyond 7 - 4 sqrt(3)
    tampered = dict(nt.certificate, mu=["1 + eps", "1 + eps"])
    assert certificate_check.check(tampered, *system, interval=(str(nt.piece.lower), str(nt.piece.upper)))
    wrong_masses = certificate_check.check(
        nt.certificate, ["1", "2", "1"], system[1], interval=(str(nt.piece.lower), str(nt.piece.upper))
    )
    assert "the Gram matrix does not match the system" in wrong_masses


def test_unequal_masses_move_the_boundary_to_the_closed_form():
    # with rho = G_01^2/(G_00 G_11), the boundary is (1 - sqrt(1 - rho))^2 / rho: derived here by hand
    m = cradle_map(masses=["1", "2", "1"], max_impulses=12)
    rho = sp.Rational(1, 9)
    expected = sp.radsimp((1 - sp.sqrt(1 - rho)) ** 2 / rho)
    (b,) = termination_boundaries(m)
    assert b == RealAlgebraic.from_number(sp.expand(expected))


def test_the_papers_aeev_rows(cmap):
    rows = {r["eps"]: r for r in aeev_rows_explained(cmap)}
    assert (rows["0.0743"]["stop"], rows["0.0743"]["iterations"]) == ("exit", 18)
    assert rows["0.01"]["stop"] == rows["0"]["stop"] == "non_terminating"


def test_counts_grow_towards_the_boundary(cmap):
    (b,) = termination_boundaries(cmap)
    counts = [n for _, n in approach_counts(b, range(2, 6))]
    assert counts == sorted(counts) and counts[-1] > 200
    for lo, hi in itertools.pairwise(counts):  # each step ten times closer: about sqrt(10) more impulses
        assert F(28, 10) < F(hi, lo) < F(36, 10)


@pytest.mark.parametrize(("balls", "bound"), [(4, 12), (5, 8)])
def test_four_and_five_balls(balls, bound):
    m = cradle_map(balls=balls, max_impulses=bound, leaving=False)
    for a, b in zip(m.parts, m.parts[1:]):
        assert a.piece.upper == b.piece.lower and a.piece.upper_closed != b.piece.lower_closed
    assert m.pieces and m.unexplored and m.non_terminating
    for part in m.pieces[-3:]:
        if not part.piece.is_point:
            r = run_cradle(inner_rational(part, F(1, 2)), v0="1", balls=balls)
            assert (r.iterations, r.impact_sets) == (part.iterations, part.impact_sets)
    assert all("no invariant cone" in p.reason or "above the boundary eps = " in p.reason for p in m.unexplored)
    # the measure of what stays undecided: the unexplored widths, from SymPy's decimals of their endpoints
    lo, hi = undecided_measure(m)
    widths = sum(sp.N(p.piece.upper.expr - p.piece.lower.expr, 30) for p in m.unexplored)
    assert 0 < lo <= hi < lo + F(1, 10**13) and abs(widths - sp.Rational(lo)) < sp.Rational(1, 10**13)
    normals = [["-1" if j == i else "1" if j == i + 1 else "0" for j in range(balls)] for i in range(balls - 1)]
    for part in m.non_terminating:  # the cone of the whole interval, at a rational point of it
        if "boundary" in part.certificate:  # checked on its whole interval in tests/maps/test_boundary.py
            continue
        if part.piece.is_point:  # eps = 0: decided as verify solve decides it, with its certificate
            assert part.piece.lower == RealAlgebraic.rational(F(0))
            cert, zeros = part.certificate, ["0"] * (balls - 1)
            if cert["kind"] == "repeating direction":
                assert certificate_check.check_repeating(cert, ["1"] * balls, normals) == []
            else:
                assert certificate_check.check_period(cert, ["1"] * balls, normals, restitution=zeros) == []
            assert run_cradle(0, v0="1", balls=balls, max_iterations=bound).stop == "non_terminating"
            continue
        eps = inner_rational(part, F(1, 2))
        cert = part.certificate
        assert cert["kind"] == "invariant cone of a period"
        at = {**cert, "restitution": [str(eps)] * (balls - 1)}
        for key in ("generators",):
            at[key] = [[str(certificate_check.read(x).subs(certificate_check.EPS, eps)) for x in g] for g in cert[key]]
        at["gram"] = [[str(certificate_check.read(x)) for x in row] for row in cert["gram"]]
        at.pop("rates")
        at["rates"] = at["generators"][0]
        assert certificate_check.check_period(at, ["1"] * balls, normals, restitution=[str(eps)] * (balls - 1)) == []
        # and a run at that point, from the map's velocity, is proved never to exit
        r = run_cradle(eps, v0="1", balls=balls, max_iterations=200)
        assert r.stop == "non_terminating"


def test_json_shape(cmap):
    data = map_json(cmap)
    assert set(data) >= {"balls", "masses", "pieces", "non_terminating", "unexplored"}
    piece = next(p for p in data["pieces"] if p["iterations"] == 3)
    assert piece["lower"] == "3 - 2*sqrt(2)" and piece["upper"] == "1"
    assert piece["lower_closed"] is True and piece["upper_closed"] is False
    assert piece["impact_sets"] == [[0], [1], [0]]
    assert sp.simplify(certificate_check.read(piece["exit_velocity"][0]) - (1 - EPS) * (EPS**2 + 3) / 8) == 0
    assert data["non_terminating"][0]["certificate"]["kind"] == "alternating invariant cone"
    json.dumps(data)


def test_bad_input():
    with pytest.raises(InvalidInput, match="must lie in"):
        cradle_map(lower="-1/2", upper="1")
    with pytest.raises(InvalidInput, match="must lie in"):
        cradle_map(lower="0", upper="3/2")
    with pytest.raises(InvalidSystem, match="balls"):
        cradle_map(balls=1)
    with pytest.raises(InvalidSystem, match="positive"):
        cradle_map(masses=["1", "0", "1"])


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["cradle-map", "--interval", "0,2"], "must lie in [0, 1]"),
        (["cradle-map", "--interval", "0"], "--interval takes two numbers"),
        (["cradle-map", "--balls", "1"], "balls must be an integer >= 2"),
        (["cradle-map", "--masses", "1,-1,1"], "must be positive"),
        (["cradle-map", "--max-impulses", "-3"], "--max-impulses must be >= 0"),
    ],
)
def test_cli_bad_input(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_cli_text_and_figure(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    fig = tmp_path / "map.png"
    assert main(["cradle-map", "--max-impulses", "10", "--approach", "3", "--figure", str(fig)]) == 0
    out = capsys.readouterr().out
    assert "3 - 2*sqrt(2)" in out and "7 - 4*sqrt(3)" in out
    assert fig.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_text_says_where_the_exact_endpoints_are_for_its_caller(capsys):
    """From the library the text names the function that holds them, from the command line --json."""
    from verify.maps.text import cradle_map_text

    small = cradle_map(max_impulses=8)
    text = cradle_map_text(small, aeev_rows=[], approach=[])
    assert "in map_json(cmap)" in text and "--json" not in text
    assert main(["cradle-map", "--max-impulses", "8", "--approach", "0"]) == 0
    assert "all of them, exactly, in --json" in capsys.readouterr().out


MAP_2112 = {"mass_matrix": [["2", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "2"]],
            "normals": [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]}  # fmt: skip


def _point_parts_and_solve(parts, system_at, velocity, cap):
    """(part, the run of solve at the part's point) for every point part with a rational value."""
    from verify.laws.rule import solve

    for part in parts:
        if part.piece.is_point and part.piece.lower.is_rational:
            yield part, solve(system_at(part.piece.lower.rational_value()), velocity, max_iterations=cap, trace=False)


@pytest.mark.parametrize("which", ["4 unit balls", "masses 2, 1, 1, 2"])
def test_a_point_part_is_decided_as_solve_decides_it(which) -> None:
    from verify.dynamics.system import System
    from verify.maps.general import eps_map
    from verify.models.cradle import cradle_system

    cap = 16
    if which == "4 unit balls":
        parts, velocity = cradle_map(4, max_impulses=cap, leaving=False).parts, ["1", "0", "0", "0"]
        masses, normals = ["1"] * 4, [[str(x) for x in row] for row in cradle_system("1", 4).source["normals"]]

        def system_at(q):
            return cradle_system(q, 4)
    else:
        velocity, masses, normals = ["1", "0", "0", "0"], ["2", "1", "1", "2"], MAP_2112["normals"]
        parts = eps_map(System(MAP_2112["mass_matrix"], normals, ["1"] * 3), velocity, ["eps"] * 3,
                        max_impulses=cap).lines[0].parts  # fmt: skip

        def system_at(q):
            return System(MAP_2112["mass_matrix"], normals, [q] * 3)

    checked = list(_point_parts_and_solve(parts, system_at, velocity, cap))
    assert checked, "no rational point part to check"
    for part, r in checked:
        assert (part.stop, part.iterations) == (r.stop, r.iterations), part.piece
    zero = next(part for part, _ in checked if part.piece.lower.rational_value() == 0)
    assert zero.stop == "non_terminating" and zero.certificate["kind"] == "repeating direction"
    # the certificate, checked by the tests' own formulas
    assert certificate_check.check_repeating(zero.certificate, masses, normals) == []
