"""Genesis (rigid solver: MuJoCo-style soft, convex contacts) as an implementation under test.

Engine: ``genesis`` (pip ``genesis-world``, which wants ``torch`` installed beside it), checked with
1.4.5 on its CPU backend (``gs.init(backend=gs.cpu, precision="64")``, once per process). Its
kernels are compiled by Quadrants (its fork of Taichi) at the first ``scene.build()`` and cached on
disk (``~/.cache/quadrants``), so the first run of ``verify engines`` is much longer than the next ones
(importing Genesis and torch is a large part of a warm run).
This adapter builds one scene per cradle size and per corner slope and resets it between cases.

Genesis's rigid solver has no coefficient of restitution. ``gs.materials.Rigid(coup_restitution=...)``
only acts in the coupler between the rigid solver and the particle solvers
(``engine/couplers/legacy_coupler.py``); its own USD importer drops a physics material's
restitution, saying "The Genesis rigid solver has no rigid-rigid restitution coefficient; contact
elasticity is governed by ``sol_params`` instead" (``utils/usd/usd_context.py``). A contact is a
soft constraint, as in MuJoCo: its reference acceleration is ``aref = -b v - k imp r`` with
``b = 2 / (dmax timeconst)`` and ``k = 1 / (dmax^2 timeconst^2 dampratio^2)`` (``imp_aref`` in
``utils/geom.py``), set by seven ``sol_params`` (``timeconst, dampratio, dmin, dmax, width, mid,
power``: MuJoCo's standard ``solref`` and ``solimp``). At full impedance a single contact follows
``r'' + (2 / timeconst) r' + r / (timeconst dampratio)^2 = 0``: a spring-damper of natural frequency
``1 / (timeconst dampratio)`` and damping ratio ``dampratio``. MuJoCo's direct format (negative
``timeconst``: stiffness and damping themselves) is not supported: Genesis warns and uses its
default instead, and it rejects ``dampratio <= 0`` (``_sanitize_sol_params`` in
``engine/solvers/rigid/rigid_solver.py``).

Combine rule: each geom has its own ``sol_params``, and a contact takes their element-wise mean,
``0.5 * (sol_params[a] + sol_params[b])``, its ``timeconst`` then floored at twice the step
(``func_set_contact_data`` in ``engine/solvers/rigid/collider/contact.py``); no per-pair parameters
exist (the MJCF importer, ``utils/mjcf.py``, reads ``<exclude>`` but no ``<pair>``, and ``condim`` only
for torsional and rolling friction). Friction is the larger of the two geoms' values, floored at 0.01
in the same place: no contact can be frictionless.

How each contact gets its own COR: the COR is mapped to a spring-damper as in
:mod:`verify.engines.adapters.mujoco`: damping ratio ``zeta = -ln e / sqrt(pi^2 + ln^2 e)`` (so that
``e = exp(-zeta pi / sqrt(1 - zeta^2))``), natural frequency ``sqrt(K)`` with ``K`` the
``stiffness`` setting, i.e. ``dampratio = zeta`` and ``timeconst = 1 / (sqrt(K) zeta)``. ``e = 0``
maps to ``zeta = 1`` (critical damping); ``e = 1`` would need ``zeta = 0``, which Genesis rejects, so
``zeta`` is at least 1e-12 (a linear COR of ``1 - 3e-12``, ``timeconst`` 1e9 s). Each contact's
``(timeconst, dampratio)`` is then solved for per-geom values whose means they are (the bodies lie on a
path: the balls in a row; wall S1, the disk, wall S2): along the path ``x_(i+1) = 2 t_i - x_i`` from a
free first value, chosen in the middle of the range that keeps every value positive (so the
smallest is as large as it can be; equal CORs give equal values). When no positive values exist
the case is ``Unsupported``; so are CORs outside [0, 1]. ``dmin``, ``dmax`` and ``width`` are the same
for every geom, hence for every contact.

Settings (all ``--set``-able): ``timestep`` 1e-4 s with ``stiffness`` 1e6 s^-2 (``omega dt = 0.1``, a
contact lasts about 31 steps, as in the MuJoCo adapter; Genesis's default 10 ms step would floor
``timeconst`` at 20 ms), ``solimp_dmin``/``solimp_dmax``/``solimp_width`` (Genesis's defaults 0.9, 0.95,
0.001, as MuJoCo's; ``mid`` 0.5 and ``power`` 2 keep theirs), ``solver`` (0 CG, 1 Newton, Genesis's
default), ``iterations`` (Genesis's 25; the solver stops earlier at its tolerance, 1e-8 in double
precision), ``integrator`` (0 Euler, 1 implicitfast, 2 approximate_implicitfast, Genesis's default),
``friction`` (0: the corner is ``Unsupported``, since Genesis floors friction at 0.01; a value of at
least 0.01 runs the corner with that friction; the cradle is head-on, so friction exerts no force
there and every ball gets the floor), ``overlap``, ``reverse_order`` (entities made last-first) and
``max_time``. Gravity 0. Spheres of radius ``sqrt(5/2)`` and density ``1 / volume`` (unit mass, so the
disk's moment of inertia ``2/5 m R^2`` is 1; checked), each case's masses then set with
``RigidEntity.set_mass``, which scales the inertia with the mass (Genesis refuses to set a
primitive's inertia directly); the corner's walls are fixed ``Plane`` entities through the origin, and
a cradle's wall (:attr:`~verify.engines.scene.Cradle.wall`) a fixed ``Plane`` facing -x at
``radius - overlap`` from the last ball's centre, the last body of the path (its geom takes part in
the mean).

What was noticed: measured two-ball CORs at the default settings are 1.0013 for ``e = 1``, 0.553 for
``e = 1/2`` and 0.136 for ``e = 0`` (at speed 1/2: 1.0006, 0.545, 0.131; ``solimp_width`` is an
absolute length), close to the MuJoCo adapter's. The 3-ball cradle at ``e = 1`` comes out near the
simultaneous answer, ``(-33.59, 66.53, 67.06)``, with a small gain of energy. The result depends on
the impedance ``solimp_dmax`` (the alternate) and on ``iterations`` (1 iteration moves the
``e = 1/2`` cradle from -4.04 to -9.57 for the first ball), not on the solver (CG and Newton agree
to about 1e-8), the integrator (no velocity-dependent force acts) or the order of the entities
(``reverse_order`` moves no result by more than 2e-11 of its scale); at ``timestep`` 1e-3
(``omega dt = 1``) the ``e = 1`` cradle gains a quarter of its energy, ``(-37.6, 41.2, 96.4)``. Run with
``friction = 0.01``, the paper's corner leaves with a spin of about 2.6 rad/s that the frictionless
laws do not give. Runs are deterministic (the same digits twice). The impact is over when the
velocities have not changed for 5 steps (no contact force acts) and no contact is approaching (or
after ``max_time``, said on stderr). A setting or state that Genesis refuses (a
``GenesisException``) skips the case with its message.
"""

