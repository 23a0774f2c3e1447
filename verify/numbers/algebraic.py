"""Exact real algebraic numbers by isolating intervals.

A :class:`RealAlgebraic` is a root of an irreducible polynomial with rational coefficients,
held with a rational interval that contains no other root (rationals are roots of degree-1
polynomials, held exactly). Comparisons and signs of polynomials at such numbers are decided
exactly: equal numbers have the same minimal polynomial and a common root in their
intervals; different numbers are separated by bisection, which always ends.

They are the endpoints of the pieces of parameter maps (:mod:`verify.numbers.backends.symbolic`), written in
the simplest exact form: rationals, radicals for degree 2, ``CRootOf(poly, k)`` otherwise; their
decimal digits are :func:`verify.numbers.format.format_decimal`'s (certified).

>>> r = RealAlgebraic.roots_in(poly_from_coeffs([1, -6, 1]))  # eps**2 - 6 eps + 1
>>> [str(x) for x in r]
['3 - 2*sqrt(2)', '2*sqrt(2) + 3']
>>> r[0] < RealAlgebraic.rational(Fraction(1716, 10000)), r[0] > RealAlgebraic.rational(Fraction(1715, 10000))
(True, True)
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from functools import cached_property, total_ordering
from typing import Any

import sympy as sp

flint: Any
try:
    import flint
except ImportError:  # pragma: no cover - the fast extra is not installed
    flint = None

from verify.numbers.backends.ratfunc import flint_in_use  # noqa: E402 (after the optional import of flint)

X = sp.Symbol("x")


def poly_from_coeffs(coeffs: list[Any]) -> sp.Poly:
    """A polynomial in x from its coefficients, highest degree first."""
    return sp.Poly(
        [sp.Rational(c) if not isinstance(c, Fraction) else sp.Rational(c.numerator, c.denominator) for c in coeffs],
        X,
        domain="QQ",
    )


def _q(x: Any) -> Fraction:
    return Fraction(int(x.p), int(x.q)) if hasattr(x, "p") else Fraction(x)


def _eval(p: sp.Poly, q: Fraction) -> Fraction:
    """p(q) exactly (Horner over Fractions)."""
    total = Fraction(0)
    for c in p.all_coeffs():
        total = total * q + _q(c)
    return total


def _eval_interval(coeffs: Sequence[Any], lo: Any, hi: Any) -> tuple[Any, Any]:
    """An enclosure of {p(t) : lo <= t <= hi} (interval Horner; exact rationals: Fractions or flint's
    fmpq, coefficients highest degree first). For lo >= 0 the least and largest of the four products
    are known from the signs of the bounds, and only those two are formed (the same enclosure)."""
    a = b = lo - lo
    if lo >= 0:
        for c in coeffs:
            a, b = (a * lo if a >= 0 else a * hi) + c, (b * hi if b >= 0 else b * lo) + c
        return a, b
    return interval_value([(c, c) for c in coeffs], lo, hi)


Interval = tuple[Fraction, Fraction]


def interval_value(coeffs: Sequence[Interval], lo: Fraction, hi: Fraction) -> Interval:
    """An enclosure of {p(t) : lo <= t <= hi} for a polynomial whose coefficients (highest degree first) are known to
    lie in intervals ``(low, high)`` of rationals (interval Horner, exact; Fractions or flint's fmpq).

    >>> interval_value([(Fraction(1), Fraction(1)), (Fraction(-1), Fraction(1))], Fraction(2), Fraction(3))
    (Fraction(1, 1), Fraction(4, 1))
    """
    a = b = lo - lo
    for c_lo, c_hi in coeffs:
        products = (a * lo, a * hi, b * lo, b * hi)
        a, b = min(products) + c_lo, max(products) + c_hi
    return a, b


def _halved(value_at: Any, lo: Any, hi: Any) -> tuple[Any, Any]:
    """The half of [lo, hi] that holds the root of the polynomial ``value_at`` evaluates (exact bisection;
    the root itself when it is the midpoint)."""
    mid = (lo + hi) / 2
    v = value_at(mid)
    if v == 0:  # cannot happen for an irreducible polynomial of degree >= 2
        return mid, mid
    return (mid, hi) if _sign(value_at(lo)) == _sign(v) else (lo, mid)


def _decided(coeffs: Sequence[Any], lo: Any, hi: Any, value_at: Any) -> tuple[int, Any, Any]:
    """The sign of p (its ``coeffs``, not 0 at the root) at the root that [lo, hi] isolates, and the
    interval halved until an interval evaluation decided it."""
    while True:
        a, b = _eval_interval(coeffs, lo, hi)
        if a > 0:
            return 1, lo, hi
        if b < 0:
            return -1, lo, hi
        if lo != hi:
            lo, hi = _halved(value_at, lo, hi)


def _fmpq(q: Fraction) -> Any:
    return flint.fmpq(q.numerator, q.denominator)


def _sign(x: Any) -> int:
    return int(x > 0) - int(x < 0)


def count_roots(p: sp.Poly, lo: Fraction, hi: Fraction) -> int:
    """The distinct real roots of p in the closed interval [lo, hi], exactly: with python-flint, from FLINT's
    certified isolation of the roots of p's square-free part (:func:`_flint_count`), else SymPy's Sturm
    sequences (the same count, far slower at high degree).

    >>> count_roots(poly_from_coeffs([1, 0, -2]), Fraction(0), Fraction(2))
    1
    >>> count_roots(poly_from_coeffs([1, -2, 1]), Fraction(1), Fraction(1))  # a double root, counted once
    1
    """
    if flint is not None and flint_in_use() and p.degree() > 0:
        return _flint_count([_q(c) for c in p.all_coeffs()], lo, hi)
    return int(p.count_roots(sp.Rational(lo.numerator, lo.denominator), sp.Rational(hi.numerator, hi.denominator)))


def _flint_count(coeffs: Sequence[Fraction], lo: Fraction, hi: Fraction) -> int:
    """:func:`count_roots` on FLINT: each real root's isolating ball (``arb_fmpz_poly_complex_roots``: one root
    in each, real roots with an imaginary part of exactly 0) is inside [lo, hi], outside it, or holds an end;
    then the root's side of that end is the side where the square-free part changes sign (exact values)."""
    f = flint.fmpq_poly([_fmpq(c) for c in reversed(coeffs)])
    f = f / f.gcd(f.derivative())  # square-free: one simple root in each ball
    a, b = _fmpq(lo), _fmpq(hi)
    count = 0
    for c, _m in f.complex_roots():
        if not c.imag.is_zero():
            continue
        (mm, me), (rm, re) = c.real.mid().man_exp(), c.real.rad().man_exp()
        mid, rad = flint.fmpq(int(mm)) * flint.fmpq(2) ** int(me), flint.fmpq(int(rm)) * flint.fmpq(2) ** int(re)
        u, v = mid - rad, mid + rad  # the root is the one zero of f in [u, v], where f changes sign
        if v < a or u > b:
            continue
        above = u >= a or f(a) == 0 or _sign(f(a)) != _sign(f(v))  # root >= lo
        below = v <= b or f(b) == 0 or _sign(f(u)) != _sign(f(b))  # root <= hi
        count += above and below
    return count


