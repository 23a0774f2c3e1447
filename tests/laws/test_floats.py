"""The float path (:mod:`verify.laws.loops.floats`): every rung gives the exact engine's branches.

Each test compares the float path with :func:`verify.laws.rule.solve` on the rational backend
(impact sets, stop, and the exit velocity inside its radius), and the rung tests check that the
case really went through the rung they name: the floats alone (the frame of the rates), the
exact catch-up, or the exact redo. Nothing here is timed (``verify bench`` measures).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from verify.bench.throughput import batch
from verify.dynamics.system import System
from verify.laws.loops import floats
from verify.laws.loops.floats import RUNG_CATCH_UP, RUNG_EXACT, RUNG_FLOATS, solve_batch, systems_batch
from verify.laws.rule import Budget, solve
from verify.models.corner import corner_batch, corner_system
from verify.properties.strategies import cases, cors, positive_rationals, small_rationals

F = Fraction
IDENTITY = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]

#: corners of the bench batch (cases 6, 18, 42, 61, 88 and 99 of ``batch()``) that alternate single
#: impacts up to the cap of 100: boxes lose their signs after 52 to 94 impulses (wrapping), the frame does not
LONG_CHAINS = [
    (F(125, 374), F(334, 91), F(130761, 136136), F(0), F(61, 228)),
    (F(47, 190), F(854, 15), F(-742553, 57000), F(47, 200), F(107, 491)),
    (F(92, 439), F(268, 47), F(-2632028, 2579125), F(42, 107), F(3, 28)),
    (F(56, 219), F(958, 17), F(-13412, 1825), F(171, 425), F(0)),
    (F(19, 139), F(255, 49), F(117249, 170275), F(415, 781), F(3, 23)),
    (F(277, 895), F(328, 45), F(-181712, 201375), F(36, 233), F(97, 295)),
]
#: corners of slope 1 of the bench batch (cases 4434 and 4574): G_01 = 0, so the multiple impact leaves
#: the rate of the wall with COR 0 exactly 0, a zero the floats cannot see and the catch-up decides
SLOPE_ONE = [(F(1), F(137, 18), F(-98777, 18000), F(1), F(0)), (F(1), F(181, 11), F(181, 2200), F(0), F(1))]


def _corners(cases_):
    return corner_batch([c[0] for c in cases_], [c[1:3] for c in cases_], [c[3:] for c in cases_])


def _assert_exact(pairs, out, max_iterations: int = 100, budget: Budget | None = None) -> list:
    """The float path's result of each (system, velocity) is the exact engine's; returns the exact results."""
    results = []
    for i, (s, v) in enumerate(pairs):
        exact = solve(s, v, max_iterations=max_iterations, trace=False, certify=False, budget=budget)
        results.append(exact)
        assert out.impact_sets(i) == list(exact.impact_sets), i
        assert out.stop[i] == exact.stop, i
        if exact.stop == "budget":
            continue
        assert out.iterations[i] == exact.iterations, i
        for j, x in enumerate(exact.exit_velocity):  # the radius encloses the exact value
            value = s.backend.to_number(x)
            if np.isinf(out.r_v[i][j]):  # beyond the float range: all the float path can say
                assert abs(value) > 2**1000
                continue
            assert abs(Fraction(float(out.v[i][j])) - value) <= Fraction(float(out.r_v[i][j])), (i, j)
    assert (out.fallback == (out.rung > 0)).all()
    return results


def _corner_pairs(cases_):
    return [(corner_system(k, e1, e2), [xd, yd, 0]) for k, xd, yd, e1, e2 in cases_]


def test_long_single_impact_chains_are_decided_by_the_frame_alone() -> None:
    out = solve_batch(_corners(LONG_CHAINS), 100)
    _assert_exact(_corner_pairs(LONG_CHAINS), out)
    assert out.rung.tolist() == [RUNG_FLOATS] * len(LONG_CHAINS)
    assert out.iterations.tolist() == [100] * len(LONG_CHAINS)


def test_boxes_lose_those_chains_and_catch_up_exactly_in_the_middle() -> None:
    """The box loop (the one for r != 2) on the same chains: it cannot decide them, catches up
    exactly after 52 to 94 impulses, and goes on in floats from there to the same result."""
    batch_ = _corners(LONG_CHAINS)
    run = floats._Run(batch_, 100, True, None)
    with np.errstate(all="ignore"):
        floats._boxes(run)
    run.redo_exactly()
    out = run.result()
    _assert_exact(_corner_pairs(LONG_CHAINS), out)
    assert out.rung.tolist() == [RUNG_CATCH_UP] * len(LONG_CHAINS)
    assert all(0 < w < 100 for w, _ in run.anchors.values())  # caught up mid-run, floats after


def test_a_zero_the_structure_does_not_explain_is_caught_up_exactly() -> None:
    out = solve_batch(_corners(SLOPE_ONE), 100)
    _assert_exact(_corner_pairs(SLOPE_ONE), out)
    assert out.rung.tolist() == [RUNG_CATCH_UP] * 2
    assert out.exact_results == {}  # not redone: the catch-up decided them
    assert out.rung_counts() == {"floats": 0, "catch_up": 2, "exact": 0}


def test_a_cor_of_0_at_a_single_impact_is_decided_in_floats() -> None:
    """After a single impact on j its rate is ``-e_j b_j >= 0``: known by structure, also when it is 0."""
    chain = [(F(1, 2), F(2), F(0), F(0), F(1)), LONG_CHAINS[0], LONG_CHAINS[3]]  # a COR of 0 each
    out = solve_batch(_corners(chain), 100)
    _assert_exact(_corner_pairs(chain), out)
    assert out.rung.tolist() == [RUNG_FLOATS] * 3


def test_the_frame_is_caught_up_mid_run_and_goes_on_in_floats() -> None:
    """Rates on the slower eigenvector of the two-impulse map (``b_0 = -3 b_1`` every other
    impulse): float errors grow against them, and after 95 impulses only exact arithmetic
    decides; the floats then go on to the cap."""
    s = System(IDENTITY, [[-2, F(3, 2), -2], [F(2, 3), F(-1, 2), F(1, 3)]], [F(1, 2), F(1, 2)])
    run = floats._Run(systems_batch([s], [[-4, -1, 0]]), 100, True, None)
    with np.errstate(all="ignore"):
        floats._plane(run)
    run.redo_exactly()
    out = run.result()
    _assert_exact([(s, [-4, -1, 0])], out)
    assert out.rung.tolist() == [RUNG_CATCH_UP] and 0 < run.anchors[0][0] < 100 == out.iterations[0]


def test_the_exact_rung_takes_what_floats_cannot_hold() -> None:
    """Velocities beyond the float range (overflow) or below it (they round to 0): the catch-up
    cannot re-anchor the floats, so the cases are redone exactly; for two and three constraints."""
    huge, tiny = F(10**400), F(1, 10**400)
    corner = corner_system(F(1, 2), F(1, 2), F(1, 3))
    three = System([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]],
                   [[-1, 1, 0, 0], [0, -1, 1, 0], [0, 0, -1, 1]], [F(1, 2), F(1, 3), 1])  # fmt: skip
    for s, velocities in (
        (corner, [[huge, 0, 0], [tiny, 0, 0], [2, 1, 0]]),
        (three, [[huge, 0, 0, 0], [tiny, 0, 0, 0], [3, 1, 0, 0]]),
    ):
        out = solve_batch(systems_batch([s] * 3, velocities), 100)
        exact = _assert_exact([(s, v) for v in velocities], out)
        assert out.rung.tolist() == [RUNG_EXACT, RUNG_EXACT, RUNG_FLOATS]
        assert sorted(out.exact_results) == [0, 1]
        assert [r.impact_sets for r in exact[:2]] != [[], []]  # the redos do impulses
        undecided = solve_batch(systems_batch([s] * 3, velocities), 100, exact_fallback=False)
        assert undecided.stop[:2] == ["undecided", "undecided"] and undecided.rung.tolist()[:2] == [RUNG_EXACT] * 2


def test_a_budget_ends_a_catch_up_where_it_ends_the_exact_run() -> None:
    budget = Budget(bits=8)
    out = solve_batch(_corners(SLOPE_ONE), 100, budget=budget)
    _assert_exact(_corner_pairs(SLOPE_ONE), out, budget=budget)
    assert out.stop == ["budget", "budget"] and out.rung.tolist() == [RUNG_CATCH_UP] * 2


def test_the_bench_batch_with_every_rung() -> None:
    cases_ = batch(600) + SLOPE_ONE + LONG_CHAINS
    out = solve_batch(_corners(cases_), 100)
    _assert_exact(_corner_pairs(cases_), out)
    assert out.rung_counts()["catch_up"] >= 2 and out.rung_counts()["floats"] > 590


@st.composite
def corner_cases(draw):
    """Corners with slope 1 drawn often (G diagonal: zeros), CORs 0 and 1 drawn often, any velocity."""
    k = draw(st.just(F(1)) | positive_rationals(max_denominator=30, bound=10))
    v = [draw(small_rationals(max_denominator=20, bound=20)), draw(small_rationals(max_denominator=20, bound=20))]
    return (k, *v, draw(cors()), draw(cors()))


@st.composite
def coincidental_zeros(draw):
    """Corners whose single impact on wall j leaves the rate of the other wall o exactly 0 (no
    structure explains it: ``b_o = S_jo q`` for ``b_j = -q``), the floats' value of it rounding
    noise of either sign. ``S_jo = -(1 + e_j)(k^2 - 1)/(k^2 + 1)`` is positive for k < 1, so o is not hit first."""
    k = draw(positive_rationals(max_denominator=30, bound=10).filter(lambda x: x != 1))
    k = min(k, 1 / k)
    e = [draw(cors()), draw(cors())]
    j = draw(st.integers(0, 1))
    q = draw(positive_rationals(max_denominator=97, bound=50))
    rate = {j: -q, 1 - j: -(1 + e[j]) * (k * k - 1) / (k * k + 1) * q}
    b0, b1 = rate[0], rate[1]
    return (k, -(b0 + b1) / (2 * k), (b0 - b1) / 2, e[0], e[1])  # b0 = -(k xd - yd), b1 = -(k xd + yd)


@settings(max_examples=40, deadline=None)
@given(st.lists(coincidental_zeros(), min_size=1, max_size=20))
def test_coincidental_zeros(drawn) -> None:
    out = solve_batch(_corners(drawn), 100)
    _assert_exact(_corner_pairs(drawn), out)
    assert (out.rung == RUNG_CATCH_UP).all()  # every such zero needs the exact catch-up


@settings(max_examples=30, deadline=None)
@given(st.lists(corner_cases(), min_size=1, max_size=30))
def test_random_corners(drawn) -> None:
    out = solve_batch(_corners(drawn), 100)
    _assert_exact(_corner_pairs(drawn), out)


@settings(max_examples=40, deadline=None)
@given(st.lists(cases("general", "general") | cases("cradle", "general"), min_size=1, max_size=8))
def test_random_systems_on_both_loops(drawn) -> None:
    """General systems (r = 1..4, some rates exactly 0) and cradles (equal masses: ties), on the
    frame (r = 2) or on boxes."""
    records = [d.record for d in drawn]
    shape = (len(records[0]["mass_matrix"]), len(records[0]["normals"]))
    records = [r for r in records if (len(r["mass_matrix"]), len(r["normals"])) == shape and not r.get("time_terms")]
    systems = [System(r["mass_matrix"], r["normals"], r["restitution"]) for r in records]
    if not systems or not all(s.backend.fraction_free for s in systems):
        return
    velocities = [r["velocity"] for r in records]
    budget = Budget(bits=4096)  # multiple impacts can triple the sizes: bound them
    out = solve_batch(systems_batch(systems, velocities), 60, budget=budget)
    _assert_exact(list(zip(systems, velocities)), out, max_iterations=60, budget=budget)


def test_a_run_decided_below_the_working_precision_is_flagged():
    """4 balls of masses 1, 2, 3, 4, eps = 0.1: exact arithmetic proves that the rule never lets go, while
    mp and float runs "exit" after their rates fall below the working precision: both say so."""
    from verify.models.cradle import cradle_system

    velocity = ["100", "0", "0", "0"]
    exact = solve(cradle_system("1/10", 4, ["1", "2", "3", "4"]), velocity, max_iterations=10_000)
    assert exact.stop == "non_terminating" and exact.doubtful is None
    for backend in ("mp", "float"):
        r = solve(cradle_system("1/10", 4, ["1", "2", "3", "4"], backend=backend), velocity, max_iterations=10_000)
        assert r.stop == "exit" and r.doubtful is not None and r.doubtful < r.iterations  # the false exit, flagged
        assert any(n.startswith(f"not to be trusted from impulse {r.doubtful} on") for n in r.notes)
        assert "--backend exact" in r.notes[-1]
    clear = solve(cradle_system("1/2", 4, ["1", "2", "3", "4"], backend="mp"), velocity)  # a short run, clear signs
    assert clear.stop == "exit" and clear.doubtful is None and not clear.notes
