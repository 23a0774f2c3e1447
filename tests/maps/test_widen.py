"""A single run's cone widened to an interval (verify.maps.widen): checked without the code that found it."""

from __future__ import annotations

import itertools
from fractions import Fraction as F

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests import certificate_check
from tests.maps.test_cradle_map import inner_rational
from verify.cli import main
from verify.maps.cradle import cradle_map
from verify.maps.line import line_parts, widened
from verify.maps.widen import _simplest, short_point
from verify.models.cradle import cradle_system, run_cradle
from verify.numbers.backends.symbolic import EPS, Piece, RootCache

NORMALS = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]


def build(K):
    return cradle_system(EPS, 4, backend=K)


@pytest.fixture(scope="module")
def unexplored():
    """Four unit balls on [0.161, 0.168] at 16 impulses: the parametric run alone leaves it all unexplored."""
    parts = line_parts(build, ["1", "0", "0", "0"], Piece.closed("0.161", "0.168"), 16, widen=0)
    assert [(p.stop, p.iterations) for p in parts] == [("max_iterations", 16)]
    return parts[0]


def _check_at(cert: dict, eps: F) -> list[str]:
    """The independent checker on the certificate with eps = a rational value (generators and rates substituted)."""
    at = {**cert, "restitution": [str(eps)] * 3}
    at["generators"] = [
        [str(certificate_check.read(x).subs(certificate_check.EPS, eps)) for x in g] for g in cert["generators"]
    ]
    at["gram"] = [[str(certificate_check.read(x)) for x in row] for row in cert["gram"]]
    at["rates"] = at["generators"][0]
    return certificate_check.check_period(at, ["1"] * 4, NORMALS, restitution=[str(eps)] * 3)


def test_a_widened_cone_holds_on_its_whole_interval(unexplored) -> None:
    parts = widened(build, ["1", "0", "0", "0"], unexplored, RootCache(), max_points=1)
    decided = [p for p in parts if p.stop == "non_terminating"]
    assert len(decided) == 1 and not decided[0].piece.is_point
    part = decided[0]
    # the parts cover the interval exactly: each end is the next one's start, once
    assert str(parts[0].piece.lower) == "161/1000" and str(parts[-1].piece.upper) == "21/125"
    for a, b in itertools.pairwise(parts):
        assert a.piece.upper == b.piece.lower and a.piece.upper_closed != b.piece.lower_closed
    for t in (F(1, 10), F(1, 2), F(9, 10)):  # the certificate, at points across the interval, checked again
        eps = inner_rational(part, t)
        assert _check_at(part.certificate, eps) == []
        assert run_cradle(eps, v0="1", balls=4, max_iterations=200).stop == "non_terminating"


def test_no_points_leave_the_map_as_it_was(unexplored) -> None:
    assert widened(build, ["1", "0", "0", "0"], unexplored, RootCache(), max_points=0)[0].piece == unexplored.piece
    on = cradle_map(balls=4, upper="1/6", max_impulses=16)
    off = cradle_map(balls=4, upper="1/6", max_impulses=16, widen=0)
    assert len(on.non_terminating) > len(off.non_terminating)
    # every part the widening did not touch is the same
    assert [str(p.piece) for p in off.parts if p.stop != "max_iterations"] == [
        str(p.piece) for p in on.parts if p.stop != "max_iterations" and p.iterations != 16
    ][: len([p for p in off.parts if p.stop != "max_iterations"])]


@given(
    st.fractions(min_value=-3, max_value=3, max_denominator=60),
    st.fractions(min_value=F(1, 60), max_value=1, max_denominator=60),
)
def test_the_point_tried_is_the_simplest_rational(a, width) -> None:
    b = a + width
    x = _simplest(a, b)
    assert a < x < b
    # no rational of a smaller denominator lies strictly between
    assert all(not any(a < F(n, d) < b for n in range(int(a * d) - 1, int(b * d) + 2)) for d in range(1, x.denominator))


def test_short_point_is_in_the_middle_third() -> None:
    q = short_point(Piece.closed("0.1604", "0.1730"))
    assert q == F(1, 6) and F(1604, 10000) + F(42, 10000) <= q <= F(1730, 10000) - F(42, 10000)


@pytest.mark.parametrize("value", ["-1", "x", "1001", "1.5"])
def test_bad_widen_is_refused(value, capsys) -> None:
    assert main(["cradle-map", "--balls", "4", "--widen", value]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "--widen" in err and "Traceback" not in err
