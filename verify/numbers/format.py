"""Numbers out: exact strings and decimal digits, rounded exactly or certified.

:func:`format_exact` writes the simplest exact string of a number, :func:`format_decimal`
its decimal digits: exact rationals are rounded exactly (integer arithmetic only, never a
binary float), closed forms and real algebraic numbers are printed from certified
enclosures (:mod:`verify.numbers.numeric`, :mod:`verify.numbers.algebraic`), so that every digit
shown is right. :func:`certified_decimal` prints the digits that an enclosure ``[lo, hi]``
certifies.

>>> format_decimal(Fraction(1, 3), 10), format_exact(Fraction(381, 8))
('0.3333333333', '381/8')
>>> import sympy
>>> format_decimal(sympy.sqrt(2), 12)
'1.41421356237'
"""

from __future__ import annotations

import operator
from fractions import Fraction
from typing import Any

from verify.numbers.parse import Number


def int_to_str(n: int) -> str:
    """Decimal digits of an integer of any size (CPython limits ``str(int)`` to 4300 digits)."""
    if n < 0:
        return "-" + int_to_str(-n)
    if n.bit_length() < 12_000:
        return str(n)
    k = (n.bit_length() * 3) // 20  # about half the number of decimal digits
    high, low = divmod(n, 10**k)
    return int_to_str(high) + int_to_str(low).rjust(k, "0")


def str_to_int(text: str) -> int:
    """The integer of a string of decimal digits of any length (the inverse of :func:`int_to_str`).

    >>> str_to_int("-" + "9" * 5000) == -(10**5000 - 1)
    True
    """
    if text.startswith("-"):
        return -str_to_int(text[1:])
    if len(text) <= 4000:
        return int(text)
    k = len(text) // 2
    high: int = str_to_int(text[:-k]) * 10**k
    return high + str_to_int(text[-k:])


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


def ilog10(num: int, den: int) -> int:
    """floor(log10(num/den)) for positive integers, exactly (integer arithmetic only).

    >>> ilog10(999, 1), ilog10(1000, 1), ilog10(1, 1000), ilog10(1, 1001)
    (2, 3, -3, -4)
    """
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
    e = ilog10(num, den)
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
    :class:`~verify.numbers.algebraic.RealAlgebraic` (digits certified by enclosures). Floats and
    unknown types raise ``TypeError``; so do number-field elements, which need their field:
    use ``K.to_decimal(x)`` of the backend that made them.

    >>> format_decimal(Fraction(2, 3), 5), format_decimal(Fraction(857766, 25000))
    ('0.66667', '34.31064')
    >>> format_decimal(Fraction(2, 3), 3, "floor"), format_decimal(Fraction(-2, 3), 3, "floor")
    ('0.666', '-0.667')
    >>> from verify.numbers.backends import RationalBackend
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
        q = ilog10(m.numerator, m.denominator) + 1
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
            return _closed_form_digits(value, digits)
        return _directed_closed_form(value, digits, rounding)
    from verify.numbers.algebraic import RealAlgebraic

    if not isinstance(value, RealAlgebraic):
        raise TypeError(
            f"format_decimal cannot read a {type(value).__module__}.{type(value).__name__}: "
            "pass a Fraction, int, an exact rational (mpq, fmpq), a SymPy closed form or a RealAlgebraic "
            "(a backend's own values: K.to_decimal(x))"
        )
    return _algebraic_digits(value, digits, rounding)


