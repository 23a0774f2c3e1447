"""Exact arithmetic in a real number field, for algebraic inputs such as ``sqrt(3)/3``."""

from __future__ import annotations

import functools
from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from verify.errors import BadNumber
from verify.numbers.backends.base import Backend
from verify.numbers.format import format_decimal
from verify.numbers.parse import Number, to_number

if TYPE_CHECKING:
    import sympy as sp

    from verify.numbers.algebraic import RealAlgebraic


#: the most SymPy numbers a field keeps converted (:meth:`NumberFieldBackend.convert`)
_CONVERTED = 4096


class NumberFieldBackend(Backend):
    """Exact arithmetic in a real number field: ``sqrt(3)/3``, ``cos(pi/12)``, ``3 - 2*sqrt(2)``.

    The field is Q(theta) for a primitive element theta of the given generators (SymPy's
    ``AlgebraicField``); elements are polynomials in theta of degree below its minimal
    polynomial's, so arithmetic and zero tests are exact. Signs are decided rigorously by
    isolating theta, a root of its minimal polynomial, in a rational interval
    (:class:`~verify.numbers.algebraic.RealAlgebraic`). The ``exact`` backend switches to it by
    itself when an input is irrational but algebraic (:func:`verify.numbers.backends.exact_for`).

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

        from verify.numbers.algebraic import RealAlgebraic

        self.generators = tuple(generators)
        self.field = _Field(sp.QQ, *self.generators)
        self.theta = RealAlgebraic.from_number(self.field.ext.as_expr())
        self.zero = self.field.zero
        self.one = self.field.one
        self._norms: dict[Any, Any] = {}
        #: SymPy numbers already converted (each conversion searches an isomorphism of fields: the same inputs
        #: come back with every case and every system built on this field); elements are immutable
        self._converted: dict[Any, Any] = {}

    def convert(self, value: Number) -> Any:
        import sympy as sp

        if isinstance(value, Fraction):  # from QQ: SymPy's from_sympy would search an isomorphism of fields
            return self.field.convert_from(sp.QQ(value.numerator, value.denominator), sp.QQ)
        key = (type(value), value)  # the type too: a value must never stand for an equal one of another kind
        found = self._converted.get(key)
        if found is not None:
            return found
        try:
            found = self.field.from_sympy(value)
        except Exception as exc:  # CoercionFailed, NotAlgebraic: not in this field
            raise BadNumber(f"{value} is not in the number field of {list(self.generators)} ({exc})") from None
        if len(self._converted) >= _CONVERTED:
            self._converted.clear()
        self._converted[key] = found
        return found

    def sign(self, x: Any) -> int:
        import sympy as sp

        from verify.numbers.algebraic import X

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

    def label(self) -> str:
        """The field's name for reports: ``Q(sqrt(2), sqrt(3))``."""
        return f"Q({', '.join(str(g) for g in self.generators)})"

    # Polynomials over the field, for maps of a parameter (:mod:`verify.numbers.backends.symbolic`): their real
    # roots lie among those of their norm, a polynomial over the rationals, so a map cuts its pieces there.

    def poly(self, coeffs: Sequence[Any], *gens: Any) -> sp.Poly:
        """The polynomial over the field with these coefficients (field elements, lowest degree first) in
        the symbol ``gens[0]`` (default x)."""
        import sympy as sp

        from verify.numbers.algebraic import X

        return sp.Poly.from_list(list(reversed(coeffs)) or [self.zero], *(gens or (X,)), domain=self.field)

    def norm(self, p: sp.Poly) -> sp.Poly:
        """The norm of p (a polynomial over the field): the product of its conjugates, a polynomial over
        the rationals in the same symbols whose zeros hold the zeros of p.

        >>> import sympy as sp
        >>> K = NumberFieldBackend([sp.sqrt(3)])
        >>> x = sp.Symbol("x")
        >>> K.norm(sp.Poly(3 * x - sp.sqrt(3), x, domain=K.field)).as_expr()
        9*x**2 - 3
        """
        found = self._norms.get(p)
        if found is None:
            found = self._norms[p] = p.norm()
        return found

    def sign_at(self, p: sp.Poly, r: RealAlgebraic, *, conjugates: bool = True) -> int:
        """The sign of p (a polynomial over the field, in one symbol) at the real algebraic number r, exactly.

        r's isolating interval is refined until it holds no root of p's norm other than r; p has no root
        there but perhaps r, and r is one when the square-free part of p changes sign across the interval.
        Where r is a root of the norm (the product of p's conjugates), it is first tried on the conjugates
        (``conjugates``, when every conjugate of the field's generator is real): an exact interval evaluation of p
        at r that excludes 0 gives the sign, and one that excludes 0 for every other conjugate of p proves
        p(r) = 0; only when neither is reached is the square-free part over the field formed (slow in SymPy).

        >>> import sympy as sp
        >>> from verify.numbers.algebraic import RealAlgebraic, poly_from_coeffs
        >>> K = NumberFieldBackend([sp.sqrt(3)])
        >>> r = RealAlgebraic.roots_in(poly_from_coeffs([3, 0, -1]))[1]  # sqrt(3)/3
        >>> x = sp.Symbol("x")
        >>> [K.sign_at(sp.Poly(e, x, domain=K.field), r) for e in (3 * x - sp.sqrt(3), x - 1, x**2 - sp.sqrt(3) * x)]
        [0, -1, -1]
        """
        from verify.numbers.algebraic import count_roots

        if p.is_zero:
            return 0
        if r.is_rational:
            return self.sign(self.value(p, r.lo))
        N = self.norm(p).sqf_part()
        if r.sign_of(N) != 0:
            while count_roots(N, r.lo, r.hi) > 0:
                r.refine()
            return self.sign(self.value(p, r.lo))
        found = self._sign_by_conjugates(p, r) if conjugates else None
        if found is not None:
            return found
        while count_roots(N, r.lo, r.hi) != 1 or not N.eval(_rational(r.lo)) or not N.eval(_rational(r.hi)):
            r.refine()
        s = p.sqf_part()
        if self.sign(self.value(s, r.lo)) * self.sign(self.value(s, r.hi)) < 0:
            return 0
        return self.sign(self.value(p, r.lo))

    def _sign_by_conjugates(self, p: sp.Poly, r: RealAlgebraic) -> int | None:
        """The sign of p at r, a root of p's norm, from interval values of p and of its conjugates at r (see
        :meth:`sign_at`), or None when the field has complex conjugates or 2^-256 wide intervals do not decide."""
        from verify.numbers.algebraic import interval_value

        thetas = self._conjugates
        if thetas is None:
            return None
        coeffs = [[Fraction(int(q.numerator), int(q.denominator)) for q in c.to_list()] for c in p.rep.to_list()]
        for bits in (64, 128, 256):
            width = Fraction(1, 2**bits)
            lo, hi = r.narrowed(width)
            values = []
            for t in thetas:
                t_lo, t_hi = t.narrowed(width)
                points = [(Fraction(0), Fraction(0)) if not c else interval_value([(q, q) for q in c], t_lo, t_hi)
                          for c in coeffs]  # fmt: skip
                values.append(interval_value(points, lo, hi))
            (own_lo, own_hi), others = values[0], values[1:]
            if own_lo > 0 or own_hi < 0:
                return 1 if own_lo > 0 else -1
            if all(a > 0 or b < 0 for a, b in others):
                return 0
        return None

    @functools.cached_property
    def _conjugates(self) -> list[RealAlgebraic] | None:
        """The field's generator theta and then its other conjugates, when they are all real; else None."""
        import sympy as sp

        from verify.numbers.algebraic import RealAlgebraic, X

        mod = sp.Poly([sp.Rational(int(c.numerator), int(c.denominator)) for c in self.field.mod.to_list()], X)
        roots = RealAlgebraic.roots_in(mod)
        own = [t for t in roots if t.cmp(self.theta) == 0]
        if len(roots) != mod.degree() or len(own) != 1:
            return None
        return own + [t for t in roots if t.cmp(self.theta) != 0]

    def value(self, p: sp.Poly, q: Fraction) -> Any:
        """p (one symbol, over the field) at the rational q: a field element."""
        c = self.convert(Fraction(q))
        total = self.zero
        for a in p.rep.to_list():
            total = total * c + a
        return total


@functools.cache
def _field_class() -> Any:
    from sympy.polys.domains.algebraicfield import AlgebraicField
    from sympy.polys.polyerrors import DomainError

    class Field(AlgebraicField):
        """SymPy's ``AlgebraicField``, but it says that it has no ring without printing itself: SymPy asks
        it in every gcd of polynomials over the field, and the printing took half of a map's time."""

        def get_ring(self) -> Any:
            raise DomainError("an algebraic field has no associated ring")

    return Field


def _Field(*args: Any) -> Any:
    return _field_class()(*args)


def _rational(q: Fraction) -> Any:
    import sympy as sp

    return sp.Rational(q.numerator, q.denominator)


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
