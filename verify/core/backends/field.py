"""Exact arithmetic in a real number field, for algebraic inputs such as ``sqrt(3)/3``."""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.core.backends.base import Backend
from verify.core.format import format_decimal
from verify.core.parse import Number, to_number
from verify.errors import BadNumber


class NumberFieldBackend(Backend):
    """Exact arithmetic in a real number field: ``sqrt(3)/3``, ``cos(pi/12)``, ``3 - 2*sqrt(2)``.

    The field is Q(theta) for a primitive element theta of the given generators (SymPy's
    ``AlgebraicField``); elements are polynomials in theta of degree below its minimal
    polynomial's, so arithmetic and zero tests are exact. Signs are decided rigorously by
    isolating theta, a root of its minimal polynomial, in a rational interval
    (:class:`~verify.core.algebraic.RealAlgebraic`). The ``exact`` backend switches to it by
    itself when an input is irrational but algebraic (:func:`verify.core.backends.exact_for`).

    >>> import sympy as sp
    >>> K = NumberFieldBackend([sp.sqrt(2)])
    >>> x = K.convert(3 - 2 * sp.sqrt(2))
    >>> K.sign(x), K.to_exact(x * x), K.to_decimal(x, 8)
    (1, '17 - 12*sqrt(2)', '0.17157288')
    """

    name = "exact"
    is_exact = True
    is_rigorous = True
    widens_to_inputs = True

    def __init__(self, generators: Any):
        import sympy as sp

        from verify.core.algebraic import RealAlgebraic

        self.generators = tuple(generators)
        self.field = sp.QQ.algebraic_field(*self.generators)
        self.theta = RealAlgebraic.from_number(self.field.ext.as_expr())
        self.zero = self.field.zero
        self.one = self.field.one

    def convert(self, value: Number) -> Any:
        import sympy as sp

        if isinstance(value, Fraction):
            return self.field.from_sympy(sp.Rational(value.numerator, value.denominator))
        try:
            return self.field.from_sympy(value)
        except Exception as exc:  # CoercionFailed, NotAlgebraic: not in this field
            raise BadNumber(f"{value} is not in the number field of {list(self.generators)} ({exc})") from None

    def sign(self, x: Any) -> int:
        import sympy as sp

        from verify.core.algebraic import X

        coeffs = x.to_list()
        if not coeffs:
            return 0
        return self.theta.sign_of(sp.Poly(coeffs, X, domain="QQ"))

    def to_number(self, x: Any) -> Number:
        import sympy as sp

        return to_number(sp.expand(self.field.to_sympy(x)))

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return format_decimal(self.to_number(x), digits)

    def size(self, x: Any) -> int:
        return sum(int(c.numerator).bit_length() + int(c.denominator).bit_length() for c in x.to_list())

    def describe(self) -> str:
        return f"exact (number field Q({', '.join(str(g) for g in self.generators)})), rigorous"


def algebraic_generators(values: Any) -> list[Any] | None:
    """The irrational values among ``values`` if they are all algebraic, else None.

    >>> import sympy as sp
    >>> algebraic_generators([Fraction(1, 2), sp.sqrt(2), sp.sqrt(2)]), algebraic_generators([sp.pi])
    ([sqrt(2)], None)
    """
    out = []
    for v in values:
        if isinstance(v, Fraction):
            continue
        if v.is_algebraic is not True:
            return None
        if v not in out:
            out.append(v)
    return out
