"""Arithmetic backends: the one contract that the rule is written against.

A backend ``K`` owns the numbers the rule computes with. The rule uses only

- ``K.convert(number)``: a parsed :data:`~verify.core.numbers.Number` (Fraction or closed form)
  into an element of ``K``, once, at the boundary;
- ``+ - * /`` between elements, and ``K.zero`` / ``K.one``;
- ``K.sign(x) -> -1 | 0 | 1``, which every branch of the rule goes through. It may raise
  :class:`~verify.errors.Undecided` when the backend cannot decide (an interval that
  contains 0); rigorous backends never guess.

and reports through ``K.to_decimal(x, digits)`` (on interval backends only the digits
that the enclosure certifies), ``K.to_number(x)`` (exact backends: the exact value back)
and ``K.enclosure(x)`` (interval backends). Flags ``is_exact`` and
``is_rigorous`` say what a result can claim; ``refined()`` returns the same backend at
higher precision (or None), which :func:`verify.core.rule.solve` uses to retry after an
undecided sign.

Backends here: ``exact`` (rationals; gmpy2 or python-flint when installed, pure-Python
:class:`~fractions.Fraction` otherwise, same results), ``mp`` (mpmath at ``dps`` digits,
heuristic signs), ``interval`` (mpmath intervals, certified signs, precision raised
automatically) and ``float`` (fast, not rigorous). An algebraic-number backend and a
symbolic-parameter backend fit the same contract: their elements support ``+ - * /`` and
their ``sign`` decides exactly or raises.

>>> K = get_backend("exact")
>>> x = K.convert(Fraction(1, 3)) - K.convert(Fraction(1, 2))
>>> K.sign(x), K.to_decimal(x, 5), K.to_number(x)
(-1, '-0.16667', Fraction(-1, 6))
"""

from __future__ import annotations

import functools
import math
import os
from fractions import Fraction
from typing import Any

from verify.core.numbers import Number, certified_decimal, format_decimal, format_exact
from verify.errors import BadNumber, InvalidInput, Undecided

BACKENDS = ("exact", "mp", "interval", "float")
DEFAULT_DPS = 50
MAX_INTERVAL_DPS = 3200


class Backend:
    """The contract (see the module docstring). Subclasses set the flags and methods."""

    name: str = "?"
    is_exact: bool = False
    is_rigorous: bool = False
    refinable: bool = False  #: whether refined() can raise the precision after an undecided sign
    is_parametric: bool = False  #: whether elements are functions of a parameter (the symbolic backend)
    fraction_free: bool = False  #: whether the rule may run over integers (rationals only)
    dps: int | None = None
    zero: Any
    one: Any

    def convert(self, value: Number) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def sign(self, x: Any) -> int:  # pragma: no cover - abstract
        raise NotImplementedError

    def to_decimal(self, x: Any, digits: int = 30) -> str:  # pragma: no cover - abstract
        raise NotImplementedError

    def nonnegative(self, x: Any) -> bool:
        """Whether ``x >= 0`` (a parameter backend answers for the whole parameter range)."""
        return self.sign(x) >= 0

    def to_number(self, x: Any) -> Number:
        """The exact value of ``x``; only exact backends have one."""
        raise TypeError(f"the {self.name} backend holds approximations, not exact values")

    def to_exact(self, x: Any) -> str:
        """The exact string of ``x`` (exact backends only)."""
        return format_exact(self.to_number(x))

    def enclosure(self, x: Any, digits: int = 30) -> tuple[str, str] | None:
        """Lower and upper bounds of ``x`` as decimal strings, for interval backends."""
        return None

    def size(self, x: Any) -> int:
        """The storage size of ``x`` in bits: numerators and denominators of exact values
        (what a size budget bounds); 0 on backends of fixed precision."""
        return 0

    def refined(self) -> Backend | None:
        """The same backend at higher precision, or None when it cannot be refined."""
        return None

    def describe(self) -> str:
        """A short label: name, precision and whether results are rigorous."""
        parts = [self.name]
        if self.dps is not None:
            parts.append(f"{self.dps} digits")
        parts.append("rigorous" if self.is_rigorous else "not rigorous")
        return ", ".join(parts)

    def __repr__(self) -> str:
        return f"<backend {self.describe()}>"


