"""Rational functions of the parameter over a real number field: the arithmetic of a map of a system whose
numbers are algebraic (the paper's corner at alpha = pi/6, normals with ``sqrt(3)/3``).

A function is a pair of SymPy polynomials in :data:`~verify.numbers.backends.ratfunc.EPS` over the field's
``AlgebraicField`` (numerator, monic denominator, no common factor: a canonical form, so that the constants
do not pile up in both as they do in SymPy's own field of fractions). :class:`FieldArithmetic` has the
interface of :mod:`verify.numbers.backends.ratfunc`'s arithmetics, except that coefficients and values at
rationals are elements of the field, whose signs :class:`~verify.numbers.backends.field.NumberFieldBackend`
decides.

>>> import sympy as sp
>>> from verify.numbers.backends.field import NumberFieldBackend
>>> A = FieldArithmetic.over(NumberFieldBackend([sp.sqrt(3)]))
>>> x = A.from_expr(sp.sqrt(3) * EPS / 3 + 1)
>>> y = (x * x - A.one) / (x - A.one)
>>> A.expr(y), A.field_of.to_exact(A.at(y, Fraction(3)))
(sqrt(3)*eps/3 + 2, 'sqrt(3) + 2')
"""

from __future__ import annotations

import functools
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.numbers.backends.ratfunc import EPS


class FieldFunc:
    """``n / d`` over a number field, ``d`` monic and coprime to ``n`` (made by :class:`FieldArithmetic`)."""

    __slots__ = ("d", "n")

    def __init__(self, n: sp.Poly, d: sp.Poly):
        self.n, self.d = n, d

    @staticmethod
    def reduced(n: sp.Poly, d: sp.Poly) -> FieldFunc:
        """``n / d`` in canonical form (``d`` non-zero)."""
        if d.is_zero:
            raise ZeroDivisionError("division by the zero function")
        if n.is_zero:
            return FieldFunc(n, n.one)
        if d.degree() > 0:
            g = n.gcd(d)
            if not g.is_one:
                n, d = n.exquo(g), d.exquo(g)
        lc = d.rep.LC()
        if d.rep.dom.one != lc:
            n, d = n.quo_ground(lc), d.quo_ground(lc)
        return FieldFunc(n, d)

    def _of(self, x: Any) -> FieldFunc | None:
        if isinstance(x, FieldFunc):
            return x
        if isinstance(x, int | Fraction):
            q = Fraction(x)
            c = self.n.rep.dom.convert_from(sp.QQ(q.numerator, q.denominator), sp.QQ)
            return FieldFunc(self.n.one.mul_ground(c), self.n.one)
        return None

    def __add__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        if o is None:
            return NotImplemented
        if self.d == o.d:
            return FieldFunc.reduced(self.n + o.n, self.d)
        return FieldFunc.reduced(self.n * o.d + o.n * self.d, self.d * o.d)

    __radd__ = __add__

    def __neg__(self) -> FieldFunc:
        return FieldFunc(-self.n, self.d)

    def __sub__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        return NotImplemented if o is None else self + (-o)

    def __rsub__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        return NotImplemented if o is None else o + (-self)

    def __mul__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        if o is None:
            return NotImplemented
        return FieldFunc.reduced(self.n * o.n, self.d * o.d)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        if o is None:
            return NotImplemented
        if o.n.is_zero:
            raise ZeroDivisionError("division by the zero function")
        return FieldFunc.reduced(self.n * o.d, self.d * o.n)

    def __rtruediv__(self, other: Any) -> FieldFunc:
        o = self._of(other)
        return NotImplemented if o is None else o / self

    def __pow__(self, k: int) -> FieldFunc:
        if not isinstance(k, int):
            return NotImplemented
        if k < 0:
            return (self._of(1) / self) ** (-k)
        return FieldFunc(self.n**k, self.d**k)

    def __eq__(self, other: object) -> bool:
        o = self._of(other)
        if o is None:
            return NotImplemented
        return bool(self.n == o.n and self.d == o.d)

    def __hash__(self) -> int:
        return hash((self.n, self.d))

    def __float__(self) -> float:
        raise TypeError("a function of the parameter has no float value")

    def __repr__(self) -> str:
        return f"FieldFunc({self.n.as_expr()} / {self.d.as_expr()})"


class FieldArithmetic:
    """The rational functions over one number field as :class:`FieldFunc` (one instance per field:
    :meth:`over`)."""

    name = "field"

    @staticmethod
    @functools.cache
    def over(number_field: Any) -> FieldArithmetic:
        """The arithmetic over this :class:`~verify.numbers.backends.field.NumberFieldBackend`, one per field (it
        caches the conversion of expressions, which SymPy makes slowly)."""
        return FieldArithmetic(number_field)

    def __init__(self, number_field: Any) -> None:
        self.field_of = number_field
        self._converted: dict[Any, FieldFunc] = {}
        one = sp.Poly(1, EPS, domain=number_field.field)
        self.zero = FieldFunc(one * 0, one)
        self.one = FieldFunc(one, one)
        self.parameter = FieldFunc(sp.Poly(EPS, EPS, domain=number_field.field), one)

    def rational(self, q: Fraction) -> FieldFunc:
        """The constant function q."""
        return self.one * q

    def from_expr(self, value: Any) -> FieldFunc:
        """A SymPy expression in :data:`EPS` with coefficients in the field (ValueError otherwise)."""
        found = self._converted.get(value)
        if found is None:
            num, den = sp.fraction(sp.together(sp.sympify(value)))
            try:
                n, d = (sp.Poly(x, EPS, domain=self.field_of.field) for x in (num, den))
            except Exception as exc:  # CoercionFailed, GeneratorsNeeded: not in the field, other symbols
                raise ValueError(str(exc)) from None
            found = self._converted[value] = FieldFunc.reduced(n, d)
        return found

    def coefficients(self, x: FieldFunc) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
        """The numerator's and the denominator's coefficients (field elements), lowest degree first."""
        return tuple(reversed(x.n.rep.to_list())), tuple(reversed(x.d.rep.to_list()))

    keys = coefficients

    def is_zero(self, x: FieldFunc) -> bool:
        """Whether x is the zero function."""
        return bool(x.n.is_zero)

    def at(self, x: FieldFunc, q: Fraction) -> Any:
        """x at the rational q (the denominator non-zero there): a field element."""
        F = self.field_of
        return F.value(x.n, q) / F.value(x.d, q)

    def expr(self, x: FieldFunc) -> Any:
        """x as a SymPy expression in :data:`EPS` (radicals in the coefficients)."""
        n, d = x.n.as_expr(), x.d.as_expr()
        return n / d if d != 1 else n

    def factored(self, x: FieldFunc) -> Any:
        """x as a factored SymPy expression in :data:`EPS` (``sp.factor`` of :meth:`expr`)."""
        return sp.factor(self.expr(x))
