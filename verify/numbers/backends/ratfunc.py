"""Rational functions of one parameter, exact: the arithmetic of :mod:`verify.numbers.backends.symbolic`.

Two implementations give the same results. :class:`FlintArithmetic` (the ``fast`` extra, python-flint)
holds a function as a pair of ``fmpq_poly`` (numerator, monic denominator, coprime: a canonical form),
with flint's multiplication and gcd; :class:`SympyArithmetic` holds it as an element of SymPy's field
of rational functions, in pure Python. :func:`arithmetic` picks flint where it is installed; both are
tested against each other (``tests/numbers/test_ratfunc.py``).

>>> A = arithmetic("flint") if FLINT else arithmetic("sympy")
>>> e = A.parameter
>>> x = (A.one + e) / (A.one - e * e)
>>> A.coefficients(x)
((Fraction(-1, 1),), (Fraction(-1, 1), Fraction(1, 1)))
>>> A.at(x, Fraction(1, 3)), A.expr(x)
(Fraction(3, 2), -1/(eps - 1))
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from fractions import Fraction
from typing import Any

import sympy as sp
from sympy import QQ
from sympy.core.mul import _keep_coeff
from sympy.polys.fields import field

flint: Any
try:
    import flint

    # VERIFY_RATIONALS=python forces the pure-Python arithmetic everywhere (the tests run the oracle so)
    FLINT = os.environ.get("VERIFY_RATIONALS", "") != "python"
except ImportError:  # pragma: no cover - the fast extra is not installed
    flint = None
    FLINT = False

EPS = sp.Symbol("eps")
#: one coefficient tuple (lowest degree first) per polynomial: what the root cache is keyed by
Coefficients = tuple[Fraction | int, ...]


def as_fraction(q: Any) -> Fraction:
    """A flint ``fmpq``, a SymPy rational or an element of SymPy's QQ (gmpy2's ``mpq``, or without gmpy2
    SymPy's pure-Python ``PythonMPQ``, which is not a ``numbers.Rational``) as a Fraction.

    >>> from sympy.external.pythonmpq import PythonMPQ
    >>> as_fraction(PythonMPQ(1, 3)), as_fraction(sp.Rational(-2, 5))
    (Fraction(1, 3), Fraction(-2, 5))
    """
    if hasattr(q, "p"):
        return Fraction(int(q.p), int(q.q))
    if hasattr(q, "numerator") and hasattr(q, "denominator"):
        return Fraction(int(q.numerator), int(q.denominator))
    return Fraction(q)


class RatFunc:
    """A rational function ``n / d`` of the parameter over flint: ``d`` monic, ``gcd(n, d) = 1``, so that
    equal functions have equal pairs (hashable, compared by value). Made by :class:`FlintArithmetic`."""

    __slots__ = ("_key", "d", "n")

    def __init__(self, n: Any, d: Any):
        self.n, self.d = n, d
        self._key: tuple[tuple[int, ...], tuple[int, ...], int, int] | None = None

    @property
    def key(self) -> tuple[tuple[int, ...], tuple[int, ...], int, int]:
        """The numerator's and the denominator's integer coefficients (each times its common denominator,
        lowest degree first), and those denominators: the canonical form, in integers."""
        if self._key is None:
            self._key = (_integers(self.n), _integers(self.d), int(self.n.denom()), int(self.d.denom()))
        return self._key

    @staticmethod
    def reduced(n: Any, d: Any) -> RatFunc:
        """``n / d`` in canonical form (``d`` non-zero)."""
        if d.is_zero():
            raise ZeroDivisionError("division by the zero function")
        if n.is_zero():
            return RatFunc(n, _ONE)
        if d.degree() > 0:
            g = n.gcd(d)
            if not g.is_one():
                n, d = n // g, d // g
        lc = d.leading_coefficient()
        if lc != 1:
            n, d = n / lc, d / lc
        return RatFunc(n, d)

    @staticmethod
    def constant(q: Fraction) -> RatFunc:
        """The constant function q."""
        return RatFunc(flint.fmpq_poly([flint.fmpq(q.numerator, q.denominator)]), _ONE)

    @staticmethod
    def _of(x: Any) -> RatFunc | None:
        if isinstance(x, RatFunc):
            return x
        if isinstance(x, int | Fraction):
            return RatFunc.constant(Fraction(x))
        return None

    def __add__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        if o is None:
            return NotImplemented
        if o.n.is_zero():
            return self
        if self.n.is_zero():
            return o
        if self.d.is_one() and o.d.is_one():
            return RatFunc(self.n + o.n, _ONE)
        if self.d == o.d:
            return RatFunc.reduced(self.n + o.n, self.d)
        return RatFunc.reduced(self.n * o.d + o.n * self.d, self.d * o.d)

    __radd__ = __add__

    def __neg__(self) -> RatFunc:
        return RatFunc(-self.n, self.d)

    def __pos__(self) -> RatFunc:
        return self

    def __sub__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        if o is None:
            return NotImplemented
        return self + (-o)

    def __rsub__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        return NotImplemented if o is None else -self + o

    def __mul__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        if o is None:
            return NotImplemented
        if self.n.is_zero() or o.n.is_zero():
            return RatFunc(flint.fmpq_poly(), _ONE)
        if self.d.is_one() and o.d.is_one():
            return RatFunc(self.n * o.n, _ONE)
        # cross-cancel: the pairs stay coprime, and the denominator monic (flint's gcds are monic, and a
        # monic polynomial divided by a monic one is monic)
        g1, g2 = self.n.gcd(o.d), o.n.gcd(self.d)
        return RatFunc((self.n // g1) * (o.n // g2), (self.d // g2) * (o.d // g1))

    __rmul__ = __mul__

    def inverse(self) -> RatFunc:
        """``1 / self`` (non-zero)."""
        if self.n.is_zero():
            raise ZeroDivisionError("division by the zero function")
        lc = self.n.leading_coefficient()
        return RatFunc(self.d / lc, self.n / lc)

    def __truediv__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        if o is None:
            return NotImplemented
        return self * o.inverse()

    def __rtruediv__(self, other: Any) -> RatFunc:
        o = RatFunc._of(other)
        return NotImplemented if o is None else o * self.inverse()

    def __pow__(self, k: int) -> RatFunc:
        if not isinstance(k, int):
            return NotImplemented
        if k < 0:
            return self.inverse() ** (-k)
        return RatFunc(self.n**k, self.d**k)

    def __eq__(self, other: object) -> bool:
        o = RatFunc._of(other)
        if o is None:
            return NotImplemented
        return bool(self.n == o.n and self.d == o.d)

    def __ne__(self, other: object) -> bool:
        eq = self.__eq__(other)
        return eq if eq is NotImplemented else not eq

    def __hash__(self) -> int:
        return hash(self.key)

    def __repr__(self) -> str:
        return f"RatFunc(({self.n}) / ({self.d}))"


_ONE = flint.fmpq_poly([1]) if FLINT else None


def _integer_expr(p: Any) -> Any:
    """An ``fmpz_poly`` as a SymPy expression in :data:`EPS`."""
    return sp.Add(*[sp.Integer(int(c)) * EPS**k for k, c in enumerate(p.coeffs()) if c != 0])


def _integers(p: Any) -> tuple[int, ...]:
    """An fmpq_poly times its (positive) common denominator, as integers, lowest degree first."""
    return tuple(int(c) for c in p.numer().coeffs())


class FlintArithmetic:
    """The rational functions as :class:`RatFunc` (flint)."""

    name = "flint"

    def __init__(self) -> None:
        self.zero = RatFunc(flint.fmpq_poly(), _ONE)
        self.one = RatFunc(flint.fmpq_poly([1]), _ONE)
        self.parameter = RatFunc(flint.fmpq_poly([0, 1]), _ONE)

    def rational(self, q: Fraction) -> RatFunc:
        """The constant function q."""
        return RatFunc.constant(q)

    def from_expr(self, value: Any) -> RatFunc:
        """A SymPy expression in :data:`EPS` with rational coefficients (ValueError otherwise)."""
        num, den = sp.fraction(sp.together(sp.sympify(value)))
        n, d = (sp.Poly(x, EPS, domain="QQ") for x in (num, den))
        return RatFunc.reduced(*(flint.fmpq_poly([flint.fmpq(int(c.p), int(c.q)) for c in reversed(p.all_coeffs())])
                                 for p in (n, d)))  # fmt: skip

    def coefficients(self, x: RatFunc) -> tuple[Coefficients, Coefficients]:
        """The numerator's and the denominator's coefficients, lowest degree first (the denominator
        monic; a scalar may move between them in the other arithmetic: compare functions, not these)."""
        return tuple(map(as_fraction, x.n.coeffs())), tuple(map(as_fraction, x.d.coeffs()))

    def keys(self, x: RatFunc) -> tuple[Coefficients, Coefficients]:
        """The numerator and the denominator as integer coefficients, lowest degree first: a multiple of
        each by the same positive number (a key for their roots; the sign of x is that of their quotient)."""
        key = x.key
        return key[0], key[1]

    def is_zero(self, x: RatFunc) -> bool:
        """Whether x is the zero function."""
        return bool(x.n.is_zero())

    def at(self, x: RatFunc, q: Fraction) -> Fraction:
        """x at the rational q (the denominator non-zero there)."""
        t = flint.fmpq(q.numerator, q.denominator)
        return as_fraction(x.n(t) / x.d(t))

    def expr(self, x: RatFunc) -> Any:
        """x as a SymPy expression in :data:`EPS`."""
        n, d = (sum(sp.Rational(int(c.p), int(c.q)) * EPS**k for k, c in enumerate(p.coeffs())) for p in (x.n, x.d))
        return n / d if d != 1 else sp.sympify(n)

    def factored(self, x: RatFunc) -> Any:
        """``sp.factor(self.expr(x))``, the same expression, from flint's factorisation: the content over the
        common denominators times each irreducible factor (primitive, positive leading coefficient) to its
        power, negative for the denominator's, put together as SymPy's ``factor`` does (``_keep_coeff``).

        >>> A = FlintArithmetic()
        >>> A.factored((A.parameter * 2 - A.one * 2) / (A.parameter * A.parameter * 3 + A.parameter * 3))
        2*(eps - 1)/(3*eps*(eps + 1))
        """
        if x.n.is_zero():
            return sp.Integer(0)
        coeff, factors = sp.Integer(1), []
        for poly, sign in ((x.n, 1), (x.d, -1)):
            content, found = poly.numer().factor()
            coeff *= sp.Rational(int(content), int(poly.denom())) ** sign
            factors += [_integer_expr(f) ** (k * sign) for f, k in found]
        return _keep_coeff(coeff, sp.Mul(*factors))


class SympyArithmetic:
    """The rational functions as elements of SymPy's ``FracField`` (pure Python)."""

    name = "sympy"

    def __init__(self) -> None:
        self.field, param = field([EPS], QQ)
        self.zero = self.field(0)
        self.one = self.field(1)
        self.parameter = param

    def rational(self, q: Fraction) -> Any:
        """The constant function q."""
        return self.field(sp.Rational(q.numerator, q.denominator))

    def from_expr(self, value: Any) -> Any:
        """A SymPy expression in :data:`EPS` with rational coefficients (ValueError otherwise)."""
        try:
            return self.field.from_expr(value)
        except Exception as exc:  # CoercionFailed: sqrt(2) and other irrational constants
            raise ValueError(str(exc)) from None

    def coefficients(self, x: Any) -> tuple[Coefficients, Coefficients]:
        """The numerator's and the denominator's coefficients, lowest degree first."""
        out = []
        for p in (x.numer, x.denom):
            terms = {m[0]: as_fraction(c) for m, c in p.items()}
            out.append(tuple(terms.get(k, Fraction(0)) for k in range(max(terms, default=-1) + 1)))
        return out[0], out[1]

    def keys(self, x: Any) -> tuple[Coefficients, Coefficients]:
        """The numerator and the denominator as coefficients, lowest degree first."""
        return self.coefficients(x)

    def is_zero(self, x: Any) -> bool:
        """Whether x is the zero function."""
        return not x.numer

    def at(self, x: Any, q: Fraction) -> Fraction:
        """x at the rational q (the denominator non-zero there)."""
        value = x.numer(q) / x.denom(q)
        return as_fraction(sp.Rational(value))

    def expr(self, x: Any) -> Any:
        """x as a SymPy expression in :data:`EPS`."""
        return x.as_expr()

    def factored(self, x: Any) -> Any:
        """x as a factored SymPy expression in :data:`EPS` (``sp.factor``)."""
        return sp.factor(x.as_expr())


