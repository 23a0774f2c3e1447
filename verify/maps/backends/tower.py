"""Rational functions of two parameters over a real number field Q(theta), for maps of cells of algebraic systems.

An element is a vector ``(a_0, ..., a_{k-1})`` of rational functions of (x, y) over the rationals
(:class:`~verify.maps.backends.plane.Frac`, each in lowest terms on flint or SymPy), standing for
``a_0 + a_1 theta + ... + a_{k-1} theta^(k-1)``, k the degree of theta's minimal polynomial m. Products are
reduced with m, inverses solve the k x k system of the multiplication by the element: so every component stays
in lowest terms over the rationals, and the curves of a map keep the degrees they have in a rational system
(SymPy's own polynomials over an algebraic field take minutes for one gcd in two variables).

A sign on a cell: with D the least common denominator of the components and N(t) = sum (a_l D) t^l, the element
is N(theta) / D; the zeros of N(theta) lie on the zero set of the norm Res_t(m, N), a polynomial over the
rationals, so the cell needs the irreducible factors of that norm and of D as known curves, and the sign is then
read at the cell's sample point: a field element at a rational point, a polynomial in y over the field at a
rational x and an algebraic y (:meth:`~verify.numbers.backends.field.NumberFieldBackend.sign_at`).

>>> import sympy as sp
>>> from verify.numbers.backends.field import NumberFieldBackend
>>> from verify.maps.backends.plane import X, Y, polys
>>> T = Tower.over(polys(), NumberFieldBackend([sp.sqrt(3)]))
>>> z = T.from_expr(sp.sqrt(3) * X - Y)
>>> str(T.expr(z * z)), str(T.expr(z / z)), str(polys().expr(T.curves(z)[0]))
('3*x**2 - 2*sqrt(3)*x*y + y**2', '1', '-3*x**2 + y**2')
"""

from __future__ import annotations

import functools
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.maps.backends.plane import Frac, Polys, X, Y


class TowerFrac:
    """An element of Q(theta)(x, y) as its components over Q(x, y) (made by :class:`Tower`)."""

    __slots__ = ("T", "c")

    def __init__(self, T: Tower, c: tuple[Frac, ...]):
        self.T, self.c = T, c

    def __add__(self, o: TowerFrac) -> TowerFrac:
        return TowerFrac(self.T, tuple(a + b for a, b in zip(self.c, o.c)))

    def __sub__(self, o: TowerFrac) -> TowerFrac:
        return TowerFrac(self.T, tuple(a - b for a, b in zip(self.c, o.c)))

    def __neg__(self) -> TowerFrac:
        return TowerFrac(self.T, tuple(-a for a in self.c))

    def __mul__(self, o: TowerFrac) -> TowerFrac:
        return self.T.times(self, o)

    def __truediv__(self, o: TowerFrac) -> TowerFrac:
        return self.T.times(self, self.T.inverse(o))

    def __eq__(self, o: object) -> bool:
        return isinstance(o, TowerFrac) and self.c == o.c

    def __hash__(self) -> int:
        return hash(self.c)

    def __float__(self) -> float:
        raise TypeError("a function of the parameters has no float value")

    def is_zero(self) -> bool:
        return all(self.T.P.is_zero(a.n) for a in self.c)

    def at(self, x: Fraction, y: Fraction) -> Any:
        """The value at the rational point (x, y), an exact number (a Fraction or radicals)."""
        return self.T.field_of.to_number(self.T.value_at(self, x, y))


