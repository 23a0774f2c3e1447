"""The restricted number parser and exact formatting."""

from __future__ import annotations

import time
from fractions import Fraction

import pytest
import sympy as sp
from hypothesis import example, given
from hypothesis import strategies as st

from verify.errors import BadNumber
from verify.numbers.format import format_decimal, format_exact, ilog10, int_to_str
from verify.numbers.parse import parse_number, split_list, to_number, to_sympy

GOOD = [
    ("7", Fraction(7)),
    ("-3/8", Fraction(-3, 8)),
    ("0.0743", Fraction(743, 10000)),
    ("0.1716", Fraction(429, 2500)),
    ("0.1", Fraction(1, 10)),
    (".5", Fraction(1, 2)),
    ("1e-9", Fraction(1, 10**9)),
    ("2.5E3", Fraction(2500)),
    (" 1 / 3 ", Fraction(1, 3)),
    ("(1 + 2) * 3 - 4/2", Fraction(7)),
    ("-2**2", Fraction(-4)),
    ("2**-2", Fraction(1, 4)),
    ("2**3**2", Fraction(512)),
    ("sqrt(9/4)", Fraction(3, 2)),
    ("4**(1/2)", Fraction(2)),
    ("sin(pi/6)", Fraction(1, 2)),
    ("cos(0)", Fraction(1)),
    ("tan(pi/4)", Fraction(1)),
    ("sqrt(2)**2", Fraction(2)),
]

CLOSED = [
    ("3 - 2*sqrt(2)", 3 - 2 * sp.sqrt(2)),
    ("sqrt(3)/3", sp.sqrt(3) / 3),
    ("tan(pi/6)", sp.sqrt(3) / 3),
    ("cos(pi/12)", sp.sqrt(6) / 4 + sp.sqrt(2) / 4),
    ("25*sqrt(6) + 25*sqrt(2)", 25 * sp.sqrt(6) + 25 * sp.sqrt(2)),
    ("pi/6", sp.pi / 6),
]

BAD = [
    ("", "empty"),
    ("1/0", "division by zero"),
    ("0**-1", "division by zero"),
    ("abc", "unknown name 'abc'"),
    ("__import__('os').system('id')", "unknown name '__import__'"),
    ("eval('1')", "unknown name 'eval'"),
    ("lambda: 1", "unknown name 'lambda'"),
    ("1; 2", "unexpected character ';'"),
    ("1 +", "unexpected end"),
    ("(1", "unexpected end"),
    ("(1 2)", "expected ')'"),
    ("1)", "unexpected ')'"),
    ("x", "'x' is only allowed inside CRootOf"),
    ("inf", "unknown name 'inf'"),
    ("nan", "unknown name 'nan'"),
    ("sqrt(-1)", "sqrt of a negative number"),
    ("(-8)**(1/3)", "negative number to a fractional power"),
    ("2**sqrt(2)", "exponents must be rational"),
    ("10**100000", "too large"),
    ("(10**900)**900", "too large"),
    ("tan(pi/2)", "not a finite real number"),
    ("CRootOf(x**2 + 1, 0)", "not a real root"),
    ("CRootOf(x**2 - 2, 2)", "not a real root"),
    ("CRootOf(x**2 - 2, 1/2)", "index must be an integer"),
    ("CRootOf(sqrt(2)*x - 1, 0)", "rational coefficients"),
    ("1" * 3000, "longer than"),
    ("(" * 200 + "1" + ")" * 200, "nested"),
    ("1e99999", "exponent larger"),
    ("0x10", "unknown name 'x10'"),
    ("1_000", "unknown name"),
    ("１", "unexpected character"),
]


@pytest.mark.parametrize(("text", "value"), GOOD, ids=[t for t, _ in GOOD])
def test_parse_rational_exactly(text, value):
    got = parse_number(text)
    assert type(got) is Fraction
    assert got == value


@pytest.mark.parametrize(("text", "value"), CLOSED, ids=[t for t, _ in CLOSED])
def test_parse_closed_forms(text, value):
    got = parse_number(text)
    assert not isinstance(got, Fraction)
    assert sp.simplify(got - value) == 0


def test_crootof_real_root():
    root = parse_number("CRootOf(x**4 - 8*x**3 - 2*x**2 - 8*x + 1, 0)")
    assert isinstance(root, sp.CRootOf)
    import mpmath

    real_roots = sorted(r.real for r in mpmath.polyroots([1, -8, -2, -8, 1]) if abs(r.imag) < 1e-20)
    assert abs(root.evalf(30) - real_roots[0]) < 1e-12  # index 0 is the smallest real root


