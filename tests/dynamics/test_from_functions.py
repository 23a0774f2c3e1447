"""System.from_functions: the time, a configuration-dependent mass matrix, errors in library terms
(issue 14, item 6)."""

from __future__ import annotations

import re
from fractions import Fraction

import pytest
import sympy as sp

from verify.dynamics.system import System
from verify.errors import BadNumber, InvalidInput, InvalidSystem
from verify.models.cradle import run_cradle
from verify.numbers.backends import RationalBackend, exact_for

t, x1, x2, R = sp.symbols("t x1 x2 R")
UNIT = [[1, 0], [0, 1]]


def test_a_time_dependent_constraint_without_the_time_says_so():
    with pytest.raises(InvalidSystem, match=r"configuration: no value for the time t.*functions\[0\]"):
        System.from_functions([x2 - x1 - t], [x1, x2], {x1: 0, x2: 0}, UNIT, [1], time=t)


def test_with_the_time_the_moving_constraint_is_in_contact():
    s = System.from_functions([x2 - x1 - t], [x1, x2], {x1: 0, x2: 1, t: 1}, UNIT, [1], time=t)
    same = System(UNIT, [[-1, 1]], [1], [-1])  # dF = (-1, 1), dF/dt = -1, typed from the function above
    assert s.names == ("F1",) and s.source == same.source


def test_a_time_nothing_depends_on_needs_no_value():
    s = System.from_functions([x2 - x1], [x1, x2], {x1: 0, x2: 0}, UNIT, [1], time=t)
    assert s.source == System(UNIT, [[-1, 1]], [1]).source


def test_a_symbol_that_is_neither_coordinate_nor_time_is_named():
    with pytest.raises(InvalidSystem, match=r"functions\[0\] = .* depends on t, .*time=\.\.\."):
        System.from_functions([x2 - x1 - t], [x1, x2], {x1: 0, x2: 0}, UNIT, [1])  # time=t forgotten
    s = System.from_functions([x2 - x1 - R], [x1, x2], {x1: 0, x2: 1, R: 1}, UNIT, [1])  # a parameter's value
    assert s.names == ("F1",)


def test_a_configuration_dependent_mass_matrix_is_evaluated_there():
    g = [[1 + x1**2, x1 * x2 / 6], [x1 * x2 / 6, 2 + x2]]
    config = {x1: 1, x2: 3}
    s = System.from_functions([x2 - x1 - 2], [x1, x2], config, g, ["1/2"])
    by_hand = System([[2, "1/2"], ["1/2", 5]], [[-1, 1]], ["1/2"])  # g at x1 = 1, x2 = 3
    assert s.source == by_hand.source
    assert s.backend.name == "exact" and s.gram == by_hand.gram


def test_an_algebraic_mass_matrix_stays_exact():
    s = System.from_functions([x2 - x1], [x1, x2], {x1: 1, x2: 1}, [[sp.sqrt(x1 + 1), 0], [0, 1]], [1])
    assert s.source["mass_matrix"][0][0] == sp.sqrt(2)
    assert s.backend is exact_for([sp.sqrt(2)])  # the exact number field, not a float backend


def test_a_mass_matrix_with_a_free_symbol_is_named():
    with pytest.raises(InvalidSystem, match=r"mass_matrix\[1\]\[1\] = R depends on R"):
        System.from_functions([x2 - x1], [x1, x2], {x1: 0, x2: 0}, [[1, 0], [0, R]], [1])
    with pytest.raises(InvalidSystem, match=r"no value for the time t, on which mass_matrix\[0\]\[0\] depends"):
        System.from_functions([x2 - x1], [x1, x2], {x1: 0, x2: 0}, [[1 + t, 0], [0, 1]], [1], time=t)


@pytest.mark.parametrize(
    "call",
    [
        lambda: System.from_functions([x2 - x1], [x1, x2], {x1: 1, x2: 1}, [[sp.tan(x1), 0], [0, 1]], [1]),
        lambda: System([["tan(1)", 0], [0, 1]], [[-1, 1]], [1]),
        lambda: run_cradle("1/2", masses=["1", "tan(1)", "1"]),
        lambda: exact_for([sp.tan(1)]),
        lambda: RationalBackend().convert(sp.sqrt(2)),
    ],
)
def test_library_errors_name_the_parameter_not_a_command_line_flag(call):
    with pytest.raises(InvalidInput) as info:
        call()
    message = str(info.value)
    assert "--" not in message
    assert 'backend="interval"' in message


def test_a_non_algebraic_entry_is_named_by_its_field():
    with pytest.raises(BadNumber, match=r"mass_matrix\[0\]\[0\] = tan\(1\) is not an algebraic number"):
        System.from_functions([x2 - x1], [x1, x2], {x1: 1, x2: 1}, [[sp.tan(x1), 0], [0, 1]], [1])


# -- binary floats (issue 34, item 15) ---------------------------------------------------------


@pytest.mark.parametrize(
    ("system", "field", "typed", "exact"),
    [
        (([x2 - 0.3 * x1], {x1: 0, x2: 0}, UNIT, [1]), r"functions\[0\] = .* holds the binary float", "0.3", "3/10"),
        (([x2 - x1], {x1: 0.1, x2: 0.1}, UNIT, [1]), r"configuration\[x1\] = 0\.1 is a binary float", "0.1", "1/10"),
        (([x2 - x1], {x1: 0, x2: 0}, [[1 + 0.1 * x1**2, 0], [0, 1]], [1]), r"mass_matrix\[0\]\[0\] = ", "0.1", "1/10"),
        (
            ([x2 - x1], {x1: 0, x2: 0}, UNIT, [sp.Float(0.7)]),
            r"restitution\[0\] = 0\.7 is a binary float",
            "0.7",
            "7/10",
        ),
    ],
)
def test_a_binary_float_is_named_as_one_with_its_exact_spelling(system, field, typed, exact):
    functions, configuration, mass, cors = system
    with pytest.raises(BadNumber) as info:
        System.from_functions(functions, [x1, x2], configuration, mass, cors)
    message = str(info.value)
    assert re.match(field, message), message
    assert f"which is not {exact}" in message and f'sympy.Rational("{typed}")' in message, message
    assert "algebraic" not in message and "backend" not in message, message


def test_the_exact_spelling_the_message_gives_is_accepted():
    with pytest.raises(BadNumber, match=r'configuration\[x1\] = 0\.1 .*sympy\.Rational\("0\.1"\)'):
        System.from_functions([x2 - 0.3 * x1], [x1, x2], {x1: 0.1, x2: sp.Rational(3, 100)}, UNIT, [1])  # the issue's
    s = System.from_functions(
        [x2 - sp.Rational("0.3") * x1], [x1, x2], {x1: Fraction(1, 10), x2: Fraction(3, 100)}, UNIT, [1]
    )
    assert s.source == System(UNIT, [["-3/10", "1"]], [1]).source


def test_a_binary_float_equal_to_its_decimal_is_refused_too():
    with pytest.raises(BadNumber, match=r"holds the binary float 0\.5 \(binary floats are refused"):
        System.from_functions([x2 - 0.5 * x1], [x1, x2], {x1: 0, x2: 0}, UNIT, [1])
