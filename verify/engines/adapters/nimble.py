"""Nimble Physics (``nimblephysics``), a differentiable fork of DART, as an implementation under test.

Engine: the Python package ``nimblephysics`` (checked with 0.10.52.1, the cp311 manylinux
wheel; it depends on ``torch``, which pip resolves to a CUDA build of about 5 GB, though only
the CPU is used). Run as ``python -m verify.engines.adapters.nimble``. The worlds are DART's, so this
adapter is :class:`~verify.engines.adapters.dartpy.DartAdapter` with what nimblephysics changed: how a
body is given its restitution and inertia, how the walls are made, and the LCP solver.
**nimblephysics 0.10.52.1 crashes with numpy 2** (a segmentation fault in the first call that
passes a vector, ``World.setGravity``: the wheel's bindings were built against numpy 1.x),
and pip installs numpy 2 unless told otherwise: with numpy 2 the adapter raises
:class:`~verify.engines.protocol.CannotRun` instead of crashing; ``pip install "numpy<2"``
(1.26.4 checked) makes it run.

**Combine rule: the product of the two BodyNodes' restitutions.** nimblephysics moved
restitution from DART's per-shape DynamicsAspect to the BodyNode: the ContactConstraint
constructor sets ``mRestitutionCoeff = mBodyNodeA->getRestitutionCoeff() *
mBodyNodeB->getRestitutionCoeff()`` (``dart/constraint/ContactConstraint.cpp`` in
keenon/nimblephysics). Checked: a restitution set on a shape's DynamicsAspect is ignored
(three balls with aspect restitution 1 come out plastic), and values are not sanitised (body
restitutions 2 and 1 give two balls a COR of 2). The restitution acts as in DART
(``ContactConstraint::getInformation``, same file): the LCP row of a contact asks for a
separating velocity of at least ``e * (approach velocity)`` measured before the step's solve;
bouncing is off when ``e <= 1e-3`` (``DART_RESTITUTION_COEFF_THRESHOLD``) or when
``e * approach <= 0.1`` (``DART_BOUNCING_VELOCITY_THRESHOLD``, in the case's units, read as
m/s), and the target is capped at ``DART_MAX_BOUNCING_VELOCITY = 100`` (checked: two unit
balls, COR 1, at speed 200 leave at (50, 150)). Penetration correction is off by default
in nimblephysics (``World.getPenetrationCorrectionEnabled()`` is False).

**The solver: one LCP, without constraint force mixing.** All contacts of a step form one
boxed LCP (``BoxedLcpConstraintSolver::solveLcp``, ``dart/constraint/BoxedLcpConstraintSolver.cpp``
in keenon/nimblephysics): Dantzig pivoting with ``cfm = 0`` (DART adds 1e-5), its answer
checked by ``LCPUtils::isLCPSolutionValid``; only if that fails is a fallback CFM
(``World.getFallbackConstraintForceMixingConstant()``, 1e-4) added and PGS (the secondary
solver) tried, then the LCP without friction. So a cradle comes out at the simultaneous
Newton law to the last digits: 3 balls, cors (1, 1): (-33.33333333333334, 66.66666666666667,
66.66666666666667).

**How CORs are set: per-body values solved through the product.** The corner's disk gets 1
and each wall its COR, each wall being its own BodyNode (two bodies welded to the world in
one skeleton, which does not collide with itself). A cradle's ball j gets ``r_j >= 0`` with
``r_i * r_(i+1) = cors[i]`` (:func:`~verify.engines.combine.product_rule_values`, unbounded:
nimblephysics takes values above 1); a 0 between two positive CORs and a negative COR are
skipped (:class:`~verify.engines.scene.Unsupported`). No per-contact COR is bound to Python.

**Scenes.** As :mod:`verify.engines.adapters.dartpy`: gravity 0, each ball or disk a Skeleton with a
FreeJoint and a SphereShape of radius 1 (friction 0), solid-sphere moments ``2/5 m`` for the
balls, unit mass and moment for the disk, walls as boxes whose faces lie on ``y = kx`` and
``y = -kx``. A cradle's fixed wall (:attr:`~verify.engines.scene.Cradle.wall`) is a BodyNode
welded to the world with one box whose face is at ``RADIUS - overlap`` from the last ball's
centre (the same ``overlap`` of 1e-9: a contact at depth 0 may be missed, below), one more
body at the end of the path whose BodyNode restitution comes out of the same product rule
(its contact gets ``cors[-1]``). The collision detector is nimblephysics' only one bound to Python (DART's own).
A case steps until the velocities have not changed for 3 steps and no contact approaches.

**Settings** (``--set``): ``time_step`` (nimblephysics' default 0.001); ``lcp_solver`` (0:
Dantzig, PGS as the fallback, the default; 1: PGS as the primary solver too);
``pgs_iterations`` (PGS's maximum sweeps, DART's default 30); ``overlap`` (1e-9, see below);
``reverse_order``; ``max_steps``. The alternate is ``lcp_solver = 1``.

**What was noticed.** The cradle cases come out at the simultaneous law to the last digits (3
balls, cors (1/2, 1/2): (0, 50, 50)); the slow cases at speed 1/2 still bounce
(``slow-cradle-3-eps-1-v0-1/2``: (-1/6, 1/3, 1/3)), while ``corner-slope-1/10-never-exits``
(``e * approach <= 0.1``) stops dead; the paper's corner gives about (-25.856, 14.928), S2's
COR 0.001 acting as 0. Contacts deeper than the world's ``mContactClippingDepth`` = 0.03 are
dropped (``dart/simulation/World.cpp``: ``World::step`` copies it into the solver every step,
and the world's setter is not bound to Python): bodies that only touch and are not detected at
depth 0 (the corner of slope sqrt(3)) are then never caught at speed 100 (0.1 per step) and
pass through each other, so ``overlap`` defaults to 1e-9 (no velocity changes with penetration
correction off). ``reverse_order = 1`` moves the 3-ball cradle, cors (1, 1), to about
(-33.314, 66.657, 66.657) (Dantzig's answer rejected and the CFM fallback used, it seems); PGS
(``lcp_solver = 1``) gives about -33.290 for the first ball, and with ``pgs_iterations = 1``
too about (0.005, 49.9975, 49.9975). The energy rise that users reported (keenon/nimblephysics
issue 143: two balls and a wall, restitution 1, time step 0.01) was reproduced: ball A at
speed 1 hits ball B resting against the wall; the wall contact at depth 0 is not detected, so
A stops and B leaves at 1; positions advance with the velocities from before each step
(``mParallelVelocityAndPositionUpdates``, true by default, same file), so two steps later B is
in the wall (depth 0.01) while A still touches B, and one LCP asks the wall contact for a
separating speed of 1 and the A-B contact, separating at 1 before the solve, for at least 0: B
is sent back at -1 and pushes A to -1 with it, the kinetic energy going from 1/2 to 1 (the
same with free or 2-D translational joints).
"""

