"""Binary64 floats: fast, not rigorous."""

from __future__ import annotations

import math
from fractions import Fraction

from verify.errors import InvalidInput
from verify.numbers.backends.base import Backend
from verify.numbers.format import format_decimal
from verify.numbers.parse import Number


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

            from verify.numbers.numeric import evaluate

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
