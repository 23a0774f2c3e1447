"""The backend contract, and the capabilities through which a backend says what it can do.

A backend ``K`` owns the numbers the rule computes with. The rule uses only

- ``K.convert(number)``: a parsed :data:`~verify.numbers.parse.Number` (Fraction or closed form)
  into an element of ``K``, once, at the boundary;
- ``+ - * /`` between elements, and ``K.zero`` / ``K.one``;
- ``K.sign(x) -> -1 | 0 | 1``, which every branch of the rule goes through. It may raise
  :class:`~verify.errors.Undecided` when the backend cannot decide (an interval that
  contains 0); rigorous backends never guess.

and reports through ``K.to_decimal(x, digits)`` (on interval backends only the digits
that the enclosure certifies), ``K.to_number(x)`` (exact backends: the exact value back)
and ``K.enclosure(x)`` (interval backends); ``refined()`` returns the same backend at
higher precision (or None), which :func:`verify.laws.rule.solve` uses to retry after an
undecided sign.

Callers never test a backend's name or class to decide what to do, and never probe it for an
attribute: they read its capabilities, the class attributes of :class:`Backend` (``is_exact``,
``is_rigorous``, ``rationals``, ``widens_to_inputs``, ``encloses``, ``refinable``, ``is_parametric``,
``fraction_free``, ``ball_form``), and call the methods it declares (``from_integers`` on a backend of
``rationals``, ``bounds`` on one that ``encloses``, ``at_sample`` on one that ``is_parametric``). :class:`Backend` is a
:class:`typing.Protocol` that every backend subclasses: a new backend declares its own capabilities,
inherits the defaults of the others, and is handled everywhere.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, Protocol

from verify.errors import Undecided
from verify.numbers.format import format_exact
from verify.numbers.parse import Number


class NotConstant(Undecided):
    """The sign asked of a function of parameters is not known to be constant where it is asked: ``polys``
    are the polynomials whose zero sets must cut the region first (each parameter backend says which). The
    message is written only when shown (a map raises thousands of these): a string or a function giving it."""

    def __init__(self, polys: list[Any], message: Any):
        super().__init__("")
        self.polys, self._message = polys, message

    def __str__(self) -> str:
        return str(self._message()) if callable(self._message) else str(self._message)


class Backend(Protocol):
    """The contract (see the module docstring). Subclasses set the capabilities and methods.

    The capabilities (the boolean class attributes below, all False here) each answer one
    question that a caller asks; subclasses set those that hold for them.
    """

    name: str = "?"  #: a label for reports (never a test of what the backend can do)
    #: whether elements are exact, so that ``to_number`` and ``to_exact`` give their values
    is_exact: bool = False
    #: whether every sign is decided rigorously (or raises Undecided): results can be claimed
    is_rigorous: bool = False
    #: whether elements are exact rationals with integer ``numerator`` and ``denominator``
    #: (Fraction, gmpy2's mpq, python-flint's fmpq), so that ``to_number`` returns a Fraction
    rationals: bool = False
    #: whether the backend is exact over the field of its inputs: the rule rebuilds the system
    #: over a larger field (:func:`verify.numbers.backends.exact_for`) when a velocity lies outside
    widens_to_inputs: bool = False
    #: whether elements are enclosures, whose certified bounds ``enclosure(x)`` returns
    encloses: bool = False
    #: whether refined() can raise the precision after an undecided sign
    refinable: bool = False
    #: whether elements are functions of a parameter (the symbolic backend)
    is_parametric: bool = False
    #: whether the rule may run over integers (:mod:`verify.laws.loops.integer`; rationals only)
    fraction_free: bool = False
    #: whether the rule may run on rate midpoints with one radius (:mod:`verify.laws.loops.balls`:
    #: mpmath intervals, whose enclosures then do not widen with the run)
    ball_form: bool = False
    dps: int | None = None  #: decimal digits of precision, None when exact
    zero: Any
    one: Any

    def convert(self, value: Number) -> Any:  # pragma: no cover - abstract
        """The element of this backend for a parsed number (BadNumber when it cannot hold it)."""
        raise NotImplementedError

    def convert_all(self, values: list[Number]) -> list[Any]:
        """The elements for a list of parsed numbers (one call: a backend may do it in bulk)."""
        return [self.convert(x) for x in values]

    def sign(self, x: Any) -> int:  # pragma: no cover - abstract
        """-1, 0 or 1; raises Undecided when the backend cannot decide."""
        raise NotImplementedError

    def to_decimal(self, x: Any, digits: int = 30) -> str:  # pragma: no cover - abstract
        """Decimal digits of ``x`` (only certified ones on rigorous approximate backends)."""
        raise NotImplementedError

    def known_zero(self, x: Any) -> bool:
        """Whether ``x`` is known to be exactly 0 (an undecidable sign counts as non-zero)."""
        try:
            return self.sign(x) == 0
        except Undecided:
            return False

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
        """Lower and upper bounds of ``x`` as decimal strings, on backends that ``encloses``."""
        return None

    def size(self, x: Any) -> int:
        """The storage size of ``x`` in bits: numerators and denominators of exact values
        (what a size budget bounds); 0 on backends of fixed precision."""
        return 0

    def refined(self) -> Backend | None:
        """The same backend at higher precision, or None when it cannot be refined."""
        return None

    def from_integers(self, numerator: Any, denominator: Any) -> Any:
        """The element ``numerator / denominator`` of two integers, on a backend of ``rationals``."""
        raise TypeError(f"the {self.name} backend's elements are not rationals")

    def bounds(self, x: Any) -> tuple[Fraction, Fraction]:
        """The exact ends of the enclosure ``x``, on backends that ``encloses``."""
        raise TypeError(f"the {self.name} backend's elements are not enclosures")

    def at_sample(self, x: Any) -> Fraction | None:
        """On a backend that ``is_parametric``: ``x`` at the sample point of its parameters, a rational, or
        None when the backend has no such point; None on every other backend."""
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
