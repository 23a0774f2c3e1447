"""Box2D (pybox2d, Box2D 2.3.x, checked with 2.3.10) as an implementation under test.

Engine: Box2D by Erin Catto through the ``box2d`` pip package (``import Box2D``), a 2D
sequential-impulse solver in single precision (``float32``: positions, velocities, impulses
and restitutions are 32-bit floats, so a result carries rounding of about 1e-7 relative, and
momentum is conserved to that, not to double precision).

Combine rule: the contact's restitution is the larger of the two fixtures' restitutions,
``b2MixRestitution(r1, r2) = r1 > r2 ? r1 : r2`` (Box2D 2.3 ``Box2D/Dynamics/Contacts/b2Contact.h``,
called from the ``b2Contact`` constructor and by ``b2Contact::ResetRestitution``).

How each contact gets its COR (``per_contact``):

- ``per_contact=1`` (default): every fixture has restitution 0 and a contact listener's
  ``PreSolve`` sets ``contact.restitution`` (``b2Contact::SetRestitution``, 2.3+) to the
  contact's COR on every step the contact touches. This works: ``PreSolve`` runs in the
  collision phase (``b2Contact::Update``), before ``b2ContactSolver`` copies
  ``m_restitution`` into the velocity constraint, so the value is used in the same step.
  Any COR can be given to any contact.
- ``per_contact=0``: per-body (per-fixture) restitutions solved through the max rule, as a
  game would set them. For bodies on a path (the cradle's balls; wall S1, disk, wall S2) the
  candidate ``r_i = min`` of the CORs of body i's contacts gives contact i the COR
  ``max(r_i, r_(i+1))``; it fails exactly when an interior contact's COR is larger than both
  neighbours' (e.g. a 4-ball cradle with CORs 1/2, 1, 1/2): that case is skipped
  (:class:`~verify.engines.scene.Unsupported`), never run with another COR.

What Box2D does with the COR (finding, cannot be changed by a setting): restitution enters
as a velocity bias ``-e * vRel`` computed ONCE per step from the relative normal velocity at
the start of the step, and only when ``vRel < -b2_velocityThreshold`` (``b2ContactSolver::
InitializeVelocityConstraints``, ``Box2D/Dynamics/Contacts/b2ContactSolver.cpp``).
``b2_velocityThreshold = 1.0`` (m/s) is a compile-time constant of ``b2Settings.h``
(pybox2d exposes it read-only as ``Box2D.b2_velocityThreshold``): a contact approaching at
1 m/s or less is solved as perfectly inelastic whatever its COR, so the golden cases with
unit speeds (``cradle-4-balls-eps-1/2``, the slow corners) come out with COR 0 at those
contacts (a 2-ball cradle with COR 1 comes out at (0.5, 0.5) from 1 m/s, and swaps from
1.01 m/s). Scaling the scene's speeds would hide this, so the adapter does not. Within one
step the targets are Newton's law applied to all contacts at once (each contact's target is
-e times its own approach speed at the start of the step), so with converged iterations a
contact at rest when the step starts (the 3-ball cradle's second contact) gets the target 0
whatever its COR: the 3-ball cradle gives the simultaneous law's (-100/3, 200/3, 200/3) for
CORs (1, 1) and the same for CORs (1, 0); the second contact's COR is never used.

Settings (all changeable with ``--set``):

- ``time_step`` (1/60 s), ``velocity_iterations`` (8), ``position_iterations`` (3): the
  values of Box2D's testbed and manual; ``warm_starting`` (1): ``b2World.warmStarting``;
- ``radius`` (1 m): the balls' and the disk's radius. Box2D works in metres (moving
  objects of 0.1 to 10 m) and moves a body at most ``b2_maxTranslation = 2`` m per step;
  at 100 m/s and 1/60 s a body moves 1.67 m per step, which passes the centre of a 0.5 m
  ball (non-bullet dynamic bodies get no continuous collision between each other), so 1 m;
- ``bullet`` (1): the moving bodies are bullets (continuous collision against dynamic
  bodies too), as Box2D's manual advises for fast bodies;
- ``overlap`` (0): initial overlap of touching bodies (balls at ``2 radius - overlap``;
  the disk at ``radius + skin - overlap`` from each wall, where skin is the edge shapes'
  radius ``b2_polygonRadius = 0.01`` m that Box2D adds to every edge);
- ``reverse_order`` (0/1): create the bodies in reverse order (balls N..1; disk, S2, S1),
  which reverses the order in which the solver visits the contacts;
- ``per_contact`` (1/0): above; ``max_time`` (1 s): at most this much simulated time.

A case ends after a step that applied no normal impulse (as reported by ``PostSolve``,
below 1e-6 of the momentum scale) with no contact approaching (closing speed below 1e-6 of
the fastest initial speed): bodies separating, or resting together. Walls are static bodies
with one edge shape each, 1000 radii long, from the apex. A cradle's fixed wall
(:attr:`~verify.engines.scene.Cradle.wall`) is one more: a static body with a vertical edge
2000 radii long, at ``radius + skin - overlap`` from the last ball's centre like the corner's
walls; it is body N on the path (ball 1 .. ball N, wall), so the listener gives its contact
``cors[-1]`` and with ``per_contact=0`` the max rule runs along that path. Gravity is off, friction 0, sleeping off; the
disk has unit mass and unit moment of inertia, a ball of mass m has m and ``m radius^2 / 2``.

Alternate setting: ``velocity_iterations=1``: one Gauss-Seidel pass per step, so the
contacts are solved one after another (pairwise, in contact order) instead of converged
together; it moves the 3-ball eps = 1 cradle from about (-33.3, 66.7, 66.7) to (0, 0, 100)
and makes the result depend on ``reverse_order`` ((0, 50, 50) reversed).

Also noticed: warm starting (on by default) leaves an eps = 0 cradle slightly apart
(33.3323, 33.3323, 33.3354) where ``warm_starting=0`` gives 33.3333 for all three; with one
velocity iteration the eps = 0 cradle's last ball leaves at 58.2 and the others at 20.9 (no
energy gain: each step's targets never exceed the approach speeds); a frictionless disk's
spin comes out as about 1e-6 rad/s instead of 0 (float32 lever arms); a cradle whose first
two balls separate at a tiny speed difference (eps = 0.99 with one iteration) is still
approaching after ``max_time``, which the adapter says on stderr, returning the velocities
it has.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, ClassVar

from verify.engines.common import ContactAdapter, ContactLog, corner_centre, corner_inputs, cradle_inputs, in_order
from verify.engines.protocol import import_engine
from verify.engines.scene import Corner, Cradle


@functools.cache
def _listener_class() -> type:
    """The contact listener (a subclass of the engine's class, made once the engine is imported)."""
    base: Any = import_engine("Box2D").b2ContactListener

    class Listener(base):
        """Sets each touching contact's restitution (``per_contact``) and records the step's impulses."""

        def __init__(self, log: ContactLog):
            super().__init__()
            self.log = log

        def PreSolve(self, contact: Any, old_manifold: Any) -> None:
            cor = self.log.cor(contact.fixtureA.body.userData, contact.fixtureB.body.userData)
            if cor is not None:
                contact.restitution = cor

        def PostSolve(self, contact: Any, impulse: Any) -> None:
            for x in impulse.normalImpulses:
                self.log.solved(abs(x))

    return Listener


class Box2DAdapter(ContactAdapter):
    """Box2D (pybox2d): a cradle of circles, a circle between two static edges."""

    name: ClassVar[str] = "box2d"
    rule: ClassVar[str] = "max"
    who: ClassVar[str] = "per-body restitutions combined by max (Box2D)"
    tolerance: ClassVar[float] = 1e-6  # a float32 engine: impulses and velocities carry about 1e-7 relative

    def checks(self) -> dict[str, bool]:
        c = self.config
        return {
            **super().checks(),
            "velocity_iterations": c["velocity_iterations"] >= 1,
            "position_iterations": c["position_iterations"] >= 0,
        }

    # -- the world ---------------------------------------------------------------------
    def _world(self, cors: list[float]) -> tuple[Any, ContactLog, Callable[[], object]]:
        """A world whose listener logs into the returned log; the function that steps it."""
        c = self.config
        log = ContactLog(cors, bool(c["per_contact"]))
        world = self.engine().b2World(gravity=(0, 0), doSleep=False, contactListener=_listener_class()(log))
        world.warmStarting = bool(c["warm_starting"])

        def step() -> None:
            world.Step(c["time_step"], int(c["velocity_iterations"]), int(c["position_iterations"]))

        return world, log, step

    @staticmethod
    def _wall(world: Any, index: int, vertices: list[tuple[float, float]], restitution: float) -> None:
        """A static body with one edge shape, ``index`` on the path of bodies (its ``userData``)."""
        wall = world.CreateStaticBody(userData=index)
        wall.CreateEdgeFixture(vertices=vertices, friction=0, restitution=restitution)

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, v0 = cradle_inputs(scene)
        b2 = self.engine()
        world, log, step = self._world(cors)
        r, c = self.config["radius"], self.config
        rest = self.body_values(cors)
        n, pitch = len(masses), 2 * r - c["overlap"]
        bodies: list[Any] = [None] * n
        for i in in_order(range(n + scene.wall), c["reverse_order"]):
            if i == n:  # the wall: its edge at the corner's distance from the last ball's centre
                x = (n - 1) * pitch + r + b2.b2_polygonRadius - c["overlap"]
                self._wall(world, n, [(x, -1000 * r), (x, 1000 * r)], rest[n])
                continue
            body = world.CreateDynamicBody(position=(i * pitch, 0), userData=i, bullet=bool(c["bullet"]))
            body.CreateCircleFixture(radius=r, density=1, friction=0, restitution=rest[i])
            body.massData = b2.b2MassData(mass=masses[i], center=(0, 0), I=masses[i] * r * r / 2)
            body.linearVelocity = (v0[i], 0)
            bodies[i] = body

        def read() -> list[float]:
            return [float(b.linearVelocity.x) for b in bodies]

        return self.settle_cradle(step, log, read, masses, v0, wall=scene.wall)

    def corner(self, scene: Corner) -> list[float]:
        k, cors, (vx, vy, w) = corner_inputs(scene)
        b2 = self.engine()
        world, log, step = self._world(cors)
        r, c = self.config["radius"], self.config
        rest = self.body_values(cors)  # path: S1 (0), disk (1), S2 (2)
        length = 1000 * r
        disk: Any = None
        for index in in_order(range(3), c["reverse_order"]):
            if index == 1:
                x = corner_centre(k, r + b2.b2_polygonRadius - c["overlap"])
                disk = world.CreateDynamicBody(position=(x, 0), userData=1, bullet=bool(c["bullet"]))
                disk.CreateCircleFixture(radius=r, density=1, friction=0, restitution=rest[1])
                disk.massData = b2.b2MassData(mass=1, center=(0, 0), I=1)
                disk.linearVelocity, disk.angularVelocity = (vx, vy), w
            else:
                slope = k if index == 0 else -k  # S1: y = kx, S2: y = -kx, towards negative x
                self._wall(world, index, [(0, 0), (-length, -slope * length)], rest[index])

        def read() -> list[float]:
            return [float(disk.linearVelocity.x), float(disk.linearVelocity.y), float(disk.angularVelocity)]

        return self.settle_corner(step, log, read, k, [vx, vy, w])


main = Box2DAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