@pytest.mark.parametrize(("text", "message"), BAD, ids=[t[:30] for t, _ in BAD])
def test_bad_numbers_are_rejected_with_a_reason(text, message):
    with pytest.raises(BadNumber) as info:
        parse_number(text, where="cases[3].normals[1][0]")
    assert str(info.value).startswith("cases[3].normals[1][0]: not a number: ")
    assert message in str(info.value)


def test_error_names_the_field_and_value_like_the_contract():
    with pytest.raises(BadNumber, match=r'^cases\[3\]\.normals\[1\]\[0\]: not a number: "1/0"'):
        parse_number("1/0", where="cases[3].normals[1][0]")


def test_hostile_string_runs_nothing(tmp_path, monkeypatch):
    marker = tmp_path / "pwned"
    monkeypatch.chdir(tmp_path)
    for text in [
        f"__import__('os').system('touch {marker}')",
        f"open('{marker}', 'w')",
        "().__class__.__bases__[0].__subclasses__()",
    ]:
        with pytest.raises(BadNumber):
            parse_number(text)
    assert not marker.exists()


def test_floats_are_refused_not_converted():
    with pytest.raises(BadNumber, match="binary float"):
        to_number(0.1)
    assert to_number(Fraction(1, 10)) == Fraction(1, 10)
    assert to_number(sp.Rational(1, 10)) == Fraction(1, 10)


@given(st.text(max_size=60))
@example("2**2**2**2**2")
@example("9" * 1000 + "/" + "7" * 1000)
@example("sin(" * 70 + "1" + ")" * 70)
def test_parser_fuzz_never_crashes_or_hangs(text):
    start = time.perf_counter()
    try:
        value = parse_number(text)
    except BadNumber:
        pass
    else:
        assert isinstance(value, Fraction) or hasattr(value, "free_symbols")
    assert time.perf_counter() - start < 2.0


@given(st.fractions(max_denominator=10**6), st.integers(min_value=1, max_value=40))
def test_format_decimal_is_correctly_rounded(q, digits):
    text = format_decimal(q, digits)
    back = parse_number(text)
    assert type(back) is Fraction
    if q == 0:
        assert back == 0
        return
    # the printed value is within half a unit of the last significant digit
    mag = abs(q)
    e = 0
    while Fraction(10) ** (e + 1) <= mag:
        e += 1
    while Fraction(10) ** e > mag:
        e -= 1
    half_unit = Fraction(10) ** (e - digits + 1) / 2
    assert abs(back - q) <= half_unit


@given(st.fractions(max_denominator=10**9))
def test_format_exact_roundtrip(q):
    assert parse_number(format_exact(q)) == q


