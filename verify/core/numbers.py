"""Number strings in and out: a restricted, non-executing parser and exact formatting.

Every number that enters :mod:`verify` as text goes through :func:`parse_number`. It
reads integers (``"7"``), rationals (``"-3/8"``), decimals (``"0.0743"``, read exactly as
743/10000, never through a binary float), scientific decimals (``"1e-9"``) and closed
forms built from the names ``sqrt pi sin cos tan CRootOf x`` and the operators
``+ - * / ** ( ) ,`` (SymPy syntax; ``docs/numbers.md`` in the source repository
describes it for users).

The parser is a small recursive-descent parser written here: it never calls ``eval``,
``exec`` or ``sympify``, so a string such as ``"__import__('os').system('id')"`` is
rejected as a bad number without running anything. Lengths, nesting depth and
exponents are bounded so that no input can make it hang or exhaust memory.

Rational results are :class:`fractions.Fraction`; SymPy is imported only when a value is
irrational (``"sqrt(2)"``), so the rational path stays light and exact.

>>> parse_number("0.1716")
Fraction(429, 2500)
>>> parse_number("3 - 2*sqrt(2)")
3 - 2*sqrt(2)
>>> format_decimal(Fraction(1, 3), 10)
'0.3333333333'
"""

from __future__ import annotations

import json
import math
import operator
import re
from fractions import Fraction
from typing import Any

from verify.errors import BadNumber

#: What a parsed number is: an exact rational, or a SymPy expression for a closed form.
Number = Fraction | Any

MAX_LENGTH = 2000  #: characters in one number string
MAX_DEPTH = 64  #: nesting of parentheses and operators
MAX_LITERAL_DIGITS = 1000  #: digits in one numeric literal
MAX_SCI_EXPONENT = 1000  #: |e| in a literal such as ``1e-9``
MAX_POWER_EXPONENT = 1000  #: |k| in ``a**k``
MAX_RESULT_BITS = 200_000  #: size of a rational produced by ``**``
MAX_DEGREE = 64  #: degree of a CRootOf polynomial

FUNCTIONS = ("sqrt", "sin", "cos", "tan", "CRootOf")
CONSTANTS = ("pi",)

_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<name>[A-Za-z_][A-Za-z_0-9]*)"
    r"|(?P<op>\*\*|[-+*/(),]))",
    re.ASCII,
)
_PLAIN_RATIONAL = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d{1,4})?(?:\s*/\s*\d+)?\s*", re.ASCII)


class _Fail(Exception):
    """Internal: carries the reason of a rejection up to :func:`parse_number`."""


def _sympy():
    import sympy  # imported lazily: the rational path never needs it

    return sympy


def _tokenize(text: str, names: set[str]) -> list[tuple[str, str]]:
    """Split into tokens; an unknown name is rejected as soon as it is read."""
    tokens = []
    pos = 0
    stripped_end = len(text.rstrip())
    while pos < stripped_end:
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            ch = text[pos:].lstrip()[:1]
            raise _Fail(f"unexpected character {ch!r}")
        kind = m.lastgroup
        if kind == "name" and m.group(kind) not in names:
            raise _Fail(f"unknown name {m.group(kind)!r} (allowed: sqrt pi sin cos tan CRootOf x)")
        tokens.append((kind, m.group(kind)))
        pos = m.end()
    return tokens


