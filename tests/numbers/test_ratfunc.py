"""The two arithmetics of rational functions of the parameter (verify.numbers.backends.ratfunc): flint's and
SymPy's give the same functions, values and signs, and a map made on either is the same, byte for byte."""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from tests.helpers import Poison
from verify.maps.cradle import cradle_map, map_json
from verify.maps.general import eps_map, eps_map_json
from verify.models.cradle import cradle_system
from verify.numbers.algebraic import RealAlgebraic, poly_from_coeffs
from verify.numbers.backends.ratfunc import EPS, FLINT, arithmetic, using
from verify.numbers.backends.symbolic import Piece, Split, SymbolicBackend

pytestmark = pytest.mark.skipif(not FLINT, reason="python-flint is not installed (the fast extra)")

rationals = st.fractions(min_value=-5, max_value=5, max_denominator=7)
#: a program over the field: each step combines two earlier values (or the parameter and constants)
programs = st.lists(
    st.tuples(st.sampled_from("+-*/"), st.integers(0, 30), st.integers(0, 30), rationals), min_size=1, max_size=12
)


def _run(A, program):
    values = [A.parameter, A.one, A.rational(F(2, 3))]
    for op, i, j, q in program:
        a, b = values[i % len(values)], values[j % len(values)] + A.rational(q)
        if op == "/" and A.is_zero(b):
            continue
        values.append({"+": a + b, "-": a - b, "*": a * b, "/": a / b if op == "/" else None}[op])
    return values


@given(programs, rationals)
def test_both_arithmetics_give_the_same_functions(program, q) -> None:
    fl, sy = _run(arithmetic("flint"), program), _run(arithmetic("sympy"), program)
    assert len(fl) == len(sy)
    for a, b in zip(fl, sy):
        assert sp.cancel(arithmetic("flint").expr(a) - arithmetic("sympy").expr(b)) == 0
        if sp.denom(sp.together(arithmetic("sympy").expr(b))).subs(EPS, sp.Rational(q.numerator, q.denominator)):
            assert arithmetic("flint").at(a, q) == arithmetic("sympy").at(b, q)


@given(programs)
def test_both_arithmetics_factor_to_the_same_text(program) -> None:
    """The text of a function in a certificate (``SymbolicBackend.to_exact``) is its factored form: from flint's
    factorisation on one side, SymPy's ``factor`` of the expression on the other; the same characters."""
    fl, sy = _run(arithmetic("flint"), program), _run(arithmetic("sympy"), program)
    for a, b in zip(fl, sy):
        assert str(arithmetic("flint").factored(a)) == str(sp.factor(arithmetic("flint").expr(a)))
        assert str(arithmetic("flint").factored(a)) == str(arithmetic("sympy").factored(b))


@given(programs)
def test_the_backend_writes_each_function_as_its_own_factored_form(program) -> None:
    """``to_exact`` keeps the texts it wrote (a map writes the same entries on many pieces): on either arithmetic,
    on backends of other pieces, and for the same function made another way, the text is SymPy's ``factor`` of that
    function, never one kept for another function or another arithmetic."""
    for name in ("flint", "sympy"):
        A = arithmetic(name)
        backends = [SymbolicBackend(Piece.closed(0, 1), arithmetic_name=name),
                    SymbolicBackend(Piece.closed(F(1, 3), F(1, 2)), arithmetic_name=name)]  # fmt: skip
        for x in _run(A, program):
            same = (x * A.parameter + x) / (A.parameter + A.one)
            for K in backends:
                assert K.to_exact(x) == K.to_exact(same) == str(sp.factor(A.expr(x)))


@given(programs)
def test_equal_functions_are_equal_elements_with_equal_hashes(program) -> None:
    A = arithmetic("flint")
    for x in _run(A, program):
        same = (x * A.parameter + x) / (A.parameter + A.one)  # the same function, made another way
        assert same == x and hash(same) == hash(x)
        assert (same != x) is False and (same != x + A.one) is True
        if A.expr(x).subs(EPS, sp.Rational(1, 9)).is_finite:
            assert type(A.at(x + A.one - A.one, F(1, 9))) is F


