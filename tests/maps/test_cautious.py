"""A map is never more cautious than a single run: a rational point drawn in what a map leaves unexplored is not
decided by verify solve's run at that point with the map's cap on impulses."""

from __future__ import annotations

import random
from fractions import Fraction as F

import pytest
import sympy as sp

from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.maps.cradle import cradle_map
from verify.maps.general import eps_map

POINTS = 100
MASSES_2112 = [["2", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "2"]]
NORMALS4 = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]


def _unit_balls(balls: int) -> list[list[str]]:
    return [["1" if i == j else "0" for j in range(balls)] for i in range(balls)]


def _normals(balls: int) -> list[list[str]]:
    return [["-1" if j == i else "1" if j == i + 1 else "0" for j in range(balls)] for i in range(balls - 1)]


def _drawn(parts, count: int, seed: int) -> list[F]:
    """``count`` rationals drawn uniformly (by length) in the unexplored intervals, each strictly inside one."""
    boxes = []
    for p in parts:
        if p.stop != "max_iterations" or p.piece.is_point:
            continue
        lo, hi = p.piece.lower, p.piece.upper
        while not lo.hi < hi.lo:
            lo.refine()
            hi.refine()
        boxes.append((lo.hi, hi.lo))
    total = sum(b - a for a, b in boxes)
    rng = random.Random(seed)
    out = []
    for _ in range(count):
        x = F(rng.randrange(1, 10**6), 10**6) * total
        for a, b in boxes:
            if x < b - a:
                out.append(a + x)
                break
            x -= b - a
    return out


def _first_decided(masses, normals, points: list[F], cap: int) -> tuple[F, str] | None:
    """The first point that a single exact run with the cap decides (exit, or proved never to exit), or None."""
    for q in points:
        system = System(masses, normals, [str(q)] * len(normals))
        r = solve(system, ["1"] + ["0"] * (len(masses) - 1), max_iterations=cap, trace=False)
        if r.stop != "max_iterations":
            return q, r.stop
    return None


@pytest.mark.slow(seconds=18)
@pytest.mark.parametrize("system", ["four unit balls", "masses 2, 1, 1, 2"])
def test_no_point_left_unexplored_is_decided_by_a_single_run(system) -> None:
    cap = 40
    if system == "four unit balls":
        masses, normals, parts = _unit_balls(4), NORMALS4, cradle_map(balls=4, max_impulses=cap).parts
    else:
        masses, normals = MASSES_2112, NORMALS4
        m = eps_map(System(masses, normals, ["1"] * 3), ["1", "0", "0", "0"], ["eps"] * 3, max_impulses=cap)
        parts = m.lines[0].parts
    points = _drawn(parts, POINTS, seed=36)
    assert len(points) == POINTS
    assert _first_decided(masses, normals, points, cap) is None


@pytest.mark.slow(seconds=39)
def test_five_balls_no_point_left_unexplored_is_decided_by_a_single_run() -> None:
    """Five unit balls (at 20 impulses, on the interval that holds all that the whole map leaves unexplored):
    below and at the boundary of (S1,S3)(S2,S4), a root of eps^2 - (22 - 8*sqrt(5)) eps + 1, every eps is proved
    never to exit by the growth argument (verify.maps.growth; its certificate is checked by
    tests/maps/test_boundary.py), so only eps above the boundary are left; and no point left unexplored is decided by
    a single run."""
    from verify.numbers.algebraic import RealAlgebraic, poly_from_coeffs

    cap = 20
    m = cradle_map(balls=5, lower="0.222", upper="0.272", max_impulses=cap)
    boundary = RealAlgebraic.roots_in(poly_from_coeffs([1, -44, 166, -44, 1]))[1]
    grown = [p for p in m.non_terminating if (p.certificate or {}).get("kind") == "dominant growth"]
    assert len(grown) == 1 and grown[0].piece.upper.cmp(boundary) == 0 and grown[0].piece.upper_closed
    assert m.unexplored and all(p.piece.lower.cmp(boundary) >= 0 for p in m.unexplored)
    assert all("above the boundary" in p.reason for p in m.unexplored if "boundary" in p.reason)
    points = _drawn(m.parts, POINTS, seed=36)
    assert _first_decided(_unit_balls(5), _normals(5), points, cap) is None


def _at(value, q: F):
    """A certificate of an interval of eps with eps = q in every number: the certificate of the point q (its
    ``boundary`` note, which names the factor in lam, is left out)."""
    from tests import certificate_check

    if isinstance(value, dict):
        return {k: _at(v, q) for k, v in value.items() if k != "boundary"}
    if isinstance(value, list):
        return [_at(v, q) for v in value]
    if isinstance(value, str) and "eps" in value:
        return str(certificate_check.read(value).subs(certificate_check.EPS, sp.Rational(q.numerator, q.denominator)))
    return value


@pytest.mark.slow(seconds=33)
def test_an_interval_below_the_boundary_gets_the_turning_cones_of_the_boundary_above_it(monkeypatch) -> None:
    """Five unit balls on [0.255, 0.2595], below eps* but not holding it, with the growth argument switched off (as
    for a system where it does not hold; on by default, it proves this interval first): the turning cones of the
    boundary above the interval decide all of it (before, the whole interval was left unexplored, while verify solve
    proves its lower end never exits). The certificate names that boundary, not reached, and holds at three points
    of the interval, 1/100 of it in from either end and in its middle (the checker's exact point mode)."""
    from tests import certificate_check
    from verify.maps import line

    monkeypatch.setattr(line, "grown_below", lambda *args, **kwargs: None)
    m = cradle_map(balls=5, lower="0.255", upper="0.2595", max_impulses=14)
    assert [p.stop for p in m.parts] == ["non_terminating"]
    cert = m.parts[0].certificate
    assert cert["boundary"]["eps"] == "CRootOf(x**4 - 44*x**3 + 166*x**2 - 44*x + 1, 1)"
    assert cert["boundary"]["reached"] is False
    run = solve(System(_unit_balls(5), _normals(5), ["51/200"] * 4), ["1", "0", "0", "0", "0"], max_iterations=14)
    assert run.stop == "non_terminating"
    monkeypatch.setattr("verify.numbers.parse.MAX_LENGTH", 10**5)  # the certificate's numbers, not a user's input
    lo, hi = F(255, 1000), F(2595, 10000)
    for q in (lo + (hi - lo) / 100, (lo + hi) / 2, hi - (hi - lo) / 100):
        assert certificate_check.check_period(_at(cert, q), ["1"] * 5, _normals(5), restitution=[str(q)] * 4) == []
