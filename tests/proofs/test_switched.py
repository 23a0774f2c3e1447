"""Runs that switch between impact sets in no period: cones around the run's own points, pushed out by a slack
(verify.proofs.cones.hull), closed by the period search and checked by the independent checker
(tests/certificate_check.py)."""

from __future__ import annotations

import copy
from fractions import Fraction
from typing import Any

import pytest

pytest.importorskip("ppl")  # pplpy: a dependency on Linux and macOS; elsewhere the search is skipped

from tests import certificate_check
from tests.properties.test_properties import AT_CAP
from verify import bounds
from verify.numbers.backends.rational import RationalBackend
from verify.proofs import termination
from verify.proofs.cones import hull
from verify.properties.verdicts import Runner

K = RationalBackend("python")


def _q(text: str) -> Any:
    return K.convert(Fraction(text))


@pytest.fixture(scope="module")
def at_cap() -> Any:
    """AT_CAP (five balls, CORs 1, 1/10, 0, 0) as the census runs it, with the census' cap, and what its search
    used. It hits (1,3) every other impulse and (0,2) or (2) between, as the sign of rate 0 says, in no period."""
    record = dict(AT_CAP, max_iterations=4000)
    with bounds.recording() as seen:
        result = Runner()(record, "general", decide=True)
    return record, result, seen


def test_a_run_that_switches_in_no_period_is_proved_never_to_exit_and_the_checker_agrees(at_cap):
    record, result, seen = at_cap
    assert result.stop == "non_terminating", result.notes
    assert result.iterations < 4000 and result.iterations >= termination.SWITCHED_AFTER
    # before the proof: (1,3) every other impulse, and (0,2) or (2) between, both taken
    sets = [tuple(J) for J in result.impact_sets]
    assert all(J == (1, 3) for J in sets[::2])
    assert set(sets[1::2]) == {(0, 2), (2,)}
    cert = result.certificate
    assert cert["kind"] == "invariant cone of a period" and cert["rigorous"] and cert["impulses"] % 2 == 0
    assert seen["hull_rays"] <= hull.MAX_HULL_RAYS and "hull_rays:reached" not in seen
    failures = certificate_check.check_period(
        cert, record["mass_matrix"], record["normals"], rates=cert.get("rates"), restitution=record["restitution"]
    )
    assert failures == []


def test_the_checker_refuses_broken_variants_of_a_switched_cone(at_cap):
    record, result, _ = at_cap
    cert = result.certificate
    masses, normals, cors = record["mass_matrix"], record["normals"], record["restitution"]

    fewer = copy.deepcopy(cert)  # a generator dropped: some vector carried through the period leaves the cone
    used = {int(k) for c in cert["carried"] for k in c["combination"]}
    last = max(used)
    fewer["generators"].pop(last)
    fewer["strict"].pop(last)
    assert certificate_check.check_period(fewer, masses, normals, restitution=cors)

    boxed = copy.deepcopy(cert)  # the run's rates said to lie elsewhere: the cone no longer holds them
    assert "box" in boxed  # the run's rates are long rationals: the cone is built around a box of short ones
    boxed["box"]["center"][0] = "1/2"
    assert certificate_check.check_period(boxed, masses, normals, restitution=cors)

    odd = copy.deepcopy(cert)  # one impulse fewer: the cone is not mapped into itself by it
    odd["impulses"] = cert["impulses"] - 1
    assert certificate_check.check_period(odd, masses, normals, restitution=cors)


def test_the_census_cap_stays_without_the_switched_search(monkeypatch: pytest.MonkeyPatch):
    """What decides AT_CAP is the cone around its own points: with that search held back, its first 400 impulses
    (short rationals at this point) end at the cap."""
    monkeypatch.setattr(termination, "SWITCHED_AFTER", 10**9)
    record = dict(AT_CAP, max_iterations=400)
    result = Runner()(record, "general", decide=True)
    assert result.stop == "max_iterations", result.notes


