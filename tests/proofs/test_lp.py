"""Exact cone membership (verify.proofs.cones.lp): the simplex against the independent checker's own
linear program, exactly, on every rational backend, and its count of pivots."""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.certificate_check import _cone_lp
from tests.helpers import Poison, exact_value
from verify.numbers.backends.rational import RationalBackend
from verify.proofs.cones.lp import SearchTooLong, feasible, pivot_budget

# small entries make degenerate cones (repeated, parallel, opposite and zero vectors) common
entries = st.integers(min_value=-3, max_value=3)


@st.composite
def problems(draw: st.DrawFn) -> tuple[list[Fraction], list[list[Fraction]]]:
    """(y, generators): rows 1..4, generators 0..8, entries halves of small integers."""
    n = draw(st.integers(min_value=1, max_value=4))
    m = draw(st.integers(min_value=0, max_value=8))
    vector = st.lists(entries, min_size=n, max_size=n).map(lambda v: [Fraction(x, 2) for x in v])
    return draw(vector), draw(st.lists(vector, min_size=m, max_size=m))


@pytest.mark.parametrize("kind", ["python", "gmpy2"])
@given(problem=problems())
def test_feasible_agrees_with_the_independent_linear_program(kind: str, problem: tuple) -> None:
    y, gens = problem
    K = RationalBackend(kind)
    d = feasible(K, [K.convert(x) for x in y], [[K.convert(x) for x in g] for g in gens])
    assert (d is not None) == _cone_lp(y, gens, [False] * len(gens), False)
    if d is not None:
        weights = {k: exact_value(K, x) for k, x in d.items()}  # exact rationals of the backend
        assert all(0 <= k < len(gens) and w > 0 for k, w in weights.items())
        assert [sum((w * gens[k][i] for k, w in weights.items()), Fraction(0)) for i in range(len(y))] == y


class _General(RationalBackend):
    """The same rationals, not declared as such: :func:`feasible` takes its general simplex (the backend's own
    arithmetic, inverse of the basis and all) instead of the fraction-free one."""

    rationals = False


@pytest.mark.parametrize("kind", ["python", "gmpy2", "flint"])
@given(problem=problems())
def test_the_fraction_free_simplex_pivots_as_the_general_one(kind: str, problem: tuple) -> None:
    """Over the rationals the simplex runs on integers (each column and y scaled, the inverse as adjugate over
    determinant); it must make the general simplex's pivots, as many of them (counted by the budget), and give
    its coefficients, of the backend's type."""
    y, gens = problem
    runs = []
    for K in (RationalBackend(kind), _General(kind)):
        with pivot_budget(10**6) as left:
            d = feasible(K, [K.convert(x) for x in y], [[K.convert(x) for x in g] for g in gens])
        runs.append((left[1] - left[0], None if d is None else {k: (type(x), x) for k, x in d.items()}))
    assert runs[0] == runs[1]


def test_feasible_takes_no_float_of_its_values() -> None:
    K = RationalBackend("python")
    gens = [[Poison(1), Poison(0), Poison(2)], [Poison(0), Poison(1), Poison(-1)], [Poison(1), Poison(1), Poison(1)]]
    y = [Poison(1, 2), Poison(1), Poison(0)]  # g0 / 2 + g1
    d = feasible(K, y, gens)
    assert d is not None
    assert [sum(d[k] * gens[k][i] for k in d) for i in range(3)] == y
    assert feasible(K, [Poison(-1), Poison(0), Poison(0)], gens) is None


def test_every_basis_change_is_counted_against_the_pivot_budget() -> None:
    # y = g0 + g1 + g2 with the unit vectors: three artificial variables leave, one pivot each
    K = RationalBackend("python")
    unit = [[K.one if i == k else K.zero for i in range(3)] for k in range(3)]
    y = [K.one, K.one, K.one]
    with pivot_budget(3):
        assert sorted(feasible(K, y, unit)) == [0, 1, 2]
    with pivot_budget(2), pytest.raises(SearchTooLong, match="spent its 2 pivots"):
        feasible(K, y, unit)


def test_the_hull_of_polar_values_is_the_same_on_every_rational_type() -> None:
    """The corners of a cone's section (polar._hull3: h rounded to 2^-16 units, turns in floating point under a
    certified bound) on Python's, gmpy2's and FLINT's rationals: the same corners, and h of plain ints."""
    from verify.numbers.backends.rational import RationalBackend
    from verify.proofs.cones.polar import _hull3

    vectors = [[3, 1, 1], [1, 3, 1], [1, 1, 3], [2, 2, 2], [5, 1, 2], [-1, 4, 4]]
    corners = []
    for impl in ("python", "gmpy2", "flint"):
        K = RationalBackend(impl)
        corners.append(_hull3(K, [([K.convert(Fraction(x)) for x in v], True) for v in vectors]))
    assert corners[0] and corners[0] == corners[1] == corners[2]
