"""MuJoCo (soft, convex contacts) as an implementation under test.

Engine: ``mujoco`` (pip ``mujoco``), checked with 4.0.0; one MJCF model compiled per case.

MuJoCo has no coefficient of restitution. A contact is a soft constraint whose reference
acceleration is a spring-damper in the penetration ``r``: ``a_ref = -b v - k r``, set by the
contact's ``solref``. With both ``solref`` numbers negative (MuJoCo's "direct" format, documented
in the modeling guide, "Solver parameters" and "Restitution": "set stiffness to some reasonably
large value and damping to zero" for a COR of 1) they are ``(-stiffness, -damping)``, and
``mj_makeImpedance`` (``src/engine/engine_core_constraint.c``) scales them by the impedance so
that at full impedance ``d = solimp[1]`` a single contact follows
``r'' + damping r' + stiffness r = 0`` per unit effective mass: independent of the masses.

Combine rule (for contacts that geoms generate on their own; ``mj_contactParam`` in
``src/engine/engine_collision_driver.c``): the geom of higher ``priority`` wins; at equal
priority a standard ``solref`` is the ``solmix``-weighted mean, a direct ``solref`` the
element-wise minimum, ``solimp`` the weighted mean and friction the maximum. This adapter does
not use it: every constraint is an explicit ``<contact><pair>`` with its own ``solref``
(pairs bypass the mixing) and every geom has ``contype = conaffinity = 0``, so no other contact
exists. Each pair has ``condim = 1`` (frictionless). A cradle's fixed wall
(:attr:`~verify.engines.scene.Cradle.wall`) is a plane geom of the world body facing -x at
``radius - overlap`` from the last ball's centre (as the corner's walls), with its own pair to
the last ball whose ``solref`` comes from ``cors[-1]`` like the balls' pairs.

COR to damping: a linear spring-damper of damping ratio ``zeta`` has
``e = exp(-zeta pi / sqrt(1 - zeta^2))``, so ``zeta = -ln e / sqrt(pi^2 + ln^2 e)`` and
``solref = (-K, -2 zeta sqrt(K))`` with ``K`` the ``stiffness`` setting. ``e = 1`` gives damping 0
(MuJoCo's own recipe); ``e = 0`` maps to ``zeta = 1``, critical damping ``2 sqrt(K)``. The formula
counts the whole half-period of the oscillator, but a contact cannot pull, so it lets go once the
damper would pull, earlier: measured two-ball CORs at the default settings are 1.0012 for
``e = 1``, 0.560 for ``e = 1/2`` and 0.1405 for ``e = 0`` (``exp(-2) = 0.135`` for the continuous
critically damped contact). A COR above 1 (negative damping, which MuJoCo would read as a
standard ``solref``) or below 0 is ``Unsupported``.

Settings (all ``--set``-able): ``timestep`` 1e-4 s with ``stiffness`` 1e6 s^-2 (``omega dt = 0.1``, a
contact lasts about 31 steps; MuJoCo's default 2 ms step would need ``stiffness`` near 2500 and a
penetration of 2 radii at speed 100), ``solimp_dmin``/``solimp_dmax``/``solimp_width`` (MuJoCo's
defaults 0.9, 0.95, 0.001; the last two ``solimp`` numbers keep their defaults 0.5, 2),
``solver`` (0 PGS, 1 CG, 2 Newton, MuJoCo's default), ``iterations`` (MuJoCo's 100), ``overlap``,
``reverse_order`` (bodies and pairs in reverse order) and ``max_time``. Gravity 0. The sphere
radius is 1, or larger when the fastest approach would press in more than a tenth of it
(``10 v / sqrt(K)``), so the spheres never pass through each other; the disk has unit mass and
unit moments of inertia (explicit ``<inertial>``).

What was noticed: the result depends on the impedance ``solimp_dmax`` (the alternate), which
sets the regularisation ``R = (1 - d) / d * A_ii`` shared by simultaneous contacts, far more than on
the solver, its iterations or the integrator (Newton, PGS and CG agree; 1 Newton iteration moves
the cradle by 0.1); the single-contact COR does not depend on it. The time step matters little
while ``omega dt`` is small, but at ``omega dt = 1`` (``timestep`` 1e-3) a COR of 0 comes out as 2.
The solver is order-independent with Newton (``reverse_order`` changes nothing), not with PGS at 1
iteration. ``solimp_width`` is an absolute length, so slow impacts are softer than fast ones (the
slow paper corner differs from the fast one scaled). The impact is over when no contact has been
active for 5 steps and none is approaching (or after ``max_time``). A case during which MuJoCo
warns (an unstable simulation, which MuJoCo silently resets to rest) is skipped with the warning.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

from verify.engines import common
from verify.engines.protocol import Adapter, silenced, whole
from verify.engines.scene import Corner, Cradle, Unsupported

SOLVERS = ("PGS", "CG", "Newton")  #: MuJoCo's mjtSolver, by value
QUIET_STEPS = 5  #: contact-free steps before the impact counts as over
Dof = tuple[str, int]  #: a body's name and an index into its free joint's velocity (vx, vy, vz, wx, wy, wz)


def damping_ratio(e: float) -> float:
    """The damping ratio of a linear spring-damper whose COR is ``e`` (1 for ``e = 0``).

    >>> damping_ratio(1.0), damping_ratio(0.0)
    (0.0, 1.0)
    >>> round(math.exp(-damping_ratio(0.5) * math.pi / math.sqrt(1 - damping_ratio(0.5) ** 2)), 12)
    0.5
    """
    if e <= 0:
        return 1.0
    log = math.log(e)
    return -log / math.sqrt(math.pi**2 + log * log) + 0.0


class MuJoCoAdapter(Adapter):
    """MuJoCo's soft contacts: one explicit contact pair per constraint, restitution through damping."""

    name: ClassVar[str] = "mujoco"
    radius: ClassVar[float | None] = 1.0  # the spheres' radius is at least 1

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"stiffness": c["stiffness"] > 0, "solimp_dmin": 0 < c["solimp_dmin"] < 1,
               "solimp_dmax": 0 < c["solimp_dmax"] < 1,
               "solimp_width": c["solimp_width"] >= 0, "iterations": whole(c["iterations"]),
               "solver": c["solver"] in range(len(SOLVERS))}  # 0 PGS, 1 CG, 2 Newton  # fmt: skip
        return {**super().checks(), **own}

    # -- a model -----------------------------------------------------------------------
    def _solref(self, e: float) -> str:
        if not 0 <= e <= 1:
            raise Unsupported(
                f"COR {e!r}: MuJoCo's direct solref needs a damping >= 0, which covers CORs in [0, 1] only"
            )
        k = self.config["stiffness"]
        return f"{-k!r} {-2 * damping_ratio(e) * math.sqrt(k)!r}"

    def _pair(self, g1: str, g2: str, e: float) -> str:
        c = self.config
        solimp = f"{c['solimp_dmin']!r} {c['solimp_dmax']!r} {c['solimp_width']!r} 0.5 2"
        return f'<pair geom1="{g1}" geom2="{g2}" condim="1" solref="{self._solref(e)}" solimp="{solimp}"/>'

    def _model(self, bodies: list[str], pairs: list[str]) -> str:
        c = self.config
        bodies, pairs = common.in_order(bodies, c["reverse_order"]), common.in_order(pairs, c["reverse_order"])
        option = (
            f'<option timestep="{c["timestep"]!r}" gravity="0 0 0" solver="{SOLVERS[int(c["solver"])]}" '
            f'iterations="{int(c["iterations"])}"/>'
        )
        return (
            f'<mujoco model="verify">{option}<worldbody>{"".join(bodies)}</worldbody>'
            f"<contact>{''.join(pairs)}</contact></mujoco>"
        )

    def _radius(self, speed: float) -> float:
        return max(1.0, 10 * speed / math.sqrt(self.config["stiffness"]))

    @staticmethod
    def _ball(name: str, pos: tuple[float, float], mass: float, inertia: float, radius: float) -> str:
        return (
            f'<body name="{name}" pos="{pos[0]!r} {pos[1]!r} 0"><freejoint/>'
            f'<inertial pos="0 0 0" mass="{mass!r}" diaginertia="{inertia!r} {inertia!r} {inertia!r}"/>'
            f'<geom name="{name}" type="sphere" size="{radius!r}" contype="0" conaffinity="0"/></body>'
        )

    @staticmethod
    def _plane(name: str, normal: tuple[float, float], pos: tuple[float, float] | None = None) -> str:
        """A fixed wall: a plane geom of the world body, facing ``normal``, through ``pos`` (by default the origin)."""
        at = "" if pos is None else f' pos="{pos[0]!r} {pos[1]!r} 0"'
        return (
            f'<geom name="{name}" type="plane" size="0 0 1"{at} zaxis="{normal[0]!r} {normal[1]!r} 0" '
            'contype="0" conaffinity="0"/>'
        )

    def _simulate(
        self, xml: str, velocity: dict[Dof, float], read: list[Dof], closing: Callable[[list[float]], float]
    ) -> list[float]:
        """Run a model from the given velocities until the impact is over; the ``read`` velocities.

        A :data:`Dof` is (body name, index in the body's free joint: 0..2 linear, 3..5 angular).
        """
        mj = self.engine()
        warnings: list[str] = []
        previous = mj.get_mju_user_warning()
        mj.set_mju_user_warning(warnings.append)  # instead of stderr and a MUJOCO_LOG.TXT in the cwd
        try:
            with silenced():
                v = self._steps(mj, xml, velocity, read, closing)
        finally:
            mj.set_mju_user_warning(previous)
        if warnings:  # e.g. an unstable simulation, which MuJoCo resets to rest and goes on with
            raise Unsupported(f"MuJoCo warned: {warnings[0]}")
        return v

    @staticmethod
    def model(mj: Any, xml: str, velocity: dict[Dof, float], read: list[Dof]) -> tuple[Any, Any, list[int]]:
        """The compiled model, its data with the velocities set, and the addresses of the velocities to read
        (:class:`Unsupported` when MuJoCo rejects the model)."""
        try:
            m = mj.MjModel.from_xml_string(xml)
        except ValueError as exc:
            raise Unsupported(f"MuJoCo rejected the model: {exc}") from None
        d = mj.MjData(m)

        def address(dof: Dof) -> int:
            return int(m.body_dofadr[m.body(dof[0]).id]) + dof[1]

        for dof, x in velocity.items():
            d.qvel[address(dof)] = x
        return m, d, [address(dof) for dof in read]

    def _steps(
        self, mj: Any, xml: str, velocity: dict[Dof, float], read: list[Dof], closing: Callable[[list[float]], float]
    ) -> list[float]:
        m, d, out = self.model(mj, xml, velocity, read)
        v, _ = common.settle(
            lambda: mj.mj_step(m, d),
            lambda: [float(d.qvel[i]) for i in out],
            steps=max(1, math.ceil(self.config["max_time"] / self.config["timestep"])),
            still=lambda _before, _after: not d.nefc,  # no active contact
            approaching=lambda v: closing(v) > 0,
            quiet=QUIET_STEPS,
        )
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, vel = common.cradle_inputs(scene)
        n = len(masses)
        names = [f"b{i}" for i in range(n)] + ["wall"] * scene.wall  # the path of bodies
        pairs = [self._pair(names[i], names[i + 1], e) for i, e in enumerate(cors)]
        speeds = [*vel, 0.0] if scene.wall else vel  # the wall stands still
        radius = self._radius(max(speeds) - min(speeds))
        pitch = 2 * radius - self.config["overlap"]
        bodies = [self._ball(f"b{i}", (i * pitch, 0.0), m, 0.4 * m * radius**2, radius) for i, m in enumerate(masses)]
        if scene.wall:  # a plane facing -x, at radius - overlap from the last ball's centre
            bodies.append(self._plane("wall", (-1.0, 0.0), ((n - 1) * pitch + radius - self.config["overlap"], 0.0)))
        xs = [(f"b{i}", 0) for i in range(n)]
        model = self._model(bodies, pairs)
        return self._simulate(model, dict(zip(xs, vel)), xs, lambda v: common.cradle_closing(v, scene.wall))

    def corner(self, scene: Corner) -> list[float]:
        k, cors, vel = common.corner_inputs(scene)
        radius = self._radius(math.hypot(vel[0], vel[1]))
        centre = common.corner_centre(k, radius - self.config["overlap"])
        # towards the admissible side x <= -|y|/k
        walls = [self._plane(f"s{j + 1}", (n[0], n[1])) for j, n in enumerate(common.wall_normals(k))]
        bodies = [*walls, self._ball("disk", (centre, 0.0), 1.0, 1.0, radius)]
        pairs = [self._pair("disk", f"s{j + 1}", e) for j, e in enumerate(cors)]
        # a free joint's angular velocity is in the body frame; the disk turns about z only
        dofs = [("disk", 0), ("disk", 1), ("disk", 5)]
        return self._simulate(
            self._model(bodies, pairs), dict(zip(dofs, vel)), dofs, lambda v: common.corner_closing(k, v)
        )


main = MuJoCoAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