from __future__ import annotations

import contextlib
import functools
import math
import sys
from collections.abc import Callable, Iterator, Sequence
from typing import Any, ClassVar

from verify.engines import common
from verify.engines.protocol import Adapter, CannotRun, import_engine, silenced, whole
from verify.engines.scene import Corner, Cradle, Unsupported

RADIUS = math.sqrt(2.5)  #: 2/5 m R^2 = 1 for the unit-mass disk
VOLUME = 4 / 3 * math.pi * RADIUS**3  #: a sphere's volume (its density is 1 / VOLUME: unit mass)
ZETA_MIN = 1e-12  #: the smallest damping ratio given (Genesis rejects 0)
FRICTION_FLOOR = 0.01  #: Genesis's smallest contact friction (collider/contact.py)
QUIET_STEPS = 5  #: steps without a change of velocity before the impact counts as over
SOLVERS = ("CG", "Newton")  #: gs.constraint_solver, by value
INTEGRATORS = ("Euler", "implicitfast", "approximate_implicitfast")  #: gs.integrator, by value


def damping_ratio(e: float) -> float:
    """The damping ratio of a linear spring-damper whose COR is ``e`` (1 for ``e = 0``), at least :data:`ZETA_MIN`.

    >>> damping_ratio(1.0), damping_ratio(0.0)
    (1e-12, 1.0)
    """
    if e <= 0:
        return 1.0
    log = math.log(e)
    return max(-log / math.sqrt(math.pi**2 + log * log), ZETA_MIN)