class _Parser:
    """Recursive descent over the token list; values are Fraction or SymPy objects."""

    def __init__(self, tokens: list[tuple[str, str]], symbols: dict[str, Any]):
        self.tokens = tokens
        self.pos = 0
        self.depth = 0
        self.symbols = symbols
        self.polynomial_var = None  # the SymPy symbol x, only inside CRootOf

    # -- helpers ---------------------------------------------------------------
    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self, value: str | None = None) -> tuple[str, str]:
        tok = self.peek()
        if tok is None:
            raise _Fail("unexpected end of expression")
        if value is not None and tok[1] != value:
            raise _Fail(f"expected {value!r}, found {tok[1]!r}")
        self.pos += 1
        return tok

    def enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise _Fail(f"nested deeper than {MAX_DEPTH} levels")

    # -- grammar ---------------------------------------------------------------
    def parse(self) -> Number:
        value = self.expr()
        if self.peek() is not None:
            raise _Fail(f"unexpected {self.peek()[1]!r}")
        return value

    def expr(self) -> Number:
        self.enter()
        value = self.term()
        while (tok := self.peek()) is not None and tok[1] in "+-" and tok[0] == "op":
            self.take()
            rhs = self.term()
            value = _add(value, rhs) if tok[1] == "+" else _add(value, _neg(rhs))
        self.depth -= 1
        return value

    def term(self) -> Number:
        value = self.unary()
        while (tok := self.peek()) is not None and tok[1] in ("*", "/"):
            self.take()
            rhs = self.unary()
            value = _mul(value, rhs) if tok[1] == "*" else _div(value, rhs)
        return value

    def unary(self) -> Number:
        tok = self.peek()
        if tok is not None and tok[1] in ("+", "-") and tok[0] == "op":
            self.take()
            self.enter()
            value = self.unary()
            self.depth -= 1
            return _neg(value) if tok[1] == "-" else value
        return self.power()

    def power(self) -> Number:
        base = self.atom()
        tok = self.peek()
        if tok is not None and tok[1] == "**":
            self.take()
            self.enter()
            exponent = self.unary()
            self.depth -= 1
            return _pow(base, exponent)
        return base

    def atom(self) -> Number:
        kind, text = self.take()
        if kind == "num":
            return _literal(text)
        if text == "(":
            value = self.expr()
            self.take(")")
            return value
        if kind == "name":
            return self.name(text)
        raise _Fail(f"unexpected {text!r}")

    def name(self, text: str) -> Number:
        if text in self.symbols:
            return self.symbols[text]
        if text == "pi":
            return _sympy().pi
        if text == "x":
            if self.polynomial_var is None:
                raise _Fail("'x' is only allowed inside CRootOf(polynomial in x, index)")
            return self.polynomial_var
        if text not in FUNCTIONS:
            raise _Fail(f"unknown name {text!r} (allowed: sqrt pi sin cos tan CRootOf x)")
        self.take("(")
        self.enter()
        if text == "CRootOf":
            value = self.crootof()
        else:
            arg = self.expr()
            self.take(")")
            value = _function(text, arg)
        self.depth -= 1
        return value

    def crootof(self) -> Number:
        sp = _sympy()
        if self.polynomial_var is not None:
            raise _Fail("CRootOf cannot be nested inside CRootOf")
        self.polynomial_var = sp.Symbol("x")
        try:
            poly_expr = self.expr()
        finally:
            x = self.polynomial_var
            self.polynomial_var = None
        self.take(",")
        index_value = self.expr()
        self.take(")")
        if not isinstance(index_value, Fraction) or index_value.denominator != 1:
            raise _Fail("the CRootOf index must be an integer")
        index = int(index_value)
        if isinstance(poly_expr, Fraction):
            raise _Fail("CRootOf needs a polynomial in x of degree at least 1")
        try:
            poly = sp.Poly(poly_expr, x, domain="QQ")
        except Exception as exc:  # PolynomialError, CoercionFailed: not a rational polynomial
            raise _Fail(f"CRootOf needs a polynomial in x with rational coefficients ({exc})") from None
        if poly.degree() < 1 or poly.degree() > MAX_DEGREE:
            raise _Fail(f"CRootOf polynomial degree must be between 1 and {MAX_DEGREE}")
        n_real = len(sp.real_roots(poly.sqf_part()))
        if not 0 <= index < n_real:
            raise _Fail(f"CRootOf index {index} is not a real root (the polynomial has {n_real})")
        return sp.CRootOf(poly, index)


def _literal(text: str) -> Fraction:
    mantissa, _, exponent = text.lower().partition("e")
    if len(mantissa) > MAX_LITERAL_DIGITS + 1:
        raise _Fail(f"literal longer than {MAX_LITERAL_DIGITS} digits")
    if exponent and abs(int(exponent)) > MAX_SCI_EXPONENT:
        raise _Fail(f"exponent larger than {MAX_SCI_EXPONENT} in literal")
    return Fraction(text)  # Fraction reads decimal and scientific strings exactly