def test_a_pushed_cone_holds_its_points_and_keeps_their_faces():
    points = [[_q(a), _q("-1"), K.zero, _q(c)] for a, c in (("1/4", "-1/2"), ("1/100", "-3/5"), ("1/8", "-1/3"))]
    for slack in hull.SLACKS:
        gens = hull.pushed_cone(K, points, slack)
        assert gens is not None
        cone = hull._cone([hull._fractions(K, g) for g in gens], 4)
        assert all(hull._holds(cone, hull._fractions(K, p)) for p in points)
        assert all(g[2] == K.zero for g in gens)  # rate 2 is 0 at every point: so at every generator
        assert all(g[0] >= K.zero and g[1] < K.zero and g[3] <= K.zero for g in gens)  # the signs the points keep
    # wider with a larger slack: the point just past the cone of the points is held only with the slack
    past = [_q("9/1000"), _q("-1"), K.zero, _q("-3/5")]
    tight = hull._cone([hull._fractions(K, p) for p in points], 4)
    assert not hull._holds(tight, hull._fractions(K, past))
    pushed = hull._cone([hull._fractions(K, g) for g in hull.pushed_cone(K, points, Fraction(1, 4))], 4)
    assert hull._holds(pushed, hull._fractions(K, past))


def test_a_grown_cone_is_mapped_into_itself_or_refused():
    shear = lambda gens: [[x[0] + x[1] / 4, x[1]] for x in gens]  # noqa: E731  draws every ray to (1, 0)
    gens = hull.grown_cone(K, [[K.one, K.one]], Fraction(1, 16), shear)
    cone = hull._cone([hull._fractions(K, g) for g in gens], 2)
    assert all(hull._holds(cone, hull._fractions(K, y)) for y in shear(gens))
    quarter = lambda gens: [[-x[1], x[0]] for x in gens]  # noqa: E731  a quarter turn leaves every pointed cone
    assert hull.grown_cone(K, [[K.one, K.one]], Fraction(1, 16), quarter) is None
    assert hull.grown_cone(K, [[K.one, K.one]], Fraction(1, 16), lambda gens: None) is None  # not carried


def test_the_extreme_rays_keep_strictness_honest():
    v = [[K.one, K.zero], [K.one, K.one], [K.zero, K.one]]
    assert sorted(tuple(map(str, g)) for g, s in hull.extreme_rays(K, [(x, True) for x in v])) == [
        ("0", "1"),
        ("1", "0"),
    ]
    # a weak vector among them: no reduction here (the linear programming of the period search decides)
    assert hull.extreme_rays(K, [(v[0], True), (v[1], False), (v[2], True)]) is None


def test_a_strict_vector_0_is_kept_for_the_linear_programming_to_refuse():
    """Two balls, COR 0: one plastic impulse sends the rates to 0 and the run exits. A carried vector 0 is not
    dropped by the reduction without linear programming, so the cone is refused as without it."""
    from verify.models.cradle import cradle_system
    from verify.proofs.cones import period

    s = cradle_system("0", 2)
    b = s.rates(s.velocity(["1", "0"]))
    assert hull.extreme_rays(s.backend, [([s.backend.zero], True)]) is None
    assert period.close(s, 1, [b], []) is None
    assert period.close(s, 1, [b], [], prune=hull.extreme_rays) is None


def test_the_switched_search_takes_no_float(monkeypatch: pytest.MonkeyPatch):
    """The search on python's Fractions, the CORs rationals whose float() raises, and Fraction.__float__ too."""
    from tests.helpers import Poison
    from verify.dynamics.system import System
    from verify.proofs.cones import period

    def refuse(self: Fraction) -> float:
        raise AssertionError("a float was taken of an exact value")

    record = AT_CAP
    cors = [Poison(Fraction(e)) for e in record["restitution"]]
    system = System(record["mass_matrix"], record["normals"], cors, record["time_terms"], backend=K)
    b = system.rates(system.velocity(record["velocity"]))
    for _ in range(80):  # past the transient, exactly
        b = period._rule_step(system, b)
    monkeypatch.setattr(Fraction, "__float__", refuse)
    found = period._hull(system, 2, [b], b)
    assert found is not None
    assert all(type(x) is Fraction for g in found[0] for x in g)
