"""The backend contract admits closed-form and symbolic arithmetic without touching the rule.

Two small backends written here, against the same contract as the shipped ones:
closed forms (SymPy numbers; signs certified by interval enclosures and an exact zero test),
and a symbolic COR (signs decided from assumptions, Undecided otherwise). The rule runs on
both unchanged, which is what the algebraic and symbolic backends of later work rely on.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp

from verify.backends import Backend
from verify.cradle import cradle_system
from verify.errors import Undecided
from verify.numeric import certified_digits, certified_sign
from verify.rule import solve
from verify.system import System


class ClosedForms(Backend):
    name = "closed-forms (test)"
    is_exact = True
    is_rigorous = True
    zero = sp.Integer(0)
    one = sp.Integer(1)

    def convert(self, value):
        return sp.Rational(value.numerator, value.denominator) if isinstance(value, Fraction) else value

    def sign(self, x):
        return certified_sign(sp.radsimp(sp.expand(x)))

    def to_number(self, x):
        return sp.radsimp(sp.expand(x))

    def to_exact(self, x):
        return str(self.to_number(x))

    def to_decimal(self, x, digits=30):
        return certified_digits(sp.expand(x), digits)


class SymbolicCOR(ClosedForms):
    name = "symbolic (test)"

    def sign(self, x):
        x = sp.factor(sp.together(x))
        if x.is_zero:
            return 0
        if x.is_positive:
            return 1
        if x.is_negative:
            return -1
        raise Undecided(f"the sign of {x} depends on the parameter")


def test_the_threshold_itself_runs_exactly_on_closed_forms():
    # at eps = 3 - 2 sqrt(2), p_L^3 is exactly tangent to S_(2,3): the run exits after 3 impulses
    s = cradle_system("3 - 2*sqrt(2)", backend=ClosedForms())
    r = solve(s, ["1", "0", "0"])
    assert (r.iterations, r.stop) == (3, "exit")
    e = 3 - 2 * sp.sqrt(2)
    K = s.backend
    expected = [(1 - e) * (3 + e**2) / 8, (1 - e**2) * (3 - e) / 8, (1 + e) ** 2 / 4]
    for got, want in zip(r.exit_velocity, expected, strict=True):
        assert sp.expand(K.to_number(got) - want) == 0
    assert K.sign(s.rates(r.exit_velocity)[1]) == 0  # grazing: decided exactly, not by rounding


def test_a_symbolic_cor_runs_until_its_sign_depends_on_eps():
    # eps in (0, 1) written as 1/(1+t) with t > 0, so that 1 - eps has a known sign
    t = sp.Symbol("t", positive=True)
    e = 1 / (1 + t)
    s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [Fraction(1, 2)] * 2, backend=SymbolicCOR())
    s.restitution = (e, e)  # the symbolic COR enters as a backend element (System validates numbers only)
    r = solve(s, ["1", "0", "0"], max_iterations=2)
    K = s.backend
    p2 = [K.to_number(x) for x in r.exit_velocity]
    assert sp.simplify(p2[2] - (1 + e) ** 2 / 4) == 0  # the paper's p_L^2
    with pytest.raises(Undecided, match="depends on the parameter"):
        solve(s, ["1", "0", "0"], max_iterations=3)  # the third sign is the threshold question