# -- exact rationals ------------------------------------------------------------------


@functools.cache
def _rational_impls() -> dict[str, Any]:
    """The installed rational types, fastest first (looked up once)."""
    impls: dict[str, Any] = {}
    try:
        import gmpy2

        impls["gmpy2"] = gmpy2.mpq
    except ImportError:
        pass
    try:
        import flint

        impls["flint"] = flint.fmpq
    except ImportError:
        pass
    impls["python"] = Fraction
    return impls


class RationalBackend(Backend):
    """Exact rationals. ``impl`` is ``"gmpy2"``, ``"flint"``, ``"python"`` or ``"auto"``.

    ``"auto"`` takes the fastest installed one (the environment variable
    ``VERIFY_RATIONALS`` can force a choice); every implementation gives the same results.
    Irrational inputs are refused with a clear error: run them on ``interval`` or ``mp``.
    """

    name = "exact"
    is_exact = True
    is_rigorous = True
    fraction_free = True  #: the rule may run over integers here (:mod:`verify.core.engines.integer`)

    def __init__(self, impl: str = "auto"):
        impls = _rational_impls()
        if impl == "auto":
            impl = os.environ.get("VERIFY_RATIONALS", "") or next(iter(impls))
        if impl not in impls:
            raise InvalidInput(f"rational implementation {impl!r} is not installed (have: {', '.join(impls)})")
        self.impl = impl
        self._q = impls[impl]
        self.zero = self._q(0)
        self.one = self._q(1)
        self._units = {-1: self._q(-1), 0: self.zero, 1: self.one}

    def convert(self, value: Number) -> Any:
        if type(value) is Fraction or isinstance(value, Fraction):
            if value.denominator == 1 and -2 < value.numerator < 2:
                return self._units[value.numerator]  # -1, 0, 1: most entries of mass matrices and normals
            return self._q(value.numerator, value.denominator)
        raise BadNumber(
            f"{value} is irrational: the exact backend computes over the rationals; "
            'use backend="interval" (certified) or backend="mp"'
        )

    def sign(self, x: Any) -> int:
        return (x > 0) - (x < 0)

    def from_integers(self, numerator: Any, denominator: Any) -> Any:
        """The element ``numerator / denominator`` (integers, denominator non-zero)."""
        if self.impl == "gmpy2":
            return self._q(numerator, denominator)
        return self._q(int(numerator), int(denominator))

    def to_number(self, x: Any) -> Fraction:
        return Fraction(int(x.numerator), int(x.denominator))

    def size(self, x: Any) -> int:
        return int(x.numerator).bit_length() + int(x.denominator).bit_length()

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return format_decimal(self.to_number(x), digits)

    def describe(self) -> str:
        return f"exact (rationals, {self.impl}), rigorous"


class NumberFieldBackend(Backend):
    """Exact arithmetic in a real number field: ``sqrt(3)/3``, ``cos(pi/12)``, ``3 - 2*sqrt(2)``.

    The field is Q(theta) for a primitive element theta of the given generators (SymPy's
    ``AlgebraicField``); elements are polynomials in theta of degree below its minimal
    polynomial's, so arithmetic and zero tests are exact. Signs are decided rigorously by
    isolating theta, a root of its minimal polynomial, in a rational interval
    (:class:`~verify.core.algebraic.RealAlgebraic`). The ``exact`` backend switches to it by
    itself when an input is irrational but algebraic.

    >>> import sympy as sp
    >>> K = NumberFieldBackend([sp.sqrt(2)])
    >>> x = K.convert(3 - 2 * sp.sqrt(2))
    >>> K.sign(x), K.to_exact(x * x), K.to_decimal(x, 8)
    (1, '17 - 12*sqrt(2)', '0.17157288')
    """

    name = "exact"
    is_exact = True
    is_rigorous = True

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

        from verify.core.numbers import to_number

        return to_number(sp.expand(self.field.to_sympy(x)))

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return format_decimal(self.to_number(x), digits)

    def size(self, x: Any) -> int:
        return sum(int(c.numerator).bit_length() + int(c.denominator).bit_length() for c in x.to_list())

    def describe(self) -> str:
        return f"exact (number field Q({', '.join(str(g) for g in self.generators)})), rigorous"


