"""Two parameters: rational functions of (x, y) whose signs are read on one cell of the plane.

The elements are rational functions of two parameters with rational coefficients, held as a pair of
polynomials (numerator, denominator) with no common factor and a denominator of leading coefficient 1,
so that equal functions have equal pairs. The polynomials are python-flint's ``fmpq_mpoly`` when the
``fast`` extra is installed, else SymPy's ``Poly`` over QQ (:class:`Polys`: the same operations, the
same results).

A :class:`PlaneBackend` works on one *cell* of a decomposition of the plane (:mod:`verify.maps.cells`):
a connected set on which every polynomial of a known set ``known`` (irreducible, canonical) has one sign.
``sign(f)`` factors the numerator and denominator of ``f``; when every factor is known, the sign is the
same on the whole cell and is read at the cell's sample point (rational, or a rational x with an
algebraic y); otherwise it raises :class:`NewCurves` with the unknown factors, and the driver
(:mod:`verify.maps.plane`) cuts the plane with their zero sets and runs again.

>>> P = polys()
>>> K = PlaneBackend(P, (Fraction(1, 2), Fraction(1, 3)), known={P.key(P.from_expr(X * Y + 1))})
>>> x, y = K.parameters
>>> K.sign(K.one + x * y)
1
>>> K.sign(x - y)
Traceback (most recent call last):
...
verify.maps.backends.plane.NewCurves: the sign of x - y is read on a cell that no curve x - y = 0 bounds
"""

from __future__ import annotations

import time
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.errors import BadNumber
from verify.maps.backends.eliminate import Stop, discriminant_y, resultant_y
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends.base import Backend, NotConstant
from verify.numbers.backends.ratfunc import FLINT, as_fraction, flint

#: whether python-flint's polynomials in two variables are there (the ``fast`` extra)
FLINT_POLYS = FLINT

X, Y = sp.symbols("x y")


#: the most SymPy expressions (and resultants, discriminants) a :class:`Polys` keeps (it starts again past it)
CONVERTED = 4096


