"""Box2D's step loop (2.3, as pybox2d runs it), exactly: warm-started sequential impulses with a velocity
threshold, then position correction.

What ``b2World::Step`` does at each step (``Box2D/Dynamics/b2Island.cpp``,
``Box2D/Dynamics/Contacts/b2ContactSolver.cpp``, constants of ``Box2D/Common/b2Settings.h``):

- a contact touches when its gap is at most 0 (``b2CollideCircles``, ``b2CollideEdgeAndCircle``); a contact
  that touched in the step before keeps its accumulated impulse and applies it first (warm starting);
- each contact's velocity bias is ``-e * vRel`` when it approaches faster than ``b2_velocityThreshold = 1``
  at the start of the step, else 0; ``velocity_iterations`` sweeps over the contacts in the island's order,
  each impulse accumulated and clamped at 0;
- the bodies move by ``time_step`` times their velocities, then ``position_iterations`` sweeps of position
  correction: each contact's separation ``s`` is pushed by ``-b2_baumgarte * (s + b2_linearSlop)`` (at most
  ``b2_maxLinearCorrection``), stopping once no separation is below ``-3 b2_linearSlop``; positions only;
- the loop ends when a step applies no impulse and no contact approaches, or after ``max_time``.

The island's order of the contacts (built from the world's lists, newest first) is named by the model.
Box2D's cap on a step's translation (``b2_maxTranslation = 2``, which scales a faster body's velocity) is
not modelled: the record's speeds stay below it (100 m/s moves 1.67 m in a step of 1/60 s).
With ``bullet`` (the adapter's default) each step ends with Box2D's continuous collision
(:mod:`~verify.engines.models.toi`): a pair that the step took deeper than ``3 b2_linearSlop`` is stopped at
its time of impact and solved again over the rest of the step.

>>> from verify.models.cradle import cradle_geometry
>>> from verify.records.results import case_record
>>> g, normals = cradle_geometry([1, 1, 1])
>>> v = Box2D().run(case_record("c", g, normals, ["1", "1"], ["100", "0", "0"]), (0, 1))
>>> [x[:9] for x in v]
['-33.33129', '66.665649', '66.665649']
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.engines.models.steps import Contacts, check_order, contacts_of, orders
from verify.engines.models.toi import MAX_CORRECTION, SLOP, Bodies
from verify.engines.scene import Corner, scene_of

BAUMGARTE = Fraction(1, 5)  #: b2_baumgarte

Order = tuple[int, ...]


class Box2D:
    """Box2D 2.3's steps (pybox2d; gravity, sleep and friction off).

    ``settings``: an engine's settings as the record holds them (``time_step``, ``velocity_iterations``,
    ``position_iterations``, ``warm_starting``, ``bullet``, ``max_time``, ``radius``, ``overlap``; the
    adapter's defaults otherwise). A variant is the island's order of the contacts, a permutation of the
    case's contacts (:meth:`variants`). :meth:`run` returns the exit velocity as 30-digit decimals of the
    exact one.
    """

    name = "Box2D's steps"

    def __init__(self, settings: dict[str, Any] | None = None):
        from verify.engines.common import step_count
        from verify.engines.scene import documented

        s = settings or {}
        self.dt = documented(s.get("time_step", 1 / 60))
        self.sweeps = int(s.get("velocity_iterations", 8))
        self.corrections = int(s.get("position_iterations", 3))
        self.warm = bool(s.get("warm_starting", 1))
        self.bullet = bool(s.get("bullet", 1))
        self.steps = step_count(float(s.get("max_time", 1.0)), float(s.get("time_step", 1 / 60)))
        self.radius = float(s.get("radius", 1.0))
        self.overlap = float(s.get("overlap", 0.0))

    def label(self, variant: Order) -> str:
        """The model in words, with its settings."""
        from verify.numbers.format import format_decimal

        return (
            f"{self.name}: sequential impulses, {self.sweeps} sweeps, threshold 1, warm start "
            f"{'on' if self.warm else 'off'}, {self.corrections} position sweeps, time of impact "
            f"{'on' if self.bullet else 'off'}, time step "
            f"{format_decimal(self.dt, 6)}, contact order {', '.join(map(str, variant))}"
        )

    def variants(self, r: int) -> list[Order]:
        """The island orders to try on ``r`` contacts."""
        return orders(r)

    def run(self, case: dict[str, Any], variant: Order) -> list[str]:
        """The exit velocity (30-digit decimals of the exact one) of the model on a case record."""
        from verify.engines.models.toi import solve_toi, velocity_sweeps

        c = contacts_of(case, radius=self.radius, overlap=self.overlap)
        variant = check_order(variant, c.system.r)
        K, s = c.K, c.system
        cv = K.convert
        bodies = _bodies(case, c)
        q = [K.zero] * s.n  # the positions, from where the adapter puts the bodies
        impulse = [K.zero] * s.r
        v = c.velocity
        for _ in range(self.steps):
            c.gaps = bodies.gaps(q)
            touching = [i for i in variant if K.sign(c.gaps[i]) <= 0]
            impulse = [impulse[i] if i in touching and self.warm else K.zero for i in range(s.r)]
            v = velocity_sweeps(s, v, touching, impulse=impulse, sweeps=self.sweeps)
            start = list(q)
            q = [x + cv(self.dt) * w for x, w in zip(q, v)]
            q = _correct(bodies, q, touching, self.corrections)
            hit = False
            if self.bullet:
                bodies.sweep(start, q)
                v, hit = solve_toi(bodies, v, variant, cv(self.dt), self.sweeps)
                q = bodies.positions()
            if not hit and all(K.sign(p) == 0 for p in impulse) and all(K.sign(w) >= 0 for w in s.rates(v)):
                break
        return [K.to_decimal(x, 30) for x in v]


def _bodies(case: dict[str, Any], c: Contacts) -> Bodies:
    """The case's bodies: a cradle's balls (a coordinate each), or the corner's disk (all three)."""
    scene = scene_of(case)
    n = c.system.n
    coordinates = [list(range(n))] if isinstance(scene, Corner) else [[k] for k in range(n)]
    K = c.K
    touched = [
        [b for b, ks in enumerate(coordinates) if any(not K.known_zero(row[k]) for k in ks)] for row in c.system.normals
    ]
    return Bodies(K, c.system, list(c.gaps), coordinates, touched)


def _correct(bodies: Bodies, q: list[Any], contacts: list[int], sweeps: int) -> list[Any]:
    """Box2D's position correction (``b2ContactSolver::SolvePositionConstraints``): the positions after it."""
    K, s = bodies.K, bodies.system
    cv = K.convert
    for _ in range(sweeps):
        lowest = K.zero
        for i in contacts:
            separation = bodies.gaps(q)[i]
            lowest = separation if K.sign(separation - lowest) < 0 else lowest
            push = cv(BAUMGARTE) * (separation + cv(SLOP))
            push = K.zero if K.sign(push) > 0 else push
            push = K.zero - cv(MAX_CORRECTION) if K.sign(push + cv(MAX_CORRECTION)) < 0 else push
            if K.sign(push) != 0:
                amount = (K.zero - push) / s.gram[i][i]
                q = [x + amount * u for x, u in zip(q, s.U[i])]
        if K.sign(lowest + 3 * cv(SLOP)) >= 0:
            break
    return q