def _rebuilt(coeffs: list[Fraction], lo: Fraction, hi: Fraction) -> RealAlgebraic:
    """A :class:`RealAlgebraic` from its pickle (:meth:`RealAlgebraic.__reduce__`)."""
    return RealAlgebraic(poly_from_coeffs(coeffs), lo, hi)


@total_ordering
class RealAlgebraic:
    """A real algebraic number: an irreducible polynomial and an isolating interval [lo, hi]."""

    __slots__ = ("__dict__", "hi", "lo", "poly")

    def __init__(self, poly: sp.Poly, lo: Fraction, hi: Fraction):
        self.poly = poly
        self.lo = lo
        self.hi = hi

    def __reduce__(self) -> tuple[Any, tuple[list[Fraction], Fraction, Fraction]]:
        """Pickled by its coefficients (Fractions), for other processes: SymPy's own pickle of a polynomial
        over QQ comes back over ZZ with python-flint's ground types, and the number would then not equal
        itself (comparing two such copies of an irrational never ends).

        >>> import pickle
        >>> r = RealAlgebraic.roots_in(poly_from_coeffs([1, 0, -2]))[1]
        >>> copy = pickle.loads(pickle.dumps(r))
        >>> copy == r, copy.poly == r.poly
        (True, True)
        """
        return (_rebuilt, ([_q(c) for c in self.poly.all_coeffs()], self.lo, self.hi))

    @classmethod
    def rational(cls, q: Fraction) -> RealAlgebraic:
        q = Fraction(q)
        return cls(sp.Poly([q.denominator, -q.numerator], X, domain="QQ").monic(), q, q)

    @classmethod
    def roots_in(cls, p: sp.Poly, lo: Fraction | None = None, hi: Fraction | None = None) -> list[RealAlgebraic]:
        """The distinct real roots of ``p`` (in [lo, hi] when given), in increasing order."""
        if p.is_zero:
            raise ValueError("the zero polynomial has every number as a root")
        out: list[RealAlgebraic] = []
        _, factors = p.factor_list()
        for f, _mult in factors:
            f = f.monic()
            if f.degree() == 1:
                c1, c0 = f.all_coeffs()
                r = -_q(c0) / _q(c1)
                out.append(cls.rational(r))
                continue
            for (a, b), _m in f.intervals():
                out.append(cls(f, _q(a), _q(b)))
        if lo is not None:
            out = [r for r in out if r >= RealAlgebraic.rational(lo)]
        if hi is not None:
            out = [r for r in out if r <= RealAlgebraic.rational(hi)]
        return sorted(out)

    @classmethod
    def from_number(cls, value: Any) -> RealAlgebraic:
        """A parsed number (Fraction or a real algebraic closed form) as a RealAlgebraic."""
        if isinstance(value, Fraction):
            return cls.rational(value)
        poly = sp.Poly(sp.minimal_polynomial(value, X), X, domain="QQ")
        candidates = cls.roots_in(poly)
        prec = 128
        while len(candidates) > 1:
            lo, hi = _interval_of(value, prec)
            candidates = [c for c in candidates if not (c.hi < lo or hi < c.lo)]
            for c in candidates:
                c.refine()
            prec *= 2
        return candidates[0]

    @property
    def is_rational(self) -> bool:
        return self.lo == self.hi

    def rational_value(self) -> Fraction:
        if not self.is_rational:
            raise ValueError(f"{self} is irrational")
        return self.lo

    def refine(self) -> None:
        """Halve the isolating interval (exact bisection)."""
        if self.is_rational:
            return
        self.lo, self.hi = _halved(lambda t: _eval(self.poly, t), self.lo, self.hi)

    def _same_root(self, other: RealAlgebraic) -> bool:
        if self.poly != other.poly:
            return False
        lo, hi = max(self.lo, other.lo), min(self.hi, other.hi)
        if lo > hi:
            return False
        # [lo, hi] lies in both isolating intervals, so it holds at most one root of the polynomial, which is
        # irreducible, so square-free: a root there is simple, and there is one exactly when the polynomial is 0
        # at an end or changes sign between them
        at_lo, at_hi = _eval(self.poly, lo), _eval(self.poly, hi)
        return at_lo == 0 or at_hi == 0 or (at_lo > 0) != (at_hi > 0)

    def cmp(self, other: RealAlgebraic) -> int:
        """-1, 0 or 1, exactly."""
        if self is other:
            return 0
        if self.hi < other.lo:
            return -1
        if other.hi < self.lo:
            return 1
        if self.is_rational and other.is_rational:
            return _sign(self.lo - other.lo)
        if self.is_rational or other.is_rational:
            irr, q, flip = (self, other.lo, 1) if other.is_rational else (other, self.lo, -1)
            while irr.lo <= q <= irr.hi:
                if _eval(irr.poly, q) == 0:  # impossible for irreducible degree >= 2
                    return 0
                irr.refine()
            return flip * (1 if irr.lo > q else -1)
        if self._same_root(other):
            return 0
        while not (self.hi < other.lo or other.hi < self.lo):
            self.refine()
            other.refine()
        return -1 if self.hi < other.lo else 1

    def __eq__(self, other: object) -> bool:
        return isinstance(other, RealAlgebraic) and self.cmp(other) == 0

    def __lt__(self, other: RealAlgebraic) -> bool:
        return self.cmp(other) < 0

    def __hash__(self) -> int:
        return hash(self.poly.as_expr()) if not self.is_rational else hash(self.lo)

    def sign_of(self, p: sp.Poly | Sequence[int | Fraction]) -> int:
        """The sign of p at this number, exactly: p a SymPy ``Poly`` or its coefficients, lowest degree
        first. The isolating interval is refined (bisection) until an interval evaluation decides it; with
        python-flint the same steps run on flint's rationals (the same interval at the end)."""
        if isinstance(p, sp.Poly):
            if p.is_zero:
                return 0
            coeffs = [_q(c) for c in p.all_coeffs()]
        else:
            coeffs = [Fraction(c) for c in reversed(p)]
            while coeffs and coeffs[0] == 0:
                coeffs.pop(0)
            if not coeffs:
                return 0
        if self.is_rational:
            total = Fraction(0)
            for c in coeffs:
                total = total * self.lo + c
            return _sign(total)
        if flint is not None and flint_in_use():  # the same steps on flint's rationals
            M = self._flint_poly
            cs = [_fmpq(c) for c in coeffs]
            if (flint.fmpq_poly(cs[::-1]) % M).is_zero():
                return 0
            sign, lo, hi = _decided(cs, _fmpq(self.lo), _fmpq(self.hi), M)
            self.lo, self.hi = _q(lo), _q(hi)
            return sign
        if sp.Poly(coeffs, X, domain="QQ").rem(self.poly).is_zero:
            return 0
        sign, self.lo, self.hi = _decided(coeffs, self.lo, self.hi, lambda t: _eval(self.poly, t))
        return sign

    def narrowed(self, width: Fraction) -> tuple[Fraction, Fraction]:
        """Rationals at most ``width`` apart around this number, by exact bisection of a copy of its isolating
        interval (on python-flint's rationals where they are in use); the number itself is left as it is.

        >>> lo, hi = RealAlgebraic.roots_in(poly_from_coeffs([1, 0, -2]))[1].narrowed(Fraction(1, 10**6))
        >>> lo < Fraction(14142136, 10**7) < hi, hi - lo <= Fraction(1, 10**6)
        (True, True)
        """
        if self.is_rational:
            return self.lo, self.lo
        value_at: Any
        if flint is not None and flint_in_use():
            value_at, lo, hi, w = self._flint_poly, _fmpq(self.lo), _fmpq(self.hi), _fmpq(width)
        else:
            value_at, lo, hi, w = (lambda t: _eval(self.poly, t)), self.lo, self.hi, width
        while hi - lo > w:
            lo, hi = _halved(value_at, lo, hi)
        return _q(lo), _q(hi)

    @cached_property
    def _flint_poly(self) -> Any:
        return flint.fmpq_poly([_fmpq(_q(c)) for c in reversed(self.poly.all_coeffs())])

    def between(self, other: RealAlgebraic) -> Fraction:
        """A rational strictly between this number and a larger one."""
        if self.cmp(other) >= 0:
            raise ValueError("between() needs a larger number")
        while not self.hi < other.lo:
            self.refine()
            other.refine()
        return (self.hi + other.lo) / 2

    @cached_property
    def expr(self) -> Any:
        """The number as a SymPy expression: a rational, radicals (degree 2) or a CRootOf."""
        if self.is_rational:
            return sp.Rational(self.lo.numerator, self.lo.denominator)
        index = self._index()
        if self.poly.degree() == 2:
            radicals = list(sp.roots(self.poly, X))
            boxes = [_interval_of(r) for r in radicals]
            if len(radicals) == 2 and (boxes[0][1] < boxes[1][0] or boxes[1][1] < boxes[0][0]):
                ordered = [r for _, r in sorted(zip(boxes, radicals), key=lambda t: t[0][0])]
                return sp.radsimp(ordered[index])
        return sp.CRootOf(self.poly.as_expr(), index)

    def _index(self) -> int:
        """How many real roots of the polynomial lie below this one (CRootOf's index): counted on FLINT below the
        isolating interval (the roots lie within Cauchy's bound; the interval's lower end is not a root of an
        irreducible polynomial of degree 2 or more), else from SymPy's isolation of all the real roots."""
        if flint is not None and flint_in_use():
            coeffs = [_q(c) for c in self.poly.all_coeffs()]
            bound = 1 + max(abs(c / coeffs[0]) for c in coeffs[1:])
            return count_roots(self.poly, -bound, self.lo)
        return next(k for k, r in enumerate(RealAlgebraic.roots_in(self.poly)) if r == self)

    def __str__(self) -> str:
        return str(self.expr)

    def words(self) -> str:
        """The number in words a reader knows: a rational, radicals, or which real root of which polynomial.

        >>> [r.words() for r in RealAlgebraic.roots_in(poly_from_coeffs([1, 0, -2]))]
        ['-sqrt(2)', 'sqrt(2)']
        >>> RealAlgebraic.roots_in(poly_from_coeffs([1, 0, -2, 0, -1]))[1].words()
        'the second real root of x**4 - 2*x**2 - 1 = 0'
        """
        if not isinstance(self.expr, sp.CRootOf):
            return str(self.expr)
        k = self._index() + 1
        nth = {1: "first", 2: "second", 3: "third", 4: "fourth", 5: "fifth"}.get(k, f"{k}th")
        return f"the {nth} real root of {self.poly.as_expr()} = 0"

    def __repr__(self) -> str:
        return f"RealAlgebraic({self})"


def _interval_of(r: Any, prec: int = 256) -> tuple[Fraction, Fraction]:
    """A certified rational enclosure of a real closed form (interval arithmetic)."""
    from verify.numbers.numeric import evaluate, interval_context, mpf_to_fraction

    x = evaluate(r, interval_context(prec))
    return mpf_to_fraction(x.a), mpf_to_fraction(x.b)
