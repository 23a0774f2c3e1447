"""What the engine adapters share beyond the frame: a scene's floats and geometry, the stepping loop.

- :func:`cradle_inputs`, :func:`corner_inputs`: a scene's numbers as an engine's floats;
- :func:`corner_centre`, :func:`wall_normals`: where the corner's disk starts, how the walls face;
- :func:`cradle_closing`, :func:`corner_closing`: how fast the bodies still approach (> 0);
- :func:`in_order`: the order in which bodies are made (``reverse_order``);
- :func:`settle`: step an engine until the impact is over (each adapter says what "over" is);
- :class:`ContactLog`, :class:`ContactAdapter`: the engines (Box2D, Pymunk) whose contact
  callbacks can set each contact's COR and report each step's impulses.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable, Sequence
from typing import Any, ClassVar, TypeVar

from verify.engines.combine import max_rule_values, product_rule_values
from verify.engines.protocol import Adapter, CannotRun, NotInstalled, import_engine, silenced
from verify.engines.scene import Corner, Cradle, Unsupported

T = TypeVar("T")
Velocities = Callable[[], list[float]]  #: reads the bodies' velocities now


def cradle_inputs(scene: Cradle) -> tuple[list[float], list[float], list[float]]:
    """The cradle's masses, CORs and velocities as floats."""
    return scene.floats(scene.masses), scene.floats(scene.cors), scene.floats(scene.velocity)


def corner_inputs(scene: Corner) -> tuple[float, list[float], list[float]]:
    """The corner's slope ``k``, CORs (S1, S2) and velocity ``(vx, vy, omega)`` as floats."""
    return scene.floats([scene.slope])[0], scene.floats(scene.cors), scene.floats(scene.velocity)


def corner_centre(k: float, clearance: float) -> float:
    """The x of the disk's centre at distance ``clearance`` from both walls ``y = kx``, ``y = -kx``.

    >>> corner_centre(0.75, 3.0)  # sqrt(1 + k^2) = 1.25
    -5.0
    """
    return -clearance * math.sqrt(1 + k * k) / k


def wall_normals(k: float) -> list[tuple[float, float]]:
    """The walls' normals (S1, S2), towards the admissible side ``x <= -|y|/k``, not unit."""
    return [(-k, 1.0), (-k, -1.0)]


def cradle_closing(v: Sequence[float], wall: bool = False) -> float:
    """The fastest approach of two neighbouring balls, or with ``wall`` of the last ball towards the
    fixed wall on its right (``v[-1]``) too (> 0: still approaching).

    >>> cradle_closing([3.0, 1.0, 2.0])
    2.0
    >>> cradle_closing([3.0, 1.0, 2.0], wall=True), cradle_closing([-1.0], wall=True)
    (2.0, -1.0)
    """
    pairs = [v[i] - v[i + 1] for i in range(len(v) - 1)]
    return max([*pairs, v[-1]]) if wall else max(pairs)


def corner_closing(k: float, v: Sequence[float]) -> float:
    """The faster approach of the disk (``v = (vx, vy, ...)``) towards wall S1 or S2 (> 0: approaching).

    >>> corner_closing(1.0, [-1.0, 0.0, 0.0]) < 0
    True
    """
    norm = math.sqrt(1 + k * k)
    return max((k * v[0] - v[1]) / norm, (k * v[0] + v[1]) / norm)


def in_order(items: Iterable[T], reverse: float) -> list[T]:
    """The items in the order bodies are made: reversed when ``reverse`` (the ``reverse_order`` setting)."""
    out = list(items)
    return out[::-1] if reverse else out


def step_count(max_time: float, time_step: float, *, slack: float = 1e-9) -> int:
    """The steps an adapter runs at most: ``max_time / time_step`` rounded up (less ``slack``, so that a whole
    count of floats like 0.2 / (1/240) is not rounded past), at least 1.

    >>> step_count(1.0, 1 / 60), step_count(0.2, 1 / 240, slack=0.0)
    (60, 48)
    """
    return max(1, math.ceil(max_time / time_step - slack))


def settle(
    step: Callable[[], object],
    read: Velocities,
    *,
    steps: int,
    still: Callable[[list[float], list[float]], bool],
    approaching: Callable[[list[float]], bool],
    quiet: int = 1,
) -> tuple[list[float], bool]:
    """Step until ``quiet`` steps in a row were ``still`` and nothing is ``approaching``, at most ``steps``.

    ``still(before, after)`` judges one step from the velocities read before and after it
    (and whatever else the engine tells). Returns the last velocities read and whether the
    impact was over (False: the steps ran out).

    >>> state = [4.0]
    >>> settle(lambda: state.append(max(state[-1] - 1, 0.0)), lambda: [state[-1]], steps=9,
    ...        still=lambda a, b: a == b, approaching=lambda v: v[0] > 0)
    ([0.0], True)
    >>> len(state)
    6
    """
    v = read()
    run = 0
    for _ in range(steps):
        step()
        w = read()
        run = run + 1 if still(v, w) else 0
        v = w
        if run >= quiet and not approaching(v):
            return v, True
    return v, False


