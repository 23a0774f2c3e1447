"""Box2D's continuous collision (``b2World::SolveTOI``, Box2D 2.3) on a model's bodies, exactly.

After the discrete step every body has swept from ``c0`` (at its time ``alpha0`` of the step, 0 at first)
to ``c``. For each contact with a bullet (every dynamic body of the adapters is one) the time of impact is
when the gap, linear along the two sweeps, reaches ``-3 b2_linearSlop`` (``b2TimeOfImpact``'s target; the
engine finds it to within ``b2_linearSlop / 4``, the model exactly); a gap already within that of the
target at the start is an impact at once, one still within it at the end is none. The earliest impact
(before ``1 - 10 b2_epsilon``, at most ``b2_maxSubSteps`` per contact) moves its two bodies back to it; if
the contact then touches, an island of those two bodies, the contact and each other touching contact of
theirs (their other bodies moved back too) gets a sub-step over the rest of the step: position correction
of the two bodies (``b2_toiBaugarte = 0.75``, up to 20 sweeps), then the restitution targets and
``velocity_iterations`` sweeps without warm starting, then the island's bodies move on. The search repeats
until no impact is left.

>>> TOI_TARGET, TOLERANCE
(Fraction(-3, 200), Fraction(1, 800))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

SLOP = Fraction(1, 200)  #: b2_linearSlop
TOI_TARGET = -3 * SLOP  #: the gap b2TimeOfImpact stops a pair at
TOLERANCE = SLOP / 4  #: b2TimeOfImpact's tolerance on the distance
TOI_BAUMGARTE = Fraction(3, 4)  #: b2_toiBaugarte
MAX_CORRECTION = Fraction(1, 5)  #: b2_maxLinearCorrection
POSITION_SWEEPS = 20  #: the TOI sub-step's position iterations
MAX_SUB_STEPS = 8  #: b2_maxSubSteps
EPSILON = Fraction(2) ** -23  #: b2_epsilon (FLT_EPSILON)
THRESHOLD = Fraction(1)  #: b2_velocityThreshold


@dataclass
class Bodies:
    """The model's bodies: each one's coordinates of the case, its sweep (start ``c0`` at time ``alpha0``,
    end ``c``), and each contact's bodies (the dynamic ones: a wall is static)."""

    K: Any
    system: Any
    gaps0: list[Any]  #: each contact's gap at positions 0
    coordinates: list[list[int]]
    contact_bodies: list[list[int]]
    c0: list[list[Any]] = field(default_factory=list)
    c: list[list[Any]] = field(default_factory=list)
    alpha0: list[Any] = field(default_factory=list)

    def gaps(self, q: list[Any]) -> list[Any]:
        """Every contact's gap at positions ``q`` (of the case's coordinates)."""
        K = self.K
        return [g + sum((a * x for a, x in zip(n, q)), K.zero) for g, n in zip(self.gaps0, self.system.normals)]

    def sweep(self, start: list[Any], end: list[Any]) -> None:
        """The discrete step's sweeps: every body from ``start`` (at time 0) to ``end``."""
        self.c0 = [[start[k] for k in ks] for ks in self.coordinates]
        self.c = [[end[k] for k in ks] for ks in self.coordinates]
        self.alpha0 = [self.K.zero] * len(self.coordinates)

    def positions(self) -> list[Any]:
        """The positions at the end of the sweeps."""
        q = [self.K.zero] * self.system.n
        for ks, values in zip(self.coordinates, self.c):
            for k, x in zip(ks, values):
                q[k] = x
        return q

    def gap(self, i: int, where: dict[int, list[Any]]) -> Any:
        """Contact ``i``'s gap with its bodies at ``where`` (body -> its coordinates' values)."""
        n = self.system.normals[i]
        total = self.gaps0[i]
        for b in self.contact_bodies[i]:
            for k, x in zip(self.coordinates[b], where[b]):
                total = total + n[k] * x
        return total

    def at(self, b: int, alpha: Any) -> list[Any]:
        """Body ``b``'s position at time ``alpha`` of its sweep."""
        K = self.K
        beta = (alpha - self.alpha0[b]) / (K.one - self.alpha0[b])
        return [a + beta * (e - a) for a, e in zip(self.c0[b], self.c[b])]

    def advance(self, b: int, alpha: Any) -> None:
        """``b2Body::Advance``: the body moved back to ``alpha``, its sweep starting there."""
        self.c0[b] = self.at(b, alpha)
        self.c[b] = list(self.c0[b])
        self.alpha0[b] = alpha


