"""A symbolic-parameter backend: eps as a symbol restricted to an interval.

Elements are rational functions of ``eps`` with rational coefficients
(:mod:`verify.numbers.backends.ratfunc`: python-flint's polynomials when installed, SymPy's ``FracField``
otherwise; the same results). The parameter lives in a :class:`Piece`, an interval of the real line with
exact algebraic endpoints, each open or closed. ``sign(x)`` returns the sign of x when it
is the same for every eps of the piece; otherwise it raises :class:`Split`, which carries
the polynomials whose real roots cut the piece into parts where every sign is constant.
The rule itself is not touched: a driver (:mod:`verify.maps.cradle`) catches the split,
cuts the piece at the roots (exactly: :class:`~verify.numbers.algebraic.RealAlgebraic`) and runs
again on each part.

>>> K = SymbolicBackend(Piece.closed(0, 1))
>>> e = K.parameter
>>> K.sign(K.one + e), K.nonnegative(e * e - e - K.one), K.nonnegative(e * e)
(1, False, True)
>>> K.sign(e - K.convert(Fraction(1, 2)))
Traceback (most recent call last):
...
verify.numbers.backends.symbolic.Split: the sign of eps - 1/2 is not constant for eps in [0, 1]
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.errors import BadNumber
from verify.numbers.algebraic import RealAlgebraic, X
from verify.numbers.backends.base import Backend, NotConstant
from verify.numbers.backends.fieldfunc import FieldArithmetic
from verify.numbers.backends.ratfunc import EPS, Coefficients, arithmetic, as_fraction


class Split(NotConstant):
    """The sign of an element is not constant on the piece: cut at the roots of ``polys``."""


@dataclass(frozen=True)
class Piece:
    """An interval of the parameter with exact endpoints; a point when lower == upper."""

    lower: RealAlgebraic
    upper: RealAlgebraic
    lower_closed: bool
    upper_closed: bool

    @classmethod
    def closed(cls, lo: Any, hi: Any) -> Piece:
        return cls(RealAlgebraic.rational(Fraction(lo)), RealAlgebraic.rational(Fraction(hi)), True, True)

    @property
    def is_point(self) -> bool:
        # points are built with the same number at both ends (cut) or from equal rationals
        return self.lower is self.upper or (
            self.lower.is_rational and self.upper.is_rational and self.lower.lo == self.upper.lo
        )

    def contains(self, x: RealAlgebraic) -> bool:
        lo, hi = x.cmp(self.lower), x.cmp(self.upper)
        return (lo > 0 or (lo == 0 and self.lower_closed)) and (hi < 0 or (hi == 0 and self.upper_closed))

    def sample(self) -> Fraction:
        """A rational strictly inside (not for points)."""
        return self.lower.between(self.upper)

    def cut(self, points: list[RealAlgebraic]) -> list[Piece]:
        """The piece cut at the given points that it contains: each such point becomes a
        piece of its own and the intervals between them are open there."""
        if self.is_point:
            return [self]
        inside: list[RealAlgebraic] = []
        for p in sorted(p for p in points if self.contains(p)):
            if not inside or inside[-1] != p:
                inside.append(p)
        bounds = [self.lower, *inside, self.upper]
        last = len(bounds) - 2
        parts = []
        for k, (a, b) in enumerate(itertools.pairwise(bounds)):
            if a == b:  # an endpoint of the piece is itself a cut point
                continue
            a_closed = k == 0 and self.lower_closed
            b_closed = k == last and self.upper_closed
            parts.append(Piece(a, b, a_closed, b_closed))
        parts += [Piece(p, p, True, True) for p in inside]
        return sorted(parts, key=lambda q: (q.lower, not q.is_point))

    def __str__(self) -> str:
        if self.is_point:
            return f"{{{self.lower}}}"
        return f"{'[' if self.lower_closed else '('}{self.lower}, {self.upper}{']' if self.upper_closed else ')'}"

    def brief(self) -> str:
        """As ``str``, with a long endpoint written short (:meth:`RealAlgebraic.brief`): what a page prints.

        >>> print(Piece.closed(0, Fraction(1, 2)).brief())
        [0, 1/2]
        """
        from verify.numbers.format import brief

        lo, hi = brief(self.lower), brief(self.upper)
        if self.is_point:
            return f"{{{lo}}}"
        return f"{'[' if self.lower_closed else '('}{lo}, {hi}{']' if self.upper_closed else ')'}"


class RootCache:
    """Real roots of polynomials, computed once per polynomial and shared by every run of a map; and the
    number field of the map's system (``field``, a :class:`~verify.numbers.backends.field.NumberFieldBackend`)
    when its numbers are not all rational: the runs then compute over that field."""

    def __init__(self, field: Any = None) -> None:
        self.field = field
        self._roots: dict[Any, list[RealAlgebraic]] = {}
        self._polys: dict[Coefficients, sp.Poly] = {}
        self._by_key: dict[Coefficients, list[RealAlgebraic]] = {}

    def poly(self, coeffs: Coefficients) -> sp.Poly:
        """A polynomial (coefficients lowest degree first) as a SymPy ``Poly`` in x."""
        if coeffs not in self._polys:
            terms = {k: sp.Rational(Fraction(c).numerator, Fraction(c).denominator) for k, c in enumerate(coeffs) if c}
            self._polys[coeffs] = sp.Poly.from_dict(terms or {0: 0}, X, domain="QQ")
        return self._polys[coeffs]

    def roots_of(self, coeffs: Coefficients) -> list[RealAlgebraic]:
        """The real roots of the polynomial of these coefficients (lowest degree first)."""
        if coeffs not in self._by_key:
            self._by_key[coeffs] = self.roots(self.poly(coeffs)) if len(coeffs) > 1 else []
        return self._by_key[coeffs]

    def roots(self, p: sp.Poly) -> list[RealAlgebraic]:
        if p not in self._roots:
            self._roots[p] = RealAlgebraic.roots_in(p) if p.degree() > 0 else []
        return self._roots[p]


#: the exact texts already written (:meth:`SymbolicBackend.to_exact`), by arithmetic and element; at most WRITTEN
_WRITTEN: dict[tuple[Any, Any], str] = {}
WRITTEN = 4096


class SymbolicBackend(Backend):
    """Rational functions of eps, with eps ranging over a :class:`Piece`.

    ``convert`` accepts rationals and SymPy expressions in the symbol ``eps``
    (:data:`EPS`); ``parameter`` is eps itself as an element. Signs are exact for the
    whole piece or raise :class:`Split`.
    """

    name = "symbolic"
    is_exact = True
    is_rigorous = True
    is_parametric = True

    def __init__(self, piece: Piece, cache: RootCache | None = None, arithmetic_name: str | None = None):
        self.piece = piece
        self.cache = cache or RootCache()
        self.field = self.cache.field
        self.arithmetic = FieldArithmetic.over(self.field) if self.field is not None else arithmetic(arithmetic_name)
        self.zero = self.arithmetic.zero
        self.one = self.arithmetic.one
        self.parameter = self.arithmetic.parameter
        self._signs: dict[Any, list[tuple[Piece, int]]] = {}

    def convert(self, value: Any) -> Any:
        if isinstance(value, Fraction):
            return self.arithmetic.rational(value)
        if value.free_symbols - {EPS}:
            raise BadNumber(f"{value}: the symbolic backend knows only the parameter eps")
        try:
            return self.arithmetic.from_expr(value)
        except Exception as exc:  # sqrt(2) and other irrational constants
            raise BadNumber(f"{value}: the symbolic backend needs rational functions of eps ({exc})") from None

    def _polys(self, x: Any) -> tuple[sp.Poly, sp.Poly]:
        """The numerator and the denominator of x, over the rationals (over a number field: their norms,
        whose real roots hold theirs)."""
        n, d = self.arithmetic.keys(x)
        if self.field is not None:
            return self._norm(n), self._norm(d)
        return self.cache.poly(n), self.cache.poly(d)

    def _norm(self, coeffs: tuple[Any, ...]) -> sp.Poly:
        return self.cache.poly(
            tuple(as_fraction(c) for c in reversed(self.field.norm(self.field.poly(coeffs)).all_coeffs()))
        )

    def _pieces_and_signs(self, x: Any) -> list[tuple[Piece, int]]:
        """The piece cut where the numerator or denominator of x vanishes, with the sign of x on each part
        (found once per element and piece: a search asks the same signs many times)."""
        found = self._signs.get(x)
        if found is None:
            found = self._signs[x] = self._cut_and_signs(x)
        return found

    def _cut_and_signs(self, x: Any) -> list[tuple[Piece, int]]:
        A = self.arithmetic
        if A.is_zero(x):
            return [(self.piece, 0)]
        if self.field is not None:
            return self._field_cut_and_signs(x)
        num, den = self.arithmetic.keys(x)
        if self.piece.is_point:
            r = self.piece.lower
            return [(self.piece, r.sign_of(num) * r.sign_of(den))]
        points = [r for p in (num, den) for r in self.cache.roots_of(p) if self.piece.contains(r)]
        parts = self.piece.cut(points) if points else [self.piece]
        out = []
        for part in parts:
            if part.is_point:
                r = part.lower
                out.append((part, r.sign_of(num) * r.sign_of(den)))
            else:
                q = part.sample()
                value = A.at(x, q)
                out.append((part, (value > 0) - (value < 0)))
        return out

    def _field_cut_and_signs(self, x: Any) -> list[tuple[Piece, int]]:
        """:meth:`_cut_and_signs` over a number field: the piece is cut at the real roots of the norms of the
        numerator and the denominator, a sign at a rational is the field's, at a root of a norm
        :meth:`~verify.numbers.backends.field.NumberFieldBackend.sign_at`'s."""
        F = self.field
        num, den = (F.poly(c) for c in self.arithmetic.keys(x))

        def sign_at(r: RealAlgebraic) -> int:
            return int(F.sign_at(num, r) * F.sign_at(den, r))

        if self.piece.is_point:
            return [(self.piece, sign_at(self.piece.lower))]
        points = [r for p in self._polys(x) for r in self.cache.roots(p) if self.piece.contains(r)]
        parts = self.piece.cut(points) if points else [self.piece]
        return [(part, sign_at(part.lower) if part.is_point else F.sign(self.arithmetic.at(x, part.sample())))
                for part in parts]  # fmt: skip

    def _split(self, x: Any, what: str) -> Split:
        polys = [p for p in self._polys(x) if p.degree() > 0]
        return Split(polys, lambda: f"the {what} of {self.arithmetic.expr(x)} is not constant for eps in {self.piece}")

    def sign(self, x: Any) -> int:
        signs = {s for _, s in self._pieces_and_signs(x)}
        if len(signs) == 1:
            return signs.pop()
        raise self._split(x, "sign")

    def nonnegative(self, x: Any) -> bool:
        """Whether x >= 0 for every eps of the piece (False: x < 0 for every eps)."""
        signs = {s >= 0 for _, s in self._pieces_and_signs(x)}
        if len(signs) == 1:
            return signs.pop()
        raise self._split(x, "sign")

    def to_number(self, x: Any) -> Any:
        return self.arithmetic.expr(x)

    def at_sample(self, x: Any) -> Fraction | None:
        """x at one rational eps strictly inside the piece (None on a point): a quick necessary test
        before a decision for the whole piece.

        >>> K = SymbolicBackend(Piece.closed(0, 1))
        >>> K.at_sample(K.parameter / (K.one + K.parameter))
        Fraction(1, 3)
        """
        if self.piece.is_point or self.field is not None:  # over a number field the values are not rationals
            return None
        value: Fraction = self.arithmetic.at(x, self.piece.sample())
        return value

    def to_exact(self, x: Any) -> str:
        key = (self.arithmetic, x)
        if key not in _WRITTEN:  # a map writes the same certificate's entries on many pieces
            if len(_WRITTEN) >= WRITTEN:
                _WRITTEN.clear()
            _WRITTEN[key] = str(self.arithmetic.factored(x))
        return _WRITTEN[key]

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return self.to_exact(x)

    def describe(self) -> str:
        return f"symbolic (eps in {self.piece}), exact"
