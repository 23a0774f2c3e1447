"""Bullet's step loop as pybullet runs it, exactly: sequential impulses with slop, warm starting and a
residual stop.

What ``btSequentialImpulseConstraintSolver`` does at each step, with pybullet's settings
(``examples/SharedMemory/PhysicsServerCommandProcessor.cpp``: ``m_erp2 = 0.08``, ``m_linearSlop = 1e-5``,
``m_numIterations = 50``, ``m_warmstartingFactor = 0.1``, ``m_leastSquaresResidualThreshold = 1e-7``) and
Bullet's own (``gContactBreakingThreshold = 0.02`` times the sphere's radius, ``restitutionCurve``):

- a ball-ball contact point is made when the gap is at most 0 and kept while it is at most the breaking
  threshold; a ball-plane point exists while the gap is below it (a speculative contact);
- each point's target: ``e * (-v_n)`` when ``|v_n|`` is at least ``restitution_velocity_threshold`` (else 0,
  and never below 0), minus ``(gap + slop) / time_step`` when that is positive, or plus ``ERP2 / time_step``
  times the penetration beyond the slop;
- warm starting applies ``0.1`` of the point's last impulse first; then sweeps over the points in the
  solver's order, each impulse accumulated and clamped at 0, stop when the largest squared residual of a
  sweep is at most ``1e-7`` (or after ``solver_iterations`` sweeps);
- the bodies move by ``time_step`` times their velocities; the loop ends when a step changes no velocity and
  no contact approaches, or after ``max_time``.

The solver's order of the points is that of the dispatcher's manifolds (not documented): the model names it.

>>> from verify.models.cradle import cradle_geometry
>>> from verify.records.results import case_record
>>> g, normals = cradle_geometry([1, 1, 1])
>>> v = Bullet().run(case_record("c", g, normals, ["1", "1"], ["100", "0", "0"]), (1, 0))
>>> [x[:12] for x in v]
['-33.33092538', '66.665461739', '66.665463646']
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.engines.models.steps import Contacts, contacts_of

ERP2 = Fraction(2, 25)  #: pybullet's m_erp2 (0.08)
WARM = Fraction(1, 10)  #: pybullet's m_warmstartingFactor
RESIDUAL = Fraction(1, 10**7)  #: pybullet's m_leastSquaresResidualThreshold
SPLIT = Fraction(-4, 100)  #: Bullet's m_splitImpulsePenetrationThreshold (m_splitImpulse is on)
RADIUS = math.sqrt(2.5)  #: the adapter's spheres (verify.engines.adapters.pybullet.RADIUS)
#: gContactBreakingThreshold (0.02) times the sphere's angular motion disc (its radius), squared, exactly
BREAKING_SQUARED = Fraction(2, 100) ** 2 * Fraction(5, 2)

Order = tuple[int, ...]


class Bullet:
    """Bullet's steps as pybullet 3 runs them (maximal coordinates, gravity and damping off)."""

    name = "Bullet's steps"

    def __init__(self, settings: dict[str, Any] | None = None):
        from verify.engines.explain import documented

        s = settings or {}
        self.dt = documented(s.get("time_step", 1 / 240))
        self.sweeps = int(s.get("solver_iterations", 50))
        self.threshold = documented(s.get("restitution_velocity_threshold", 0.2))
        self.slop = documented(s.get("contact_slop", 1e-05))
        self.steps = int(documented(s.get("max_time", 0.2)) / self.dt)

    def label(self, variant: Order) -> str:
        """The model in words, with its settings."""
        from verify.numbers.format import format_decimal

        return (
            f"{self.name}: sequential impulses, {self.sweeps} sweeps, slop {format_decimal(self.slop, 6)}, split "
            f"impulse, warm start 0.1 on planes, residual 1e-7, threshold {format_decimal(self.threshold, 6)}, "
            f"time step {format_decimal(self.dt, 6)}, contact order {', '.join(map(str, variant))}"
        )

    def variants(self, r: int) -> list[Order]:
        """The solver orders to try on ``r`` contacts (:func:`~verify.engines.models.orders`)."""
        from verify.engines.models import orders

        return orders(r)

    def run(self, case: dict[str, Any], variant: Order) -> list[str]:
        """The exit velocity (30-digit decimals of the exact one) of the model on a case record."""
        c = contacts_of(case, radius=RADIUS)
        K, s = c.K, c.system
        cv = K.convert
        dt, r = cv(self.dt), s.r
        held = [False] * r
        impulse = [K.zero] * r
        v = c.velocity
        for _ in range(self.steps):
            for i, gap in enumerate(c.gaps):
                inside = K.sign(gap * gap - cv(BREAKING_SQUARED))  # against the breaking threshold
                if c.planes[i]:  # a plane's point exists while the gap is below the threshold
                    held[i] = K.sign(gap) <= 0 or inside < 0
                else:  # a ball's is made at gap 0 and kept up to the threshold
                    held[i] = K.sign(gap) <= 0 or (held[i] and inside <= 0)
                if not held[i]:
                    impulse[i] = K.zero
            points = [i for i in variant if held[i]]
            rates = s.rates(v)
            rhs, push_rhs = {}, {}
            for i in points:
                velocity_target, push_target = self._targets(K, s.restitution[i], rates[i], c.gaps[i] + cv(self.slop))
                rhs[i] = (velocity_target - rates[i]) / s.gram[i][i]
                if push_target is not None:
                    push_rhs[i] = push_target / s.gram[i][i]
            # the split impulse first: deep penetrations are pushed out in position only, by sweeps of their own
            still = (K.zero,) * s.n
            push = _sweeps(
                c, [i for i in points if i in push_rhs], still, still, rhs=push_rhs, impulse={}, sweeps=self.sweeps
            )
            w = v
            for i in points:  # warm starting
                impulse[i] = impulse[i] * cv(WARM) if c.planes[i] else K.zero  # measured: none between balls
                if K.sign(impulse[i]) != 0:
                    w = c.push(w, i, impulse[i])
            w = _sweeps(c, points, v, w, rhs=rhs, impulse=impulse, sweeps=self.sweeps)
            changed = any(K.sign(a - b) != 0 for a, b in zip(w, v))
            v = w
            c.move(tuple(a + b for a, b in zip(v, push)), dt)
            if not changed and all(K.sign(x) >= 0 for x in s.rates(v)):
                break
        return [K.to_decimal(x, 30) for x in v]

    def _targets(self, K: Any, e: Any, rate: Any, depth: Any) -> tuple[Any, Any]:
        """A point's target normal speed (restitution, less the speculative gap or plus the error reduction),
        and, for a penetration deeper than the split impulse's threshold, the push speed that corrects it in
        position only (None otherwise)."""
        cv = K.convert
        speed = rate if K.sign(rate) >= 0 else K.zero - rate
        bounce = e * (K.zero - rate) if K.sign(speed - cv(self.threshold)) >= 0 else K.zero
        bounce = bounce if K.sign(bounce) > 0 else K.zero
        if K.sign(depth) > 0:
            return bounce - depth / cv(self.dt), None
        correction = (K.zero - depth) * cv(ERP2) / cv(self.dt)
        if K.sign(depth - cv(SPLIT)) > 0:
            return bounce + correction, None
        return bounce, correction


