"""Numerical evaluation of closed forms (SymPy expressions) under an mpmath context.

One walker, :func:`evaluate`, serves the ``mp`` context (heuristic), the ``iv`` interval
context (a certified enclosure) and ``fp``. It handles exactly what the number parser can
build: rationals, ``pi``, ``+ * **``, ``sqrt``, ``sin cos tan`` and ``CRootOf``.

:func:`certified_sign` decides the sign of a closed form rigorously: from interval
enclosures at rising precision (:func:`interval_context`), with an exact zero test (the
minimal polynomial) when the enclosure keeps containing 0. :func:`mpf_to_fraction` reads the
exact value of a bound. Their digits are printed by :func:`verify.numbers.format.format_decimal`.

>>> import sympy
>>> certified_sign(3 - 2 * sympy.sqrt(2))
1
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.errors import NoConvergence

START_PREC = 64  # bits
MAX_PREC = 1 << 15  # bits


def evaluate(expr: Any, ctx: Any) -> Any:
    """Evaluate a SymPy closed form (or a Fraction) in the mpmath context ``ctx``.

    Under an interval context the result encloses the true value.
    """
    import sympy as sp

    if isinstance(expr, Fraction):
        return ctx.mpf(expr.numerator) / ctx.mpf(expr.denominator)
    if expr.is_Rational:
        return ctx.mpf(int(expr.p)) / ctx.mpf(int(expr.q))
    if expr is sp.pi:
        return ctx.pi
    if expr.is_Add:
        total = ctx.mpf(0)
        for arg in expr.args:
            total += evaluate(arg, ctx)
        return total
    if expr.is_Mul:
        prod = ctx.mpf(1)
        for arg in expr.args:
            prod *= evaluate(arg, ctx)
        return prod
    if expr.is_Pow:
        base, exp = expr.args
        b = evaluate(base, ctx)
        if exp.is_Integer:
            k = int(exp)
            return b**k if k >= 0 else ctx.mpf(1) / b ** (-k)
        if exp.is_Rational:
            p, q = int(exp.p), int(exp.q)
            root = ctx.sqrt(b) if q == 2 else ctx.exp(ctx.log(b) / q)
            return root**p if p >= 0 else ctx.mpf(1) / root ** (-p)
        raise NoConvergence(f"cannot evaluate {expr}: irrational exponent")
    if isinstance(expr, sp.sin):
        return ctx.sin(evaluate(expr.args[0], ctx))
    if isinstance(expr, sp.cos):
        return ctx.cos(evaluate(expr.args[0], ctx))
    if isinstance(expr, sp.tan):
        return ctx.tan(evaluate(expr.args[0], ctx))
    if isinstance(expr, sp.CRootOf):
        prec = getattr(ctx, "prec", 53)
        dx = sp.Rational(1, 2 ** (prec + 8))
        approx = expr.eval_rational(dx=dx, n=prec // 3 + 10)
        mid = ctx.mpf(int(approx.p)) / ctx.mpf(int(approx.q))
        from mpmath.ctx_iv import MPIntervalContext

        if isinstance(ctx, MPIntervalContext):
            err = ctx.mpf(int(dx.p)) / ctx.mpf(int(dx.q))
            return mid + ctx.mpf([-1, 1]) * err
        return mid
    raise NoConvergence(f"cannot evaluate {expr} numerically")


def interval_context(prec: int) -> Any:
    """A fresh mpmath interval context at ``prec`` bits (its own, so precision never leaks).

    >>> x = evaluate(Fraction(1, 3), interval_context(64))
    >>> mpf_to_fraction(x.a) < Fraction(1, 3) < mpf_to_fraction(x.b)
    True
    """
    from mpmath.ctx_iv import MPIntervalContext

    ctx = MPIntervalContext()
    ctx.prec = prec
    return ctx


def _is_exact_zero(expr: Any) -> bool:
    import sympy as sp

    try:
        poly = sp.minimal_polynomial(expr, sp.Symbol("_z"))
    except Exception:  # not algebraic (e.g. involves pi): no exact test here
        return bool(sp.simplify(expr) == 0)
    return bool(poly.as_poly().eval(0) == 0) and poly.as_poly().degree() == 1


def certified_sign(expr: Any) -> int:
    """The sign of a closed form, decided rigorously (interval enclosures, exact zero test)."""
    if isinstance(expr, Fraction):
        return (expr > 0) - (expr < 0)
    prec = START_PREC
    while prec <= MAX_PREC:
        x = evaluate(expr, interval_context(prec))
        if x.a > 0:
            return 1
        if x.b < 0:
            return -1
        if prec == START_PREC * 4 and _is_exact_zero(expr):
            return 0
        prec *= 2
    if _is_exact_zero(expr):
        return 0
    raise NoConvergence(f"cannot decide the sign of {shown(expr)} at {MAX_PREC} bits")


def shown(expr: Any, limit: int = 200) -> str:
    """``expr`` as text for a message, or how long it is when longer than ``limit`` characters (or when its
    integers are too long for Python to print under its default limit).

    >>> shown(Fraction(1, 3)), shown(Fraction(10**300))
    ('1/3', '<a number of 301 characters>')
    """
    try:
        text = str(expr)
    except ValueError:  # an integer of more digits than sys.get_int_max_str_digits()
        return "<a number with integers of more than 4300 digits>"
    return text if len(text) <= limit else f"<a number of {len(text)} characters>"


def mpf_to_fraction(x: Any) -> Fraction:
    """The exact value of an mpmath number or of a degenerate interval (an endpoint).

    Reads the raw (sign, mantissa, exponent, bits) tuple, so nothing is rounded.

    >>> from mpmath import mp
    >>> mpf_to_fraction(mp.mpf(3) / 8)
    Fraction(3, 8)
    """
    raw = x._mpi_[0] if hasattr(x, "_mpi_") else x._mpf_
    sign, man, exp, _ = raw
    if not man and exp:
        raise ValueError("an infinite or undefined bound has no exact value")
    value = Fraction(int(man) * 2 ** int(exp)) if exp >= 0 else Fraction(int(man), 2 ** int(-exp))
    return -value if sign else value
