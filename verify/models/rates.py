"""Velocities with chosen constraint rates: ``v = w + sum_k c_k g^-1 a_k`` whose rates ``p(F_j)`` are given.

The hard cases of the oracle and the property suite's strategies both build their incoming
velocities here (a free part, then exact target rates on a chosen set of constraints), in the
fastest installed rationals; the results are plain Fractions.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.numbers.backends import RationalBackend
from verify.numbers.linalg import dot, ldl, solve_spd

#: the fastest installed rationals, for the linear algebra (results are given back as Fractions: the same numbers)
_F = RationalBackend("auto")
_FACTORS: dict[str, Any] = {}


def fractions(x: Any) -> Any:
    """``x`` (a number or nested lists of them) as Fractions: never ints, since int / int is a float.

    >>> fractions([1, "1/2"])
    [Fraction(1, 1), Fraction(1, 2)]
    """
    return [fractions(y) for y in x] if isinstance(x, (list, tuple)) else Fraction(x)


def metric_inverse_apply(g: list[list[Fraction]], a: list[Any]) -> tuple[Any, ...]:
    """``g^-1 a`` in the fastest installed rationals (``a`` Fractions or those); the factorisation of the
    last g is kept (a draw asks it several times).

    >>> [x == Fraction(1, 2) for x in metric_inverse_apply([[Fraction(2)]], [Fraction(1)])]
    [True]
    """
    key = repr(g)
    if key not in _FACTORS:
        _FACTORS.clear()
        _FACTORS[key] = ldl(_F, [_F.convert_all(row) for row in g])
    return solve_spd(_F, _FACTORS[key], [x if type(x) is not Fraction else _F.convert(x) for x in a])


def velocity_with_rates(system: tuple[Any, ...], w: list[Fraction], targets: dict[int, Fraction]) -> list[Fraction]:
    """``v = w + sum_k c_k g^-1 a_k`` whose rates ``p(F_j)`` equal ``targets[j]`` exactly.

    ``system`` is ``(g, normals, time_terms)``; the other rates are whatever follows.

    >>> velocity_with_rates(([[1, 0], [0, 1]], [[1, 1]], [0]), [0, 0], {0: -2})
    [Fraction(-1, 1), Fraction(-1, 1)]
    """
    g, normals, time_terms = (fractions(x) for x in system)
    chosen = sorted(targets)
    U = [metric_inverse_apply(g, normals[k]) for k in chosen]
    a = {j: _F.convert_all(normals[j]) for j in chosen}
    w = _F.convert_all(fractions(list(w)))
    rates = [_F.convert(time_terms[j]) + dot(_F, a[j], w) for j in chosen]
    G = [[dot(_F, a[j], u) for u in U] for j in chosen]
    c = solve_spd(_F, ldl(_F, G), [_F.convert(Fraction(targets[j])) - b for j, b in zip(chosen, rates)])
    return [_F.to_number(x + dot(_F, c, [u[i] for u in U])) for i, x in enumerate(w)]