def test_no_float_enters_the_flint_arithmetic() -> None:
    A = arithmetic("flint")
    x = A.from_expr((1 + EPS) / (3 - EPS**2))
    third = A.rational(Poison(F(1, 3)))  # an exact value whose __float__ raises: taken exactly
    assert A.at(third * x, F(1, 2)) == F(2, 11)
    assert A.at(x, F(1, 2)) == F(6, 11) and type(A.at(x, F(1, 2))) is F
    with pytest.raises(ZeroDivisionError):
        x / A.zero


@pytest.mark.parametrize("name", ["flint", "sympy"])
def test_the_backend_refuses_what_is_not_a_rational_function(name) -> None:
    from verify.errors import BadNumber

    K = SymbolicBackend(Piece.closed(0, 1), arithmetic_name=name)
    with pytest.raises(BadNumber, match="rational functions of eps"):
        K.convert(sp.sqrt(2) * EPS)


@pytest.mark.parametrize("name", ["flint", "sympy"])
def test_signs_and_splits_are_the_same_on_either(name) -> None:
    K = SymbolicBackend(Piece.closed(0, 1), arithmetic_name=name)
    e = K.parameter
    assert K.sign(K.one + e) == 1 and K.nonnegative(e * e)
    with pytest.raises(Split) as split:
        K.sign(e * e - K.convert(F(1, 2)))
    assert [str(r) for p in split.value.polys for r in K.cache.roots(p)] == ["-sqrt(2)/2", "sqrt(2)/2"]
    point = SymbolicBackend(Piece(*[RealAlgebraic.roots_in(poly_from_coeffs([2, 0, -1]))[1]] * 2, True, True),
                            arithmetic_name=name)  # fmt: skip
    x = point.parameter
    assert point.sign(x * x - point.convert(F(1, 2))) == 0 and point.sign(x - point.convert(F(7, 10))) == 1


def test_the_flint_sign_of_an_algebraic_number_refines_as_the_sympy_one() -> None:
    from verify.numbers import algebraic

    def refined(use_flint):
        r = RealAlgebraic.roots_in(poly_from_coeffs([1, -8, 12, 8, -90, 8, 12, -8, 1]))[2]
        saved = algebraic.flint
        algebraic.flint = algebraic.flint if use_flint else None
        try:
            sign = r.sign_of([F(-1, 4), 0, 0, 1])  # x^3 - 1/4 at the root
        finally:
            algebraic.flint = saved
        return sign, r.lo, r.hi

    assert refined(True) == refined(False)


@pytest.mark.parametrize("balls, impulses", [(3, 12), (4, 12)])
def test_a_cradle_map_is_the_same_byte_for_byte_on_either_arithmetic(balls, impulses) -> None:
    fast = json.dumps(map_json(cradle_map(balls, max_impulses=impulses)))
    with using("sympy"):
        slow = json.dumps(map_json(cradle_map(balls, max_impulses=impulses)))
    assert fast == slow


def test_a_general_map_is_the_same_byte_for_byte_on_either_arithmetic() -> None:
    from verify.models.corner import corner_system

    system = corner_system("1/2", "1", "1")
    fast = json.dumps(eps_map_json(eps_map(system, ["1", "-1/10", "0"], ["e1", "e2"], lines=2)))
    with using("sympy"):
        slow = json.dumps(eps_map_json(eps_map(system, ["1", "-1/10", "0"], ["e1", "e2"], lines=2)))
    assert fast == slow


def test_a_system_on_either_arithmetic_has_the_same_gram_matrix() -> None:
    a = cradle_system(EPS, 4, backend=SymbolicBackend(Piece.closed(0, 1), arithmetic_name="flint"))
    b = cradle_system(EPS, 4, backend=SymbolicBackend(Piece.closed(0, 1), arithmetic_name="sympy"))
    assert [[a.backend.to_exact(x) for x in row] for row in a.gram] == [
        [b.backend.to_exact(x) for x in row] for row in b.gram
    ]
