"""Number strings in: a restricted, non-executing parser.

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

Numbers out (decimal and exact strings) are :mod:`verify.numbers.format`'s.
"""

from __future__ import annotations

import json
import math
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


def _sympy() -> Any:
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
        kind = str(m.lastgroup)  # one of the alternatives always matched
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
        if (tok := self.peek()) is not None:
            raise _Fail(f"unexpected {tok[1]!r}")
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


def to_sympy(x: Number) -> Any:
    """A parsed number as a SymPy expression (a Fraction becomes a SymPy ``Rational``, exactly).

    >>> to_sympy(Fraction(-3, 8))
    -3/8
    """
    if isinstance(x, Fraction):
        return _sympy().Rational(x.numerator, x.denominator)
    return x


def _normalize(x: Any) -> Number:
    if isinstance(x, Fraction):
        return x
    if x.is_Rational:
        return Fraction(int(x.p), int(x.q))
    if x.has(_sympy().zoo, _sympy().oo, -_sympy().oo, _sympy().nan):
        raise _Fail("not a finite real number")
    return x


def _add(a: Number, b: Number) -> Number:
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a + b
    return _normalize(to_sympy(a) + to_sympy(b))


def _neg(a: Number) -> Number:
    return -a


def _mul(a: Number, b: Number) -> Number:
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a * b
    return _normalize(to_sympy(a) * to_sympy(b))


def _div(a: Number, b: Number) -> Number:
    if isinstance(b, Fraction):
        if b == 0:
            raise _Fail("division by zero")
        if isinstance(a, Fraction):
            return a / b
    elif b.is_zero:
        raise _Fail("division by zero")
    return _normalize(to_sympy(a) / to_sympy(b))


def _pow(base: Number, exponent: Number) -> Number:
    if not isinstance(exponent, Fraction):
        raise _Fail("exponents must be rational numbers")
    if abs(exponent.numerator) > MAX_POWER_EXPONENT or exponent.denominator > MAX_POWER_EXPONENT:
        raise _Fail(f"exponent {exponent} is too large (limit {MAX_POWER_EXPONENT})")
    if isinstance(base, Fraction) and exponent.denominator == 1:
        k = exponent.numerator
        if base == 0 and k < 0:
            raise _Fail("division by zero")
        size = max(base.numerator.bit_length(), base.denominator.bit_length()) * abs(k)
        if size > MAX_RESULT_BITS:
            raise _Fail("the power is too large")
        return base**k
    negative = base < 0 if isinstance(base, Fraction) else (not base.free_symbols and _closed_form_sign(base) < 0)
    if negative and exponent.denominator != 1:
        raise _Fail("a negative number to a fractional power is not real")
    sp = _sympy()
    return _normalize(sp.Pow(to_sympy(base), sp.Rational(exponent.numerator, exponent.denominator)))


def _closed_form_sign(x: Any) -> int:
    """The certified sign of a closed form (see :func:`verify.numbers.numeric.certified_sign`)."""
    from verify.errors import Undecided
    from verify.numbers.numeric import certified_sign

    try:
        return certified_sign(x)
    except Undecided as exc:
        raise _Fail(f"cannot decide the sign of {x}: {exc}") from None


def _function(name: str, arg: Number) -> Number:
    sp = _sympy()
    if name == "sqrt":
        if isinstance(arg, Fraction):
            if arg < 0:
                raise _Fail("sqrt of a negative number")
            rn, rd = math.isqrt(arg.numerator), math.isqrt(arg.denominator)
            if rn * rn == arg.numerator and rd * rd == arg.denominator:
                return Fraction(rn, rd)
        elif not arg.free_symbols and _closed_form_sign(arg) < 0:
            raise _Fail("sqrt of a negative number")
        return _normalize(sp.sqrt(to_sympy(arg)))
    func = {"sin": sp.sin, "cos": sp.cos, "tan": sp.tan}[name]
    return _normalize(func(to_sympy(arg)))


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
    if hasattr(value, "json_number_text"):  # see verify.records.files.BareJSONNumber
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