def algebraic_generators(values: Any) -> list[Any] | None:
    """The irrational values among ``values`` if they are all algebraic, else None."""
    out = []
    for v in values:
        if isinstance(v, Fraction):
            continue
        if v.is_algebraic is not True:
            return None
        if v not in out:
            out.append(v)
    return out


def exact_for(values: Any) -> Backend:
    """The exact backend for these parsed numbers: rationals when they all are, else their
    number field; BadNumber when one is not algebraic (such as tan(3/10))."""
    gens = algebraic_generators(list(values))
    if gens is None:
        bad = next(v for v in values if not isinstance(v, Fraction) and v.is_algebraic is not True)
        raise BadNumber(
            f"{bad} is not an algebraic number, so the exact backend cannot hold it: "
            'use backend="interval" (certified) or backend="mp"'
        )
    if not gens:
        return RationalBackend()
    key = tuple(str(g) for g in gens)
    if key not in _FIELDS:  # building a field (primitive element, isolation) costs more than a short run
        _FIELDS[key] = NumberFieldBackend(gens)
    return _FIELDS[key]


_FIELDS: dict[tuple[str, ...], NumberFieldBackend] = {}


# -- mpmath -------------------------------------------------------------------------------


class _ContextBackend(Backend):
    """A backend over a private mpmath context (precision is part of the backend's value)."""

    def __init__(self, dps: int = DEFAULT_DPS):
        if not isinstance(dps, int) or dps < 5:
            raise InvalidInput(f"dps must be an integer >= 5, got {dps!r}")
        self.dps = dps
        self.ctx = self._context()
        self.ctx.dps = dps
        self.zero = self.ctx.mpf(0)
        self.one = self.ctx.mpf(1)

    def _context(self) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def convert(self, value: Number) -> Any:
        from verify.core.numeric import evaluate

        return evaluate(value, self.ctx)


class MPBackend(_ContextBackend):
    """mpmath floating point at ``dps`` decimal digits; signs are heuristic (not rigorous)."""

    name = "mp"

    def _context(self) -> Any:
        from mpmath import MPContext

        return MPContext()

    def sign(self, x: Any) -> int:
        return (x > 0) - (x < 0)

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        return self.ctx.nstr(x, min(digits, self.dps))