_ARITHMETICS: dict[str, Any] = {}
#: the arithmetic :func:`arithmetic` gives when none is named (None: the fastest installed); see :func:`using`
_CHOSEN: list[str | None] = [None]


def arithmetic(name: str | None = None) -> Any:
    """The arithmetic named (``"flint"``, ``"sympy"``), or the one chosen by :func:`using`, or the fastest
    installed; one instance each.

    >>> arithmetic("sympy").name
    'sympy'
    """
    name = name or _CHOSEN[-1] or ("flint" if FLINT else "sympy")
    if name not in _ARITHMETICS:
        if name == "flint" and not FLINT:
            raise ValueError("the flint arithmetic needs python-flint (pip install '.[fast]')")
        if name not in ("flint", "sympy"):
            raise ValueError(f"no arithmetic {name!r}: flint or sympy")
        _ARITHMETICS[name] = FlintArithmetic() if name == "flint" else SympyArithmetic()
    return _ARITHMETICS[name]


def flint_in_use() -> bool:
    """Whether the parameter's arithmetic is flint's now (:func:`using` may choose SymPy's): the signs at
    algebraic points (:meth:`verify.numbers.algebraic.RealAlgebraic.sign_of`) then run on flint's rationals too.

    >>> with using("sympy"):
    ...     flint_in_use()
    False
    """
    return bool(arithmetic().name == "flint")


@contextmanager
def using(name: str) -> Iterator[None]:
    """Within the block, every symbolic backend made without naming its arithmetic uses ``name``, and with
    ``"sympy"`` the signs at algebraic points run on Python's fractions: the maps as they run without
    python-flint, to compare (``verify bench``, the tests).

    >>> with using("sympy"):
    ...     arithmetic().name
    'sympy'
    """
    arithmetic(name)  # refused here if it is not installed
    _CHOSEN.append(name)
    try:
        yield
    finally:
        _CHOSEN.pop()
