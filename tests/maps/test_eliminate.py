"""Resultants and discriminants by interpolation (verify.maps.backends.eliminate) give flint's own polynomials."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from verify.maps.backends.plane import FLINT_POLYS

pytestmark = pytest.mark.skipif(not FLINT_POLYS, reason="python-flint is not installed (the fast extra)")

if FLINT_POLYS:
    import flint

    from verify.maps.backends.eliminate import THRESHOLD, discriminant_y, resultant_y

coefficients = st.fractions(min_value=-20, max_value=20, max_denominator=12)
terms = st.dictionaries(st.tuples(st.integers(0, 7), st.integers(0, 7)), coefficients, min_size=1, max_size=14)


def _poly(t: dict[tuple[int, int], Fraction]) -> object:
    ctx = flint.fmpq_mpoly_ctx.get(("x", "y"))
    return ctx.from_dict({k: flint.fmpq(v.numerator, v.denominator) for k, v in t.items() if v})


@given(terms, terms)
def test_resultant_is_flints(a: dict, b: dict) -> None:
    p, q = _poly(a), _poly(b)
    if p.is_zero() or q.is_zero():
        return
    assert resultant_y(p, q, threshold=0) == p.resultant(q, "y")


@given(terms)
def test_discriminant_is_flints(a: dict) -> None:
    p = _poly(a)
    if p.is_zero() or int(p.degrees()[1]) < 2:
        return
    assert discriminant_y(p, threshold=0) == p.discriminant("y")


def test_large_curves_take_the_interpolation_and_agree() -> None:
    """Curves of degree about 10, as a norm over a number field gives: past the threshold, the same polynomials; and
    a leading coefficient in y with integer roots around 0 moves the points of interpolation away from them."""
    rng = random.Random(36)
    ctx = flint.fmpq_mpoly_ctx.get(("x", "y"))
    x, y = ctx.gens()
    dense = _poly({(i, j): Fraction(rng.randint(-30, 30), rng.randint(1, 9)) for i in range(4) for j in range(4)})
    lead = 1
    for r in range(-12, 13, 3):  # zeros of the leading coefficient among the first points tried
        lead = lead * (x - r)
    p = dense * dense + lead * y**7
    q = p.derivative("x") + y * dense
    total, dx, dy = p.total_degree(), int(p.degrees()[0]), int(p.degrees()[1])
    assert min(total * (total - 1), (2 * dy - 1) * dx) >= THRESHOLD  # past it: the interpolation runs for both
    assert min(total * q.total_degree(), dy * int(q.degrees()[0]) + int(q.degrees()[1]) * dx) >= THRESHOLD
    assert discriminant_y(p) == p.discriminant("y")
    assert resultant_y(p, q) == p.resultant(q, "y")
