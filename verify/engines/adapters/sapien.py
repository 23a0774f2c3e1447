"""SAPIEN (PhysX 5, CPU simulation) as an implementation under test.

Engine: the Python package ``sapien`` (checked with 3.0.3, whose wheel bundles PhysX 5.3.1:
``PX_PHYSICS_VERSION`` in the headers it ships), run on the CPU: each case gets a
``sapien.Scene`` holding only a ``PhysxCpuSystem`` (the default scene also makes a render
system, which fails here with "failed to find a rendering device"). Run as
``python -m verify.engines.adapters.sapien``. PhysX computes in single precision: answers agree with
exact ones to about 1e-7 of the speed at best.

**Combine rule: the average, by default.** Each shape has a ``PhysxMaterial(static_friction,
dynamic_friction, restitution)``; a contact's restitution is ``combineScalars(r0, r1, mode)``
with the larger of the two materials' restitution combine modes, ``0.5 * (r0 + r1)`` for
``PxCombineMode::eAVERAGE``, PhysX's default (``PxsCombineRestitution`` in
``physx/source/lowlevel/software/include/PxsMaterialCombiner.h``, NVIDIA-Omniverse/PhysX;
``PxMaterial::setRestitutionCombineMode``, "Default: PxCombineMode::eAVERAGE", in
``PxMaterial.h``). SAPIEN 3.0.3 binds no combine-mode setter, so the average is the rule.
Checked: restitutions (1, 0) give two balls a COR of 1/2, (1, 1/2) give 3/4, (1/5, 3/5) give
2/5; PhysX documents a restitution range of ``[-INF, 1]`` (negative values being spring
stiffnesses for compliant contacts), but a value above 1 is used as it is (1.5 and 1.5 give a
COR of 1.5; 2 and 0 give 1).

**What the solver does with it.** A contact whose approach speed is not above the scene's
``bounceThresholdVelocity`` does not bounce ("A contact with a relative velocity below this
will not bounce", ``PxSceneDesc.h``; PhysX's default ``0.2 * PxTolerancesScale::speed`` =
2 m/s, SAPIEN's ``PhysxSceneConfig.bounce_threshold`` = 2.0, velocities in the case's units
read as m/s; checked: two balls meeting at 2 stick, at 10 bounce). Above it the contact's
target separating velocity is ``-e * v_n``, taken from the velocities before the solve, and
the contacts are solved one at a time, sweep after sweep (projected Gauss-Seidel, or its
temporal variant TGS, SAPIEN's default, ``enable_tgs``), for ``solver_position_iterations``
(SAPIEN's default 10) and then ``solver_velocity_iterations`` (1) sweeps per step.

**How CORs are set: per-body values solved through the average.** Bodies lie on a path
(cradle: the balls; corner: wall S1, the disk, wall S2), contact ``i`` between bodies ``i``
and ``i + 1``: values with ``r_i + r_(i+1) = 2 * cors[i]`` are ``r_j = a_j + (-1)^j t`` for
one free ``t``. The adapter takes the middle of the ``t`` for which every value lies in
``[0, 1]``; when there is none, with ``bounded = 0`` (the default) the middle of those for
which every value is at least 0 (values above 1, measured to work); else the case is skipped
(:class:`~verify.engines.scene.Unsupported`), as is any COR below 0. The paper's corner
(CORs 0.999 and 0.001) needs S1 at about 1.997: it runs only with ``bounded = 0``.

**Scenes.** Gravity 0, friction 0 (static and dynamic), damping 0, sleeping off (threshold
0). Balls and the disk are spheres of radius 1 (``PhysxRigidDynamicComponent``), the balls'
moments ``2/5 m``, the disk's mass and moment 1; each wall is a static box
(``PhysxRigidStaticComponent``) whose face lies on ``y = kx`` or ``y = -kx``. A cradle's fixed
wall (:attr:`~verify.engines.scene.Cradle.wall`) is one more static box, its face at ``RADIUS -
overlap`` from the last ball's centre, facing -x: the last body of the path (ball 1 .. ball N,
wall), its material's restitution from the same average rule (its contact gets ``cors[-1]``). A case steps
until a step changes no velocity and no contact approaches (closing speed below 1e-6 of the
speed, single precision), or ``max_time``.

**Settings** (``--set``): ``time_step`` (SAPIEN's 0.01), ``position_iterations`` (10),
``velocity_iterations`` (1), ``bounce_threshold`` (2.0), ``tgs`` (1: TGS, SAPIEN's default;
0: PGS), ``contact_offset`` (SAPIEN's 0.01), ``bounded``, ``overlap``, ``reverse_order``,
``max_time``. The alternate is ``position_iterations = 1``.

**What was noticed.** With TGS the 3-ball cradle, CORs (1, 1), comes out lopsided, about
(-33.93, 65.76, 68.17) (time step 0.01 or 0.001 alike); PGS (``tgs = 0``) gives the
simultaneous law, about (-33.3333, 66.6667, 66.6667); one position iteration gives about
(-7.0, 33.76, 73.24) with TGS and (-25, 62.5, 62.5) with PGS, not the pairwise (0, 0, 100).
With TGS a two-ball COR of 1 at speed 10 comes out as about 0.997. The paper's corner (with S1
at 1.997) gives about (-25.810, 14.901), PGS (-25.927, 14.887), ``reverse_order = 1``
(-25.845, 14.840). Cases slower than the bounce threshold are plastic (the slow paper corner
stops dead). Two unit balls against a wall, CORs (1, 1), the first at 100: PGS gives exactly the
sequential law's 11 sweeps (10 position, 1 velocity), (-99.90234375, 0); TGS gives about
(-114.18, 0), more kinetic energy than it started with.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

from verify.engines import common
from verify.engines.combine import check_range
from verify.engines.protocol import Adapter, CannotRun, import_engine, whole
from verify.engines.scene import Corner, Cradle, Unsupported

RADIUS = 1.0  #: every ball and the disk
TOLERANCE = 1e-6  #: relative: a closing speed below it counts as none (single precision)
WALL_HALF_LENGTH, WALL_THICKNESS = 20 * RADIUS, RADIUS  #: a wall's box: half its length, its thickness
#: the per-body values and their rule, in a skip's reason
WHO = "per-material restitutions averaged (PhysX's default combine mode; SAPIEN binds no other)"


def average_rule_values(cors: Sequence[float], who: str, *, bounded: bool) -> list[float]:
    """Values ``r`` with ``(r[i] + r[i+1]) / 2 == cors[i]``; :class:`Unsupported` if none.

    The middle of the free value's range that keeps every value in [0, 1]; failing that
    (unless ``bounded``), every value at least 0.

    >>> average_rule_values([0.5, 0.5], "average", bounded=True)
    [0.5, 0.5, 0.5]
    >>> average_rule_values([0.5, 1.0], "average", bounded=True)
    [0.0, 1.0, 1.0]
    >>> [round(x, 6) for x in average_rule_values([0.999, 0.001], "average", bounded=False)]
    [1.997, 0.001, 0.001]
    >>> average_rule_values([0.999, 0.001], "average", bounded=True)
    Traceback (most recent call last):
    ...
    verify.engines.scene.Unsupported: average cannot give the CORs [0.999, 0.001] with every value in [0, 1]
    """
    check_range(cors, who, bounded=True)
    a = [0.0]
    for e in cors:
        a.append(2 * e - a[-1])
    # r_j = a_j + t (j even), a_j - t (j odd)
    for top in (1.0, math.inf) if not bounded else (1.0,):
        even, odd = a[0::2], a[1::2]
        lo = max(*(-x for x in even), *(x - top for x in odd))
        hi = min(*(top - x for x in even), *odd)
        if lo <= hi:
            t = (lo + hi) / 2
            return [max(0.0, a[j] + t if j % 2 == 0 else a[j] - t) for j in range(len(a))]
    span = "[0, 1]" if bounded else "[0, inf)"
    raise Unsupported(f"{who} cannot give the CORs {list(cors)!r} with every value in {span}")


def _placed(sapien: Any, scene: Any, body: Any, shape: Any, pose: Any) -> Any:
    """``body`` (a PhysX component) with its ``shape``, on an entity of its own at ``pose``, added to ``scene``."""
    entity = sapien.Entity()
    body.attach(shape)
    entity.add_component(body)
    entity.set_pose(pose)
    scene.add_entity(entity)
    return body


class SapienAdapter(Adapter):
    """SAPIEN's PhysX 5 on the CPU: sequential (TGS or PGS) sweeps, restitution averaged per material."""

    name: ClassVar[str] = "sapien"
    radius: ClassVar[float | None] = RADIUS

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"position_iterations": whole(c["position_iterations"]),
               "velocity_iterations": whole(c["velocity_iterations"], 0),
               "bounce_threshold": c["bounce_threshold"] > 0, "tgs": c["tgs"] in (0, 1),
               "contact_offset": c["contact_offset"] > 0, "bounded": c["bounded"] in (0, 1)}  # fmt: skip
        return {**super().checks(), **own}

    def engine(self) -> Any:
        with warnings.catch_warnings():  # "Failed to find system libvulkan" at import: no renderer is used
            warnings.simplefilter("ignore")
            sapien = import_engine(self.module)
        try:
            sapien.physx.PhysxCpuSystem()
        except RuntimeError as exc:  # pragma: no cover - a machine where PhysX cannot start
            raise CannotRun(f"sapien {sapien.__version__}: PhysxCpuSystem(): {exc}") from None
        return sapien

    def body_values(self, cors: Sequence[float]) -> list[float]:
        """Per-body restitutions along a path of bodies (the average rule; Unsupported if none)."""
        return average_rule_values(cors, WHO, bounded=bool(self.config["bounded"]))

    # -- a scene -----------------------------------------------------------------------
    def _scene(self, sapien: Any) -> Any:
        px = sapien.physx
        c = self.config
        config = px.PhysxSceneConfig()
        config.gravity = [0.0, 0.0, 0.0]
        config.bounce_threshold = float(c["bounce_threshold"])
        config.enable_tgs = bool(c["tgs"])
        px.set_scene_config(config)  # read when the system is made
        shape = px.get_shape_config()
        shape.contact_offset = float(c["contact_offset"])
        shape.rest_offset = 0.0
        px.set_shape_config(shape)
        scene = sapien.Scene([px.PhysxCpuSystem()])
        scene.set_timestep(float(c["time_step"]))
        return scene

    def _ball(
        self, sapien: Any, scene: Any, *, mass: float, moment: float, restitution: float, pos: list[float]
    ) -> Any:
        px = sapien.physx
        sphere = px.PhysxCollisionShapeSphere(RADIUS, px.PhysxMaterial(0.0, 0.0, restitution))
        body = _placed(sapien, scene, px.PhysxRigidDynamicComponent(), sphere, sapien.Pose(pos))
        body.set_mass(mass)
        body.set_inertia([moment, moment, moment])
        body.set_linear_damping(0.0)
        body.set_angular_damping(0.0)
        body.set_sleep_threshold(0.0)
        body.set_solver_position_iterations(int(self.config["position_iterations"]))
        body.set_solver_velocity_iterations(int(self.config["velocity_iterations"]))
        return body

    def _wall(self, sapien: Any, scene: Any, k: float, sign: float, restitution: float) -> None:
        """A static box whose face is the line ``y = sign * k * x``, the box on the far side."""
        s = math.hypot(1.0, k)
        into = [k / s, -sign / s]  # the wall's normal, out of the admissible region
        angle = math.atan2(sign * k, 1.0)  # the box's x axis along the wall
        centre = [into[0] * WALL_THICKNESS / 2, into[1] * WALL_THICKNESS / 2, 0.0]
        quaternion = [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]
        half = [WALL_HALF_LENGTH, WALL_THICKNESS / 2, 2 * RADIUS]
        self._static_box(sapien, scene, half=half, centre=centre, quaternion=quaternion, restitution=restitution)

    @staticmethod
    def _static_box(
        sapien: Any, scene: Any, *, half: list[float], centre: list[float], quaternion: list[float], restitution: float
    ) -> None:
        """A static actor with one box shape of these half sizes, at this pose (``quaternion``: w, x, y, z)."""
        px = sapien.physx
        box = px.PhysxCollisionShapeBox(half, px.PhysxMaterial(0.0, 0.0, restitution))
        _placed(sapien, scene, px.PhysxRigidStaticComponent(), box, sapien.Pose(centre, quaternion))

    def _settle(
        self, scene: Any, read: Callable[[], list[float]], closing: Callable[[list[float]], float]
    ) -> list[float]:
        """Step until a step changes no velocity and no contact approaches (or ``max_time``)."""
        speed = max(1.0, *(abs(x) for x in read()))
        v, _ = common.settle(
            scene.step,
            read,
            steps=max(1, math.ceil(self.config["max_time"] / self.config["time_step"] - 1e-9)),
            still=lambda before, after: after == before,
            approaching=lambda v: not closing(v) <= TOLERANCE * speed,
        )
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, velocity = common.cradle_inputs(scene)
        rest = self.body_values(cors)
        sapien = self.engine()
        world = self._scene(sapien)
        n, pitch = len(masses), 2 * RADIUS - self.config["overlap"]
        balls: dict[int, Any] = {}
        for j in common.in_order(range(n + scene.wall), self.config["reverse_order"]):
            if j == n:  # the wall: a box whose face is at RADIUS - overlap from the last ball's centre, facing -x
                face = (n - 1) * pitch + RADIUS - self.config["overlap"]
                half, centre = [WALL_THICKNESS / 2, WALL_HALF_LENGTH, 2 * RADIUS], [face + WALL_THICKNESS / 2, 0.0, 0.0]
                upright = [1.0, 0.0, 0.0, 0.0]  # the box's axes are the world's
                self._static_box(sapien, world, half=half, centre=centre, quaternion=upright, restitution=rest[n])
                continue
            moment = 0.4 * masses[j] * RADIUS**2  # a solid sphere
            balls[j] = self._ball(
                sapien, world, mass=masses[j], moment=moment, restitution=rest[j], pos=[j * pitch, 0, 0]
            )
            balls[j].set_linear_velocity([velocity[j], 0.0, 0.0])
        ordered = [balls[j] for j in range(n)]

        def read() -> list[float]:
            return [float(b.get_linear_velocity()[0]) for b in ordered]

        return self._settle(world, read, lambda v: common.cradle_closing(v, scene.wall))

    def corner(self, scene: Corner) -> list[float]:
        k, cors, (vx, vy, omega) = common.corner_inputs(scene)
        s1, r_disk, s2 = self.body_values(cors)  # the path S1, disk, S2
        sapien = self.engine()
        world = self._scene(sapien)
        centre = common.corner_centre(k, RADIUS - self.config["overlap"])
        made: list[Any] = []
        makers: list[Callable[[], Any]] = [
            lambda: self._ball(sapien, world, mass=1.0, moment=1.0, restitution=r_disk, pos=[centre, 0.0, 0.0]),
            lambda: self._wall(sapien, world, k, 1.0, s1),
            lambda: self._wall(sapien, world, k, -1.0, s2),
        ]
        for make in common.in_order(makers, self.config["reverse_order"]):
            made.append(make())
        disk = made[-1] if self.config["reverse_order"] else made[0]
        disk.set_linear_velocity([vx, vy, 0.0])
        disk.set_angular_velocity([0.0, 0.0, omega])

        def read() -> list[float]:
            lin, ang = disk.get_linear_velocity(), disk.get_angular_velocity()
            return [float(lin[0]), float(lin[1]), float(ang[2])]

        return self._settle(world, read, lambda v: common.corner_closing(k, v))


main = SapienAdapter.main
if __name__ == "__main__":
    raise SystemExit(main())
