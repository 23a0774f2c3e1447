"""DART (``dartpy``) as an implementation under test: the cradle and the corner in a DART world.

Engine: DART, the Python package ``dartpy`` (checked with 6.20.0). Run as
``python -m verify.engines.adapters.dartpy`` (the module's name is the engine's; ``import dartpy``
inside it is an absolute import and finds the engine, not this file).

**Combine rule: the product.** DART gives each ShapeNode one restitution coefficient (its
DynamicsAspect) and a contact between shapes A and B gets ``e = e_A * e_B``
(``DefaultContactSurfaceHandler::createParams`` in ``dart/constraint/ContactSurface.cpp``,
``params.mRestitutionCoeff = restitutionCoeffA * restitutionCoeffB``; older releases have the
same line in ``ContactConstraint``'s constructor). Each per-shape value outside ``[0, 1]`` is
replaced by the default 0 with a warning (``sanitizeRestitutionCoefficient``, same file).
The restitution acts in ``ContactConstraint::getInformation``
(``dart/constraint/ContactConstraint.cpp``): the LCP row of a contact asks for a separating
velocity of at least ``e * (approach velocity)`` measured before the step's solve, with three
thresholds (``dart/constraint/ContactSurface.hpp``): bouncing is off when
``e <= DART_RESTITUTION_COEFF_THRESHOLD = 1e-3`` (a COR of 0.001 acts as 0), when
``e * approach <= DART_BOUNCING_VELOCITY_THRESHOLD = 0.1`` (velocities are in the case's
units, read as m/s), and the target is capped at ``DART_MAX_BOUNCING_VELOCITY = 100``.
All contacts of a step form one boxed LCP (Dantzig pivoting by default, PGS as its fallback).

**How CORs are set: per-body values solved through the product.** The corner's disk gets 1
and each wall shape gets its COR. A cradle's ball j gets ``r_j`` in ``[0, 1]`` with
``r_i * r_(i+1) = cors[i]``: a ball every contact of which has COR 0 gets 0; each run of
positive CORs is solved by giving one ball 1 and dividing along the chain, trying each ball in
turn until all values are at most 1. A cradle with no such solution (e.g. cors ``(1, 1/2, 1)``:
the two end contacts force all four balls to 1) and any COR outside ``[0, 1]`` are skipped
(:class:`~verify.engines.scene.Unsupported`). ``dartpy`` binds neither
``ContactSurfaceHandler`` (DART's per-contact hook) nor ``ContactConstraint``'s ERP/CFM
setters, so no per-contact COR and no change of the constraint force mixing (1e-5, which
shifts the answers in the fifth digit) are possible from Python.

**Scenes.** Gravity 0; each ball or disk is a Skeleton with a FreeJoint and a SphereShape of
radius 1 (collision and dynamics aspects, friction 0); the two walls are box ShapeNodes of one
body welded to the world (one body, so the walls do not collide with each other), faces on the
lines ``y = kx`` and ``y = -kx``. A cradle's fixed wall (:attr:`~verify.engines.scene.Cradle.wall`)
is such a welded body with one box, its face at ``RADIUS - overlap`` from the last ball's centre,
facing -x: one more body at the end of the path, its shape's restitution from the same product
rule (its contact gets ``cors[-1]``). Balls are solid spheres (moment ``2/5 m``); the disk has unit
mass and unit moment. Velocities are set and read in the world frame. A case steps until the
velocities have not changed for 3 steps and no contact approaches (or ``max_steps``).

**Settings** (``--set``): ``time_step`` (DART's default 0.001); ``lcp_solver`` (0: Dantzig
with PGS fallback, DART's default; 1: PGS with PGS as its fallback); ``pgs_iterations``
(PGS's maximum sweeps, DART's default 30; used by PGS in both modes); ``collision_detector`` (0 FCL, DART's default;
1 DART; 2 Bullet; 3 ODE); ``overlap`` (initial overlap of touching bodies); ``reverse_order``
(1: the bodies are created, and added to the world, in reverse order); ``max_steps``.
The alternate is ``lcp_solver = 1`` (with ``pgs_iterations``'s default).

**What was noticed.** Touching bodies are all detected in the first step, so one LCP holds
every contact and the answer is the simultaneous Newton law up to the CFM: 3 balls, cors
(1, 1): about (-33.331, 66.666, 66.666), cors (1/2, 1/2): about (0.0017, 49.999, 49.999);
the paper's corner: about (-25.854, 14.927), S2's COR 0.001 acting as 0 (the 1e-3 threshold;
0.001 * approach is also under 0.1). The time step changes nothing visible; the FCL, DART
and Bullet detectors agree to 1e-5 of the speed; reversing the creation order (or ODE's
detector) moves the cradle by about 1e-4 of the speed (the order of the LCP's rows). PGS
(``lcp_solver = 1``) stops on its relative tolerance (-33.299 for the first ball); with
``pgs_iterations = 1`` too it gives (0.001, 50, 50). A case that bounces at less than
0.1 m/s just stops (``corner-slope-1/10``).
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

from verify.engines.combine import check_range, product_rule_values
from verify.engines.common import corner_closing, corner_inputs, cradle_closing, cradle_inputs, in_order, settle
from verify.engines.protocol import Adapter, silenced, whole
from verify.engines.scene import Corner, Cradle

RADIUS = 1.0  #: every ball and the disk
SETTLE = 3  #: steps without a velocity change that end a case
DETECTORS = ("FCL", "DART", "BULLET", "ODE")  #: collision_detector 0..3
#: the per-body values and their rule, in a skip's reason (DART replaces a value outside [0, 1] by 0)
WHO = "per-body restitutions multiplied (DART; dartpy binds no per-contact setting)"
SLACK = 1e-12  #: a per-body value up to 1 + SLACK (a rounding) is given as 1


#: a wall: a point of its face, the face's direction in the xy plane, its normal pointing into the wall (out of
#: the bodies' side), its restitution and its name
Wall = tuple[list[float], list[float], list[float], float, str]
WALL_HALF_LENGTH, WALL_THICKNESS = 20 * RADIUS, RADIUS
WALL_BOX = [2 * WALL_HALF_LENGTH, WALL_THICKNESS, 4 * RADIUS]  #: a wall's box: along, across, z


def wall_frame(d: Any, wall: Wall) -> Any:
    """Where a wall's box (:data:`WALL_BOX`) lies: its x axis along the face, its y axis out of the wall."""
    foot, along, into = wall[0], wall[1], wall[2]
    side = [-along[1], along[0], 0.0]  # (along, side, z) right-handed: side = -into
    frame = d.math.Isometry3()
    frame.set_rotation([[along[i], side[i], [0.0, 0.0, 1.0][i]] for i in range(3)])
    frame.set_translation([foot[i] + into[i] * WALL_THICKNESS / 2 for i in range(3)])
    return frame