def mean_values(targets: Sequence[float], what: str) -> list[float]:
    """Positive values ``x`` with ``(x[i] + x[i+1]) / 2 == targets[i]``, the smallest as large as it can be.

    :class:`Unsupported` when no positive values exist.

    >>> mean_values([2.0, 2.0], "t")
    [2.0, 2.0, 2.0]
    >>> mean_values([1.0, 3.0], "t")
    [1.0, 1.0, 5.0]
    >>> mean_values([3.0, 1.0, 3.0], "t")
    [5.0, 1.0, 1.0, 5.0]
    >>> mean_values([1.0, 3.0, 1.0], "t")  # x[1] + x[2] = 6 with x[1], x[2] < 2
    Traceback (most recent call last):
    ...
    verify.engines.scene.Unsupported: no positive per-geom t has the means [1.0, 3.0, 1.0] ...
    """
    # x[i] = sign[i] * x[0] + c[i]
    c, sign = [0.0], [1.0]
    for t in targets:
        c.append(2 * t - c[-1])
        sign.append(-sign[-1])
    low = max(-ci for ci, s in zip(c, sign) if s > 0)  # x[0] > low keeps the even-indexed values positive
    high = min(ci for ci, s in zip(c, sign) if s < 0)  # x[0] < high keeps the odd-indexed ones positive
    if not low < high:
        raise Unsupported(
            f"no positive per-geom {what} has the means {list(targets)!r} (Genesis gives a contact the mean of "
            "its two geoms' sol_params)"
        )
    first = (low + high) / 2
    return [s * first + ci for ci, s in zip(c, sign)]