class IntervalBackend(_ContextBackend):
    """mpmath intervals at ``dps`` digits: every sign is certified or raises Undecided.

    :meth:`refined` doubles the precision up to ``max_dps``; :func:`verify.core.rule.solve`
    retries with it when a sign is undecided and says so in the result's notes.
    """

    name = "interval"
    is_rigorous = True
    refinable = True

    def __init__(self, dps: int = DEFAULT_DPS, max_dps: int = MAX_INTERVAL_DPS):
        super().__init__(dps)
        self.max_dps = max(max_dps, dps)

    def _context(self) -> Any:
        from mpmath.ctx_iv import MPIntervalContext

        return MPIntervalContext()

    def sign(self, x: Any) -> int:
        if x.a > 0:
            return 1
        if x.b < 0:
            return -1
        if x.a == 0 and x.b == 0:
            return 0
        if not all(bound._mpi_[0][1] or not bound._mpi_[0][2] for bound in (x.a, x.b)):  # inf or nan
            raise Undecided(f"an unbounded interval at {self.dps} digits (a division by an interval around 0)")
        lo, hi = self._bounds(x)
        raise Undecided(
            f"the interval [{format_decimal(lo, 6, 'floor')}, {format_decimal(hi, 6, 'ceiling')}] "
            f"contains 0 at {self.dps} digits"
        )

    def _bounds(self, x: Any) -> tuple[Fraction, Fraction]:
        from verify.core.numeric import _mpf_to_fraction

        return _mpf_to_fraction(x.a), _mpf_to_fraction(x.b)

    def to_decimal(self, x: Any, digits: int = 30) -> str:
        """Only the digits that the enclosure certifies (at most ``digits``; see
        :func:`~verify.core.numbers.certified_decimal`): ``"4.7625000000000000"`` when the
        bounds agree to 17 digits, the value itself for a point, ``"0e-19"`` for an
        enclosure of 0. The midpoint's further digits would be noise.

        >>> K = IntervalBackend(20)
        >>> third = K.one / K.convert(Fraction(3))
        >>> K.to_decimal(third, 30), K.to_decimal(K.convert(Fraction(1, 4)), 30)
        ('0.333333333333333333333', '0.25')
        >>> K.to_decimal(third * K.convert(Fraction(3)) - K.one)
        '0e-20'
        """
        lo, hi = self._bounds(x)
        return certified_decimal(lo, hi, digits)

    def enclosure(self, x: Any, digits: int = 30) -> tuple[str, str]:
        lo, hi = self._bounds(x)
        return format_decimal(lo, digits, "floor"), format_decimal(hi, digits, "ceiling")

    def contains(self, x: Any, value: Fraction) -> bool:
        """Whether the exact rational ``value`` lies in the interval ``x``."""
        lo, hi = self._bounds(x)
        return lo <= value <= hi

    def refined(self) -> IntervalBackend | None:
        if self.dps >= self.max_dps:
            return None
        return IntervalBackend(min(2 * self.dps, self.max_dps), self.max_dps)


class FloatBackend(Backend):
    """Python floats: fast, not rigorous (branches may differ from the exact ones)."""

    name = "float"

    def __init__(self) -> None:
        self.zero = 0.0
        self.one = 1.0
        self.dps = 15

    def convert(self, value: Number) -> float:
        """The nearest float; a value beyond the float range is bad input (InvalidInput).

        >>> FloatBackend().convert(Fraction(1, 3))
        0.3333333333333333
        """
        try:
            if isinstance(value, Fraction):
                return value.numerator / value.denominator  # correctly rounded
            from mpmath import fp

            from verify.core.numeric import evaluate

            result = float(evaluate(value, fp))
        except OverflowError:
            result = float("inf")
        if not math.isfinite(result):
            shown = format_decimal(value, 6) if isinstance(value, Fraction) else str(value)
            raise InvalidInput(f"{shown} is beyond the range of binary64 floats: use another backend")
        return result

    def sign(self, x: float) -> int:
        return (x > 0) - (x < 0)

    def to_decimal(self, x: float, digits: int = 17) -> str:
        return repr(x)

    def describe(self) -> str:
        return "float (binary64), not rigorous"


def get_backend(name: str | Backend = "exact", *, dps: int | None = None) -> Backend:
    """A backend by name: ``exact``, ``mp``, ``interval`` or ``float``.

    >>> get_backend("interval", dps=30).describe()
    'interval, 30 digits, rigorous'
    """
    if isinstance(name, Backend):
        return name
    if name == "exact":
        return RationalBackend()
    if name == "mp":
        return MPBackend(dps or DEFAULT_DPS)
    if name == "interval":
        return IntervalBackend(dps or DEFAULT_DPS)
    if name == "float":
        return FloatBackend()
    raise InvalidInput(f"unknown backend {name!r} (choose from {', '.join(BACKENDS)})")