class Polys:
    """Polynomials in (x, y) over the rationals: flint's ``fmpq_mpoly`` (``name="flint"``) or SymPy's
    ``Poly`` (``name="sympy"``). Each method takes and returns this arithmetic's polynomials.

    >>> P = polys("sympy")
    >>> f = P.from_expr(X**2 + Y**2 - 1)
    >>> P.in_x(P.discriminant(f)), P.in_y(f, Fraction(0))
    ((Fraction(4, 1), Fraction(0, 1), Fraction(-4, 1)), (Fraction(-1, 1), Fraction(0, 1), Fraction(1, 1)))
    """

    def __init__(self, name: str):
        self.name = name
        self._shown: dict[tuple[Any, ...], str] = {}
        #: SymPy expressions already converted (a map converts the same velocity on each of its cells)
        self.converted: dict[tuple[Any, ...], Any] = {}
        #: exact texts already written (a map writes the same certificate's numbers on many cells)
        self.written: dict[tuple[Any, ...], str] = {}
        self._projections: dict[tuple[Any, ...], Any] = {}  #: resultants, discriminants and factors already computed
        if name == "flint":
            self.ctx = flint.fmpq_mpoly_ctx.get(("x", "y"))
            self.x, self.y = self.ctx.gens()
            self.zero, self.one = self.ctx.from_dict({}), self.ctx.from_dict({(0, 0): 1})
        else:
            self.x, self.y = sp.Poly(X, X, Y, domain="QQ"), sp.Poly(Y, X, Y, domain="QQ")
            self.zero, self.one = sp.Poly(0, X, Y, domain="QQ"), sp.Poly(1, X, Y, domain="QQ")

    def from_dict(self, terms: dict[tuple[int, int], Fraction]) -> Any:
        if self.name == "flint":
            return self.ctx.from_dict({k: flint.fmpq(v.numerator, v.denominator) for k, v in terms.items() if v})
        coeffs = {k: sp.Rational(v.numerator, v.denominator) for k, v in terms.items() if v}
        return sp.Poly.from_dict(coeffs or {(0, 0): 0}, X, Y, domain="QQ")

    def terms(self, p: Any) -> dict[tuple[int, int], Fraction]:
        """The coefficients of p by exponents (i, j) of x^i y^j."""
        if self.name == "flint":
            return {(int(k[0]), int(k[1])): as_fraction(v) for k, v in p.to_dict().items()}
        return {(int(k[0]), int(k[1])): as_fraction(v) for k, v in p.as_dict().items() if v}

    def from_expr(self, e: Any) -> Any:
        """A SymPy polynomial expression in x and y (rational coefficients)."""
        poly = sp.Poly(sp.sympify(e), X, Y, domain="QQ")
        return self.from_dict({k: as_fraction(v) for k, v in poly.as_dict().items()})

    def expr(self, p: Any, names: tuple[str, str] = ("x", "y")) -> Any:
        a, b = sp.Symbol(names[0]), sp.Symbol(names[1])
        return sp.Add(*[sp.Rational(c.numerator, c.denominator) * a**i * b**j for (i, j), c in self.terms(p).items()])

    def show(self, p: Any, names: tuple[str, str] = ("x", "y")) -> str:
        """p as SymPy prints it, in the parameters' ``names`` (once per polynomial: a map names its curves in
        every cell they bound)."""
        key = (self.key(p), names)
        if key not in self._shown:
            self._shown[key] = str(self.expr(p, names))
        return self._shown[key]

    def key(self, p: Any) -> Any:
        """A hashable key, equal for equal polynomials."""
        return str(p) if self.name == "flint" else tuple(sorted(self.terms(p).items()))

    def is_zero(self, p: Any) -> bool:
        return bool(p.is_zero()) if self.name == "flint" else bool(p.is_zero)

    def is_one(self, p: Any) -> bool:
        return bool(p.is_one()) if self.name == "flint" else bool(p.is_one)

    def is_constant(self, p: Any) -> bool:
        return bool(p.is_constant()) if self.name == "flint" else p.total_degree() <= 0

    def degree_y(self, p: Any) -> int:
        return max(int(p.degrees()[1]), 0) if self.name == "flint" else max(p.degree(Y), 0)

    def leading(self, p: Any) -> Fraction:
        """The leading coefficient in the lexicographic order of x then y."""
        return as_fraction(p.leading_coefficient() if self.name == "flint" else p.LC())

    def monic(self, p: Any) -> Any:
        c = self.leading(p)
        return p if c == 1 else self.scaled(p, 1 / c)

    def scaled(self, p: Any, c: Fraction) -> Any:
        if self.name == "flint":
            return p * flint.fmpq(c.numerator, c.denominator)
        return p * sp.Rational(c.numerator, c.denominator)

    def gcd(self, p: Any, q: Any) -> Any:
        return self.monic(p.gcd(q)) if self.name == "flint" else self.monic(sp.gcd(p, q))

    def quo(self, p: Any, q: Any) -> Any:
        """p / q, exact."""
        return p // q if self.name == "flint" else sp.exquo(p, q)

    def factors(self, p: Any) -> list[Any]:
        """The distinct irreducible factors of p of positive degree, each made monic (:meth:`monic`); each p is
        factored once (the cells of a map read the signs of the same functions)."""
        key = ("factors", self.key(p))
        if key not in self._projections:
            found = [f for f, _ in (p.factor() if self.name == "flint" else p.factor_list())[1]]
            self._remember(key, [self.monic(f) for f in found if not self.is_constant(f)])
        return list(self._projections[key])

    def resultant(self, p: Any, q: Any, stop: Stop = None) -> Any:
        """The resultant of p and q in y (a polynomial in x); each pair is computed once (a decomposition meets the
        same pairs of curves on many cells). ``stop`` may end a long one by raising (with flint; see
        :mod:`~verify.maps.backends.eliminate`)."""
        key = ("resultant", self.key(p), self.key(q))
        if key not in self._projections:
            if self.name == "flint":
                found = resultant_y(p, q, stop=stop)
            else:
                found = sp.Poly(sp.resultant(p.as_expr(), q.as_expr(), Y), X, Y, domain="QQ")
            self._remember(key, found)
        return self._projections[key]

    def discriminant(self, p: Any, stop: Stop = None) -> Any:
        """The discriminant of p in y (a polynomial in x), computed once for each p; ``stop`` as for
        :meth:`resultant`."""
        key = ("discriminant", self.key(p))
        if key not in self._projections:
            if self.name == "flint":
                found = discriminant_y(p, stop=stop)
            else:
                found = sp.Poly(sp.discriminant(p.as_expr(), Y), X, Y, domain="QQ")
            self._remember(key, found)
        return self._projections[key]

    def _remember(self, key: tuple[Any, ...], value: Any) -> None:
        if len(self._projections) >= CONVERTED:
            self._projections.clear()
        self._projections[key] = value

    def derivative_x(self, p: Any) -> Any:
        return p.derivative("x") if self.name == "flint" else p.diff(X)

    def in_x(self, p: Any) -> tuple[Fraction, ...]:
        """A polynomial in x only, as its coefficients (lowest degree first)."""
        t = self.terms(p)
        n = max((i for i, _ in t), default=0)
        return tuple(sum((c for (i, j), c in t.items() if i == k), Fraction(0)) for k in range(n + 1))

    def leading_in_y(self, p: Any) -> tuple[Fraction, ...]:
        """The coefficient of the highest power of y, a polynomial in x (coefficients, lowest degree first)."""
        t = self.terms(p)
        top = self.degree_y(p)
        n = max((i for i, j in t if j == top), default=0)
        return tuple(t.get((k, top), Fraction(0)) for k in range(n + 1))

    def in_y(self, p: Any, x: Fraction) -> tuple[Fraction, ...]:
        """p(x, y) at a rational x: its coefficients in y, lowest degree first."""
        out = [Fraction(0)] * (self.degree_y(p) + 1)
        if self.name == "flint":  # substituted by flint, then read off
            for (_, j), c in p.subs({"x": flint.fmpq(x.numerator, x.denominator)}).to_dict().items():
                out[int(j)] = as_fraction(c)
            return tuple(out)
        t = self.terms(p)
        for (i, j), c in t.items():
            out[j] += c * x**i
        return tuple(out)

    def value(self, p: Any, x: Fraction, y: Fraction, *, exact: bool = True) -> Any:
        """p at the rational point (x, y): a Fraction, or with ``exact=False`` flint's own rational (the same number,
        not converted: enough for its sign)."""
        if self.name == "flint":
            v = p(flint.fmpq(x.numerator, x.denominator), flint.fmpq(y.numerator, y.denominator))
            return as_fraction(v) if exact else v
        return sum((c * x**i * y**j for (i, j), c in self.terms(p).items()), Fraction(0))

    def at_y(self, p: Any, y: Fraction) -> tuple[Fraction, ...]:
        """p(x, y) at a rational y: its coefficients in x, lowest degree first."""
        t = self.terms(p)
        out = [Fraction(0)] * (max((i for i, _ in t), default=0) + 1)
        for (i, j), c in t.items():
            out[i] += c * y**j
        return tuple(out)