class GenesisAdapter(Adapter):
    """Genesis's rigid solver on the CPU: soft contacts, restitution through per-geom sol_params."""

    name: ClassVar[str] = "genesis"
    radius: ClassVar[float | None] = RADIUS

    def __init__(self, overrides: dict[str, float] | None = None):
        super().__init__(overrides)
        self._scenes: dict[Any, Any] = {}

    def checks(self) -> dict[str, bool]:
        c = self.config
        own = {"stiffness": c["stiffness"] > 0, "solimp_dmin": 0 < c["solimp_dmin"] < 1,
               "solimp_dmax": 0 < c["solimp_dmax"] < 1,
               "solimp_width": c["solimp_width"] >= 0, "solver": c["solver"] in range(len(SOLVERS)),
               "iterations": whole(c["iterations"]), "integrator": c["integrator"] in range(len(INTEGRATORS)),
               "friction": c["friction"] == 0 or FRICTION_FLOOR <= c["friction"] <= 5}  # fmt: skip
        return {**super().checks(), **own}

    # -- the engine --------------------------------------------------------------------
    def engine(self) -> Any:
        """Genesis, initialised once on the CPU backend in double precision."""
        gs = import_engine(self.module)
        if getattr(gs, "_initialized", False):
            return gs
        try:
            with _quiet():
                gs.init(backend=gs.cpu, precision="64", logging_level="warning")
        except Exception as exc:  # what stops Genesis here, with its version
            raise CannotRun(f"gs.init(backend=gs.cpu): {type(exc).__name__}: {exc}; {_version()}") from None
        return gs

    def version(self) -> str:
        self.engine()
        return _version().removeprefix("genesis-world ")

    # -- a scene -----------------------------------------------------------------------
    def _scene(self, key: Any, make: Callable[[Any, Any], list[Any]]) -> tuple[Any, list[Any]]:
        """A built scene and its entities (``make(gs, scene)`` adds them), built once per ``key``."""
        if key not in self._scenes:
            gs = self.engine()
            c = self.config
            with _quiet(), _rejected(gs):
                scene = gs.Scene(
                    sim_options=gs.options.SimOptions(dt=float(c["timestep"]), gravity=(0.0, 0.0, 0.0)),
                    rigid_options=gs.options.RigidOptions(
                        constraint_solver=getattr(gs.constraint_solver, SOLVERS[int(c["solver"])]),
                        iterations=int(c["iterations"]),
                        integrator=getattr(gs.integrator, INTEGRATORS[int(c["integrator"])]),
                        constraint_timeconst=None,
                    ),
                    profiling_options=gs.options.ProfilingOptions(show_FPS=False),
                    show_viewer=False,
                )
                entities = make(gs, scene)
                scene.build()
            self._scenes[key] = (scene, entities)
        built: tuple[Any, list[Any]] = self._scenes[key]
        return built

    def _material(self, gs: Any) -> Any:
        """Unit mass for a sphere (its inertia 2/5 m R^2 = 1), the least friction Genesis allows, or more."""
        return gs.materials.Rigid(rho=1 / VOLUME, friction=max(self.config["friction"], FRICTION_FLOOR))

    def _sphere(self, gs: Any, sc: Any, x: float) -> Any:
        """A free sphere of radius :data:`RADIUS` and unit mass centred at ``(x, 0, 0)``."""
        return sc.add_entity(gs.morphs.Sphere(radius=RADIUS, pos=(x, 0.0, 0.0)), material=self._material(gs))

    def _plane(self, gs: Any, sc: Any, normal: tuple[float, float, float], x: float) -> Any:
        """A fixed plane through ``(x, 0, 0)`` with this unit normal (towards the bodies)."""
        return sc.add_entity(gs.morphs.Plane(pos=(x, 0.0, 0.0), normal=normal, fixed=True), material=self._material(gs))

    def _sol_params(self, cors: Sequence[float]) -> list[list[float]]:
        """Each body's (geom's) sol_params along the path, whose means give each contact its COR."""
        for e in cors:
            if not 0 <= e <= 1:
                raise Unsupported(f"COR {e!r}: a spring-damper's COR is in [0, 1] only")
        c = self.config
        omega = math.sqrt(c["stiffness"])
        zetas = [damping_ratio(e) for e in cors]
        taus = mean_values([1 / (omega * z) for z in zetas], "timeconst")
        ratios = mean_values(zetas, "dampratio")
        imp = [c["solimp_dmin"], c["solimp_dmax"], c["solimp_width"], 0.5, 2.0]
        return [[t, z, *imp] for t, z in zip(taus, ratios)]

    def _simulate(
        self,
        scene: Any,
        setup: Callable[[], None],
        read: Callable[[], list[float]],
        closing: Callable[[list[float]], float],
    ) -> list[float]:
        c = self.config
        with _quiet(), _rejected(self.engine()):
            scene.reset()
            setup()
            v, over = common.settle(
                scene.step,
                read,
                steps=max(1, math.ceil(c["max_time"] / c["timestep"] - 1e-9)),
                still=lambda before, after: after == before,
                approaching=lambda v: not closing(v) <= 0,  # a NaN never ends a case
                quiet=QUIET_STEPS,
            )
        if not over:
            print(f"{self.name}: after max_time = {c['max_time']} s: closing speed {closing(v)!r}", file=sys.stderr)
        return v

    # -- the scenes --------------------------------------------------------------------
    def cradle(self, scene: Cradle) -> list[float]:
        masses, cors, vel = common.cradle_inputs(scene)
        params = self._sol_params(cors)  # the path of bodies: the balls, then the wall if any
        n, reverse = len(masses), self.config["reverse_order"]
        pitch = 2 * RADIUS - self.config["overlap"]

        def make(gs: Any, sc: Any) -> list[Any]:
            makers: list[Callable[[], Any]] = [functools.partial(self._sphere, gs, sc, i * pitch) for i in range(n)]
            if scene.wall:  # a plane facing -x, at RADIUS - overlap from the last ball's centre
                makers.append(
                    lambda: self._plane(gs, sc, (-1.0, 0.0, 0.0), (n - 1) * pitch + RADIUS - self.config["overlap"])
                )
            made = [make() for make in common.in_order(makers, reverse)]
            return common.in_order(made, reverse)

        sc, bodies = self._scene(("cradle", n, scene.wall), make)
        balls = bodies[:n]

        def setup() -> None:
            for body, p in zip(bodies, params):
                body.geoms[0].set_sol_params(p)
            for ball, m, x in zip(balls, masses, vel):
                ball.set_mass(m)
                ball.set_dofs_velocity([x, 0.0, 0.0, 0.0, 0.0, 0.0])

        def read() -> list[float]:
            return [float(b.get_dofs_velocity()[0]) for b in balls]

        return self._simulate(sc, setup, read, lambda v: common.cradle_closing(v, scene.wall))

    def corner(self, scene: Corner) -> list[float]:
        k, cors, vel = common.corner_inputs(scene)
        if self.config["friction"] < FRICTION_FLOOR:
            raise Unsupported(
                "Genesis floors every contact's friction at 0.01 (func_set_contact_data, engine/solvers/rigid/"
                "collider/contact.py): frictionless walls cannot be set (--set friction=0.01 runs it with friction)"
            )
        wall1, disk_params, wall2 = self._sol_params(cors)
        centre = common.corner_centre(k, RADIUS - self.config["overlap"])

        def make(gs: Any, sc: Any) -> list[Any]:
            makers: list[Callable[[], Any]] = [functools.partial(self._sphere, gs, sc, centre)]
            for nx, ny in common.wall_normals(k):
                norm = math.hypot(nx, ny)
                makers.append(functools.partial(self._plane, gs, sc, (nx / norm, ny / norm, 0.0), 0.0))
            made = [make() for make in common.in_order(makers, self.config["reverse_order"])]
            return common.in_order(made, self.config["reverse_order"])  # disk, S1, S2

        sc, (disk, s1, s2) = self._scene(("corner", k), make)

        def setup() -> None:
            disk.set_mass(1.0)  # and the inertia scaled with it (a ball's mass may have been set before)
            for entity, p in ((s1, wall1), (disk, disk_params), (s2, wall2)):
                entity.geoms[0].set_sol_params(p)
            disk.set_dofs_velocity([vel[0], vel[1], 0.0, 0.0, 0.0, vel[2]])

        def read() -> list[float]:
            v = disk.get_dofs_velocity()
            return [float(v[0]), float(v[1]), float(v[5])]

        return self._simulate(sc, setup, read, lambda v: common.corner_closing(k, v))


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Genesis's log (on ``sys.stdout``) and its compiler's warnings (on fd 2) sent to /dev/null."""
    with silenced(), silenced(2):
        try:
            yield
        finally:
            sys.stdout.flush()
            sys.stderr.flush()


@contextlib.contextmanager
def _rejected(gs: Any) -> Iterator[None]:
    """A :class:`GenesisException` (a setting or state Genesis refuses) as :class:`Unsupported`."""
    try:
        yield
    except gs.GenesisException as exc:
        raise Unsupported(f"Genesis refused: {exc}") from None


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return f"genesis-world {version('genesis-world')}"
    except PackageNotFoundError:  # pragma: no cover - an unpackaged checkout
        return "genesis-world (version unknown)"


main = GenesisAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