from __future__ import annotations

from typing import Any, ClassVar

from verify.engines.adapters.dartpy import WALL_BOX, DartAdapter, Wall, wall_frame
from verify.engines.combine import product_rule_values
from verify.engines.protocol import Adapter, CannotRun, import_engine, whole

#: the per-body values and their rule, in a skip's reason
WHO = "per-body restitutions multiplied (nimblephysics BodyNode values; no per-contact setting)"


class NimbleAdapter(DartAdapter):
    """Nimble Physics: DART's boxed LCP solved by Dantzig without CFM, restitution a product of BodyNodes'."""

    bounded: ClassVar[bool] = False  # restitutions above 1 are taken (a two-ball COR of 2 from restitution 2)

    name: ClassVar[str] = "nimblephysics"

    def checks(self) -> dict[str, bool]:
        c = self.config
        return {  # the shared ranges (Adapter's: DART's collision detectors are no setting here) and nimble's own
            **Adapter.checks(self),
            "lcp_solver": c["lcp_solver"] in (0, 1),
            "pgs_iterations": whole(c["pgs_iterations"]),
        }

    def engine(self) -> Any:
        module = import_engine(self.module)
        import numpy

        if int(numpy.__version__.split(".")[0]) >= 2:
            raise CannotRun(
                f"nimblephysics {_installed()} crashes (segmentation fault in World.setGravity) with numpy "
                f"{numpy.__version__}; it needs numpy<2"
            )
        return module

    def version(self) -> str:
        self.engine()
        return _installed()

    def body_values(self, cors: list[float]) -> list[float]:
        """The cradle's per-ball restitutions (the product rule, no upper bound; Unsupported if none)."""
        return product_rule_values(cors, WHO, bounded=False)

    @staticmethod
    def _material(node: Any, body: Any) -> Any:
        """nimblephysics reads the BodyNode's restitution and friction, not the shape's."""
        return body

    @staticmethod
    def _inertia(d: Any, mass: float, moment: float) -> Any:
        return d.dynamics.Inertia(mass, [0.0, 0.0, 0.0], [[moment, 0, 0], [0, moment, 0], [0, 0, moment]])

    def _wall_skeleton(self, d: Any, walls: list[Wall]) -> Any:
        """One skeleton of BodyNodes welded to the world, a box each (restitution is a BodyNode's value)."""
        skeleton = d.dynamics.Skeleton("walls")
        parent = None
        for wall in walls:
            _, body = skeleton.createWeldJointAndBodyNodePair(*([] if parent is None else [parent]))
            parent = body  # welded with identity transforms: every body's frame is the world's
            node = self._shape(d, body, d.dynamics.BoxShape(WALL_BOX), wall[3])
            # (no ShapeNode.setName: it crashes in nimblephysics 0.10.52.1)
            node.setRelativeTransform(wall_frame(d, wall))
        return skeleton


def _installed() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("nimblephysics")
    except PackageNotFoundError:  # pragma: no cover - an unpackaged build
        return "?"


main = NimbleAdapter.main
if __name__ == "__main__":
    raise SystemExit(main())
