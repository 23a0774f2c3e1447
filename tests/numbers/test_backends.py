"""One contract table run against every backend, plus what each backend promises."""

from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp

import verify.numbers.backends
from verify.errors import BadNumber, InvalidInput, Undecided
from verify.numbers.backends import (
    BACKENDS,
    IntervalBackend,
    NumberFieldBackend,
    RationalBackend,
    get_backend,
    rational_impls,
)
from verify.numbers.backends.base import Backend
from verify.numbers.backends.symbolic import Piece, SymbolicBackend
from verify.numbers.format import format_decimal

# (name, operation on (K, a, b), exact expected value) with a = 1/3 and b = -5/7
CONTRACT = [
    ("add", lambda K, a, b: a + b, Fraction(-8, 21)),
    ("sub", lambda K, a, b: a - b, Fraction(22, 21)),
    ("mul", lambda K, a, b: a * b, Fraction(-5, 21)),
    ("div", lambda K, a, b: a / b, Fraction(-7, 15)),
    ("zero", lambda K, a, b: K.zero + a - a, Fraction(0)),
    ("one", lambda K, a, b: K.one * a, Fraction(1, 3)),
]


@pytest.fixture(params=BACKENDS)
def backend(request):
    return get_backend(request.param)


@pytest.mark.parametrize(("name", "op", "expected"), CONTRACT, ids=[c[0] for c in CONTRACT])
def test_contract_arithmetic(backend, name, op, expected):
    K = backend
    x = op(K, K.convert(Fraction(1, 3)), K.convert(Fraction(-5, 7)))
    if K.is_exact:
        assert K.to_number(x) == expected
    elif K.encloses:
        assert K.contains(x, expected)
        if expected == 0:  # a - a encloses 0 without being the point 0: undecidable, by design
            with pytest.raises(Undecided):
                K.sign(x)
            return
    else:
        assert abs(Fraction(K.to_decimal(x, 12)) - expected) < Fraction(1, 10**10)
    assert K.sign(x) == (expected > 0) - (expected < 0)


def test_flags(backend):
    assert backend.is_exact == (backend.name == "exact")
    assert backend.is_rigorous == (backend.name in ("exact", "interval"))
    assert backend.name in backend.describe()


CAPABILITIES = ("is_exact", "is_rigorous", "rationals", "widens_to_inputs", "encloses", "refinable", "is_parametric")


@pytest.mark.parametrize(
    ("K", "declared"),
    [
        (RationalBackend("python"), {"is_exact", "is_rigorous", "rationals", "widens_to_inputs"}),
        (NumberFieldBackend([sp.sqrt(2)]), {"is_exact", "is_rigorous", "widens_to_inputs"}),
        (get_backend("interval"), {"is_rigorous", "encloses", "refinable"}),
        (get_backend("mp"), set()),
        (get_backend("float"), set()),
        (SymbolicBackend(Piece.closed(0, 1)), {"is_exact", "is_rigorous", "is_parametric"}),
    ],
    ids=["rational", "field", "interval", "mp", "float", "symbolic"],
)
def test_capabilities_are_declared_and_kept(K: Backend, declared: set[str]) -> None:
    """Each backend declares what it can do, and does it: callers read these, never names."""
    assert {c for c in CAPABILITIES if getattr(K, c)} == declared
    x = K.convert(Fraction(-5, 7))
    assert (K.enclosure(x) is not None) == K.encloses
    assert (K.refined() is not None) == K.refinable
    if K.rationals:
        assert type(K.to_number(x)) is Fraction and K.to_number(x) == Fraction(-5, 7)
    if not K.is_exact:
        with pytest.raises(TypeError):
            K.to_number(x)


def test_the_package_exports_its_public_names() -> None:
    for name in verify.numbers.backends.__all__:
        assert getattr(verify.numbers.backends, name) is not None
    assert not [n for n in verify.numbers.backends.__all__ if n.startswith("_")]


@pytest.mark.parametrize("impl", list(rational_impls()))
def test_every_rational_implementation_gives_the_same_results(impl):
    from verify.models.cradle import run_cradle

    K = RationalBackend(impl)
    result = run_cradle("0.1715", backend=K)
    assert [K.to_number(x) for x in result.exit_velocity] == [
        RationalBackend("python").to_number(x)
        for x in run_cradle("0.1715", backend=RationalBackend("python")).exit_velocity
    ]


def test_exact_backend_refuses_irrationals_with_a_clear_message():
    with pytest.raises(BadNumber, match="irrational"):
        get_backend("exact").convert(sp.sqrt(2))


@pytest.mark.parametrize("impl", list(rational_impls()))
def test_exact_backend_takes_integers_and_sympy_rationals_exactly_and_refuses_floats(impl):
    """An int, a SymPy Integer or Rational is the rational it is (a map's system put at a point hands SymPy
    numbers over); a float, Python's or SymPy's, is refused as one, not called irrational."""
    K = RationalBackend(impl)
    big = 10**30 + 1
    pairs = [(0, Fraction(0)), (7, Fraction(7)), (sp.Integer(0), Fraction(0)), (sp.Integer(-3), Fraction(-3)),
             (sp.Rational(big, 3), Fraction(big, 3))]  # fmt: skip
    for value, exact in pairs:
        assert K.to_number(K.convert(value)) == exact and type(K.to_number(K.convert(value))) is Fraction
    for value in (0.5, sp.Float("0.5")):
        with pytest.raises(BadNumber, match="is a float"):
            K.convert(value)