_POLYS: dict[str, Polys] = {}


def polys(name: str | None = None) -> Polys:
    """The polynomial arithmetic ``name`` (``"flint"`` or ``"sympy"``; default flint when installed)."""
    name = name or ("flint" if flint is not None else "sympy")
    if name == "flint" and flint is None:  # pragma: no cover
        raise ImportError("python-flint is not installed (the fast extra)")
    if name not in _POLYS:
        _POLYS[name] = Polys(name)
    return _POLYS[name]


class Frac:
    """A rational function n / d of (x, y): no common factor, d of leading coefficient 1."""

    __slots__ = ("P", "_hash", "d", "n")

    def __init__(self, P: Polys, n: Any, d: Any, reduce: bool = True):
        if reduce:
            if P.is_zero(d):
                raise ZeroDivisionError("division by the zero function")
            if P.is_zero(n):
                d = P.one
            elif not P.is_constant(d):
                g = P.gcd(n, d)
                if not P.is_constant(g):
                    n, d = P.quo(n, g), P.quo(d, g)
            c = P.leading(d)
            if c != 1:
                n, d = P.scaled(n, 1 / c), P.scaled(d, 1 / c)
        self.P, self.n, self.d = P, n, d
        self._hash: int | None = None

    def __add__(self, o: Frac) -> Frac:
        if self.d == o.d:
            return Frac(self.P, self.n + o.n, self.d)
        return Frac(self.P, self.n * o.d + o.n * self.d, self.d * o.d)

    def __sub__(self, o: Frac) -> Frac:
        return self + (-o)

    def __neg__(self) -> Frac:
        return Frac(self.P, -self.n, self.d, reduce=False)

    def __mul__(self, o: Frac) -> Frac:
        return Frac(self.P, self.n * o.n, self.d * o.d)

    def __truediv__(self, o: Frac) -> Frac:
        if self.P.is_zero(o.n):
            raise ZeroDivisionError("division by the zero function")
        return Frac(self.P, self.n * o.d, self.d * o.n)

    def __eq__(self, o: object) -> bool:
        return isinstance(o, Frac) and self.n == o.n and self.d == o.d

    def __hash__(self) -> int:
        if self._hash is None:
            self._hash = hash((self.P.key(self.n), self.P.key(self.d)))
        return self._hash

    def __float__(self) -> float:
        raise TypeError("a rational function of the parameters has no float value")

    def expr(self, names: tuple[str, str] = ("x", "y")) -> Any:
        return self.P.expr(self.n, names) / self.P.expr(self.d, names)

    def at(self, x: Fraction, y: Fraction) -> Fraction:
        """The value at the rational point (x, y) (the denominator non-zero there)."""
        v = self.P.value(self.n, x, y, exact=False) / self.P.value(self.d, x, y, exact=False)
        return v if isinstance(v, Fraction) else as_fraction(v)


