"""What every engine's step model starts from: the contacts of a case in physical units and their gaps.

An engine steps time: at each step it detects the contacts (a gap at or below its own threshold), solves
them for impulses, then moves the bodies by ``time_step`` times their velocities. A model of an engine
does the same exactly: the case's constraints with unit normals (a rate is then a normal speed, in the
engine's units), the gaps start where the adapter puts the bodies (touching, less the ``overlap`` setting;
for a cradle, the engine's own float positions read exactly, since ``i * (2r - overlap)`` rounds for an
irrational ``r``), and each step moves every gap by ``time_step`` times its rate. Every sign is decided
exactly, in the number field of the case.

>>> from verify.models.cradle import cradle_geometry
>>> from verify.records.results import case_record
>>> g, normals = cradle_geometry([1, 1, 1])
>>> c = contacts_of(case_record("c", g, normals, ["1", "1"], ["100", "0", "0"]), radius=1.0)
>>> [str(x) for x in c.gaps], [str(x) for x in c.system.rates(c.velocity)]
(['0', '0'], ['-100', '0'])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from itertools import permutations
from typing import Any

from verify.engines.scene import Corner, Cradle, scene_of, speed_scale


@dataclass
class Contacts:
    """A case as an engine's contacts: the system with unit normals over an exact backend ``K``, the velocity,
    each contact's gap, and whether the contact is a ball's with a plane (a wall) rather than with a ball."""

    K: Any
    system: Any
    velocity: tuple[Any, ...]
    gaps: list[Any]
    planes: list[bool]

    def push(self, v: Sequence[Any], i: int, impulse: Any) -> tuple[Any, ...]:
        """The velocity after an impulse ``impulse`` along contact ``i``."""
        return tuple(a + impulse * u for a, u in zip(v, self.system.U[i]))

    def move(self, v: Sequence[Any], dt: Any) -> None:
        """One step of the bodies at velocity ``v``: each gap grows by ``dt`` times its rate."""
        self.gaps = [g + dt * w for g, w in zip(self.gaps, self.system.rates(v))]


def contacts_of(case: dict[str, Any], *, radius: float | None = None, overlap: float = 0.0) -> Contacts:
    """The contacts of a cradle or corner case (:func:`~verify.engines.scene.scene_of`); ``radius``: the
    adapter's ball radius (a float), whose layout ``i * (2r - overlap)`` gives a cradle's first gaps exactly;
    ``overlap``: the adapter's setting (every gap starts at minus it otherwise)."""
    from verify.dynamics.system import System
    from verify.numbers.backends import exact_for
    from verify.numbers.parse import to_number

    scene = scene_of(case)
    scale = [to_number(str(s)) for s in speed_scale(case)]
    g = [[to_number(x) for x in row] for row in case["mass_matrix"]]
    normals = [[to_number(x) / s for x in row] for row, s in zip(case["normals"], scale)]
    velocity = [to_number(x) for x in case["velocity"]]
    cors = [to_number(x) for x in case["restitution"]]
    K = exact_for([x for row in normals for x in row] + velocity + cors)
    system = System(g, normals, cors, None, backend=K)
    r = system.r
    gaps = [K.convert(-Fraction(overlap))] * r
    planes = [isinstance(scene, Corner)] * r
    if isinstance(scene, Cradle):
        planes[-1] = scene.wall
        if radius is not None:
            gaps = [K.convert(x) for x in _cradle_gaps(len(scene.masses), radius, scene.wall, overlap)]
    return Contacts(K, system, system.velocity(velocity), gaps, planes)


def _cradle_gaps(n: int, radius: float, wall: bool, overlap: float = 0.0) -> list[Fraction]:
    """The first gaps of an adapter's cradle, exactly: ball ``i`` at the float ``i * (2 r - overlap)``, the
    wall's face at the float ``(n - 1) * (2 r - overlap) + r - overlap`` (what the adapters build)."""
    pitch = 2 * radius - overlap
    x = [Fraction(i * pitch) for i in range(n)]
    r = Fraction(radius)
    gaps = [x[i + 1] - x[i] - 2 * r for i in range(n - 1)]
    if wall:
        gaps.append(Fraction((n - 1) * pitch + radius - overlap) - x[-1] - r)
    return gaps


#: up to this many contacts every order of the solver is tried; beyond, the order given and its reverse
ALL_ORDERS = 5


def orders(r: int) -> list[tuple[int, ...]]:
    """The contact orders a model tries on ``r`` contacts (the engines do not document theirs).

    >>> len(orders(5)), orders(6)[1]
    (120, (5, 4, 3, 2, 1, 0))
    """
    if r <= ALL_ORDERS:
        return list(permutations(range(r)))
    return [tuple(range(r)), tuple(reversed(range(r)))]


def check_order(order: Any, r: int) -> tuple[int, ...]:
    """A contact order given to a model: a permutation of the case's ``r`` contacts (0 .. r - 1, the case's
    order of constraints, a cradle's wall last); anything else is a :class:`ValueError`.

    >>> check_order((1, 0), 2)
    (1, 0)
    """
    whole = isinstance(order, (tuple, list)) and all(isinstance(i, int) and not isinstance(i, bool) for i in order)
    if not whole or sorted(order) != list(range(r)):
        raise ValueError(f"a contact order is a permutation of 0..{r - 1} (the case's contacts), got {order!r}")
    return tuple(order)
