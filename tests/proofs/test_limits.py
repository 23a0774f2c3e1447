"""Where a run that never exits tends (verify.proofs.limits): the cradle's collapse to the common velocity.

The limit is checked against the run itself: the rule's single impulses, applied alternately by hand (eq. 4
written out here, not the package's loop), approach it geometrically.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from tests.helpers import Poison, assert_exact_vector, exact_value
from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.models.cradle import cradle_system
from verify.proofs.limits import alternation_limit


@pytest.mark.parametrize("eps", ["0", "1/100", "7/100"])
def test_three_balls_tend_to_the_common_velocity(eps: str) -> None:
    system = cradle_system(eps)
    run = solve(system, [Poison(100), Poison(0), Poison(0)])
    assert run.stop == "non_terminating"
    limit = run.limit
    assert limit is not None
    assert_exact_vector([Fraction(100, 3)] * 3, system.backend, limit.velocity)
    assert exact_value(system.backend, limit.kinetic_energy) == Fraction(5000, 3)
    assert exact_value(system.backend, limit.determinant) == Fraction(eps) ** 2


def _impulse(v: list[Fraction], j: int, e: Fraction, masses: tuple[int, ...] = (1, 1, 1), *, forced: bool = False):
    """Eq. (4) for balls j and j + 1 of these masses, written out: the impulse that turns their relative velocity
    w into -e w (none when they separate, unless ``forced``: then it is the linear map of one impact)."""
    w = v[j + 1] - v[j]
    if w >= 0 and not forced:
        return v
    impulse = -(1 + e) * w / (Fraction(1, masses[j]) + Fraction(1, masses[j + 1]))
    out = list(v)
    out[j] -= impulse / masses[j]
    out[j + 1] += impulse / masses[j + 1]
    return out


def test_unequal_masses_and_cors_tend_to_their_common_velocity() -> None:
    """Masses 1, 2, 3, CORs 1/100 and 3/100: the limit is the velocity of the centre of mass, and the period map's
    trace and determinant are the ones of the period written out here (two impacts applied to two velocities)."""
    masses, e = (1, 2, 3), (Fraction(1, 100), Fraction(3, 100))
    system = System([[1, 0, 0], [0, 2, 0], [0, 0, 3]], [[-1, 1, 0], [0, -1, 1]], [str(x) for x in e])
    limit = solve(system, ["100", "0", "0"]).limit
    assert limit is not None
    assert_exact_vector([Fraction(50, 3)] * 3, system.backend, limit.velocity)

    def rates(v: list[Fraction]) -> tuple[Fraction, Fraction]:
        return v[1] - v[0], v[2] - v[1]

    def period(v: list[Fraction]) -> tuple[Fraction, Fraction]:
        return rates(_impulse(_impulse(v, 0, e[0], masses, forced=True), 1, e[1], masses, forced=True))

    (a, c), (b, d) = period([Fraction(-1), Fraction(0), Fraction(0)]), period([Fraction(0), Fraction(0), Fraction(1)])
    # the velocities above have rates (1, 0) and (0, 1): the columns of P
    assert exact_value(system.backend, limit.trace) == a + d
    assert exact_value(system.backend, limit.determinant) == a * d - b * c


def test_the_run_approaches_its_limit_geometrically() -> None:
    e = Fraction(1, 100)
    v = [Fraction(100), Fraction(0), Fraction(0)]
    limit = solve(cradle_system(e), v).limit
    assert limit is not None
    target = [Fraction(x) for x in limit.velocity]
    gaps = []
    for k in range(40):
        v = _impulse(v, k % 2, e)
        gaps.append(max(abs(a - b) for a, b in zip(v, target)))
    assert all(b < a for a, b in zip(gaps[1::2], gaps[3::2])), "the gap falls every period"
    assert gaps[-1] < Fraction(1, 10**6) < gaps[0]


def test_no_limit_is_claimed_without_a_proof() -> None:
    cone = {"kind": "alternating invariant cone"}
    elastic = cradle_system("1")  # det P = e0 e1 = 1: the rates need not fall
    assert alternation_limit(elastic, elastic.velocity(["100", "0", "0"]), cone) is None
    assert solve(elastic, ["100", "0", "0"]).limit is None, "a run that exits has no limit"
    inelastic = cradle_system("1/100")
    v = inelastic.velocity(["100", "0", "0"])
    assert alternation_limit(inelastic, v, None) is None
    assert alternation_limit(inelastic, v, {"kind": "repeating direction"}) is None
    floats = cradle_system("1/100", backend="mp")
    assert solve(floats, ["100", "0", "0"]).limit is None, "signs on a backend that is not rigorous prove nothing"