def _sweeps(
    c: Contacts, points: list[int], base: Sequence[Any], start: Sequence[Any], *, rhs: dict[int, Any],
    impulse: dict[int, Any] | list[Any], sweeps: int,
) -> tuple[Any, ...]:  # fmt: skip
    """Bullet's Gauss-Seidel sweeps from the velocity ``start``: each point's impulse (accumulated in
    ``impulse``, clamped at 0) moves its rate, measured from ``base``, towards ``rhs`` times its Delassus
    entry; they stop when a sweep's largest squared residual is at most ``RESIDUAL``, or after ``sweeps``."""
    K, s = c.K, c.system
    before = s.rates(base)
    w = tuple(start)
    for _ in range(sweeps):
        worst = K.zero
        for i in points:
            delta = rhs[i] - (s.rates(w)[i] - before[i]) / s.gram[i][i]
            held = impulse[i] if isinstance(impulse, list) or i in impulse else K.zero
            if K.sign(held + delta) < 0:
                delta = K.zero - held
            impulse[i] = held + delta
            if K.sign(delta) != 0:
                w = c.push(w, i, delta)
            residual = delta * s.gram[i][i]
            worst = residual * residual if K.sign(residual * residual - worst) > 0 else worst
        if K.sign(worst - K.convert(RESIDUAL)) <= 0:
            break
    return w