def test_interval_sign_raises_when_the_enclosure_contains_zero():
    K = get_backend("interval", dps=20)
    third = K.convert(Fraction(1, 3))
    almost_zero = third * K.convert(Fraction(3)) - K.one  # encloses 0 but is not the point 0
    with pytest.raises(Undecided):
        K.sign(almost_zero)
    assert K.sign(K.zero) == 0


def test_interval_refines_up_to_a_limit():
    K = IntervalBackend(50, max_dps=200)
    dps = []
    while K is not None:
        dps.append(K.dps)
        K = K.refined()
    assert dps == [50, 100, 200]


def test_interval_encloses_closed_forms():
    K = get_backend("interval", dps=30)
    x = K.convert(sp.sqrt(2))
    lo, hi = K.enclosure(x)
    assert Fraction(lo) < Fraction(hi)
    assert Fraction(lo) ** 2 < 2 < Fraction(hi) ** 2  # printed bounds are rounded outward
    assert K.sign(x - K.convert(Fraction(14142135623, 10**10))) == 1


def test_mp_precision_is_private():
    import mpmath

    before = mpmath.mp.dps
    K = get_backend("mp", dps=80)
    x = K.convert(Fraction(1, 3))
    assert K.to_decimal(x, 60).startswith("0." + "3" * 59)
    assert mpmath.mp.dps == before


def test_unknown_backend_and_bad_dps():
    with pytest.raises(InvalidInput, match="unknown backend"):
        get_backend("quantum")
    with pytest.raises(InvalidInput, match="dps"):
        get_backend("mp", dps=2)


def _significant_digits(text: str) -> int:
    mantissa = text.lstrip("-").lower().split("e")[0]
    return len(mantissa.replace(".", "").lstrip("0"))


@pytest.mark.parametrize(
    "q", [Fraction(381, 80), Fraction(1, 3), Fraction(-22, 7), Fraction(10**25, 3), Fraction(1, 7 * 10**12)]
)
def test_interval_decimals_show_only_the_digits_the_enclosure_certifies(q):
    K = IntervalBackend(20)
    seven_tenths = K.convert(Fraction(7, 10))
    x = K.convert(q) * seven_tenths / seven_tenths  # an enclosure of q, wider than a point
    lo, hi = (Fraction(b) for b in K.enclosure(x, 40))
    assert lo < q < hi
    text = K.to_decimal(x, 30)
    d = _significant_digits(text)
    assert 15 <= d < 30  # 20-digit intervals certify about 20 digits here, not 30
    assert Fraction(text) == Fraction(format_decimal(q, d))  # q correctly rounded to the digits shown
    assert K.to_decimal(x, 8) == format_decimal(q, 8) or _significant_digits(K.to_decimal(x, 8)) == 8


def test_interval_decimals_of_a_point_and_of_an_enclosure_of_zero():
    K = IntervalBackend(20)
    assert K.to_decimal(K.convert(Fraction(1, 4)), 30) == "0.25"  # a point is exact
    third = K.convert(Fraction(1, 3))
    zero = third * K.convert(Fraction(3)) - K.one  # encloses 0: no significant digit is certain
    text = K.to_decimal(zero, 30)
    assert text.startswith("0e-") and Fraction(text) == 0
    lo, hi = (Fraction(b) for b in K.enclosure(zero, 30))
    assert max(-lo, hi) < Fraction(1, 10 ** int(text[3:])) / 2  # every value inside rounds to 0 there


def test_float_backend_refuses_a_value_beyond_the_float_range() -> None:
    """1e400 read exactly has no binary64 value: bad input (InvalidInput), not an OverflowError."""
    from verify.errors import InvalidInput

    with pytest.raises(InvalidInput, match=r"1e\+400 is beyond the range"):
        get_backend("float").convert(Fraction(10) ** 400)


def test_roots_of_one_polynomial_are_equal_exactly_when_their_intervals_share_the_root() -> None:
    """Two real algebraic numbers on one polynomial whose isolating intervals overlap: the same root (however
    narrowed) compares equal, two roots whose intervals overlap where there is no root do not, either order, as
    count_roots on the overlap says."""
    from verify.numbers.algebraic import RealAlgebraic, count_roots, poly_from_coeffs

    first, second = RealAlgebraic.roots_in(poly_from_coeffs([10, -30, 21]))  # 1.11... and 1.88...
    p = first.poly  # irreducible
    low, high = RealAlgebraic(p, Fraction(1), Fraction(3, 2)), RealAlgebraic(p, Fraction(7, 5), Fraction(2))
    assert count_roots(p, Fraction(7, 5), Fraction(3, 2)) == 0
    assert low.cmp(high) == -1 and RealAlgebraic(p, Fraction(7, 5), Fraction(2)).cmp(first) == 1
    narrow = RealAlgebraic(p, Fraction(1), Fraction(3, 2))
    narrow.refine()
    narrow.refine()
    assert low.cmp(narrow) == 0 and narrow.cmp(first) == 0 and second.cmp(high) == 0
    sqrt2 = RealAlgebraic.from_number(sp.sqrt(2))
    assert sqrt2.cmp(RealAlgebraic(sqrt2.poly, Fraction(1), Fraction(2))) == 0
