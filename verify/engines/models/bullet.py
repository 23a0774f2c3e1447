"""Bullet's step loop as pybullet runs it, exactly: sequential impulses with slop, warm starting and a
residual stop.

What ``btSequentialImpulseConstraintSolver`` does at each step, with pybullet's settings
(``examples/SharedMemory/PhysicsServerCommandProcessor.cpp``: ``m_erp2 = 0.08``, ``m_linearSlop = 1e-5``,
``m_numIterations = 50``, ``m_warmstartingFactor = 0.1``, ``m_leastSquaresResidualThreshold = 1e-7``) and
Bullet's own (``gContactBreakingThreshold = 0.02`` times the sphere's radius, ``restitutionCurve``):

- a ball-ball contact point exists while the gap is at most 0, and only for that step: Bullet clears a
  sphere-sphere manifold every step (``#define CLEAR_MANIFOLD 1`` in ``btSphereSphereCollisionAlgorithm.cpp``,
  "it disables warmstarting"); a ball-plane point exists while the gap is below the breaking threshold (a
  speculative contact) and keeps its impulse from step to step;
- each point's target: ``e * (-v_n)`` when ``|v_n|`` is at least ``restitution_velocity_threshold`` (else 0,
  and never below 0), minus ``(gap + slop) / time_step`` when that is positive, or plus ``ERP2 / time_step``
  times the penetration beyond the slop;
- warm starting applies ``0.1`` of a kept point's last impulse first; then sweeps over the points in the
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

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.engines.adapters.pybullet import RADIUS
from verify.engines.models.steps import Contacts, check_order, contacts_of, orders

ERP2 = Fraction(2, 25)  #: pybullet's m_erp2 (0.08)
WARM = Fraction(1, 10)  #: pybullet's m_warmstartingFactor
RESIDUAL = Fraction(1, 10**7)  #: pybullet's m_leastSquaresResidualThreshold
SPLIT = Fraction(-4, 100)  #: Bullet's m_splitImpulsePenetrationThreshold (m_splitImpulse is on)
#: gContactBreakingThreshold (0.02) times the sphere's angular motion disc (the adapter's float radius), squared
BREAKING_SQUARED = (Fraction(2, 100) * Fraction(RADIUS)) ** 2

Order = tuple[int, ...]


class Bullet:
    """Bullet's steps as pybullet 3 runs them (maximal coordinates, gravity and damping off).

    ``settings``: an engine's settings as the record holds them (``time_step``, ``solver_iterations``,
    ``restitution_velocity_threshold``, ``contact_slop``, ``max_time``, ``overlap``; pybullet's defaults
    otherwise). A variant is the solver's order of the contacts, a permutation of the case's contacts
    (:meth:`variants`). :meth:`run` returns the exit velocity as 30-digit decimals of the exact one.
    """

    name = "Bullet's steps"

    def __init__(self, settings: dict[str, Any] | None = None):
        from verify.engines.common import step_count
        from verify.engines.scene import documented

        s = settings or {}
        self.dt = documented(s.get("time_step", 1 / 240))
        self.sweeps = int(s.get("solver_iterations", 50))
        self.threshold = documented(s.get("restitution_velocity_threshold", 0.2))
        self.slop = documented(s.get("contact_slop", 1e-05))
        self.steps = step_count(float(s.get("max_time", 0.2)), float(s.get("time_step", 1 / 240)), slack=0.0)
        self.overlap = float(s.get("overlap", 0.0))

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
        return orders(r)

    def run(self, case: dict[str, Any], variant: Order) -> list[str]:
        """The exit velocity (30-digit decimals of the exact one) of the model on a case record."""
        c = contacts_of(case, radius=RADIUS, overlap=self.overlap)
        variant = check_order(variant, c.system.r)
        K, s = c.K, c.system
        cv = K.convert
        dt = cv(self.dt)
        impulse = dict.fromkeys(range(s.r), K.zero)
        v = c.velocity
        for _ in range(self.steps):
            points = []
            for i in variant:
                gap = c.gaps[i]
                # a plane's point exists while the gap is below the breaking threshold; a ball's while it is <= 0
                near = c.planes[i] and K.sign(gap * gap - cv(BREAKING_SQUARED)) < 0
                if K.sign(gap) <= 0 or near:
                    points.append(i)
                else:
                    impulse[i] = K.zero
            rates = s.rates(v)
            rhs, push_rhs = {}, {}
            for i in points:
                penetration = c.gaps[i] + cv(self.slop)  # Bullet's name: positive when apart
                velocity_target, push_target = self._targets(K, s.restitution[i], rates[i], penetration)
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
                impulse[i] = impulse[i] * cv(WARM) if c.planes[i] else K.zero  # a ball's point is new every step
                if K.sign(impulse[i]) != 0:
                    w = c.push(w, i, impulse[i])
            w = _sweeps(c, points, v, w, rhs=rhs, impulse=impulse, sweeps=self.sweeps)
            changed = any(K.sign(a - b) != 0 for a, b in zip(w, v))
            v = w
            c.move(tuple(a + b for a, b in zip(v, push)), dt)
            if not changed and all(K.sign(x) >= 0 for x in s.rates(v)):
                break
        return [K.to_decimal(x, 30) for x in v]

    def _targets(self, K: Any, e: Any, rate: Any, penetration: Any) -> tuple[Any, Any]:
        """A point's target normal speed (restitution, less the speculative gap or plus the error reduction),
        and, for a penetration deeper than the split impulse's threshold, the push speed that corrects it in
        position only (None otherwise)."""
        cv = K.convert
        speed = rate if K.sign(rate) >= 0 else K.zero - rate
        bounce = e * (K.zero - rate) if K.sign(speed - cv(self.threshold)) >= 0 else K.zero
        bounce = bounce if K.sign(bounce) > 0 else K.zero
        if K.sign(penetration) > 0:
            return bounce - penetration / cv(self.dt), None
        correction = (K.zero - penetration) * cv(ERP2) / cv(self.dt)
        if K.sign(penetration - cv(SPLIT)) > 0:
            return bounce + correction, None
        return bounce, correction


def _sweeps(
    c: Contacts, points: list[int], base: Sequence[Any], start: Sequence[Any], *, rhs: dict[int, Any],
    impulse: dict[int, Any], sweeps: int,
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
            held = impulse.get(i, K.zero)
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