def _closed_form_digits(expr: Any, digits: int) -> str:
    """``digits`` significant digits of a closed form (rounded half to even), certified by an
    interval enclosure at rising precision."""
    from verify.errors import NoConvergence
    from verify.numbers.numeric import (
        MAX_PREC,
        START_PREC,
        certified_sign,
        evaluate,
        interval_context,
        mpf_to_fraction,
        shown,
    )

    try:
        if certified_sign(expr) == 0:
            return "0"
    except NoConvergence:
        if not expr.is_algebraic:
            raise
        prec = MAX_PREC + 1  # long coefficients cancel beyond MAX_PREC: the exact number decides (below)
    else:
        prec = max(START_PREC, digits * 10 // 3 + 32)
    while prec <= MAX_PREC:
        x = evaluate(expr, interval_context(prec))
        lo = format_decimal(mpf_to_fraction(x.a), digits)
        hi = format_decimal(mpf_to_fraction(x.b), digits)
        if lo == hi:
            return lo
        prec *= 2
    if expr.is_algebraic:  # long coefficients cancel beyond MAX_PREC: its minimal polynomial decides
        from verify.numbers.algebraic import RealAlgebraic

        return _algebraic_digits(RealAlgebraic.from_number(expr), digits, "half_even")
    raise NoConvergence(f"cannot certify {digits} digits of {shown(expr)}")


def _directed_closed_form(value: Any, digits: int, rounding: str) -> str:
    """Floor or ceiling digits of a closed form: from interval enclosures at rising precision,
    until both ends round alike; an algebraic value that keeps straddling a rounding boundary
    may be a decimal exactly, and is then settled by its minimal polynomial."""
    from verify.errors import NoConvergence
    from verify.numbers.numeric import MAX_PREC, evaluate, interval_context, mpf_to_fraction

    prec = max(64, digits * 4 + 32)
    for attempt in range(64):
        if prec > MAX_PREC:
            break
        x = evaluate(value, interval_context(prec))
        lo, hi = (format_decimal(mpf_to_fraction(b), digits, rounding) for b in (x.a, x.b))
        if lo == hi:
            return lo
        if attempt == 3 and value.is_algebraic:
            from verify.numbers.algebraic import RealAlgebraic

            return _algebraic_digits(RealAlgebraic.from_number(value), digits, rounding)
        prec *= 2
    raise NoConvergence(f"cannot certify {digits} digits of {value} rounded towards {rounding}")


def _algebraic_digits(value: Any, digits: int, rounding: str) -> str:
    """Digits of a RealAlgebraic: exact when it is rational, else from its isolating interval,
    refined until both ends round alike (an irrational number hits no rounding boundary)."""
    if value.is_rational:
        return format_decimal(value.rational_value(), digits, rounding)
    while True:
        lo, hi = format_decimal(value.lo, digits, rounding), format_decimal(value.hi, digits, rounding)
        if lo == hi:
            return lo
        value.refine()


# -- counts in words ------------------------------------------------------------------------------


def plural(n: int, word: str) -> str:
    """``word`` for one, its plural otherwise (``-es`` after s, sh, ch, x; ``-ies`` for a consonant and y).

    >>> plural(1, "mismatch"), plural(2, "case"), plural(2, "mismatch"), plural(4, "printed entry")
    ('mismatch', 'cases', 'mismatches', 'printed entries')
    """
    if n == 1:
        return word
    if word.endswith("y") and word[-2:-1] not in ("a", "e", "o", "u", ""):
        return word[:-1] + "ies"
    return word + ("es" if word.endswith(("s", "sh", "ch", "x")) else "s")


def counted(n: int, word: str) -> str:
    """``n`` and its noun, singular or plural.

    >>> counted(1, "mismatch"), counted(0, "case")
    ('1 mismatch', '0 cases')
    """
    return f"{n} {plural(n, word)}"


def brief(x: Any, limit: int = 72) -> str:
    """A real algebraic number as a page prints it: its words (:meth:`RealAlgebraic.words`: a rational, radicals,
    or which real root of which polynomial) when they are short, else 12 certified significant digits and the
    degree of its polynomial (the closed form stays in the JSON records).

    >>> from verify.numbers.algebraic import RealAlgebraic, poly_from_coeffs
    >>> brief(RealAlgebraic.roots_in(poly_from_coeffs([1, 0, -2]))[1])
    'sqrt(2)'
    >>> brief(RealAlgebraic.roots_in(poly_from_coeffs([-1, -1, 0, 1]))[0], limit=10)
    '0.754877666247 (a root of degree 3)'
    """
    text: str = x.words()
    if len(text) <= limit:
        return text
    return f"{format_decimal(x, 12)} (a root of degree {x.poly.degree()})"