def _is_fraction(x: Any) -> bool:
    return isinstance(x, Fraction)


def _to_sympy(x: Number) -> Any:
    if _is_fraction(x):
        return _sympy().Rational(x.numerator, x.denominator)
    return x


def _normalize(x: Any) -> Number:
    if _is_fraction(x):
        return x
    if x.is_Rational:
        return Fraction(int(x.p), int(x.q))
    if x.has(_sympy().zoo, _sympy().oo, -_sympy().oo, _sympy().nan):
        raise _Fail("not a finite real number")
    return x


def _add(a: Number, b: Number) -> Number:
    if _is_fraction(a) and _is_fraction(b):
        return a + b
    return _normalize(_to_sympy(a) + _to_sympy(b))


def _neg(a: Number) -> Number:
    return -a


def _mul(a: Number, b: Number) -> Number:
    if _is_fraction(a) and _is_fraction(b):
        return a * b
    return _normalize(_to_sympy(a) * _to_sympy(b))


def _div(a: Number, b: Number) -> Number:
    if _is_fraction(b):
        if b == 0:
            raise _Fail("division by zero")
        if _is_fraction(a):
            return a / b
    elif b.is_zero:
        raise _Fail("division by zero")
    return _normalize(_to_sympy(a) / _to_sympy(b))


def _pow(base: Number, exponent: Number) -> Number:
    if not _is_fraction(exponent):
        raise _Fail("exponents must be rational numbers")
    if abs(exponent.numerator) > MAX_POWER_EXPONENT or exponent.denominator > MAX_POWER_EXPONENT:
        raise _Fail(f"exponent {exponent} is too large (limit {MAX_POWER_EXPONENT})")
    if _is_fraction(base) and exponent.denominator == 1:
        k = exponent.numerator
        if base == 0 and k < 0:
            raise _Fail("division by zero")
        size = max(base.numerator.bit_length(), base.denominator.bit_length()) * abs(k)
        if size > MAX_RESULT_BITS:
            raise _Fail("the power is too large")
        return base**k
    negative = base < 0 if _is_fraction(base) else (not base.free_symbols and _closed_form_sign(base) < 0)
    if negative and exponent.denominator != 1:
        raise _Fail("a negative number to a fractional power is not real")
    sp = _sympy()
    return _normalize(sp.Pow(_to_sympy(base), sp.Rational(exponent.numerator, exponent.denominator)))


def _closed_form_sign(x: Any) -> int:
    """The certified sign of a closed form (see :func:`verify.core.numeric.certified_sign`)."""
    from verify.core.numeric import certified_sign
    from verify.errors import Undecided

    try:
        return certified_sign(x)
    except Undecided as exc:
        raise _Fail(f"cannot decide the sign of {x}: {exc}") from None


def _function(name: str, arg: Number) -> Number:
    sp = _sympy()
    if name == "sqrt":
        if _is_fraction(arg):
            if arg < 0:
                raise _Fail("sqrt of a negative number")
            rn, rd = math.isqrt(arg.numerator), math.isqrt(arg.denominator)
            if rn * rn == arg.numerator and rd * rd == arg.denominator:
                return Fraction(rn, rd)
        elif not arg.free_symbols and _closed_form_sign(arg) < 0:
            raise _Fail("sqrt of a negative number")
        return _normalize(sp.sqrt(_to_sympy(arg)))
    func = {"sin": sp.sin, "cos": sp.cos, "tan": sp.tan}[name]
    return _normalize(func(_to_sympy(arg)))


def _quote(text: str) -> str:
    shown = text if len(text) <= 80 else text[:77] + "..."
    return json.dumps(shown)