def solve_toi(bodies: Bodies, v: tuple[Any, ...], order: tuple[int, ...], dt: Any, sweeps: int) -> tuple[Any, bool]:
    """Box2D's TOI events after a discrete step (the sweeps set in ``bodies``); the velocity after them and
    whether any impulse was applied."""
    K, s = bodies.K, bodies.system
    cv = K.convert
    count = [0] * s.r
    cached: dict[int, Any] = {}
    pushed = False
    while True:
        best, alpha_min = None, K.one
        for i in order:
            if count[i] > MAX_SUB_STEPS or not bodies.contact_bodies[i]:
                continue
            if i not in cached:
                cached[i] = _time_of_impact(bodies, i)
            if K.sign(cached[i] - alpha_min) < 0:
                best, alpha_min = i, cached[i]
        if best is None or K.sign(alpha_min - (K.one - 10 * cv(EPSILON))) >= 0:
            return v, pushed
        pair = bodies.contact_bodies[best]
        saved = {b: (bodies.c0[b], bodies.c[b], bodies.alpha0[b]) for b in pair}
        for b in pair:
            bodies.advance(b, alpha_min)
        count[best] += 1
        cached.pop(best)
        where = {b: bodies.c[b] for b in range(len(bodies.coordinates))}
        if K.sign(bodies.gap(best, where)) > 0:  # not touching at the impact: the sweeps restored
            for b, (a, e, t) in saved.items():
                bodies.c0[b], bodies.c[b], bodies.alpha0[b] = a, e, t
            continue
        island, members = [best], list(pair)
        for b in pair:
            for j in order:
                if j in island or b not in bodies.contact_bodies[j]:
                    continue
                others = [o for o in bodies.contact_bodies[j] if o not in members]
                kept = {o: (bodies.c0[o], bodies.c[o], bodies.alpha0[o]) for o in others}
                for o in others:
                    bodies.advance(o, alpha_min)
                where = {k: bodies.c[k] for k in range(len(bodies.coordinates))}
                if K.sign(bodies.gap(j, where)) > 0:
                    for o, (a, e, t) in kept.items():
                        bodies.c0[o], bodies.c[o], bodies.alpha0[o] = a, e, t
                    continue
                island.append(j)
                members += others
        v, hit = _sub_step(bodies, v, island, pair=pair, members=members, h=(K.one - alpha_min) * dt, sweeps=sweeps)
        pushed = pushed or hit
        for j in list(cached):
            if any(b in members for b in bodies.contact_bodies[j]):
                cached.pop(j)


def velocity_sweeps(s: Any, v: tuple[Any, ...], contacts: list[int], *, impulse: Any, sweeps: int) -> tuple[Any, ...]:
    """Box2D's velocity solve (``b2ContactSolver``): each contact's bias ``-e vRel`` when it approaches faster
    than ``b2_velocityThreshold``, the accumulated impulses in ``impulse`` applied first (warm starting),
    then ``sweeps`` sweeps of clamped impulses; the velocity after them."""
    K = s.backend
    rates = s.rates(v)
    bias = {}
    for i in contacts:
        fast = K.sign(rates[i] + K.convert(THRESHOLD)) < 0
        bias[i] = K.zero - s.restitution[i] * rates[i] if fast else K.zero
        if K.sign(impulse[i]) != 0:
            v = tuple(a + impulse[i] * u for a, u in zip(v, s.U[i]))
    for _ in range(sweeps):
        for i in contacts:
            delta = (bias[i] - s.rates(v)[i]) / s.gram[i][i]
            if K.sign(impulse[i] + delta) < 0:
                delta = K.zero - impulse[i]
            impulse[i] = impulse[i] + delta
            if K.sign(delta) != 0:
                v = tuple(a + delta * u for a, u in zip(v, s.U[i]))
    return v


def _time_of_impact(bodies: Bodies, i: int) -> Any:
    """The contact's time of impact in the step (1: none), both sweeps put on the later start."""
    K = bodies.K
    cv = K.convert
    pair = bodies.contact_bodies[i]
    alpha0 = max(bodies.alpha0[b] for b in pair) if len(pair) > 1 else bodies.alpha0[pair[0]]
    if len(pair) > 1:
        for b in pair:
            if K.sign(bodies.alpha0[b] - alpha0) < 0:
                bodies.c0[b] = bodies.at(b, alpha0)
                bodies.alpha0[b] = alpha0
    start = bodies.gap(i, {b: bodies.c0[b] for b in pair})
    end = bodies.gap(i, {b: bodies.c[b] for b in pair})
    if K.sign(start - cv(TOI_TARGET + TOLERANCE)) < 0:
        beta = K.zero
    elif K.sign(end - cv(TOI_TARGET - TOLERANCE)) > 0:  # within the tolerance at the end: Box2D goes to 1
        return K.one
    else:
        beta = (start - cv(TOI_TARGET)) / (start - end)
    alpha = alpha0 + (K.one - alpha0) * beta
    return alpha if K.sign(alpha - K.one) < 0 else K.one


def _sub_step(
    bodies: Bodies, v: tuple[Any, ...], island: list[int], *, pair: list[int], members: list[int], h: Any, sweeps: int
) -> tuple[tuple[Any, ...], bool]:
    """``b2Island::SolveTOI``: the two bodies' positions corrected, the island's velocities solved, its bodies
    moved on by ``h``."""
    K, s = bodies.K, bodies.system
    cv = K.convert
    moving = {k for b in pair for k in bodies.coordinates[b]}
    for _ in range(POSITION_SWEEPS):
        lowest = K.zero
        for i in island:
            where = {b: bodies.c[b] for b in range(len(bodies.coordinates))}
            separation = bodies.gap(i, where)
            lowest = separation if K.sign(separation - lowest) < 0 else lowest
            push = cv(TOI_BAUMGARTE) * (separation + cv(SLOP))
            push = K.zero if K.sign(push) > 0 else push
            push = K.zero - cv(MAX_CORRECTION) if K.sign(push + cv(MAX_CORRECTION)) < 0 else push
            u = [x if k in moving else K.zero for k, x in enumerate(s.U[i])]
            stiffness = sum((a * b for a, b in zip(s.normals[i], u)), K.zero)
            if K.sign(push) != 0 and K.sign(stiffness) > 0:
                amount = (K.zero - push) / stiffness
                for b in pair:
                    bodies.c[b] = [x + amount * u[k] for k, x in zip(bodies.coordinates[b], bodies.c[b])]
        if K.sign(lowest + cv(Fraction(3, 2) * SLOP)) >= 0:
            break
    for b in pair:
        bodies.c0[b] = list(bodies.c[b])
    impulse = dict.fromkeys(island, K.zero)
    v = velocity_sweeps(s, v, island, impulse=impulse, sweeps=sweeps)
    for b in members:
        bodies.c[b] = [x + h * v[k] for k, x in zip(bodies.coordinates[b], bodies.c[b])]
    return v, any(K.sign(p) != 0 for p in impulse.values())
