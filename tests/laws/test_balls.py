"""The ball engine (:mod:`verify.laws.loops.balls`) against the exact rule.

Every run here is compared with :func:`verify.laws.rule.solve` on the rationals: the same
impact sets and stop, and enclosures (exit velocity, betas) that contain the exact values.
Nothing is timed (``verify bench`` measures).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

import pytest
from hypothesis import given, settings

from verify.bench.throughput import LONG_RUN
from verify.dynamics.policy import Limits, Run
from verify.dynamics.system import System
from verify.errors import Undecided
from verify.laws.loops import balls
from verify.laws.rule import Budget, _ExactRates, impulse, solve
from verify.models.corner import corner_system
from verify.numbers.backends import IntervalBackend
from verify.properties.strategies import cases

DPS = 50


def _exact_check(exact: System, velocity: Sequence[Any], calls: list[int] | None = None) -> Callable:
    """The ``exact`` callback: replays the impact sets exactly, 0 for an exact 0, else raises."""

    def check(system: System, impact_sets: Sequence[tuple[int, ...]], i: int, exc: Undecided) -> int:
        if calls is not None:
            calls.append(i)
        v = exact.velocity(velocity)
        for J in impact_sets:
            v = tuple(x + y for x, y in zip(v, impulse(exact, v, J)))
        if exact.backend.sign(exact.rates(v)[i]) == 0:
            return 0
        raise exc

    return check


def _assert_encloses(system: System, run: Run, exact: Any) -> None:
    """Same impact sets and stop as the exact result, and enclosures that contain its values."""
    K, Q = system.backend, exact.backend
    assert run.impact_sets == list(exact.impact_sets)
    assert run.stop == exact.stop
    for x, y in zip(run.v, exact.exit_velocity, strict=True):
        assert K.contains(x, Fraction(Q.to_number(y))), (K.enclosure(x), Q.to_exact(y))
    for b, y in zip(run.betas, exact.betas, strict=True):
        assert (b is None) == (y is None)
        if b is not None:
            assert K.contains(b, Fraction(Q.to_number(y)))


def _ball_run(exact: System, velocity: Sequence[Any], cap: int, dps: int = DPS) -> tuple[System, Run]:
    """The ball engine from ``dps`` digits, doubling them after an undecided sign (as solve does)."""
    while True:
        system = exact.convert_to(IntervalBackend(dps, max_dps=800))
        try:
            return system, balls.iterate(
                system, system.velocity(velocity), Limits(cap), exact=_exact_check(exact, velocity)
            )
        except Undecided:
            if dps >= 800:
                raise
            dps *= 2


def _check_drawn(drawn: Any, cap: int = 60, dps: int = DPS) -> None:
    rec = drawn.record
    s = System(rec["mass_matrix"], rec["normals"], rec["restitution"], rec.get("time_terms"))
    exact = solve(s, rec["velocity"], max_iterations=cap, trace=False, certify=False, budget=Budget(bits=4096))
    if exact.stop == "budget":
        return
    system, run = _ball_run(s, rec["velocity"], cap, dps)
    _assert_encloses(system, run, exact)


@settings(max_examples=80, deadline=None)
@given(cases("general", "general"))
def test_general_systems_enclose_the_exact_run(drawn) -> None:
    _check_drawn(drawn)


@settings(max_examples=80, deadline=None)
@given(cases("general", "general"))
def test_general_systems_at_low_precision(drawn) -> None:
    """From 6 digits: the system's own constants are then wide intervals and the radius is near
    its bounds, so an error bound too small would show here first."""
    _check_drawn(drawn, dps=6)


@settings(max_examples=40, deadline=None)
@given(cases("cradle", "general"))
def test_cradles_enclose_the_exact_run(drawn) -> None:
    """Cradles: many general multiple impacts (adjacent contacts are coupled)."""
    _check_drawn(drawn)


@settings(max_examples=40, deadline=None)
@given(cases("corner", "general"))
def test_corners_enclose_the_exact_run(drawn) -> None:
    _check_drawn(drawn)


def _long_run(count: int, dps: int = DPS) -> tuple[System, Run, Any]:
    k, (xd, yd), (e1, e2) = LONG_RUN["slope"], LONG_RUN["velocity"], LONG_RUN["cors"]
    exact = solve(corner_system(k, e1, e2), [xd, yd, 0], max_iterations=count, trace=False, certify=False)
    system = corner_system(k, e1, e2, backend=IntervalBackend(dps))
    return system, balls.iterate(system, system.velocity([xd, yd, 0]), Limits(count)), exact


def test_the_long_corner_run_keeps_its_precision() -> None:
    """2,000 impulses of the bench's long run at 50 digits (component-wise intervals need
    hundreds there): no undecided sign, the exact impact sets, 40 digits of the velocity kept."""
    system, run, exact = _long_run(2000)
    assert len(run.impact_sets) == 2000 and run.stop == "max_iterations"
    _assert_encloses(system, run, exact)
    assert system.backend.dps == DPS
    for x in run.v:
        lo, hi = (Fraction(s) for s in system.backend.enclosure(x, 60))
        assert hi - lo < Fraction(1, 10**40)


def test_the_error_is_added_per_impulse_not_multiplied() -> None:
    """Each impulse adds an error relative to the rates (the maps do not expand), so the relative
    width of the enclosure grows about linearly with the impulses: about 10 times from 200 to
    2,000 (component-wise intervals lose half a digit per impulse: 10^900 times)."""

    def relative_width(count: int) -> Fraction:
        system, run, _ = _long_run(count)
        lo, hi = (Fraction(s) for s in system.backend.enclosure(run.v[1], 60))
        return (hi - lo) / abs(hi)

    assert relative_width(2000) < 20 * relative_width(200)


def test_exit_and_caps_follow_the_shared_stop_policy() -> None:
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    si = s.convert_to(IntervalBackend(DPS))
    for cap in range(5):
        exact = solve(s, ["100", "0", "0"], max_iterations=cap, trace=False, certify=False)
        run = balls.iterate(si, si.velocity(["100", "0", "0"]), Limits(cap))
        assert run.stop == ("exit" if cap >= 3 else "max_iterations")
        _assert_encloses(si, run, exact)


def test_moving_constraints() -> None:
    """Time terms shift the rates; the exit velocity still encloses the exact one."""
    s = System([[2, 0, 0], [0, 1, 0], [0, 0, 3]], [[-1, 1, 0], [0, -1, 1]], ["1/3", "2/7"], ["1/5", "-1/3"])
    velocity = ["7/3", "1/11", "-2/9"]
    exact = solve(s, velocity, trace=False, certify=False)
    si = s.convert_to(IntervalBackend(DPS))
    run = balls.iterate(si, si.velocity(velocity), Limits(1000))
    assert exact.iterations > 2
    _assert_encloses(si, run, exact)


def test_a_cor_of_zero_is_an_exact_zero_without_an_exact_check() -> None:
    """A single impact with COR 0 makes its rate exactly 0, and the impulses on constraints
    orthogonal to it (G_1j = 0) keep that knowledge: every sign is decided with no exact
    callback, which an interval around 0 would need otherwise."""
    normals = [["1/3", 0, 0, 0], [0, 1, "1/5", 0], [0, -1, "1/7", "1/3"]]  # S1 orthogonal to S2, S3
    s = System([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], normals, [0, "1/2", 1])
    velocity = ["-1", "-1", "0", "0"]  # S1 and S2 hit together: G_12 = 0, two single impacts
    exact = solve(s, velocity, trace=False, certify=False)
    si = s.convert_to(IntervalBackend(DPS))
    run = balls.iterate(si, si.velocity(velocity), Limits(100))  # exact=None: an Undecided would raise
    _assert_encloses(si, run, exact)
    assert run.impact_sets[0] == (0, 1) and run.betas[0] == si.backend.one
    assert len(run.impact_sets) > 2 and all(0 not in J for J in run.impact_sets[1:])  # S1's rate stays 0
    assert Fraction(s.backend.to_number(s.rates(exact.exit_velocity)[0])) == 0


def test_a_cor_of_zero_in_a_corner() -> None:
    """The corner with COR 0 on S1 at a single impact: rate 1 is exactly 0 next (sign 0)."""
    s = corner_system("1/3", 0, "1/2")
    velocity = ["0", "-1", "0"]
    exact = solve(s, velocity, trace=False, certify=False)
    si = corner_system("1/3", 0, "1/2", backend=IntervalBackend(DPS))
    run = balls.iterate(si, si.velocity(velocity), Limits(100))
    assert run.impact_sets[0] == (0,)
    _assert_encloses(si, run, exact)


def _grazing() -> tuple[System, list[str]]:
    """A rate that is exactly 0 but not by structure: 1/3 * 3 - 1 is an interval around 0."""
    return System([[1, 0], [0, 1]], [["1/3", 1], [1, "-1/2"]], [1, 1]), ["3", "-1"]


def test_an_undecided_sign_raises_without_an_exact_check() -> None:
    s, velocity = _grazing()
    si = s.convert_to(IntervalBackend(DPS))
    with pytest.raises(Undecided, match="rate of S1 after 0 impulses"):
        balls.iterate(si, si.velocity(velocity), Limits(10))


def test_an_undecided_sign_goes_to_the_exact_check() -> None:
    s, velocity = _grazing()
    si = s.convert_to(IntervalBackend(DPS))
    calls: list[int] = []
    run = balls.iterate(si, si.velocity(velocity), Limits(10), exact=_exact_check(s, velocity, calls))
    assert calls == [0]  # asked once: then known to be 0
    _assert_encloses(si, run, solve(s, velocity, trace=False, certify=False))
    # the rule's own exact check (what solve passes) gives the same
    checks = _ExactRates(si, velocity).at(limit=False)
    assert balls.iterate(si, si.velocity(velocity), Limits(10), exact=checks).impact_sets == run.impact_sets


def test_a_tiny_non_zero_rate_is_left_to_more_precision() -> None:
    """A rate of 10^-60 at 50 digits: the exact check finds it non-zero and raises; at 100
    digits the ball decides it."""
    s = System([[1, 0], [0, 1]], [["1/3", 1]], [1])
    velocity = ["3", f"-1 + 1/{10**60}"]
    si = s.convert_to(IntervalBackend(DPS))
    with pytest.raises(Undecided):
        balls.iterate(si, si.velocity(velocity), Limits(10), exact=_exact_check(s, velocity))
    finer = s.convert_to(IntervalBackend(2 * DPS))
    run = balls.iterate(finer, finer.velocity(velocity), Limits(10))
    _assert_encloses(finer, run, solve(s, velocity, trace=False, certify=False))


def test_the_engine_refuses_other_backends() -> None:
    s = System([[1, 0], [0, 1]], [[-1, 1]], ["1/2"])
    with pytest.raises(ValueError, match="interval backend"):
        balls.iterate(s, s.velocity(["1", "0"]), Limits(10))


def test_the_lipschitz_bound_is_a_bound() -> None:
    """Over every multiple impulse of a cradle run: at least the norm of the Jacobian at the
    midpoint (computed in floats), and not far above it."""
    import numpy as np

    from verify.models.cradle import cradle_system

    seen: list[tuple[float, float]] = []
    original = balls.lipschitz_bound

    def spy(wide: balls.Wide, jac: Sequence[Sequence[Any]]) -> Any:
        bound = original(wide, jac)
        G = np.array([[float(balls._mid(x)) for x in row] for row in wide.gram])
        M = np.array([[float(balls._mid(x)) for x in row] for row in jac])
        L = np.linalg.cholesky(G)
        seen.append((float(bound), float(np.linalg.norm(np.linalg.solve(L, M @ L), 2))))
        return bound

    balls.lipschitz_bound = spy
    try:
        s = cradle_system(["1", "1/2", "1"], 4, ["1", "2", "1", "3"])
        velocity = ["2", "0", "-1", "0"]  # both contacts of ball 2 at once: G_12 != 0
        exact = solve(s, velocity, trace=False, certify=False)
        si = s.convert_to(IntervalBackend(DPS))
        _assert_encloses(si, balls.iterate(si, si.velocity(velocity), Limits(200)), exact)
    finally:
        balls.lipschitz_bound = original
    assert seen
    for bound, norm in seen:
        assert norm * (1 - 1e-9) <= bound <= norm * (1 + 1e-5) + 1e-10


def test_the_ball_holds_every_run_from_a_box_of_velocities() -> None:
    """The left velocity an interval box 10^-12 wide: the ball then is mostly that width carried
    through the impulses (general multiple impacts with Jacobians of norm up to 5 here), and its
    exit enclosure must hold the exact runs from the corners of the box."""
    from itertools import product

    from verify.models.cradle import cradle_system

    s = cradle_system(["1", "1/2", "1"], 4, ["1", "2", "1", "3"])
    centre = [Fraction(2), Fraction(0), Fraction(-1), Fraction(0)]
    half = Fraction(1, 10**12)
    si = s.convert_to(IntervalBackend(DPS))
    K = si.backend
    box = tuple(K.ctx.mpf([K.convert(x - half).a, K.convert(x + half).b]) for x in centre)
    run = balls.iterate(si, box, Limits(200))
    assert any(b is not None for b in run.betas)
    for signs in product((-1, 1), repeat=4):
        corner = [x + sign * half for x, sign in zip(centre, signs)]
        _assert_encloses(si, run, solve(s, corner, trace=False, certify=False))


def test_any_sum_of_coefficients_gives_an_enclosure(monkeypatch) -> None:
    """The exit velocity ``v0 + U^T mu + U^T G^-1 (b - m + e)`` holds for any mu (e = m - b0 - G mu
    takes up the difference): a mu off by 10^-20 still gives an enclosure, only a wider one."""
    s = corner_system("1/7", "1/3", 1)
    velocity = ["1", "1/11", "0"]
    exact = solve(s, velocity, trace=False, certify=False)
    si = corner_system("1/7", "1/3", 1, backend=IntervalBackend(DPS))
    original = balls._velocity

    def shifted(system: System, data: balls.BallData, v0: Any, b0: Any, ball: Any) -> Any:
        ball.mu = [x + (1 << ball.P) // 10**20 for x in ball.mu]
        return original(system, data, v0, b0, ball)

    plain = balls.iterate(si, si.velocity(velocity), Limits(100))
    monkeypatch.setattr(balls, "_velocity", shifted)
    run = balls.iterate(si, si.velocity(velocity), Limits(100))
    _assert_encloses(si, run, exact)
    lo, hi = (Fraction(x) for x in si.backend.enclosure(run.v[0], 60))
    lo0, hi0 = (Fraction(x) for x in si.backend.enclosure(plain.v[0], 60))
    assert hi - lo > 10**10 * (hi0 - lo0)


def test_an_untouched_zero_survives_a_general_multiple_impulse() -> None:
    """Rate 1 is exactly 0 from the start (a point interval); the multiple impulse on S2 and S3
    (coupled: beta from the rates) does not touch S1 (G_12 = G_13 = 0), so its sign stays 0."""
    normals = [[1, 0, 0, 0], [0, 1, "1/5", 0], [0, -1, "1/7", "1/3"]]
    s = System([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], normals, ["1/2", "1/2", "1/2"])
    velocity = ["0", "0", "-1", "-1"]
    exact = solve(s, velocity, trace=False, certify=False)
    si = s.convert_to(IntervalBackend(DPS))
    run = balls.iterate(si, si.velocity(velocity), Limits(100))  # exact=None
    assert run.impact_sets[0] == (1, 2) and run.betas[0] != si.backend.one
    _assert_encloses(si, run, exact)


def _exact_phi(G: list[list[Fraction]], e: list[Fraction], b: list[Fraction], J: tuple[int, ...]) -> list[Fraction]:
    """The multiple impulse on J in rates (eq. 8 with beta from the rates), in Fractions."""
    lam = {j: b[j] / G[j][j] for j in J}
    beta = sum(b[j] * lam[j] for j in J) / sum(lam[j] * G[j][k] * lam[k] for j in J for k in J)
    c = {j: -beta * (1 + e[j]) * lam[j] for j in J}
    return [b[i] + sum(G[i][j] * c[j] for j in J) for i in range(len(b))]


def test_a_general_multiple_impulse_keeps_the_ball_invariant() -> None:
    """From a ball of radius 10^-12 around m, every point b of it (the direction of greatest
    stretch included: the Jacobian's norm is 2.78 here) has its exact image in the new ball,
    measured exactly in the norm d^T G^-1 d."""
    import numpy as np

    from verify.numbers.backends import RationalBackend
    from verify.numbers.linalg import ldl, solve_spd

    s = System([[1, 0, 0], [0, 2, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    Q = s.backend
    G = [[Fraction(Q.to_number(x)) for x in row] for row in s.gram]
    K = RationalBackend("python")
    factors = ldl(K, G)
    columns = [solve_spd(K, factors, [Fraction(int(i == k)) for i in range(2)]) for k in range(2)]
    inverse = [[columns[k][i] for k in range(2)] for i in range(2)]

    def norm2(d: Sequence[Fraction]) -> Fraction:
        return sum(d[i] * inverse[i][k] * d[k] for i in range(2) for k in range(2))

    si = s.convert_to(IntervalBackend(DPS))
    data = balls.ball_data(si)
    P = data.bits
    M = [round(Fraction(-1) * (1 << P)), round(Fraction(-2, 3) * (1 << P))]
    m = [Fraction(x, 1 << P) for x in M]
    radius = Fraction(1, 10**12)
    ball = balls._Ball(list(M), [0, 0], int(radius * (1 << P)), P, [False, False])
    wide = data.widened(si)
    jac, _ = balls._jacobian(wide, [wide.backend.convert(x) for x in m], (0, 1))
    balls._general(si, data, ball, (0, 1), ())
    new_m = [Fraction(x, 1 << P) for x in ball.M]
    new_radius = Fraction(ball.rho, 1 << P)
    Gf = np.array([[float(x) for x in row] for row in G])
    L = np.linalg.cholesky(Gf)
    Jf = np.array([[float(balls._mid(x)) for x in row] for row in jac])
    h = Fraction(1, 10**20)  # the Jacobian is the map's: against exact difference quotients
    at = _exact_phi(G, [Fraction(1), Fraction(1)], m, (0, 1))
    for k in range(2):
        moved = _exact_phi(G, [Fraction(1), Fraction(1)], [x + h * (i == k) for i, x in enumerate(m)], (0, 1))
        for i in range(2):
            assert abs(float((moved[i] - at[i]) / h) - Jf[i][k]) < 1e-9
    _, stretch, vt = np.linalg.svd(np.linalg.solve(L, Jf @ L))
    assert stretch[0] > 2.7
    directions = [L @ vt[0], -(L @ vt[0]), L @ vt[1], np.array([1.0, 0.0]), np.array([0.3, -1.0])]
    for direction in directions:
        d = [Fraction(float(x)) for x in direction]
        scale = radius / (Fraction(math.isqrt(math.ceil(norm2(d) * 10**40)) + 1, 10**20))  # ||scale d|| <= radius
        image = _exact_phi(G, [Fraction(1), Fraction(1)], [mi + scale * di for mi, di in zip(m, d)], (0, 1))
        assert norm2([y - z for y, z in zip(image, new_m)]) <= new_radius**2
    # and the bound is not loose: the stretched direction reaches 90 % of the new radius
    d = [Fraction(float(x)) for x in L @ vt[0]]
    scale = radius / (Fraction(math.isqrt(math.ceil(norm2(d) * 10**40)) + 1, 10**20))
    image = _exact_phi(G, [Fraction(1), Fraction(1)], [mi + scale * di for mi, di in zip(m, d)], (0, 1))
    assert norm2([y - z for y, z in zip(image, new_m)]) >= (new_radius * Fraction(9, 10)) ** 2