def parse_number(text: str, *, where: str | None = None, symbols: dict[str, Any] | None = None) -> Number:
    """Parse a number string exactly, without executing anything.

    Returns a :class:`~fractions.Fraction` when the value is rational and a SymPy
    expression otherwise. ``where`` names the field for the error message, as in
    ``cases[3].normals[1][0]: not a number: "1/0" (division by zero)``. ``symbols`` maps
    extra names (such as ``eps``) to SymPy symbols for symbolic runs.

    >>> parse_number("-3/8")
    Fraction(-3, 8)
    >>> parse_number("1e-9")
    Fraction(1, 1000000000)
    >>> parse_number("sqrt(12)/2")
    sqrt(3)
    >>> parse_number("__import__('os')")
    Traceback (most recent call last):
    ...
    verify.errors.BadNumber: not a number: "__import__('os')" (unknown name '__import__' ...)
    """
    prefix = f"{where}: " if where else ""
    if not isinstance(text, str):
        raise BadNumber(f"{prefix}not a number: expected a string, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise BadNumber(f"{prefix}not a number: {_quote(text)} (longer than {MAX_LENGTH} characters)")
    if _PLAIN_RATIONAL.fullmatch(text) and len(text) <= MAX_LITERAL_DIGITS:
        # fast path: "7", "-3/8", "0.0743", "1e-9" need no tokenizer and no SymPy
        num, _, den = text.partition("/")
        try:
            value = Fraction(num.strip())
            if den:
                d = int(den)
                if d == 0:
                    raise BadNumber(f"{prefix}not a number: {_quote(text)} (division by zero)")
                value /= d
            return value
        except (ValueError, OverflowError):
            pass  # fall through to the full parser for a precise message
    try:
        tokens = _tokenize(text, {*FUNCTIONS, *CONSTANTS, "x", *(symbols or {})})
        if not tokens:
            raise _Fail("empty")
        return _Parser(tokens, symbols or {}).parse()
    except _Fail as exc:
        raise BadNumber(f"{prefix}not a number: {_quote(text)} ({exc})") from None
    except RecursionError:
        raise BadNumber(f"{prefix}not a number: {_quote(text)} (nested too deeply)") from None


_SMALL_INTS = 16
_INT_FRACTIONS = {i: Fraction(i) for i in range(-_SMALL_INTS + 1, _SMALL_INTS)}


def to_number(value: Any, *, where: str | None = None) -> Number:
    """Turn a user value into a :data:`Number`: strings are parsed, ints and Fractions kept.

    Binary floats are refused rather than converted, because ``0.1`` is not 1/10:
    pass ``"0.1"`` (read exactly) or ``Fraction(1, 10)``. SymPy numbers are accepted.

    >>> to_number(3), to_number("0.5"), to_number(Fraction(2, 4))
    (Fraction(3, 1), Fraction(1, 2), Fraction(1, 2))
    >>> to_number(0.1)
    Traceback (most recent call last):
    ...
    verify.errors.BadNumber: not a number: 0.1 is a binary float; pass "0.1" (read exactly) or a Fraction
    """
    if type(value) is Fraction:  # the common case, already exact and immutable
        return value
    if type(value) is int and -_SMALL_INTS < value < _SMALL_INTS:  # 0 and 1 fill mass matrices
        return _INT_FRACTIONS[value]
    prefix = f"{where}: " if where else ""
    if isinstance(value, str):
        return parse_number(value, where=where)
    if isinstance(value, bool):
        raise BadNumber(f"{prefix}not a number: {value!r}")
    if isinstance(value, int):
        return Fraction(value)
    if isinstance(value, Fraction):
        return Fraction(value.numerator, value.denominator)
    if isinstance(value, float):
        raise BadNumber(
            f'{prefix}not a number: {value!r} is a binary float; pass "{value!r}" (read exactly) or a Fraction'
        )
    if hasattr(value, "json_number_text"):  # see verify.records.results.BareJSONNumber
        text = value.json_number_text
        raise BadNumber(f'{prefix}not a number: bare JSON number {text}; write it as a string, "{text}"')
    if hasattr(value, "is_number") and hasattr(value, "free_symbols"):  # a SymPy expression
        if value.free_symbols:
            return value
        try:
            return _normalize(value)
        except _Fail as exc:
            raise BadNumber(f"{prefix}not a number: {value} ({exc})") from None
    if hasattr(value, "numerator") and hasattr(value, "denominator"):  # gmpy2.mpq, flint.fmpq
        return Fraction(int(value.numerator), int(value.denominator))
    raise BadNumber(f"{prefix}not a number: {value!r} of type {type(value).__name__}")


def split_list(text: str) -> list[str]:
    """Split ``"1, 2, CRootOf(x**2 - 2, 1)"`` at the commas outside parentheses.

    >>> split_list("1/2, sqrt(2), CRootOf(x**2 - 2, 1)")
    ['1/2', 'sqrt(2)', 'CRootOf(x**2 - 2, 1)']
    """
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return parts


# -- output -----------------------------------------------------------------------


def int_to_str(n: int) -> str:
    """Decimal digits of an integer of any size (CPython limits ``str(int)`` to 4300 digits)."""
    if n < 0:
        return "-" + int_to_str(-n)
    if n.bit_length() < 12_000:
        return str(n)
    k = (n.bit_length() * 3) // 20  # about half the number of decimal digits
    high, low = divmod(n, 10**k)
    return int_to_str(high) + int_to_str(low).rjust(k, "0")


def format_exact(value: Number) -> str:
    """The simplest exact string: ``"381/8"``, ``"-2"``, ``"-sqrt(2)/4 + sqrt(6)/4"``.

    >>> format_exact(Fraction(381, 8)), format_exact(Fraction(-2))
    ('381/8', '-2')
    """
    if isinstance(value, Fraction):
        if value.denominator == 1:
            return int_to_str(value.numerator)
        return f"{int_to_str(value.numerator)}/{int_to_str(value.denominator)}"
    return str(value)


def _ilog10(num: int, den: int) -> int:
    """floor(log10(num/den)) for positive integers, exactly (integer arithmetic only)."""
    e = ((num.bit_length() - den.bit_length()) * 30103) // 100000
    while True:  # correct the estimate exactly
        if e >= 0:
            lo_ok = num >= den * 10**e
            hi_ok = num < den * 10 ** (e + 1)
        else:
            lo_ok = num * 10 ** (-e) >= den
            hi_ok = num * 10 ** (-e - 1) < den
        if lo_ok and hi_ok:
            return e
        e = e - 1 if not lo_ok else e + 1


def _exact_rational(value: Any) -> Fraction | None:
    """``value`` as a Fraction when it is an exact rational of a known kind, else None.

    Fractions and ints, and any type with integer ``numerator`` and ``denominator``
    (gmpy2's ``mpq``, python-flint's ``fmpq``): read through those integers, never through
    a float. Floats are refused (``TypeError``): they are not the exact values they print as.
    """
    if isinstance(value, Fraction):
        return value
    if isinstance(value, (bool, float)):
        raise TypeError(
            f"format_decimal needs an exact number, got {type(value).__name__} {value!r}: "
            'pass a Fraction or a string such as "0.1" (read exactly)'
        )
    if isinstance(value, int):
        return Fraction(value)
    if hasattr(value, "free_symbols"):  # SymPy: rationals here, closed forms by the caller
        return Fraction(int(value.p), int(value.q)) if getattr(value, "is_Rational", False) else None
    try:
        num, den = value.numerator, value.denominator
        return Fraction(operator.index(num), operator.index(den))  # index(): integers only, never a float
    except (AttributeError, TypeError):
        return None


def _decimal_digits(value: Fraction, digits: int, rounding: str) -> tuple[str, str, int]:
    """``value`` rounded to ``digits`` significant digits: (sign, the digit string, exponent of
    its first digit); ``value`` is not 0."""
    sign = "-" if value < 0 else ""
    num, den = abs(value.numerator), value.denominator
    e = _ilog10(num, den)
    shift = digits - 1 - e
    scaled_num = num * 10**shift if shift >= 0 else num
    scaled_den = den if shift >= 0 else den * 10 ** (-shift)
    q, r = divmod(scaled_num, scaled_den)
    away = {"floor": sign == "-", "ceiling": sign == "", "half_even": None}[rounding]
    if away is None:
        away = 2 * r > scaled_den or (2 * r == scaled_den and q % 2 == 1)
    if r and away:
        q += 1
    if q == 10**digits:  # rounding carried into a new digit
        q //= 10
        e += 1
    return sign, int_to_str(q), e


def format_decimal(value: Any, digits: int = 30, rounding: str = "half_even") -> str:
    """A decimal string with ``digits`` significant digits, rounded exactly.

    ``rounding`` is ``"half_even"`` (default), ``"floor"`` or ``"ceiling"`` (for printing
    the bounds of an enclosure outward). Trailing zeros are dropped, so exact decimals read
    naturally (``"34.316164"``); magnitudes outside [1e-7, 1e30) use an exponent (``"1e-9"``).

    ``value`` is any exact number: a Fraction or int, an exact rational of another library
    (gmpy2's ``mpq``, python-flint's ``fmpq``, as the exact backend returns them: read
    through their integer numerator and denominator), a closed form (SymPy) or a
    :class:`~verify.core.algebraic.RealAlgebraic` (digits certified by enclosures). Floats and
    unknown types raise ``TypeError``; so do number-field elements, which need their field:
    use ``K.to_decimal(x)`` of the backend that made them.

    >>> format_decimal(Fraction(2, 3), 5), format_decimal(Fraction(857766, 25000))
    ('0.66667', '34.31064')
    >>> format_decimal(Fraction(2, 3), 3, "floor"), format_decimal(Fraction(-2, 3), 3, "floor")
    ('0.666', '-0.667')
    >>> from verify.core.backends import RationalBackend
    >>> x = RationalBackend().convert(Fraction(2, 3))  # gmpy2's mpq when installed
    >>> format_decimal(x, 5), format_decimal(7)
    ('0.66667', '7')
    >>> format_decimal(0.5)
    Traceback (most recent call last):
    ...
    TypeError: format_decimal needs an exact number, got float 0.5: pass a Fraction or a string such as "0.1" ...
    """
    if rounding not in ("half_even", "floor", "ceiling"):
        raise ValueError(f"rounding must be 'half_even', 'floor' or 'ceiling', got {rounding!r}")
    exact = _exact_rational(value)
    if exact is None:
        return _format_algebraic_decimal(value, digits, rounding)
    if exact == 0:
        return "0"
    sign, mantissa, e = _decimal_digits(exact, digits, rounding)
    return sign + _place_point(mantissa.rstrip("0") or "0", e)


def certified_decimal(lo: Fraction, hi: Fraction, digits: int = 30) -> str:
    """The digits of every number in ``[lo, hi]``: the longest rounding (half to even, at most
    ``digits`` significant digits) on which both ends agree, trailing zeros kept (they are
    certified too).

    Rounding is monotone, so every number between ``lo`` and ``hi`` rounds to the same
    string: it is the correctly rounded value of the unknown number, with as many digits as
    the enclosure certifies. A point (``lo == hi``) is exact and prints as
    :func:`format_decimal` does. An enclosure of 0 that certifies no digit prints as
    ``"0e-N"``: the number rounds to 0 at N decimal places (|x| < 10^-N / 2). An enclosure
    too wide for even one digit prints as itself, ``"[lo, hi]"`` (two digits, outward).

    >>> certified_decimal(Fraction(476241, 100000), Fraction(476249, 100000), 30)
    '4.762'
    >>> certified_decimal(Fraction(90499, 1000), Fraction(90501, 1000), 30)
    '90.50'
    >>> certified_decimal(Fraction(10**25, 3) - 1, Fraction(10**25, 3) + 1, 30)
    '3.33333333333333333333333e+24'
    >>> certified_decimal(Fraction(-3, 10**20), Fraction(1, 10**20), 30)
    '0e-19'
    >>> certified_decimal(Fraction(1, 4), Fraction(1, 4))
    '0.25'
    """
    if lo > hi:
        raise ValueError(f"an empty enclosure: {lo} > {hi}")
    if lo == hi:
        return format_decimal(lo, digits)
    if lo <= 0 <= hi:  # no significant digit is certain; how many decimal places round to 0 is
        m = 2 * max(-lo, hi)  # every |x| <= m/2 rounds to 0 at 10^q once m < 10^q
        q = _ilog10(m.numerator, m.denominator) + 1
        return f"0e{q:+d}" if q > 0 else f"0e{q}"
    for d in range(digits, 0, -1):
        low, high = _decimal_digits(lo, d, "half_even"), _decimal_digits(hi, d, "half_even")
        if low == high:
            sign, mantissa, e = low
            if e >= len(mantissa):  # zeros padding the integer part would look certified: an exponent
                return f"{sign}{mantissa[0]}{'.' if mantissa[1:] else ''}{mantissa[1:]}e{e:+d}"
            return sign + _place_point(mantissa, e)
    return f"[{format_decimal(lo, 2, 'floor')}, {format_decimal(hi, 2, 'ceiling')}]"  # not one digit agrees


def _place_point(mantissa: str, e: int) -> str:
    """Put the decimal point in a digit string d1 d2 ... whose value is d1.d2... * 10**e."""
    if -7 <= e < 30:
        if e >= 0:
            whole = mantissa[: e + 1].ljust(e + 1, "0")
            frac = mantissa[e + 1 :]
            return whole + ("." + frac if frac else "")
        return "0." + "0" * (-e - 1) + mantissa
    frac = mantissa[1:]
    return mantissa[0] + ("." + frac if frac else "") + f"e{e:+d}"


def _format_algebraic_decimal(value: Any, digits: int, rounding: str) -> str:
    """Decimal digits of a closed form or a real algebraic number, from certified enclosures."""
    if hasattr(value, "free_symbols") and hasattr(value, "is_number"):  # a SymPy closed form
        if value.free_symbols:
            names = sorted(map(str, value.free_symbols))
            raise TypeError(f"format_decimal needs a number, got an expression in {', '.join(names)}")
        if rounding == "half_even":
            from verify.core.numeric import certified_digits

            return certified_digits(value, digits)
        return _directed_closed_form(value, digits, rounding)
    from verify.core.algebraic import RealAlgebraic

    if not isinstance(value, RealAlgebraic):
        raise TypeError(
            f"format_decimal cannot read a {type(value).__module__}.{type(value).__name__}: "
            "pass a Fraction, int, an exact rational (mpq, fmpq), a SymPy closed form or a RealAlgebraic "
            "(a backend's own values: K.to_decimal(x))"
        )
    return value.decimal(digits) if rounding == "half_even" else _directed_algebraic(value, digits, rounding)


def _directed_closed_form(value: Any, digits: int, rounding: str) -> str:
    """Floor or ceiling digits of a closed form: from interval enclosures at rising precision,
    until both ends round alike; an algebraic value that keeps straddling a rounding boundary
    may be a decimal exactly, and is then settled by its minimal polynomial."""
    from verify.core.numeric import MAX_PREC, _interval_context, _mpf_to_fraction, evaluate
    from verify.errors import NoConvergence

    prec = max(64, digits * 4 + 32)
    for attempt in range(64):
        if prec > MAX_PREC:
            break
        x = evaluate(value, _interval_context(prec))
        lo, hi = (format_decimal(_mpf_to_fraction(b), digits, rounding) for b in (x.a, x.b))
        if lo == hi:
            return lo
        if attempt == 3 and value.is_algebraic:
            from verify.core.algebraic import RealAlgebraic

            return _directed_algebraic(RealAlgebraic.from_number(value), digits, rounding)
        prec *= 2
    raise NoConvergence(f"cannot certify {digits} digits of {value} rounded towards {rounding}")


def _directed_algebraic(value: Any, digits: int, rounding: str) -> str:
    """Floor or ceiling digits of a RealAlgebraic (exact when it is rational)."""
    if value.is_rational:
        return format_decimal(value.rational_value(), digits, rounding)
    while True:  # irrational: no rounding boundary is hit, so the isolating interval shrinks past it
        lo, hi = format_decimal(value.lo, digits, rounding), format_decimal(value.hi, digits, rounding)
        if lo == hi:
            return lo
        value.refine()
