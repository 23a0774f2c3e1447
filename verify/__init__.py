"""verify: exact verification of the multiple-impact rule of Pasquero (2021).

The public API: build a :class:`System` (mass matrix, constraint normals, time terms,
CORs) on a backend, and :func:`solve` it from a left velocity (:func:`solve_many` for many
velocities or CORs over one geometry).

>>> from verify import System, solve
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["0.5", "0.5"])
>>> r = solve(s, ["100", "0", "0"])
>>> r.iterations, r.stop, [s.backend.to_exact(x) for x in r.exit_velocity]
(3, 'exit', ['325/16', '375/16', '225/4'])
"""

from verify.dynamics.policy import Halted, StopTest
from verify.dynamics.system import System
from verify.errors import (
    BadNumber,
    InvalidInput,
    InvalidSystem,
    NoConvergence,
    Undecided,
    VerifyError,
)
from verify.laws.outcome import Result, Step
from verify.laws.rule import (
    RULES,
    beta,
    global_orthogonal_component,
    impact_set,
    impulse,
    orthogonal_component,
    solve,
    solve_many,
)
from verify.laws.sequential import Sequential
from verify.models.cradle import cradle_system, cradle_system_full, run_cradle
from verify.numbers.backends import BACKENDS, Backend, get_backend
from verify.numbers.format import format_decimal, format_exact
from verify.numbers.parse import parse_number

__version__ = "0.4.0"

#: names imported when first used (they load SymPy and Hypothesis, which the command line's parser does not)
_LAZY = {
    "eps_map": "verify.maps.general",
    "family_verdicts": "verify.properties.own",
}


def __getattr__(name: str) -> object:
    """:func:`~verify.maps.general.eps_map` (the map of any system's CORs as parameters) and
    :func:`~verify.properties.own.family_verdicts` (the property suite on a family of your own)."""
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'verify' has no attribute {name!r}")


__all__ = [
    "BACKENDS",
    "RULES",
    "Backend",
    "BadNumber",
    "Halted",
    "InvalidInput",
    "InvalidSystem",
    "NoConvergence",
    "Result",
    "Sequential",
    "Step",
    "StopTest",
    "System",
    "Undecided",
    "VerifyError",
    "__version__",
    "beta",
    "cradle_system",
    "cradle_system_full",
    "eps_map",
    "family_verdicts",
    "format_decimal",
    "format_exact",
    "get_backend",
    "global_orthogonal_component",
    "impact_set",
    "impulse",
    "orthogonal_component",
    "parse_number",
    "run_cradle",
    "solve",
    "solve_many",
]