def test_huge_integers_format_past_the_str_limit():
    n = 7**20000  # about 16900 digits, beyond CPython's default str() limit
    text = int_to_str(n)
    assert len(text) > 4300
    assert text.isdigit()
    assert int(text[-100:]) == n % 10**100
    assert int(text[:100]) == int(str(n // 10 ** (len(text) - 100)))


def test_split_list_respects_parentheses():
    assert split_list("1/2, sqrt(2), CRootOf(x**2 - 2, 1)") == ["1/2", "sqrt(2)", "CRootOf(x**2 - 2, 1)"]


# -- format_decimal takes every exact number the library hands out ------------------------------------


class _RationalWithoutFloat:
    """An exact rational of an unknown library: integer numerator and denominator, no float."""

    def __init__(self, numerator: int, denominator: int):
        self.numerator, self.denominator = numerator, denominator

    def __float__(self) -> float:
        raise AssertionError("format_decimal went through a float")


def test_format_decimal_reads_exact_rationals_through_their_integers():
    q = Fraction(-(10**40) - 1, 3)  # 41 digits: a float would lose them
    assert format_decimal(_RationalWithoutFloat(q.numerator, q.denominator), 35) == format_decimal(q, 35)
    assert format_decimal(7) == "7"


@pytest.mark.parametrize("impl", ["gmpy2", "flint", "python"])
def test_format_decimal_reads_the_values_of_every_rational_backend(impl):
    from verify.dynamics.system import System
    from verify.laws.rule import solve
    from verify.numbers.backends import RationalBackend, rational_impls

    if impl not in rational_impls():
        pytest.skip(f"{impl} is not installed")
    K = RationalBackend(impl)
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/3", "1/7"], backend=K)
    r = solve(s, ["100", "0", "0"])
    for x in r.exit_velocity:
        assert format_decimal(x, 25) == format_decimal(K.to_number(x), 25)
        assert format_decimal(x, 25, "floor") == format_decimal(K.to_number(x), 25, "floor")


def test_format_decimal_of_the_default_backend_values():
    from verify import System, solve

    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["0.5", "0.5"])
    r = solve(s, ["100", "0", "0"])  # gmpy2's mpq or flint's fmpq when the fast extras are installed
    for x in r.exit_velocity:
        assert format_decimal(x) == format_decimal(s.backend.to_number(x))


@pytest.mark.parametrize(
    ("value", "name"), [(0.5, "float"), (True, "bool"), (object(), "object"), (sp.Symbol("x") + 1, "x")]
)
def test_format_decimal_refuses_floats_and_unknown_types_by_name(value, name):
    with pytest.raises(TypeError, match=name):
        format_decimal(value)


def test_format_decimal_refuses_number_field_elements_and_points_to_the_backend():
    from verify.numbers.backends import NumberFieldBackend

    K = NumberFieldBackend([sp.sqrt(2)])
    x = K.convert(3 - 2 * sp.sqrt(2))
    with pytest.raises(TypeError, match="to_decimal"):
        format_decimal(x)
    assert K.to_decimal(x, 8) == format_decimal(3 - 2 * sp.sqrt(2), 8)


def test_format_decimal_rounds_algebraic_values_in_the_direction_asked():
    from verify.numbers.algebraic import RealAlgebraic

    assert (format_decimal(sp.sqrt(2), 3, "floor"), format_decimal(sp.sqrt(2), 3, "ceiling")) == ("1.41", "1.42")
    assert format_decimal(-sp.sqrt(2), 3, "floor") == "-1.42"
    root = RealAlgebraic.from_number(sp.sqrt(3))
    assert (format_decimal(root, 4, "floor"), format_decimal(root, 4, "ceiling"), format_decimal(root, 4)) == (
        "1.732",
        "1.733",
        "1.732",
    )
    one = (sp.sqrt(2) + 1) * (sp.sqrt(2) - 1)  # exactly 1, though not written so
    assert format_decimal(one, 3, "floor") == format_decimal(one, 3, "ceiling") == "1"


@given(st.integers(1, 10**60), st.integers(1, 10**60))
def test_ilog10_is_the_exact_floor_of_log10(num, den):
    e = ilog10(num, den)
    assert Fraction(10) ** e <= Fraction(num, den) < Fraction(10) ** (e + 1)


def test_to_sympy_is_exact_and_keeps_closed_forms():
    assert to_sympy(Fraction(10**30 + 1, 3)) == sp.Rational(10**30 + 1, 3)
    assert to_sympy(sp.sqrt(2)) is sp.sqrt(2)


def test_a_closed_form_that_cancels_beyond_the_precision_bound_is_decided_exactly(monkeypatch) -> None:
    """(sqrt(2) - 1)^400 written as a + b sqrt(2): a and b have 153 digits and cancel to 1e-153, beyond
    256 bits of interval arithmetic; the number's minimal polynomial then decides its sign and digits."""
    import mpmath

    from verify.errors import NoConvergence
    from verify.numbers import numeric

    monkeypatch.setattr(numeric, "MAX_PREC", 256)
    x = sp.expand((sp.sqrt(2) - 1) ** 400)
    with pytest.raises(NoConvergence, match="cannot decide the sign of <a number of"):
        numeric.certified_sign(x)  # intervals alone: undecided, said in one line
    with mpmath.workdps(60):  # the same number without the cancellation, as a reference
        reference = mpmath.nstr((mpmath.sqrt(2) - 1) ** 400, 30, min_fixed=1, max_fixed=0)
    digits = format_decimal(x, 30)
    assert sp.Float(digits, 30) == sp.Float(reference, 30) and digits.startswith(reference.split("e")[0][:20])


def test_the_command_line_lifts_the_limit_on_printed_integers_and_restores_it(monkeypatch, capsys) -> None:
    """Exact outputs are printed whole (SymPy prints its rationals with Python's str, limited to 4300 digits
    by default); the process's limit is as it was afterwards."""
    import sys

    from verify.cli import main
    from verify.records import text

    seen = []
    monkeypatch.setattr(text, "cradle_text", lambda *a, **k: seen.append(str(sp.Integer(10) ** 5000)) or "")
    before = sys.get_int_max_str_digits()
    assert main(["cradle", "--eps", "1/2"]) == 0
    assert sys.get_int_max_str_digits() == before and len(seen[0]) == 5001
    assert "Traceback" not in capsys.readouterr().err