class Tower:
    """The arithmetic of :class:`TowerFrac` over the rational polynomials ``P`` and the number field ``field_of``
    (a :class:`~verify.numbers.backends.field.NumberFieldBackend`); one instance per pair (:meth:`over`)."""

    @staticmethod
    @functools.cache
    def over(P: Polys, number_field: Any) -> Tower:
        """The tower over these polynomials and this field, one per pair (it caches conversions and curves)."""
        return Tower(P, number_field)

    def __init__(self, P: Polys, number_field: Any):
        self.P, self.field_of = P, number_field
        mod = [Fraction(int(c.numerator), int(c.denominator)) for c in number_field.field.mod.to_list()]
        self.k = len(mod) - 1
        self.reduction = [-c / mod[0] for c in reversed(mod[1:])]  # theta^k = sum reduction[i] theta^i
        self._zero, self._one = Frac(P, P.zero, P.one), Frac(P, P.one, P.one)
        self.zero = self.of([self._zero])
        self.one = self.of([self._one])
        self.theta = sp.expand(number_field.field.ext.as_expr())
        self._converted: dict[Any, TowerFrac] = {}
        self._curves: dict[TowerFrac, list[Any]] = {}

    def of(self, comps: list[Frac]) -> TowerFrac:
        return TowerFrac(self, tuple(comps) + (self._zero,) * (self.k - len(comps)))

    def constant(self, q: Fraction) -> Frac:
        return Frac(self.P, self.P.from_dict({(0, 0): q}), self.P.one)

    def element(self, values: list[Fraction]) -> Any:
        """The field element sum values[l] theta^l."""
        return self.field_of.field.new([sp.QQ(v.numerator, v.denominator) for v in reversed(values)])

    def times(self, a: TowerFrac, b: TowerFrac) -> TowerFrac:
        k = self.k
        conv = [self._zero] * (2 * k - 1)
        for i, x in enumerate(a.c):
            if self.P.is_zero(x.n):
                continue
            for j, y in enumerate(b.c):
                if not self.P.is_zero(y.n):
                    conv[i + j] = conv[i + j] + x * y
        for d in range(2 * k - 2, k - 1, -1):  # theta^d = theta^(d-k) * sum reduction[i] theta^i
            top = conv[d]
            if not self.P.is_zero(top.n):
                for i, r in enumerate(self.reduction):
                    if r:
                        conv[d - k + i] = conv[d - k + i] + top * self.constant(r)
        return TowerFrac(self, tuple(conv[:k]))

    def inverse(self, a: TowerFrac) -> TowerFrac:
        """1 / a: the solution z of a * z = 1, the k x k linear system over Q(x, y), by exact elimination."""
        if a.is_zero():
            raise ZeroDivisionError("division by the zero function")
        k = self.k
        theta = self.of([self._zero, self._one]) if k > 1 else self.one
        columns, power = [], a
        for _ in range(k):
            columns.append(list(power.c))
            power = self.times(power, theta)
        rows = [[columns[j][i] for j in range(k)] + [self._one if i == 0 else self._zero] for i in range(k)]
        for col in range(k):
            pivot = next(r for r in range(col, k) if not self.P.is_zero(rows[r][col].n))
            rows[col], rows[pivot] = rows[pivot], rows[col]
            p = rows[col][col]
            rows[col] = [v / p for v in rows[col]]
            for r in range(k):
                if r != col and not self.P.is_zero(rows[r][col].n):
                    f = rows[r][col]
                    rows[r] = [v - f * w for v, w in zip(rows[r], rows[col])]
        return self.of([rows[i][k] for i in range(k)])

    def from_expr(self, e: Any) -> TowerFrac:
        """A SymPy rational expression in x and y with coefficients in the field."""
        found = self._converted.get(e)
        if found is None:
            n, d = sp.fraction(sp.together(e))
            found = self._converted[e] = self.times(self._poly(n), self.inverse(self._poly(d)))
        return found

    def _poly(self, e: Any) -> TowerFrac:
        p = sp.Poly(e, X, Y, domain=self.field_of.field)
        comps: list[dict[tuple[int, int], Fraction]] = [{} for _ in range(self.k)]
        for (i, j), c in p.rep.terms():
            coeffs = c.to_list()
            for l, v in enumerate(reversed(coeffs)):
                if v:
                    comps[l][(int(i), int(j))] = Fraction(int(v.numerator), int(v.denominator))
        return self.of([Frac(self.P, self.P.from_dict(t), self.P.one) for t in comps])

    def expr(self, a: TowerFrac, names: tuple[str, str] = ("x", "y")) -> Any:
        return sp.Add(*(c.expr(names) * self.theta**l for l, c in enumerate(a.c) if not self.P.is_zero(c.n)))

    def split(self, a: TowerFrac) -> tuple[list[Any], Any]:
        """(N_0, ..., N_{k-1}) and D, polynomials over the rationals with a = sum N_l theta^l / D."""
        P = self.P
        D = P.one
        for c in a.c:
            if not P.is_zero(c.n):
                g = P.gcd(D, c.d)
                D = P.quo(D * c.d, g)
        return [P.zero if P.is_zero(c.n) else c.n * P.quo(D, c.d) for c in a.c], D

    def curves(self, a: TowerFrac) -> list[Any]:
        """The polynomials (over the rationals) whose zero sets hold the points where a is zero or has a pole: the
        norm of its numerator (Res_t(m, N)) and its common denominator."""
        found = self._curves.get(a)
        if found is None:
            N, D = self.split(a)
            found = self._curves[a] = [self._norm(N), D]
        return found

    def _norm(self, N: list[Any]) -> Any:
        P = self.P
        terms = {(i, j, l): c for l, p in enumerate(N) for (i, j), c in P.terms(p).items()}
        mod = [Fraction(1)] + [-r for r in reversed(self.reduction)]  # monic m, highest degree first
        if P.name == "flint":
            import flint

            ctx = flint.fmpq_mpoly_ctx.get(("x", "y", "t"))
            num = ctx.from_dict({k: flint.fmpq(v.numerator, v.denominator) for k, v in terms.items()})
            m = ctx.from_dict(
                {(0, 0, self.k - i): flint.fmpq(v.numerator, v.denominator) for i, v in enumerate(mod) if v}
            )
            r = num.resultant(m, "t") if num.degrees()[2] > 0 else num**self.k
            return P.from_dict({(int(i), int(j)): Fraction(int(c.p), int(c.q)) for (i, j, _), c in r.to_dict().items()})
        t = sp.Symbol("t")
        num = sp.Add(*(sp.Rational(v.numerator, v.denominator) * X**i * Y**j * t**l for (i, j, l), v in terms.items()))
        m = sp.Add(*(sp.Rational(v.numerator, v.denominator) * t ** (self.k - i) for i, v in enumerate(mod)))
        return P.from_expr(sp.expand(sp.resultant(m, num, t)))

    def sign_at(self, a: TowerFrac, x: Fraction, y: Any) -> int:
        """The sign of a at (x, y): x rational, y rational or a RealAlgebraic."""
        from verify.numbers.algebraic import RealAlgebraic

        F, P = self.field_of, self.P
        if not isinstance(y, RealAlgebraic):
            return int(F.sign(self.value_at(a, x, y)))
        N, D = self.split(a)
        sd = y.sign_of(P.in_y(D, x))
        if sd:
            return int(F.sign_at(self._in_y(N, x), y)) * sd
        num, den = self._reduced_in_y(N, D, x)
        return int(F.sign_at(num, y) * F.sign_at(den, y))

    def value_at(self, a: TowerFrac, x: Fraction, y: Fraction) -> Any:
        """a at the rational point (x, y), a field element (where the common denominator vanishes there, the
        value of a in lowest terms over the field along the line of that x)."""
        F, P = self.field_of, self.P
        N, D = self.split(a)
        d = P.value(D, x, y)
        if d:
            return self.element([P.value(p, x, y) / d for p in N])
        num, den = self._reduced_in_y(N, D, x)
        return F.value(num, y) / F.value(den, y)

    def _in_y(self, N: list[Any], x: Fraction) -> sp.Poly:
        """sum N_l(x, y) theta^l at the rational x: a polynomial in y over the field."""
        rows = [self.P.in_y(p, x) for p in N]
        top = max(len(r) for r in rows)
        coeffs = [self.element([r[j] if j < len(r) else Fraction(0) for r in rows]) for j in range(top)]
        return sp.Poly.from_list(list(reversed(coeffs)), Y, domain=self.field_of.field)

    def _reduced_in_y(self, N: list[Any], D: Any, x: Fraction) -> tuple[sp.Poly, sp.Poly]:
        """N(theta) / D at the rational x in lowest terms over the field (they may share a factor over the field
        that they do not share over the rationals): two polynomials in y."""
        num = self._in_y(N, x)
        den = self._in_y([D], x)
        if not num.is_zero and den.degree() > 0:
            g = num.gcd(den)
            if g.degree() > 0:
                num, den = num.exquo(g), den.exquo(g)
        return num, den


def _sign(q: Fraction) -> int:
    return (q > 0) - (q < 0)
