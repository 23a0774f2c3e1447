"""MuJoCo Warp (MuJoCo's soft contacts, in NVIDIA Warp, on the CPU) as an implementation under test.

Engine: MuJoCo Warp (pip ``mujoco-warp``, module ``mujoco_warp``), checked with 4.0.0 on
``mujoco`` 4.0.0 and Warp 1.19.0, run on Warp's CPU device: a GPU-first port of MuJoCo's
pipeline whose kernels Warp compiles with its bundled LLVM/Clang on first use and caches in
``~/.cache/warp/<warp version>`` (a cold cache costs a long compile on the first run; a warm one, a
short start-up). Float32 throughout (MuJoCo's C library: float64). It reads an
``mujoco.MjModel`` compiled by MuJoCo's C library (``mujoco_warp.put_model``,
``mujoco_warp.put_data``) and steps with ``mujoco_warp.step``; one world per case. Warp prints
its banner and kernel-compile lines on standard output, so all engine work runs with standard
output silenced (:func:`~verify.engines.protocol.silenced`). Newton's ``SolverMuJoCo`` runs
this same engine.

MuJoCo has no coefficient of restitution; the model, the mapping from COR to a direct
``solref`` and everything about it are :mod:`verify.engines.adapters.mujoco`'s, reused here by
subclassing :class:`~verify.engines.adapters.mujoco.MuJoCoAdapter` (its ``damping_ratio``, ``_solref``,
``_pair``, ``_model`` and the two scenes): one explicit ``<contact><pair>`` per constraint with
``solref = (-K, -2 zeta sqrt(K))``, ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``, every geom with
``contype = conaffinity = 0`` and ``condim = 1``. Only the stepping differs (below).

Combine rule: as MuJoCo's (``mj_contactParam``), not used: explicit pairs bypass the mixing.
MuJoCo Warp turns a direct ``solref`` into the reference acceleration the same way
(``_contact_kbimp`` in ``mujoco_warp/_src/constraint.py``: ``k = -solref[0] / dmax^2``,
``b = -solref[1] / dmax``, impedance from ``solimp``, "see
https://mujoco.readthedocs.io/en/latest/modeling.html#solver-parameters").

What the engine does with it: a soft contact (no threshold: a contact acts whenever the
geoms' distance is below the margin, 0 here) solved by the primal solver, Newton (default) or
CG; MuJoCo's PGS is not ported (``SolverType`` in ``mujoco_warp/_src/types.py``: "unsupported:
PGS"), so ``solver=0`` is out of range here. The restitution comes out of the damped
spring's release, as in MuJoCo: a measured two-ball COR of 1.0012 for ``e = 1``, 0.560 for
``e = 1/2``, 0.1405 for ``e = 0``, MuJoCo's.

Settings: :mod:`verify.engines.adapters.mujoco`'s (``timestep`` 1e-4, ``stiffness`` 1e6,
``solimp_dmin``/``solimp_dmax``/``solimp_width`` 0.9/0.95/0.001, ``solver`` 2 = Newton (1 = CG),
``iterations`` 100, ``overlap``, ``reverse_order``, ``max_time`` 0.2). The impact is over when
no constraint row has been active (``nefc`` of the world is 0) for 5 steps and no contact is
approaching, or after ``max_time``. MuJoCo Warp has no warning callback; a case whose
velocities come out non-finite, or whose contact or constraint buffers overflowed
(``Data.warn_overflow``, checked when present), is skipped with the reason.

Alternate setting: ``solimp_dmax=0.5``, as for MuJoCo: more regularisation shared by
simultaneous contacts.

What was noticed: MuJoCo Warp on the CPU gives MuJoCo's C answers to float32 precision: the
3-ball eps = 1 cradle (-33.5966, 63.9885, 69.6081) against (-33.5967, 63.9882, 69.6085), the
paper corner (-35.7819, 11.8547, 0) against (-35.7818, 11.8547, 0). A cold kernel cache makes the
first run much longer (``time verify engines --engine mujoco_warp`` measures it).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

from verify.engines.adapters.mujoco import QUIET_STEPS, Dof, MuJoCoAdapter
from verify.engines.common import settle, warp_on_cpu
from verify.engines.protocol import import_engine, silenced
from verify.engines.scene import Unsupported


class MuJoCoWarpAdapter(MuJoCoAdapter):
    """MuJoCo Warp on Warp's CPU device: MuJoCo's model (explicit pairs, direct solref), Warp's step."""

    name: ClassVar[str] = "mujoco_warp"

    def checks(self) -> dict[str, bool]:
        # 1 CG, 2 Newton: MuJoCo Warp has no PGS
        return {**super().checks(), "solver": self.config["solver"] in (1, 2)}

    def engine(self) -> Any:
        """MuJoCo Warp, with Warp initialised on its CPU device (:class:`CannotRun` if Warp cannot run there)."""
        mjw = import_engine(self.module)
        warp_on_cpu("mujoco_warp", mjw.__version__)
        return mjw

    def version(self) -> str:
        mjw = self.engine()
        mj, wp = import_engine("mujoco"), import_engine("warp")
        return f"{mjw.__version__} (mujoco {mj.__version__}, warp {wp.__version__}, device cpu)"

    def _simulate(
        self, xml: str, velocity: dict[Dof, float], read: list[Dof], closing: Callable[[list[float]], float]
    ) -> list[float]:
        mjw = self.engine()
        with silenced():
            v, overflow = self._warp_steps(mjw, xml, velocity, read, closing)
        if overflow:
            raise Unsupported(f"MuJoCo Warp's buffers overflowed (warn_overflow = {overflow})")
        if not all(math.isfinite(x) for x in v):
            raise Unsupported(f"MuJoCo Warp gave non-finite velocities {v!r} (an unstable simulation)")
        return v

    def _warp_steps(
        self, mjw: Any, xml: str, velocity: dict[Dof, float], read: list[Dof], closing: Callable[[list[float]], float]
    ) -> tuple[list[float], int]:
        m, d, out = self.model(import_engine("mujoco"), xml, velocity, read)
        try:
            wm = mjw.put_model(m)
            wd = mjw.put_data(m, d)
        except NotImplementedError as exc:
            raise Unsupported(f"MuJoCo Warp cannot run the model: {exc}") from None
        v, _ = settle(
            lambda: mjw.step(wm, wd),
            lambda: [float(x) for x in wd.qvel.numpy()[0, out]],
            steps=max(1, math.ceil(self.config["max_time"] / self.config["timestep"])),
            still=lambda _before, _after: not int(wd.nefc.numpy()[0]),  # no active constraint row
            approaching=lambda v: closing(v) > 0,
            quiet=QUIET_STEPS,
        )
        overflow = getattr(wd, "warn_overflow", None)
        return v, int(overflow.numpy().max()) if overflow is not None else 0


main = MuJoCoWarpAdapter.main

if __name__ == "__main__":
    raise SystemExit(main())
