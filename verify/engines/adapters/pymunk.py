"""Pymunk (checked with 7.3.1, on Munk2D 2.0.1, a fork of Chipmunk2D 7) as an implementation under test.

Engine: Pymunk, the Python binding of Munk2D/Chipmunk2D, a 2D sequential-impulse solver in
double precision. This module is ``verify.engines.adapters.pymunk``; it imports the engine lazily
with ``import pymunk``, which (absolute imports) finds the installed top-level package, not
this module.

Combine rule: the arbiter's restitution is the product of the two shapes' elasticities,
``arb->e = a->e * b->e`` (``cpArbiterUpdate`` in Chipmunk2D ``src/cpArbiter.c``, kept in
Munk2D; Pymunk's ``Arbiter.restitution`` documents it: "The default calculation multiplies
the elasticity of the two shapes together").

How each contact gets its COR (``per_contact``):

- ``per_contact=1`` (default): every shape has elasticity 0 and a ``pre_solve`` callback
  (``Space.on_collision``, Pymunk 7) sets ``arbiter.restitution`` to the contact's COR on
  every step the shapes touch. This works: ``cpArbiterUpdate`` computes ``e`` and then calls
  the handler's pre-solve, and ``cpArbiterPreStep`` (after the callbacks) turns ``e`` into the
  contact's target ``bounce = e * vn``. Any COR can be given to any contact.
- ``per_contact=0``: per-shape elasticities in [0, 1] (Chipmunk advises against 1 or more)
  solved through the product rule on the path of bodies (the cradle's balls; wall S1, disk,
  wall S2): a COR 0 needs a body of elasticity 0, whose other contact then has COR 0 too, so
  e.g. CORs (1, 0, 1) cannot be given; nor can CORs that would need an elasticity above 1
  (e.g. 1, 1/4, 1). Such cases are skipped (:class:`~verify.engines.scene.Unsupported`),
  never run with other CORs. Products agree with the CORs to within one rounding.

What Chipmunk does with the COR: the bounce target ``-e vn`` is taken from the normal
velocity at the start of each step (``cpArbiterPreStep``), with no threshold, and the solver
warm-starts from the previous step's impulses. Positions are integrated BEFORE collision
detection in a step (``cpSpaceStep``), and circles touching at exactly zero distance do not
collide (the test is strict), so with ``overlap=0`` a row of touching balls is hit pair by
pair, one contact per step, as the first ball moves into the second; with a tiny overlap
(the alternate) every contact exists from the first step and the solver converges them
together.

Settings (all changeable with ``--set``):

- ``time_step`` (1/60 s), ``iterations`` (10, ``Space.iterations``' default);
- ``radius`` (10): the balls' and the disk's radius in Pymunk's usual pixel-sized units
  (a body at 100 units/s moves 1.7 units per step, far less than a radius);
- ``overlap`` (0): initial overlap of touching bodies (balls at ``2 radius - overlap``, the
  disk at ``radius - overlap`` from each wall, segments of radius 0);
- ``reverse_order`` (0/1): add the bodies to the space in reverse order (balls N..1; disk,
  S2, S1), which changes the order in which the solver visits the contacts;
- ``per_contact`` (1/0): above; ``max_time`` (1 s): at most this much simulated time.

A case ends after a step that applied no normal impulse (``arbiter.total_impulse`` in
``post_solve``, below 1e-9 of the momentum scale) with no contact approaching (closing speed
below 1e-9 of the fastest initial speed): bodies separating, or resting together. Walls are
static bodies with one segment each, 1000 radii long, from the apex. A cradle's fixed wall
(:attr:`~verify.engines.scene.Cradle.wall`) is one more: a static vertical segment, 2000 radii
long, at ``radius - overlap`` from the last ball's centre; it is body N on the path (ball 1 ..
ball N, wall), so the ``pre_solve`` callback gives its contact ``cors[-1]`` and with
``per_contact=0`` the product rule runs along that path. Gravity off, friction
0, no damping; the disk has unit mass and unit moment of inertia, a ball of mass m has m and
``m radius^2 / 2``.

Alternate setting: ``overlap=1e-6``: all contacts of the row exist from the first step, so
the solver treats them together: it moves the 3-ball eps = 1 cradle from (0, 0, 100) (one
pair per step) to about (-33.3, 66.7, 66.7), the simultaneous law's.

Also noticed: ``iterations=1`` with warm starting (Chipmunk applies the previous step's
impulses first) can GAIN energy: the 3-ball cradle at eps = 0.9 leaves with about twice its
kinetic energy (-40.4, 2.6, 137.8), the ideal pi/12 corner with 3.2 times; at the defaults
the 3-ball eps = 0.99 cradle ends with its first two balls 0.0025 apart in speed and a gap
between them, still approaching after ``max_time`` (the adapter says so on stderr and returns
the velocities it has); a frictionless disk's spin comes out within 1e-13 of its input.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

from verify.engines.common import ContactAdapter, ContactLog, corner_centre, corner_inputs, cradle_inputs, in_order
from verify.engines.scene import Corner, Cradle


class PymunkAdapter(ContactAdapter):
    """Pymunk (Munk2D/Chipmunk2D): a cradle of circles, a circle between two static segments."""

    name: ClassVar[str] = "pymunk"
    rule: ClassVar[str] = "product"
    who: ClassVar[str] = "per-body elasticities multiplied (Chipmunk)"
    tolerance: ClassVar[float] = 1e-9  # double precision

    def checks(self) -> dict[str, bool]:
        return {**super().checks(), "iterations": self.config["iterations"] >= 1}

    def version(self) -> str:
        return str(self.engine().version)

    # -- the space ---------------------------------------------------------------------
    def _space(self, cors: list[float], index: dict[Any, int]) -> tuple[Any, ContactLog, Callable[[], object]]:
        """A space whose handler sets each contact's COR (``per_contact``) and logs the step's impulses;
        the function that steps it. ``index`` maps each shape to its body's place on the path."""
        space = self.engine().Space()
        space.gravity = (0, 0)
        space.iterations = int(self.config["iterations"])
        log = ContactLog(cors, bool(self.config["per_contact"]))

        def pre_solve(arbiter: Any, _space: Any, _data: Any) -> None:
            cor = log.cor(*(index[s] for s in arbiter.shapes))
            if cor is not None:
                arbiter.restitution = cor

        def post_solve(arbiter: Any, _space: Any, _data: Any) -> None:
            log.solved(abs(arbiter.total_impulse))

        space.on_collision(pre_solve=pre_solve, post_solve=post_solve)
        dt = self.config["time_step"]
        return space, log, lambda: space.step(dt)

    def _wall(
        self, space: Any, index: dict[Any, int], i: int, ends: tuple[tuple[float, float], ...], elasticity: float
    ) -> None:
        """A static body with one segment of radius 0 between the two ``ends``, body ``i`` on the path."""
        pm = self.engine()
        body = pm.Body(body_type=pm.Body.STATIC)
        shape = pm.Segment(body, ends[0], ends[1], 0)
        shape.friction, shape.elasticity = 0, elasticity
        space.add(body, shape)
        index[shape] = i

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, v0 = cradle_inputs(scene)
        pm = self.engine()
        index: dict[Any, int] = {}
        space, log, step = self._space(cors, index)
        r, c = self.config["radius"], self.config
        elasticity = self.body_values(cors)
        n, pitch = len(masses), 2 * r - c["overlap"]
        bodies: list[Any] = [None] * n
        for i in in_order(range(n + scene.wall), c["reverse_order"]):
            if i == n:  # the wall, at r - overlap from the last ball's centre
                x = (n - 1) * pitch + r - c["overlap"]
                self._wall(space, index, n, ((x, -1000 * r), (x, 1000 * r)), elasticity[n])
                continue
            body = pm.Body(masses[i], masses[i] * r * r / 2)
            body.position, body.velocity = (i * pitch, 0), (v0[i], 0)
            shape = pm.Circle(body, r)
            shape.friction, shape.elasticity = 0, elasticity[i]
            space.add(body, shape)
            index[shape], bodies[i] = i, body

        def read() -> list[float]:
            return [float(b.velocity.x) for b in bodies]

        return self.settle_cradle(step, log, read, masses, v0, wall=scene.wall)

    def corner(self, scene: Corner) -> list[float]:
        k, cors, (vx, vy, w) = corner_inputs(scene)
        pm = self.engine()
        index: dict[Any, int] = {}
        space, log, step = self._space(cors, index)
        r, c = self.config["radius"], self.config
        elasticity = self.body_values(cors)  # path: S1 (0), disk (1), S2 (2)
        length = 1000 * r
        disk: Any = None
        for i in in_order(range(3), c["reverse_order"]):
            if i == 1:
                disk = pm.Body(1, 1)
                disk.position, disk.velocity = (corner_centre(k, r - c["overlap"]), 0), (vx, vy)
                disk.angular_velocity = w
                shape = pm.Circle(disk, r)
                shape.friction, shape.elasticity = 0, elasticity[i]
                space.add(disk, shape)
                index[shape] = i
            else:
                slope = k if i == 0 else -k  # S1: y = kx, S2: y = -kx, towards negative x
                self._wall(space, index, i, ((0, 0), (-length, -slope * length)), elasticity[i])

        def read() -> list[float]:
            return [float(disk.velocity.x), float(disk.velocity.y), float(disk.angular_velocity)]

        return self.settle_corner(step, log, read, k, [vx, vy, w])


main = PymunkAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
