"""PyBullet (Bullet 3, sequential-impulse solver) as an implementation under test.

Engine: ``pybullet`` (pip ``pybullet``), checked with 3.2.7, run in ``DIRECT`` mode with a fresh
physics client per case (disconnected after it).

Combine rule: the product. ``btManifoldResult::calculateCombinedRestitution`` returns
``body0->getRestitution() * body1->getRestitution()``
(``src/BulletCollision/CollisionDispatch/btManifoldResult.cpp`` in bullet3); the solver then aims at a
separating normal velocity ``combined * -v_n`` for a contact approaching at ``v_n``, and at 0 when
``|v_n|`` is below ``restitutionVelocityThreshold``
(``btSequentialImpulseConstraintSolver::restitutionCurve``). The target is fixed once per step, from
the velocities before the step. Bullet accepts restitutions above 1 (checked: a restitution of 2
gives a two-ball COR of 2).

How each contact gets its own COR: per-body restitutions (``changeDynamics(restitution=...)``)
solved through the product rule. Corner: the disk has restitution 1, wall S1 ``cors[0]``, S2
``cors[1]``: always expressible. A cradle's fixed wall (:attr:`~verify.engines.scene.Cradle.wall`)
is a static (mass 0) plane facing -x at ``RADIUS - overlap`` from the last ball's centre (as
the corner's walls), one more body at the end of the path whose restitution comes out of the
same product rule (its contact gets ``cors[-1]``). Cradle: ball restitutions ``r`` with ``r_i * r_(i+1) = e_i``;
along a run of positive CORs ``r_(i+1) = e_i / r_i``, the first ``r`` chosen so that the largest
``r`` is as small as it can be (equal CORs give ``r = sqrt(e)`` for every ball). A COR of 0 needs a
ball of restitution 0, which makes both contacts of that ball 0: a 0 between two positive CORs
cannot be expressed (``Unsupported``), nor can a negative COR.

Settings (all ``--set``-able): ``time_step`` (Bullet's 1/240 s), ``solver_iterations`` (pybullet's
50), ``restitution_velocity_threshold`` (Bullet's 0.2), ``contact_slop`` (pybullet's 1e-5; see
below), ``maximal_coordinates`` (1: a free ``btRigidBody`` per ball; 0: pybullet's default
Featherstone ``btMultiBody``, whose base velocity pybullet caps at ``maxJointVelocity`` = 100 unless
raised, which this adapter does), ``overlap``, ``reverse_order`` (create the bodies last-first)
and ``max_time`` (simulated seconds before giving up on the impact being over). Gravity 0,
friction 0, damping 0 (pybullet's default damping 0.04 is switched off). Spheres of radius
``sqrt(5/2)``, so the unit-mass disk has unit moment of inertia (``changeDynamics
(localInertiaDiagonal=...)`` on a maximal-coordinates body sets its mass to 0 in pybullet 3.2.7).

What was noticed: the 3-ball cradle with 50 iterations comes out at the simultaneous-impact
answer (near ``(-100/3, 200/3, 200/3)`` for ``e = 1``); with 1 iteration (the alternate) the
sequential answer ``(0, 0, 100)``. ``contact_slop`` makes touching bodies count as ``slop`` apart, which
lowers every contact's target separation speed by ``slop / time_step`` (0.0024 at 1/240 s: a
two-ball COR of 1 at speed 100 comes out as 0.999976). Below the restitution threshold contacts
are plastic: the paper's corner at speed 1/2 stops dead (about 1e-4), at speed 100 it does not.
In ``maximal_coordinates=0`` mode without the raised cap, speeds of 100 are clipped and momentum is
lost. The impact is over when a step changes no velocity and no contact is approaching.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

from verify.engines import common
from verify.engines.combine import check_range, product_rule_values
from verify.engines.protocol import Adapter, silenced, whole
from verify.engines.scene import Corner, Cradle

RADIUS = math.sqrt(2.5)  #: 2/5 m R^2 = 1 for the unit-mass disk
FREE_SPEED = 1e9  #: the multibody speed cap used instead of pybullet's 100
WHO = "per-body restitutions multiplied (Bullet)"  #: the per-body values and their rule, in a skip's reason


class PyBulletAdapter(Adapter):
    """Bullet's sequential-impulse solver (pybullet), one fresh DIRECT client per case."""

    name: ClassVar[str] = "pybullet"
    radius: ClassVar[float | None] = RADIUS

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"solver_iterations": whole(c["solver_iterations"]), "contact_slop": c["contact_slop"] >= 0,
               "restitution_velocity_threshold": c["restitution_velocity_threshold"] >= 0,
               "maximal_coordinates": c["maximal_coordinates"] in (0, 1)}  # fmt: skip
        return {**super().checks(), **own}

    def version(self) -> str:
        self.engine()
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("pybullet")
        except PackageNotFoundError:  # pragma: no cover - an unpackaged build
            return str(self.engine().getAPIVersion())

    def body_values(self, cors: list[float]) -> list[float]:
        """The cradle's per-body restitutions, balls then the wall if any (the product rule, no upper bound;
        Unsupported if none)."""
        return product_rule_values(cors, WHO, bounded=False)

    # -- a world -----------------------------------------------------------------------
    def _connect(self, p: Any) -> int:
        with silenced():
            cid = int(p.connect(p.DIRECT))
        p.setGravity(0, 0, 0, physicsClientId=cid)
        p.setPhysicsEngineParameter(
            fixedTimeStep=float(self.config["time_step"]),
            numSolverIterations=int(self.config["solver_iterations"]),
            restitutionVelocityThreshold=float(self.config["restitution_velocity_threshold"]),
            contactSlop=float(self.config["contact_slop"]),
            physicsClientId=cid,
        )
        return cid

    def _body(self, p: Any, cid: int, *, mass: float, shape: int, pos: list[float], restitution: float) -> int:
        maximal = bool(self.config["maximal_coordinates"])
        body = int(
            p.createMultiBody(
                baseMass=mass,
                baseCollisionShapeIndex=shape,
                basePosition=pos,
                useMaximalCoordinates=maximal,
                physicsClientId=cid,
            )
        )
        extra: dict[str, float] = {} if maximal or mass == 0 else {"maxJointVelocity": FREE_SPEED}
        p.changeDynamics(
            body,
            -1,
            restitution=restitution,
            lateralFriction=0.0,
            rollingFriction=0.0,
            spinningFriction=0.0,
            linearDamping=0.0,
            angularDamping=0.0,
            physicsClientId=cid,
            **extra,
        )
        return body

    def _settle(
        self, p: Any, cid: int, read: Callable[[], list[float]], closing: Callable[[list[float]], float]
    ) -> list[float]:
        """Step until a step changes no velocity and no contact approaches (or ``max_time``)."""
        v, _ = common.settle(
            lambda: p.stepSimulation(physicsClientId=cid),
            read,
            steps=common.step_count(self.config["max_time"], self.config["time_step"], slack=0.0),
            still=lambda before, after: after == before,
            approaching=lambda v: closing(v) > 0,
        )
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, vel = common.cradle_inputs(scene)
        rest = self.body_values(cors)
        p = self.engine()
        cid = self._connect(p)
        try:
            shape = p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS, physicsClientId=cid)
            n, pitch = len(masses), 2 * RADIUS - self.config["overlap"]
            ids: dict[int, int] = {}
            for i in common.in_order(range(n + scene.wall), self.config["reverse_order"]):
                if i == n:  # the wall: a plane facing -x, at RADIUS - overlap from the last ball's centre
                    face = (n - 1) * pitch + RADIUS - self.config["overlap"]
                    self._wall(p, cid, [-1.0, 0.0, 0.0], rest[n], [face, 0.0, 0.0])()
                    continue
                ids[i] = self._body(p, cid, mass=masses[i], shape=shape, pos=[i * pitch, 0.0, 0.0], restitution=rest[i])
                p.resetBaseVelocity(ids[i], [vel[i], 0.0, 0.0], [0.0, 0.0, 0.0], physicsClientId=cid)
            balls = [ids[i] for i in range(n)]

            def read() -> list[float]:
                return [float(p.getBaseVelocity(b, physicsClientId=cid)[0][0]) for b in balls]

            return self._settle(p, cid, read, lambda v: common.cradle_closing(v, scene.wall))
        finally:
            p.disconnect(physicsClientId=cid)

    def corner(self, scene: Corner) -> list[float]:
        k, cors, vel = common.corner_inputs(scene)
        check_range(cors, WHO, bounded=False)  # the disk has restitution 1, each wall its COR
        p = self.engine()
        cid = self._connect(p)
        try:
            centre = [common.corner_centre(k, RADIUS - self.config["overlap"]), 0.0, 0.0]
            sphere = p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS, physicsClientId=cid)
            makers: list[Callable[[], int]] = [
                lambda: self._body(p, cid, mass=1.0, shape=sphere, pos=centre, restitution=1.0),
                *(self._wall(p, cid, [*n, 0.0], e) for n, e in zip(common.wall_normals(k), cors)),
            ]
            made = [make() for make in common.in_order(makers, self.config["reverse_order"])]
            disk = made[-1] if self.config["reverse_order"] else made[0]
            p.resetBaseVelocity(disk, [vel[0], vel[1], 0.0], [0.0, 0.0, vel[2]], physicsClientId=cid)

            def read() -> list[float]:
                lin, ang = p.getBaseVelocity(disk, physicsClientId=cid)
                return [float(lin[0]), float(lin[1]), float(ang[2])]

            return self._settle(p, cid, read, lambda v: common.corner_closing(k, v))
        finally:
            p.disconnect(physicsClientId=cid)

    def _wall(
        self, p: Any, cid: int, normal: list[float], restitution: float, pos: list[float] | None = None
    ) -> Callable[[], int]:
        """What makes a static (mass 0) plane of this normal through ``pos`` (the origin by default)."""

        def make() -> int:
            plane = p.createCollisionShape(p.GEOM_PLANE, planeNormal=normal, physicsClientId=cid)
            at = [0.0, 0.0, 0.0] if pos is None else pos
            return self._body(p, cid, mass=0.0, shape=plane, pos=at, restitution=restitution)

        return make


main = PyBulletAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
