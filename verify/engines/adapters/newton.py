"""Newton (checked with 1.8.0 on NVIDIA Warp 1.19.0, CPU device) as an implementation under test.

Engine: Newton (pip ``newton``), a GPU-first physics library written in NVIDIA Warp, run here
on Warp's CPU device (``device="cpu"``: Warp compiles each kernel module with its bundled
LLVM/Clang on first use and caches it in ``~/.cache/warp/<warp version>``; a cold cache costs a
long compile per solver, a warm one a short start-up).
Float32 throughout. This
module is ``verify.engines.adapters.newton``; it imports the engine lazily with ``import newton``, which
(absolute imports) finds the installed top-level package, not this module. Warp prints its
banner and kernel-compile lines on standard output, so all engine work runs with standard
output silenced (:func:`~verify.engines.protocol.silenced`).

Solvers (setting ``solver``): Newton has several; two apply a coefficient of restitution to
rigid contacts.

- ``solver=0``: ``SolverXPBD`` (extended position-based dynamics, Mueller et al. 2020) with
  ``enable_restitution=True``. A step projects positions (``iterations`` Jacobi-style
  iterations, each body's correction divided by its number of active contacts,
  ``rigid_contact_con_weighting``, which the solver's docstring says does not conserve
  momentum), derives velocities, then runs a velocity pass for contacts that penetrated during
  the projection (``newton/_src/solvers/xpbd/restitution_kernels.py``:
  ``mark_restitution_contacts``, ``build_restitution_manifolds``,
  ``solve_manifold_restitution``): contacts are grouped per body pair; each pair is solved by 8
  Gauss-Seidel sweeps of accumulated, lower-bounded impulses towards the target ``-e u_old``
  taken from the PRE-solve velocity of the step; pairs are coupled by averaging each body's
  velocity change over the pairs that fired (Jacobi), repeated ``restitution_iterations``
  times (``rigid_contact_restitution_iterations``, default 2). Threshold:
  ``impact_threshold = 2 |g| dt``, 0 here (gravity off): any approaching contact bounces.
- ``solver=1``: ``SolverSteel``, a reduced-coordinate projected Gauss-Seidel solver
  (``solve_mode="serial"``, ``steel_iterations`` sweeps, default 12): an impacting contact
  replaces its position bias by the rebound target ``-e u_start`` (the relative normal
  velocity at the START of the step) as a lower bound on its separating velocity, only if it
  closes faster than ``restitution_velocity_threshold`` (default 0.5 m/s, strict:
  ``contact_restitution_target`` in ``newton/_src/solvers/steel/kernels.py`` returns 0 when
  ``u_start >= -threshold``), and only if it touches or is predicted to reach the surface in
  the step (the ``SolverSteel.__init__`` docstring).

Newton's other solvers are not used: ``SolverSemiImplicit`` and ``SolverFeatherstone`` have
penalty contacts (``ke``/``kd``, no restitution); ``SolverMuJoCo`` runs MuJoCo Warp, which has
its own adapter (``verify.engines.adapters.mujoco_warp``); ``SolverVBD`` has no rigid restitution;
``SolverKamino`` has restitution (``restitution_mix_mode``, default "min") and is not wired
here yet. The ``solver`` description (``--describe``) is the chosen solver's: XPBD's is of kind
"position-based" (a projection then a Jacobi-coupled velocity pass: no sequential or
simultaneous impulse model fits, so it names no sweeps count), Steel's "sequential".

Combine rule: both solvers take the ARITHMETIC MEAN of the two shapes' ``restitution``
(``ShapeConfig.restitution``): XPBD in ``build_restitution_manifolds``
(``restitution_kernels.py``: the sum over the two shapes divided by their count, no clamp; a
negative mean skips the contact), Steel in ``mixed_contact_restitution``
(``steel/kernels.py``: each value clamped to [0, 1] first). Static walls are shapes with their
own restitution, so every contact has two.

How each contact gets its COR (``per_contact``):

- ``per_contact=1`` (default): each contact gets its own pair of shapes. A ball gets one
  sphere shape per neighbour (two coincident spheres of the same radius on the same body,
  no mass of their own: ``density=0``, ``lock_inertia``), the disk one sphere per wall; the
  two shapes of a contact both have the contact's COR, so their mean IS the COR (exactly, in
  float32), and ``ModelBuilder.add_shape_collision_filter_pair`` filters every other pair of
  shapes. Any COR in [0, inf) for XPBD, [0, 1] for Steel (its clamp). A contact between
  bodies that are not neighbours is filtered out, so it can never happen (in a row of balls
  it cannot without a ball passing through another).
- ``per_contact=0``: one shape per body, per-body values through the mean rule on the path
  of bodies (the balls; wall S1, disk, wall S2): ``r_i + r_(i+1) = 2 e_i`` leaves one free
  value, taken in the middle of the interval that keeps every value >= 0 (and <= 1 for
  Steel); equal CORs give every body the COR. When no such values exist (e.g. CORs (1, 0) for
  Steel: values (1, 1, -1)) the case is skipped (``Unsupported``), never run with other CORs.

Settings (all changeable with ``--set``):

- ``solver`` (0 XPBD, 1 Steel); ``time_step`` (1e-3 s, one ``solver.step`` per step, no
  substeps: a body at 100 m/s moves a tenth of a radius per step);
- XPBD: ``iterations`` (2, its default position iterations), ``restitution_iterations`` (2,
  its default ``rigid_contact_restitution_iterations``), ``contact_weighting`` (1/0, its
  ``rigid_contact_con_weighting``, default on);
- Steel: ``steel_iterations`` (12, its default ``iterations``), ``restitution_threshold`` (0.5,
  its default ``restitution_velocity_threshold``); its default angular damping of free bodies
  (``steel:rigid_body_angular_damping`` 0.05 1/s, PhysX's, which slows a spinning disk by
  1.5e-4 of its spin per step) is set to 0 through ``SolverSteel.register_custom_attributes``;
- ``radius`` (1), ``overlap`` (0, initial overlap of touching bodies), ``rigid_gap`` (0.1,
  ``ModelBuilder.rigid_gap``' default: the contact detection gap, contacts within it are
  generated speculatively);
- ``reverse_order`` (0/1: bodies and shapes made in reverse order), ``per_contact`` (1/0),
  ``max_time`` (1 s).

Bodies: free bodies (``add_body``), sphere shapes, gravity 0, no friction of any kind
(``mu``, ``mu_torsional`` and ``mu_rolling`` 0: ``ShapeConfig`` defaults them to 1, 0.005 and
1e-4); a ball of mass m has inertia ``2/5 m r^2``; the disk is a sphere of unit mass and unit
moments of inertia, started with angular velocity ``omega`` about z; the walls are infinite
static planes (``add_shape_plane``, width = length = 0) through the apex, normals
``(-k, +-1, 0)`` (unit) towards the admissible side. Velocities are set as the free joints'
``joint_qd`` (linear then angular, world frame) and spread to the bodies by ``newton.eval_fk``
(Steel integrates joint coordinates); exit velocities are read from ``State.body_qd`` (centre
of mass velocity and world angular velocity). Each step: ``CollisionPipeline.collide`` then
``solver.step``. A case ends when for 5 steps in a row no velocity changed by more than 1e-6
of the fastest initial speed and no contact is approaching (closing speed at most 1e-6 of it),
or after ``max_time`` (said on stderr).

Alternate setting: ``solver=1`` (Steel). It gives the 3-ball eps = 1 cradle the simultaneous
law's (-33.3333, 66.6667, 66.6667) (all contacts exist from the first step and 12 Gauss-Seidel
sweeps converge), where XPBD gives (-23.0, 43.0, 60.0). On the engine cases (with the 52 cases
of ``verify.engines.run.engine_cases``) Steel's answers are within float32 precision (1e-5
of the speed) of an exact model on 39 of 52: the simultaneous law, or the sequential law with
12 (or 13) sweeps and the 0.5 threshold; XPBD's on 3.

Also noticed: XPBD does not conserve momentum on a row of balls: the 3-ball cradle leaves with
momentum 80 at eps = 1 (-23, 43, 60) and 105 at eps = 0 (29.04, 35.00, 40.96: the balls
separate, the projection's overshoot kept), from 100; the position projection's contact
weighting (documented in ``SolverXPBD``) and the restitution pass's averaging over the body
pairs (Jacobi) both scale a middle ball's response. More restitution iterations move it
(``restitution_iterations=20``: (-40, 60, 60)), more position iterations too
(``iterations=10``: (-27.42, 47.42, 60.0)); neither reaches a law. Two balls come out exact
((0, 100) at eps = 1, (25, 75) at 1/2, (50, 50) at 0). The paper corner with XPBD leaves at
(-28.70, 16.49, 0), the simultaneous law's (-25.93, 14.89, 0) with ``iterations=10``. XPBD turns
a spinning disk's spin at a contact (3 -> 3.0077 rad/s at slope 1/2: the contact point, stored
in the body's frame, turns with it during the step). Steel's threshold of 0.5 m/s is the slow
cases' approach speed or more, and the comparison is strict, so they do not bounce: the slow
3-ball eps = 1 cradle leaves at (1/6, 1/6, 1/6). A cold kernel cache makes the first run
several times longer (``time verify engines --engine newton`` measures it).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from typing import Any, ClassVar

from verify.engines import common
from verify.engines.protocol import Adapter, description, import_engine, silenced, whole
from verify.engines.scene import Corner, Cradle, Unsupported

SOLVERS = ("XPBD", "Steel")  #: the ``solver`` setting's values
QUIET_STEPS = 5  #: steps without a change before the impact counts as over
TOLERANCE = 1e-6  #: relative: float32 engine


def mean_rule_values(cors: Sequence[float], *, bounded: bool) -> list[float]:
    """Per-body values ``r`` with ``(r[i] + r[i+1]) / 2 == cors[i]``, all >= 0 (and <= 1 when ``bounded``).

    ``r[i] = s[i] + (-1)^i t`` for one free ``t``, taken in the middle of the interval that keeps
    every value in range; :class:`Unsupported` when the interval is empty.

    >>> mean_rule_values([0.5, 0.5], bounded=True)
    [0.5, 0.5, 0.5]
    >>> mean_rule_values([1.0, 0.0], bounded=False)
    [2.0, 0.0, 0.0]
    >>> mean_rule_values([1.0, 0.0], bounded=True)
    Traceback (most recent call last):
    ...
    verify.engines.scene.Unsupported: per-body restitutions averaged (Newton Steel, each clamped to [0, 1]) ...
    """
    who = "per-body restitutions averaged " + ("(Newton Steel, each clamped to [0, 1])" if bounded else "(Newton XPBD)")
    if any(c < 0 or (bounded and c > 1) for c in cors):
        raise Unsupported(f"CORs {list(cors)!r}: {who} give CORs in {'[0, 1]' if bounded else '[0, inf)'} only")
    s = [0.0]
    for i, c in enumerate(cors):
        s.append(2 * c - s[i])  # r[i+1] = 2 c - r[i], with t = 0
    lo, hi = -math.inf, math.inf
    for i, x in enumerate(s):  # r[i] = x + t (i even), x - t (i odd), in [0, 1 or inf)
        top = 1.0 if bounded else math.inf
        if i % 2 == 0:
            lo, hi = max(lo, -x), min(hi, top - x)
        else:
            lo, hi = max(lo, x - top), min(hi, x)
    if lo > hi + 1e-12:
        raise Unsupported(f"{who} cannot give the CORs {list(cors)!r}: no per-body values in range")
    t = (lo + hi) / 2
    return [max(0.0, x + t if i % 2 == 0 else x - t) for i, x in enumerate(s)]


class NewtonAdapter(Adapter):
    """Newton on Warp's CPU device: XPBD (solver=0) or Steel (solver=1); spheres and planes."""

    name: ClassVar[str] = "newton"

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"solver": c["solver"] in range(len(SOLVERS)), "iterations": whole(c["iterations"]),
               "restitution_iterations": whole(c["restitution_iterations"]),
               "contact_weighting": c["contact_weighting"] in (0, 1), "steel_iterations": whole(c["steel_iterations"]),
               "restitution_threshold": c["restitution_threshold"] >= 0,
               "rigid_gap": c["rigid_gap"] >= 0}  # fmt: skip
        return {**super().checks(), **own}

    # -- the engine --------------------------------------------------------------------
    def engine(self) -> Any:
        """Newton, with Warp initialised on its CPU device (:class:`CannotRun` if Warp cannot run there)."""
        newton = import_engine(self.module)
        common.warp_on_cpu("newton", newton.__version__)
        return newton

    def version(self) -> str:
        newton = self.engine()
        return f"{newton.__version__} (warp {import_engine('warp').__version__}, device cpu)"

    def describe(self) -> dict[str, Any]:
        out = super().describe()
        steel = description(self.name)["steel_solver"]  # the solver in use: XPBD's (the default) or Steel's
        out["solver"] = {**Adapter.solver, **(self.solver if self.config["solver"] == 0 else steel)}
        return out

    # -- a model -----------------------------------------------------------------------
    def _shape_cfg(self, newton: Any, restitution: float) -> Any:
        # no friction of any kind (ShapeConfig's defaults: mu 1, mu_torsional 0.005, mu_rolling 1e-4), no mass
        return newton.ModelBuilder.ShapeConfig(
            mu=0.0, mu_torsional=0.0, mu_rolling=0.0, restitution=restitution, density=0.0
        )

    def _solver(self, newton: Any, model: Any) -> Any:
        c = self.config
        if c["solver"] == 0:
            return newton.solvers.SolverXPBD(
                model,
                iterations=int(c["iterations"]),
                rigid_contact_restitution_iterations=int(c["restitution_iterations"]),
                rigid_contact_con_weighting=bool(c["contact_weighting"]),
                enable_restitution=True,
            )
        return newton.solvers.SolverSteel(
            model,
            iterations=int(c["steel_iterations"]),
            enable_restitution=True,
            restitution_velocity_threshold=c["restitution_threshold"],
        )

    def _values(self, cors: Sequence[float]) -> list[float] | None:
        """Per-body restitutions with ``per_contact=0``; None with ``per_contact=1``."""
        if self.config["per_contact"]:
            bounded = self.config["solver"] == 1
            if any(c < 0 or (bounded and c > 1) for c in cors):
                span = "[0, 1] (Steel clamps each shape's value)" if bounded else "[0, inf)"
                raise Unsupported(f"CORs {list(cors)!r}: Newton {SOLVERS[int(self.config['solver'])]} takes {span}")
            return None
        return mean_rule_values(cors, bounded=self.config["solver"] == 1)

    def _simulate(
        self,
        build: Callable[[Any, Any], list[tuple[int, list[float]]]],
        read: Callable[[Any], list[float]],
        closing: Callable[[list[float]], float],
        speed: float,
    ) -> list[float]:
        """Build a model (``build(newton, builder)`` makes the bodies and returns each one's index and
        initial velocity ``[vx, vy, vz, wx, wy, wz]``), run it until the impact is over, ``read`` the state."""
        newton = self.engine()
        with silenced():
            builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
            builder.rigid_gap = self.config["rigid_gap"]
            steel = self.config["solver"] == 1
            if steel:  # Steel damps free bodies' spin by default (0.05 1/s, PhysX's): its attribute, set to 0 below
                newton.solvers.SolverSteel.register_custom_attributes(builder)
            starts = build(newton, builder)
            model = builder.finalize(device="cpu")
            if steel:
                model.steel.rigid_body_angular_damping.fill_(0.0)
            state, other = model.state(), model.state()
            qd = state.joint_qd.numpy()
            dof_start = model.joint_qd_start.numpy()
            joint_of = {int(body): joint for joint, body in enumerate(model.joint_child.numpy())}
            for body, v in starts:
                start = int(dof_start[joint_of[body]])
                qd[start : start + 6] = v  # a free joint: linear, then angular velocity
            state.joint_qd.assign(qd)
            newton.eval_fk(model, state.joint_q, state.joint_qd, state)
            pipeline = newton.CollisionPipeline(model)
            contacts = pipeline.contacts()
            solver = self._solver(newton, model)
            control = model.control()
            dt = self.config["time_step"]
            states = [state, other]

            def step() -> None:
                states[0].clear_forces()
                pipeline.collide(states[0], contacts)
                solver.step(states[0], states[1], control, contacts, dt)
                states.reverse()

            tol = TOLERANCE * (speed or 1.0)
            v, over = common.settle(
                step,
                lambda: read(states[0]),
                steps=max(1, math.ceil(self.config["max_time"] / dt - 1e-9)),
                still=lambda a, b: max(abs(x - y) for x, y in zip(a, b)) <= tol,
                approaching=lambda v: not closing(v) <= tol,  # a NaN closing speed never ends a case
                quiet=QUIET_STEPS,
            )
        if not over:
            print(
                f"{self.name}: after max_time = {self.config['max_time']} s: closing speed {closing(v)!r}",
                file=sys.stderr,
            )
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, v0 = common.cradle_inputs(scene)

        def side_shapes(side: dict[int, int], ball: int) -> list[int]:
            return [side[ball]] if ball in side else []

        values = self._values(cors)
        c, r = self.config, self.config["radius"]
        n = len(masses)
        bodies: list[int] = [0] * n  # ball -> body index (bodies are numbered in the order they are made)

        def build(newton: Any, b: Any) -> list[tuple[int, list[float]]]:
            import warp as wp

            left: dict[int, int] = {}  # ball -> its shape facing ball - 1
            right: dict[int, int] = {}  # ball -> its shape facing ball + 1
            for i in common.in_order(range(n), c["reverse_order"]):
                m = masses[i]
                inertia = 0.4 * m * r * r
                body = b.add_body(
                    xform=wp.transform(wp.vec3(i * (2 * r - c["overlap"]), 0.0, 0.0), wp.quat_identity()),
                    mass=m,
                    inertia=wp.mat33(inertia, 0.0, 0.0, 0.0, inertia, 0.0, 0.0, 0.0, inertia),
                    lock_inertia=True,
                )
                bodies[i] = body
                if values is not None:
                    right[i] = left[i] = b.add_shape_sphere(body, radius=r, cfg=self._shape_cfg(newton, values[i]))
                    continue
                sides = [("left", i - 1), ("right", i)]
                for side, j in common.in_order(sides, c["reverse_order"]):
                    if 0 <= j < n - 1:
                        shape = b.add_shape_sphere(body, radius=r, cfg=self._shape_cfg(newton, cors[j]))
                        (left if side == "left" else right)[i] = shape
            if values is None:
                keep = {(right[i], left[i + 1]) for i in range(n - 1)}
                shapes = [(i, s) for i in range(n) for s in sorted({*side_shapes(left, i), *side_shapes(right, i)})]
                for x, (i, s) in enumerate(shapes):
                    for j, t in shapes[x + 1 :]:
                        if i != j and (s, t) not in keep and (t, s) not in keep:
                            b.add_shape_collision_filter_pair(s, t)
            return [(bodies[i], [v0[i], 0.0, 0.0, 0.0, 0.0, 0.0]) for i in range(n)]

        def read(state: Any) -> list[float]:
            qd = state.body_qd.numpy()
            return [float(qd[bodies[i]][0]) for i in range(n)]

        return self._simulate(build, read, common.cradle_closing, max(map(abs, v0)) or 1.0)

    def corner(self, scene: Corner) -> list[float]:
        k, cors, (vx, vy, w) = common.corner_inputs(scene)
        values = self._values(cors)  # path: S1 (0), disk (1), S2 (2)
        c, r = self.config, self.config["radius"]
        disk_body: list[int] = []

        def build(newton: Any, b: Any) -> list[tuple[int, list[float]]]:
            import warp as wp

            walls: dict[int, int] = {}
            disk_shapes: dict[int, int] = {}
            for i in common.in_order(range(3), c["reverse_order"]):
                if i == 1:
                    body = b.add_body(
                        xform=wp.transform(
                            wp.vec3(common.corner_centre(k, r - c["overlap"]), 0.0, 0.0), wp.quat_identity()
                        ),
                        mass=1.0,
                        inertia=wp.mat33(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
                        lock_inertia=True,
                    )
                    disk_body.append(body)
                    if values is not None:
                        shape = b.add_shape_sphere(body, radius=r, cfg=self._shape_cfg(newton, values[1]))
                        disk_shapes[0] = disk_shapes[1] = shape
                    else:
                        for j in common.in_order(range(2), c["reverse_order"]):
                            disk_shapes[j] = b.add_shape_sphere(body, radius=r, cfg=self._shape_cfg(newton, cors[j]))
                else:
                    j = 0 if i == 0 else 1
                    nx, ny = common.wall_normals(k)[j]
                    norm = math.hypot(nx, ny)
                    e = values[i] if values is not None else cors[j]
                    walls[j] = b.add_shape_plane(
                        plane=(nx / norm, ny / norm, 0.0, 0.0), width=0.0, length=0.0, cfg=self._shape_cfg(newton, e)
                    )
            if values is None:
                b.add_shape_collision_filter_pair(disk_shapes[0], walls[1])
                b.add_shape_collision_filter_pair(disk_shapes[1], walls[0])
            return [(disk_body[0], [vx, vy, 0.0, 0.0, 0.0, w])]

        def read(state: Any) -> list[float]:
            qd = state.body_qd.numpy()[disk_body[0]]
            return [float(qd[0]), float(qd[1]), float(qd[5])]

        return self._simulate(build, read, lambda v: common.corner_closing(k, v), math.hypot(vx, vy) or 1.0)


main = NewtonAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