class DartAdapter(Adapter):
    """DART (dartpy): all contacts of a step in one boxed LCP, restitution combined as a product."""

    name: ClassVar[str] = "dartpy"
    radius: ClassVar[float | None] = RADIUS
    #: whether a wall's restitution must lie in [0, 1] (DART replaces others by 0; nimblephysics takes them)
    bounded: ClassVar[bool] = True

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"lcp_solver": c["lcp_solver"] in (0, 1), "pgs_iterations": whole(c["pgs_iterations"]),
               "collision_detector": c["collision_detector"] in range(len(DETECTORS))}  # fmt: skip
        return {**super().checks(), **own}

    def body_values(self, cors: list[float]) -> list[float]:
        """The cradle's per-ball restitutions (the product rule, in [0, 1]; Unsupported if none)."""
        return product_rule_values(cors, WHO, bounded=True, slack=SLACK)

    # -- the world ---------------------------------------------------------------------
    def _world(self, d: Any) -> Any:
        world = d.simulation.World()
        world.setGravity([0.0, 0.0, 0.0])
        world.setTimeStep(self.config["time_step"])
        if "collision_detector" in self.config:  # (nimblephysics keeps its own detector: no such setting)
            detector = DETECTORS[int(self.config["collision_detector"])]
            world.setCollisionDetector(getattr(d.simulation.CollisionDetectorType, detector))
        solver = world.getConstraintSolver()
        pgs = solver.getSecondaryBoxedLcpSolver()  # the PGS fallback (no constructor is bound)
        option = d.constraint.PgsBoxedLcpSolverOption()
        option.mMaxIteration = int(self.config["pgs_iterations"])
        pgs.setOption(option)
        if self.config["lcp_solver"] == 1:
            # PGS first and PGS as the fallback, as C++'s BoxedLcpConstraintSolver(PGS) has it; the one
            # bound PGS object serves as both. DART warns "Ignoring this request" and sets it all the same
            # (BoxedLcpConstraintSolver::setBoxedLcpSolver): the misleading warning is not passed on.
            # A fallback's unconverged answer is used, while a primary alone that does not converge has its
            # impulses zeroed (BoxedLcpConstraintSolver::solveConstrainedGroup).
            with silenced(2):
                solver.setBoxedLcpSolver(pgs)
        return world

    def _shape(self, d: Any, body: Any, shape: Any, restitution: float) -> Any:
        node = body.createShapeNode(shape)
        node.createCollisionAspect()
        holder = self._material(node, body)
        holder.setRestitutionCoeff(restitution)
        holder.setFrictionCoeff(0.0)
        return node

    @staticmethod
    def _material(node: Any, body: Any) -> Any:
        """What holds a shape's restitution and friction: the shape node's dynamics aspect in DART."""
        return node.createDynamicsAspect()

    @staticmethod
    def _inertia(d: Any, mass: float, moment: float) -> Any:
        """A body's inertia: ``mass`` and the same ``moment`` about every axis."""
        inertia = d.dynamics.Inertia()
        inertia.setMass(mass)
        inertia.setMoment([[moment, 0.0, 0.0], [0.0, moment, 0.0], [0.0, 0.0, moment]])
        return inertia

    def _free_sphere(self, d: Any, name: str, mass: float, moment: float, restitution: float) -> tuple[Any, Any]:
        skeleton = d.dynamics.Skeleton(name)
        joint, body = skeleton.createFreeJointAndBodyNodePair()
        self._shape(d, body, d.dynamics.SphereShape(RADIUS), restitution)
        body.setInertia(self._inertia(d, mass, moment))
        return skeleton, joint

    def _settle(self, world: Any, read: Any, closing: Any) -> list[float]:
        """Step until the velocities stop changing and no contact approaches; the last velocities."""
        scale = max(1.0, *(abs(x) for x in read()))
        v, _ = settle(
            world.step,
            read,
            steps=int(self.config["max_steps"]),
            still=lambda before, after: all(abs(a - b) <= 1e-12 * scale for a, b in zip(before, after)),
            approaching=lambda v: closing(v) > 1e-9 * scale,
            quiet=SETTLE,
        )
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, velocity = cradle_inputs(scene)
        restitution = self.body_values(cors)
        d = self.engine()
        with silenced():
            world = self._world(d)
            n, gap = len(masses), 2 * RADIUS - self.config["overlap"]
            balls: list[Any] = [None] * n
            for j in in_order(range(n + scene.wall), self.config["reverse_order"]):
                if j == n:  # the wall: its face at RADIUS - overlap from the last ball's centre, facing -x
                    face = [(n - 1) * gap + RADIUS - self.config["overlap"], 0.0, 0.0]
                    wall = (face, [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], restitution[n], "wall")
                    world.addSkeleton(self._wall_skeleton(d, [wall]))
                    continue
                moment = 0.4 * masses[j] * RADIUS**2  # a solid sphere
                skeleton, joint = self._free_sphere(d, f"ball{j}", masses[j], moment, restitution[j])
                joint.setPositions([0.0, 0.0, 0.0, j * gap, 0.0, 0.0])
                joint.setVelocities([0.0, 0.0, 0.0, velocity[j], 0.0, 0.0])
                world.addSkeleton(skeleton)
                balls[j] = skeleton.getBodyNode(0)

            def read() -> list[float]:
                return [float(b.getLinearVelocity()[0]) for b in balls]

            return self._settle(world, read, lambda v: cradle_closing(v, scene.wall))

    def _walls(self, d: Any, k: float, cors: list[float], centre: float) -> Any:
        """The corner's walls (S1: y = kx, S2: y = -kx), a box each, welded to the world."""
        s = math.hypot(1.0, k)
        walls: list[Wall] = []
        for w in in_order([0, 1], self.config["reverse_order"]):
            sign = 1.0 if w == 0 else -1.0
            along = [1 / s, sign * k / s, 0.0]
            into = [k / s, -sign / s, 0.0]  # the wall's normal, pointing out of the admissible region
            foot = [centre / s * x for x in along]  # the disk centre's foot on the wall's line
            walls.append((foot, along, into, cors[w], f"S{w + 1}"))
        return self._wall_skeleton(d, walls)

    def _wall_skeleton(self, d: Any, walls: list[Wall]) -> Any:
        """One body welded to the world with a box shape per wall (so the walls do not collide)."""
        skeleton = d.dynamics.Skeleton("walls")
        _, body = skeleton.createWeldJointAndBodyNodePair()
        for wall in walls:
            node = self._shape(d, body, d.dynamics.BoxShape(WALL_BOX), wall[3])
            node.setName(wall[4])
            node.setRelativeTransform(wall_frame(d, wall))
        return skeleton

    def corner(self, scene: Corner) -> list[float]:
        k, cors, (vx, vy, omega) = corner_inputs(scene)
        check_range(cors, WHO, bounded=self.bounded)  # the disk has restitution 1, each wall its COR
        d = self.engine()
        with silenced():
            world = self._world(d)
            # the disk's centre: at distance RADIUS - overlap from both lines through the origin, with the
            # walls' hypot (not common.corner_centre's sqrt(1 + k^2)): it touches them as _walls places them
            centre = -(RADIUS - self.config["overlap"]) * math.hypot(1.0, k) / k
            disk, joint = self._free_sphere(d, "disk", 1.0, 1.0, 1.0)
            joint.setPositions([0.0, 0.0, 0.0, centre, 0.0, 0.0])
            joint.setVelocities([0.0, 0.0, omega, vx, vy, 0.0])
            walls = self._walls(d, k, cors, centre)
            for skeleton in in_order([walls, disk], self.config["reverse_order"]):
                world.addSkeleton(skeleton)
            body = disk.getBodyNode(0)

            def read() -> list[float]:
                lin, ang = body.getLinearVelocity(), body.getAngularVelocity()
                return [float(lin[0]), float(lin[1]), float(ang[2])]

            return self._settle(world, read, lambda v: corner_closing(k, v))


main = DartAdapter.main
if __name__ == "__main__":
    raise SystemExit(main())