class NewCurves(NotConstant):
    """A sign asked on a cell depends on curves the decomposition does not know yet: ``polys`` (irreducible
    factors, canonical) must cut the plane first."""


class OutOfTime(Exception):
    """The wall-clock deadline of a map passed during a cell's run (the cell is then left unexplored)."""


#: a sample point: a rational x and a rational or real algebraic y
Sample = tuple[Fraction, "Fraction | RealAlgebraic"]


class PlaneBackend(Backend):
    """Rational functions of two parameters on one cell (see the module): ``parameters`` are the two as
    elements; ``known`` the keys (:meth:`Polys.key`) of the polynomials with one sign on the cell; on a cell
    that is a ``point``, every sign is read at the sample."""

    name = "plane"
    is_exact = True
    is_rigorous = True

    def __init__(
        self,
        P: Polys,
        sample: Sample,
        known: set[tuple[Any, ...]],
        names: tuple[str, str] = ("x", "y"),
        *,
        point: bool = False,
        deadline: float | None = None,
        tower: Any = None,
        asked: dict[Any, int] | None = None,
    ):
        self.P, self.sample, self.known, self.names, self.point = P, sample, known, names, point
        #: when given, every function whose sign is asked is put in it, with that sign: the curves of their factors are
        #: those a run at a point would need to know on a cell
        self.asked = asked
        self.deadline = deadline  #: a time.monotonic() after which a sign raises OutOfTime
        self.zero, self.one = Frac(P, P.zero, P.one), Frac(P, P.one, P.one)
        self.parameters: tuple[Any, Any] = (Frac(P, P.x, P.one), Frac(P, P.y, P.one))
        self._signs: dict[Any, int] = {}
        #: for a system over a number field, its :class:`~verify.maps.backends.tower.Tower` (over ``P``): the
        #: elements are then its TowerFracs
        self.tower = tower
        if tower is not None:
            self.zero, self.one = tower.zero, tower.one
            self.parameters = (tower.of([self.parameters[0]]), tower.of([self.parameters[1]]))

    def convert(self, value: Any) -> Any:
        if isinstance(value, Fraction):
            c = Frac(self.P, self.P.from_dict({(0, 0): value}), self.P.one)
            return c if self.tower is None else self.tower.of([c])
        e = sp.sympify(value)
        a, b = sp.Symbol(self.names[0]), sp.Symbol(self.names[1])
        if e.free_symbols - {a, b}:
            raise BadNumber(f"{value}: a map of two parameters knows only {a} and {b}")
        if self.tower is not None:
            try:
                return self.tower.from_expr(e.subs({a: X, b: Y}, simultaneous=True))
            except (sp.PolynomialError, sp.polys.polyerrors.CoercionFailed):
                raise BadNumber(
                    f"{value}: not a rational function of the parameters over {self.tower.field_of.label()}"
                ) from None
        key = (self.names, e)
        if key in self.P.converted:
            return self.P.converted[key]
        n, d = sp.fraction(sp.cancel(sp.together(e.subs({a: X, b: Y}, simultaneous=True))))
        try:
            out = Frac(self.P, self.P.from_expr(n), self.P.from_expr(d))
        except sp.PolynomialError:
            raise BadNumber(f"{value}: a map needs rational functions of the parameters") from None
        if len(self.P.converted) >= CONVERTED:
            self.P.converted.clear()
        self.P.converted[key] = out
        return out

    def factors_of(self, p: Any) -> list[Any]:
        return self.P.factors(p)

    def value_sign(self, p: Any) -> int:
        """The sign of the polynomial p at the sample point, exactly."""
        x, y = self.sample
        if not isinstance(y, RealAlgebraic):
            v = self.P.value(p, x, y, exact=False)
            return int(v > 0) - int(v < 0)
        return y.sign_of(self.P.in_y(p, x))

    def sign(self, f: Any) -> int:
        found = self._signs.get(f)
        if found is not None:
            if self.asked is not None:
                self.asked[f] = found
            return found
        T = self.tower
        if f.is_zero() if T is not None else self.P.is_zero(f.n):
            if self.asked is not None:
                self.asked[f] = 0
            return 0
        polys = T.curves(f) if T is not None else (f.n, f.d)
        new = [] if self.point else [g for p in polys for g in self.factors_of(p) if self.P.key(g) not in self.known]
        if self.deadline is not None and time.monotonic() > self.deadline:
            raise OutOfTime("the map's wall-clock budget ran out during a cell's run")
        if new:

            def message() -> str:
                shown = ", ".join(f"{self.P.show(g, self.names)} = 0" for g in new)
                if T is not None:
                    what = str(T.expr(f, self.names))
                else:
                    what = self.P.show(f.n, self.names) if self.P.is_one(f.d) else str(f.expr(self.names))
                return f"the sign of {what} is read on a cell that no curve {shown} bounds"

            raise NewCurves(new, message)
        s = int(T.sign_at(f, *self.sample)) if T is not None else self.value_sign(f.n) * self.value_sign(f.d)
        self._signs[f] = s
        if self.asked is not None:
            self.asked[f] = s
        return s

    def at_sample(self, x: Any) -> Fraction | None:
        """x at the cell's sample point, when that point is rational and the system's numbers are (None else): where
        a cone's membership is decided (:func:`~verify.proofs.cones.period.member`), the combination is found there,
        and only the signs of its coefficients are then asked on the cell, not those of every pivot."""
        y = self.sample[1]
        if self.tower is not None or isinstance(y, RealAlgebraic):
            return None
        value: Fraction = x.at(self.sample[0], y)
        return value

    def to_number(self, x: Any) -> Any:
        return x.expr(self.names) if self.tower is None else self.tower.expr(x, self.names)

    def to_exact(self, x: Any) -> str:
        if self.tower is not None:
            return str(sp.factor(self.to_number(x)))
        key = (self.names, x)
        if key not in self.P.written:
            if len(self.P.written) >= CONVERTED:
                self.P.written.clear()
            self.P.written[key] = str(sp.factor(self.to_number(x)))
        return self.P.written[key]

    def to_decimal(self, x: Frac, digits: int = 30) -> str:
        return self.to_exact(x)

    def describe(self) -> str:
        return f"plane ({self.names[0]}, {self.names[1]} on one cell), exact"
