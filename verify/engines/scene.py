"""The scenes a physics engine can build from a case record: a cradle of balls, a disk in a corner.

A case record (``docs/records.md``) describes a system by its mass matrix and normals; an
engine needs bodies. :func:`scene_of` recognises, exactly, the two geometries of
:mod:`verify.models` (the one owner of each): a cradle (diagonal mass matrix, the normals
``e_(i+1) - e_i`` of :func:`~verify.models.cradle.cradle_geometry`) and a corner (the unit
mass matrix and walls ``(-k, 1, 0)``, ``(-k, -1, 0)`` of
:func:`~verify.models.corner.corner_geometry`, ``k > 0``), both with fixed constraints.
Any other case raises :class:`Unsupported` with the reason.

>>> from verify.models.cradle import cradle_geometry
>>> from verify.records.results import case_record
>>> g, normals = cradle_geometry([1, 1, 1])
>>> s = scene_of(case_record("c", g, normals, ["1", "1"], ["100", "0", "0"]))
>>> type(s).__name__, [str(m) for m in s.masses], s.floats(s.velocity)
('Cradle', ['1', '1', '1'], [100.0, 0.0, 0.0])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from verify.models.corner import corner_geometry
from verify.models.cradle import cradle_geometry
from verify.numbers.numeric import certified_sign
from verify.numbers.parse import Number, to_number


class Unsupported(Exception):
    """A case that an engine cannot build (the message says why)."""


def _float(x: Number) -> float:
    """The nearest binary float of an exact number, for an engine's input (not an exact path)."""
    if isinstance(x, Fraction):
        return x.numerator / x.denominator  # int / int: correctly rounded
    import sympy as sp

    return float(sp.Float(sp.N(x, 40), 40))


def _same(a: Number, b: Number) -> bool:
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a == b
    return certified_sign(a - b) == 0


def _same_matrix(a: list[list[Number]], b: list[list[Number]]) -> bool:
    return len(a) == len(b) and all(len(x) == len(y) and all(map(_same, x, y)) for x, y in zip(a, b))


@dataclass(frozen=True)
class Cradle:
    """Balls of equal radius in a row along x, ball i touching ball i+1 (contact i, COR ``cors[i]``)."""

    masses: tuple[Number, ...]
    cors: tuple[Number, ...]
    velocity: tuple[Number, ...]  # along x, one per ball
    #: a fixed wall touching the last ball on its right (x = (N - 1) * 2 r + r with ball i at 2 r i): the last
    #: contact, ``cors[-1]``, is the last ball's with the wall (one more contact than ball pairs)
    wall: bool = False

    @staticmethod
    def floats(values: tuple[Number, ...] | list[Number]) -> list[float]:
        """The engine's inputs: the nearest floats of exact numbers."""
        return [_float(x) for x in values]


@dataclass(frozen=True)
class Corner:
    """A disk of unit mass (and unit moment of inertia) between the walls ``kx - y = 0`` (S1, COR
    ``cors[0]``) and ``kx + y = 0`` (S2, ``cors[1]``) of slope ``k = tan(alpha)``, admissible side
    ``x < -|y|/k`` (the corner opens towards negative x); velocity ``(vx, vy, omega)``."""

    slope: Number
    cors: tuple[Number, Number]
    velocity: tuple[Number, Number, Number]

    floats = staticmethod(Cradle.floats)


Scene = Cradle | Corner


def _numbers(case: dict[str, Any], field: str) -> list[Any]:
    value = case.get(field)
    if field == "time_terms" and value is None:
        return [Fraction(0)] * len(case.get("normals") or [])
    if not isinstance(value, list):
        raise Unsupported(f"{field}: expected a list")
    if value and isinstance(value[0], list):
        return [[to_number(x, where=f"{field}[{i}][{j}]") for j, x in enumerate(row)] for i, row in enumerate(value)]
    return [to_number(x, where=f"{field}[{i}]") for i, x in enumerate(value)]


def scene_of(case: dict[str, Any]) -> Scene:
    """The cradle or corner that a case record describes, exactly; :class:`Unsupported` otherwise.

    >>> from verify.models.corner import corner_geometry
    >>> from verify.records.results import case_record
    >>> g, normals = corner_geometry(Fraction(1, 2))
    >>> scene_of(case_record("k", g, normals, ["1/3", "2/3"], ["1", "-1/5", "0"])).slope
    Fraction(1, 2)
    """
    g, normals = _numbers(case, "mass_matrix"), _numbers(case, "normals")
    cors, velocity = _numbers(case, "restitution"), _numbers(case, "velocity")
    if any(certified_sign(c) != 0 for c in _numbers(case, "time_terms")):
        raise Unsupported("a moving constraint (a time term is not 0): engines' contacts here are fixed")
    n = len(g)
    diagonal = [g[i][i] for i in range(n)]
    cradle_g, cradle_normals = cradle_geometry(diagonal)
    if n >= 2 and _same_matrix(g, cradle_g) and _same_matrix(normals, cradle_normals):
        return Cradle(tuple(diagonal), tuple(cors), tuple(velocity))
    walled = cradle_geometry(diagonal, wall=True)[1]
    if n >= 1 and _same_matrix(g, cradle_g) and _same_matrix(normals, walled):
        return Cradle(tuple(diagonal), tuple(cors), tuple(velocity), wall=True)
    if n == 3 and len(normals) == 2 and len(normals[0]) == 3:
        k = -normals[0][0]
        corner_g, corner_normals = corner_geometry(k)
        if certified_sign(k) > 0 and _same_matrix(g, corner_g) and _same_matrix(normals, corner_normals):
            return Corner(k, (cors[0], cors[1]), (velocity[0], velocity[1], velocity[2]))
    raise Unsupported("neither a cradle nor a corner: an engine needs bodies, and only these two are built")


def documented(x: Any) -> Fraction:
    """An engine description's number (a JSON float, as the engine documents it: 0.2 is 1/5) exactly.

    >>> documented(0.2), documented(8)
    (Fraction(1, 5), Fraction(8, 1))
    """
    return Fraction(repr(x)) if isinstance(x, float) else Fraction(x)


def speed_scale(case: dict[str, Any]) -> list[Any]:
    """Per constraint, the rate of a unit normal speed (1 for a cradle; sqrt(1 + k^2) for a corner's walls)."""
    import sympy as sp

    scene = scene_of(case)
    if isinstance(scene, Corner):
        k = scene.slope
        k = sp.Rational(k.numerator, k.denominator) if isinstance(k, Fraction) else k
        return [sp.sqrt(1 + k**2)] * 2
    return [1] * len(case["normals"])