class ContactLog:
    """What one step's contact callbacks saw, on a path of bodies (bodies ``i``, ``i + 1`` touch at contact ``i``)."""

    def __init__(self, cors: Sequence[float], per_contact: bool):
        self.cors, self.per_contact = list(cors), per_contact
        self.impulse = 0.0  # the largest normal impulse of the step
        self.stray: tuple[int, int] | None = None  # two bodies that are not neighbours touched

    def cor(self, a: int, b: int) -> float | None:
        """The COR to give a contact of bodies ``a`` and ``b`` before it is solved (None: leave it)."""
        i, j = sorted((a, b))
        if j - i != 1:
            self.stray = (i, j)
            return None
        return self.cors[i] if self.per_contact else None

    def solved(self, impulse: float) -> None:
        """A contact was solved with this normal impulse (>= 0)."""
        self.impulse = max(self.impulse, impulse)

    def step(self, engine_step: Callable[[], object]) -> None:
        """One engine step, logged afresh; :class:`Unsupported` if two non-neighbours touched."""
        self.impulse = 0.0
        engine_step()
        if self.stray is not None:
            i, j = self.stray
            raise Unsupported(f"bodies {i + 1} and {j + 1}, not neighbours, came into contact (no COR given)")


class ContactAdapter(Adapter):
    """An engine whose contact callbacks can set a contact's COR and report its impulse (Box2D, Pymunk).

    ``per_contact=1``: every body has restitution 0 and a callback gives each touching contact
    its COR every step; ``per_contact=0``: per-body values through the engine's combine rule
    (:attr:`rule`, :mod:`verify.engines.combine`). A case ends after a step that applied no
    normal impulse (below :attr:`tolerance` of the momentum scale) with no contact approaching
    (closing speed below :attr:`tolerance` of the fastest initial speed), or after
    ``max_time``, which is said on stderr. Settings: ``time_step``, ``radius`` (of the balls
    and the disk), ``overlap``, ``reverse_order``, ``per_contact``, ``max_time``.
    """

    rule: ClassVar[str] = "product"  #: the combine rule: "max" or "product"
    who: ClassVar[str] = "?"  #: the per-body values and the rule, in a skip's reason
    tolerance: ClassVar[float] = 1e-9  #: relative: an impulse or a closing speed below it counts as none

    def checks(self) -> dict[str, bool]:
        c = self.config  # a negative overlap is a gap: allowed
        return {**super().checks(), "overlap": c["overlap"] < c["radius"]}

    def body_values(self, cors: Sequence[float]) -> list[float]:
        """Each body's restitution: 0 with the per-contact callback, else through the combine rule."""
        if self.config["per_contact"]:
            return [0.0] * (len(cors) + 1)
        if self.rule == "max":
            return max_rule_values(cors, self.who)
        return product_rule_values(cors, self.who, bounded=True)

    def settle_cradle(
        self,
        step: Callable[[], object],
        log: ContactLog,
        read: Velocities,
        masses: list[float],
        v0: list[float],
        *,
        wall: bool = False,
    ) -> list[float]:
        """Run a cradle (``step``: one engine step; ``wall``: it has a fixed wall) until the impact is
        over; the balls' velocities."""
        momentum = sum(m * abs(x) for m, x in zip(masses, v0)) or 1.0
        speed = max(map(abs, v0)) or 1.0
        return self._settle(step, log, read, lambda v: cradle_closing(v, wall), momentum=momentum, speed=speed)

    def settle_corner(
        self, step: Callable[[], object], log: ContactLog, read: Velocities, k: float, v0: list[float]
    ) -> list[float]:
        """Run a corner until the impact is over; the disk's ``(vx, vy, omega)``."""
        speed = math.hypot(v0[0], v0[1]) or 1.0
        return self._settle(step, log, read, lambda v: corner_closing(k, v), momentum=speed, speed=speed)

    def _settle(
        self,
        step: Callable[[], object],
        log: ContactLog,
        read: Velocities,
        closing: Callable[[list[float]], float],
        *,
        momentum: float,
        speed: float,
    ) -> list[float]:
        c, tol = self.config, self.tolerance
        v, over = settle(
            lambda: log.step(step),
            read,
            steps=step_count(c["max_time"], c["time_step"]),
            still=lambda _before, _after: log.impulse <= tol * momentum,
            approaching=lambda v: not closing(v) <= tol * speed,  # a NaN closing speed never ends a case
        )
        if not over:
            print(
                f"{self.name}: after max_time = {c['max_time']} s: closing speed {closing(v)!r}, "
                f"last step's impulse {log.impulse!r}",
                file=sys.stderr,
            )
        return v


def warp_on_cpu(engine: str, version: str) -> Any:
    """NVIDIA Warp initialised on its CPU device, quietly (its banner and CUDA warning silenced); :class:`CannotRun`
    with Warp's error and ``engine``'s ``version`` when it cannot run there (the engines built on Warp: Newton,
    MuJoCo Warp)."""
    try:
        with silenced(), silenced(2):
            wp = import_engine("warp")
            wp.config.quiet = True
            wp.init()
            if not wp.is_cpu_available():  # Warp built without its CPU (LLVM/Clang) backend
                raise RuntimeError(f"warp {wp.__version__}: no CPU device (wp.is_cpu_available() is False)")
            wp.set_device("cpu")
    except NotInstalled:
        raise
    except Exception as exc:  # Warp's own errors (no CPU backend, a missing library)
        line = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise CannotRun(f"{line}; {engine} {version}") from None
    return wp
