"""The sequential-impulse law: the sweeps of projected Gauss-Seidel that physics engines run, done exactly.

Engines (Box2D, Bullet, Chipmunk/Pymunk, ...) do not solve the simultaneous law
(:mod:`verify.laws.simultaneous`); they approach it by sweeps of single-contact impulses. On the
same :class:`~verify.dynamics.system.System`, with the pre-impact rates ``w_i = p(F_i)`` of the left
velocity v (eq. 2), Gram matrix G and ``U_i = g^{-1} dF_i^T``:

1. the **restitution target** of each constraint is taken once, from the rates before the solve:
   ``t_i = -e_i w_i`` when the constraint is incoming faster than the threshold
   (``-w_i > threshold_i``), else ``t_i = 0`` (a separating or slow contact is only kept from
   penetrating);
2. the **accumulated impulses** ``lambda_i`` start at 0 (no warm start);
3. a **sweep** visits the constraints in ``order``; at constraint i, with ``w_i`` the rate of the
   current velocity, ``lambda_i <- max(lambda_i + (t_i - w_i) / G_ii, 0)`` (the accumulated
   impulse is clamped at 0, as in Catto's sequential impulses), and the velocity takes the change:
   ``v <- v + (new - old) U_i``;
4. ``iterations`` sweeps are run (engines' defaults: 10 in Bullet's ``numSolverIterations`` and
   Chipmunk's ``iterations``, 8 in Box2D 2.3's velocity iterations; :data:`DEFAULT_ITERATIONS`).

A sweep that changes no impulse leaves the state as it found it, so every later sweep does too:
the run then stops early with the same result. When the sweeps stop changing, the impulses solve
the simultaneous law's complementarity problem with the targets ``t`` (with threshold 0: the
simultaneous law itself); as ``iterations`` grows they tend to it (Gauss-Seidel on a positive
definite G converges; Cottle, Pang & Stone, Thm 5.2.4), and the exit velocity with them. The
run's stop is ``"exit"`` when every exit rate is ``>= 0`` (outgoing), else ``"max_iterations"``
(still incoming after the sweeps: an engine would carry that velocity into its next step).

Every sign (incoming, above the threshold, the clamp, whether an impulse changed, outgoing) is
decided by ``K.sign``: exactly on the exact backends; on an approximate backend (interval, mp,
float) with rational or algebraic inputs, on the exact backend first, the approximate run then
following the same branches; with other inputs on intervals at raised precision
(:class:`~verify.errors.NoConvergence` at the limit).

>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
>>> r = solve_sequential(s, ["100", "0", "0"], Sequential(iterations=1))
>>> [s.backend.to_exact(x) for x in r.exit_velocity], r.stop, [s.backend.to_exact(x) for x in r.impulses]
(['0', '50', '50'], 'exit', ['100', '50'])
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from verify.dynamics.system import System, exact_backend_for_velocity, source_numbers, velocity_numbers
from verify.errors import BadNumber, InvalidSystem
from verify.laws.outcome import Result, Step
from verify.laws.simultaneous import refining
from verify.numbers.backends import Backend, exact_for
from verify.numbers.format import format_exact
from verify.numbers.numeric import certified_sign
from verify.numbers.parse import to_number

#: the sweeps of the sequential law by default: Bullet's ``numSolverIterations`` and Chipmunk's
#: ``iterations`` (Box2D 2.3: 8 velocity iterations)
DEFAULT_ITERATIONS = 10


@dataclass(frozen=True)
class Sequential:
    """The settings of the sequential-impulse law: ``iterations`` sweeps (>= 1), the constraints'
    ``order`` in a sweep (a permutation of their 0-based indices; ``"reversed"``; None: as given), and the
    ``threshold``: no restitution for a constraint incoming at this speed or slower (a number, or one
    per constraint; compared with the rate ``-p(F_i)`` as the system states it, the relative normal
    speed when the normals are unit; 0 by default). Pass it as ``law=`` to
    :func:`verify.laws.rule.solve` (``law="sequential"`` is ``Sequential()``).

    >>> Sequential(iterations=3, order=(1, 0)).settings(2)
    {'iterations': 3, 'order': [1, 0], 'threshold': ['0', '0']}
    """

    iterations: int = DEFAULT_ITERATIONS
    order: tuple[int, ...] | str | None = None
    threshold: Any = 0

    name: ClassVar[str] = "sequential"

    def __post_init__(self) -> None:
        k = self.iterations
        if isinstance(k, bool) or not isinstance(k, int) or k < 1:
            raise InvalidSystem(f"the sequential law's iterations must be a positive integer, got {k!r}")
        if self.order == "reversed":
            return
        if self.order is not None:
            order = tuple(self.order)
            if not all(isinstance(i, int) and not isinstance(i, bool) for i in order):
                raise InvalidSystem(f"the sequential law's order must be constraint indices, got {self.order!r}")
            object.__setattr__(self, "order", order)

    def sweep_order(self, r: int) -> tuple[int, ...]:
        """The order of a sweep over ``r`` constraints (checked: each index once)."""
        if self.order == "reversed":
            return tuple(reversed(range(r)))
        order: tuple[int, ...] = tuple(range(r)) if self.order is None else tuple(int(i) for i in self.order)
        if sorted(order) != list(range(r)):
            raise InvalidSystem(
                f"the sequential law's order {list(order)} is not an order of the {r} constraints "
                f"(0 to {r - 1}, each once)"
            )
        return order

    def thresholds(self, r: int) -> list[Any]:
        """The threshold of each of ``r`` constraints as an exact number (checked: >= 0)."""
        given = self.threshold
        values = list(given) if isinstance(given, (list, tuple)) else [given] * r
        if len(values) != r:
            raise InvalidSystem(f"the sequential law's threshold has {len(values)} values for {r} constraints")
        out = [to_number(x, where=f"threshold[{i}]") for i, x in enumerate(values)]
        for i, x in enumerate(out):
            if certified_sign(x) < 0:
                raise InvalidSystem(f"the sequential law's threshold[{i}] = {values[i]} is negative")
        return out

    def settings(self, r: int) -> dict[str, Any]:
        """The settings as a record's ``law_settings`` (numbers as exact strings)."""
        return {
            "iterations": self.iterations,
            "order": list(self.sweep_order(r)),
            "threshold": [_text(x) for x in self.thresholds(r)],
        }

    def __str__(self) -> str:
        """The law's name, with the settings that are not the defaults (a row's or a task's label).

        >>> str(Sequential()), str(Sequential(iterations=3, threshold="1/2"))
        ('sequential', 'sequential (iterations 3, threshold 1/2)')
        """
        return self.name + (f" ({', '.join(f'{k} {v}' for k, v in self._changed())})" if self._changed() else "")

    def flags(self) -> str:
        """The command-line options that give this law (``--law sequential`` and the settings changed).

        >>> Sequential(iterations=3, order=(1, 0)).flags()
        '--law sequential --iterations 3 --order 1,0'
        """
        return " ".join([f"--law {self.name}", *(f"--{k} {v}" for k, v in self._changed())])

    def _changed(self) -> list[tuple[str, str]]:
        out = []
        if self.iterations != DEFAULT_ITERATIONS:
            out.append(("iterations", str(self.iterations)))
        if self.order == "reversed":
            out.append(("order", "reversed"))
        elif self.order is not None:
            out.append(("order", ",".join(map(str, self.order))))
        given = self.threshold
        values = list(given) if isinstance(given, (list, tuple)) else [given]
        if any(to_number(x, where="threshold") != 0 for x in values):
            out.append(("threshold", ",".join(format_exact(to_number(x, where="threshold")) for x in values)))
        return out

    @classmethod
    def from_settings(cls, settings: dict[str, Any]) -> Sequential:
        """The settings of a record's ``law_settings`` (:meth:`settings`) as a ``Sequential``.

        >>> Sequential.from_settings(Sequential(iterations=2).settings(3)) == Sequential(2, (0, 1, 2), ("0", "0", "0"))
        True
        """
        try:
            return cls(int(settings["iterations"]), tuple(settings["order"]), tuple(settings["threshold"]))
        except (KeyError, TypeError, ValueError) as exc:
            raise InvalidSystem(f"law_settings: expected iterations, order and threshold ({exc})") from None

    def describe(self, names: Sequence[str]) -> str:
        """One line: the sweeps, the order by the constraints' names, the threshold."""
        order = ", ".join(names[i] for i in self.sweep_order(len(names)))
        given = self.threshold
        t = (
            ", ".join(_text(x) for x in self.thresholds(len(names)))
            if isinstance(given, (list, tuple))
            else _text(to_number(given, where="threshold"))
        )
        return (
            f"{self.iterations} sweeps of projected Gauss-Seidel over {order}; restitution above incoming speed {t}, "
            "target from the rates before the solve, no warm start"
        )


def _text(x: Any) -> str:
    return format_exact(x)


Law = str | Sequential  #: an impact law as the library takes it: a name of ``LAWS``, or the sequential law's settings


def law_of_record(record: dict[str, Any]) -> Law:
    """The law of a result record: its ``law`` (``"rule"`` when absent), with its ``law_settings``.

    >>> law_of_record({"law": "sequential", "law_settings": {"iterations": 1, "order": [0], "threshold": ["0"]}})
    Sequential(iterations=1, order=(0,), threshold=('0',))
    """
    law = str(record.get("law", "rule"))
    if law == Sequential.name and isinstance(record.get("law_settings"), dict):
        return Sequential.from_settings(record["law_settings"])
    return law


def case_settings(settings: dict[str, Any], r: int, base: Sequential | None = None) -> Sequential:
    """The sequential law of a case that carries its own ``law_settings`` (any of ``iterations``, ``order``,
    ``threshold``), the others from ``base`` (the command's); checked against its ``r`` constraints.

    >>> case_settings({"order": [1, 0]}, 2, Sequential(iterations=3))
    Sequential(iterations=3, order=(1, 0), threshold=0)
    >>> case_settings({"order": [0, 0]}, 2)
    Traceback (most recent call last):
    ...
    verify.errors.InvalidSystem: the sequential law's order [0, 0] is not an order of the 2 constraints ...
    """
    base = base or Sequential()
    if not isinstance(settings, dict) or set(settings) - {"iterations", "order", "threshold"}:
        raise InvalidSystem("expected an object with iterations, order or threshold")
    order = settings.get("order", base.order)
    threshold = settings.get("threshold", base.threshold)
    if isinstance(order, list):
        order = tuple(order)
    if isinstance(threshold, list):
        threshold = tuple(threshold)
    law = Sequential(settings.get("iterations", base.iterations), order, threshold)
    law.sweep_order(r)
    law.thresholds(r)
    return law


def law_for_case(law: Law, settings: dict[str, Any] | None, r: int) -> Law:
    """The law a case runs under: ``law``; under the sequential law with the case's own ``law_settings``
    in place of the command's.

    >>> law_for_case("rule", {"order": [1, 0]}, 2), law_for_case("sequential", {"order": [1, 0]}, 2).order
    ('rule', (1, 0))
    """
    sequential = isinstance(law, Sequential) or law == Sequential.name
    if not settings or not sequential:
        return law
    return case_settings(settings, r, law if isinstance(law, Sequential) else None)


class _Choices:
    """The branches of one run: decided (and recorded) by the given tests, or replayed from a record."""

    def __init__(self, replay: list[bool] | None = None):
        self.record: list[bool] = []
        self._replay = None if replay is None else iter(replay)

    def __call__(self, test: Callable[..., bool], *args: Any) -> bool:
        if self._replay is not None:
            return next(self._replay)
        answer = test(*args)
        self.record.append(answer)
        return answer


def _incoming(K: Backend, w: Any, threshold: Any) -> bool:
    """Whether a constraint of rate ``w`` is incoming faster than ``threshold`` (it then restitutes)."""
    return K.sign(w) < 0 and K.sign(K.zero - w - threshold) > 0


def _negative(K: Backend, x: Any) -> bool:
    return not K.known_zero(x) and K.sign(x) < 0


def _changed(K: Backend, x: Any) -> bool:
    """Whether an impulse's change is not 0 (decided on exact backends; not known to be 0 on others)."""
    return not K.known_zero(x) and (K.sign(x) != 0 if K.is_exact else True)


def _outgoing(K: Backend, rates: Sequence[Any]) -> bool:
    return all(K.sign(x) >= 0 for x in rates)


def _sweeps(
    system: System, v: tuple[Any, ...], law: Sequential, thresholds: Sequence[Any], choose: _Choices
) -> tuple[Any, ...]:
    """The sweeps from velocity ``v``: the impulses, the exit velocity, the steps (one per sweep that
    changed an impulse) and whether the exit velocity is outgoing."""
    K, r = system.backend, system.r
    w = list(system.rates(v))
    targets = _targets(system, w, thresholds, choose)
    lam = [K.zero] * r
    order = law.sweep_order(r)
    inverse = system.inverse_gram_diag
    steps: list[Step] = []
    for _ in range(law.iterations):
        before, rates_before = v, tuple(w)
        changed: list[tuple[int, Any]] = []
        for i in order:
            new = lam[i] + (targets[i] - w[i]) * inverse[i]
            if choose(_negative, K, new):
                new = K.zero
            change = new - lam[i]
            if not choose(_changed, K, change):
                continue
            lam[i] = new
            changed.append((i, change))
            v = tuple(x + d for x, d in zip(v, system.combine_normals([(i, change)])))
            w[i] = w[i] + system.gram[i][i] * change
            for k, gik in system.gram_columns[i]:
                w[k] = w[k] + gik * change
        if not changed:
            break
        impulse = tuple(x - y for x, y in zip(v, before))
        steps.append(Step(tuple(sorted(i for i, _ in changed)), rates_before, None, impulse, v, system, tuple(changed)))
    outgoing = choose(_outgoing, K, system.rates(v))
    return tuple(lam), v, tuple(steps), outgoing


def _targets(system: System, w: Sequence[Any], thresholds: Sequence[Any], choose: _Choices) -> list[Any]:
    """The restitution target of each constraint from its rate ``w_i`` before the solve: ``-e_i w_i`` when it
    is incoming faster than its threshold, else 0."""
    K = system.backend
    return [
        K.zero - e * x if choose(_incoming, K, x, t) else K.zero for e, x, t in zip(system.restitution, w, thresholds)
    ]


def restitution_targets(system: System, velocity: Sequence[Any], law: Sequential) -> tuple[System, list[Any]]:
    """The target rates of the law from the left velocity ``velocity``, exactly: the system in the number
    field of the velocity and thresholds, and one target per constraint.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", 1])
    >>> t_system, t = restitution_targets(s, ["100", "0", "0"], Sequential(threshold=1))
    >>> [t_system.backend.to_exact(x) for x in t]
    ['50', '0']
    """
    values = velocity_numbers(velocity)
    thresholds = law.thresholds(system.r)
    exact = system.convert_to(exact_for(source_numbers(system) + values + thresholds))
    w = exact.rates(exact.velocity(values))
    return exact, _targets(exact, w, exact.backend.convert_all(thresholds), _Choices())


def _exact_choices(system: System, velocity: Sequence[Any], law: Sequential) -> list[bool] | None:
    """The branches of the run decided on the exact backend, or None when an input is not algebraic."""
    values = velocity_numbers(velocity)
    thresholds = law.thresholds(system.r)
    try:
        exact = system.convert_to(exact_for(source_numbers(system) + values + thresholds))
    except BadNumber:
        return None
    choose = _Choices()
    _sweeps(exact, exact.velocity(values), law, exact.backend.convert_all(thresholds), choose)
    return choose.record


def solve_sequential(
    system: System, velocity: Sequence[Any], law: Sequential | None = None, *, rule: str = "general"
) -> Result:
    """The sequential law's exit velocity from the left velocity ``velocity`` (settings ``law``).

    Use it through :func:`verify.laws.rule.solve` with ``law="sequential"`` or ``law=Sequential(...)``
    (which also applies the ``rule`` variants' CORs). The result's ``impulses`` are the accumulated
    impulses, its steps one per sweep that changed them, ``max_iterations`` the sweeps allowed.

    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [0, 0])
    >>> r = solve_sequential(s, ["100", "0", "0"], Sequential(iterations=1))
    >>> [s.backend.to_exact(x) for x in r.exit_velocity], r.stop
    (['50', '25', '25'], 'max_iterations')
    """
    law = law or Sequential()
    law.sweep_order(system.r)
    thresholds = law.thresholds(system.r)
    replay = None if system.backend.is_exact else _exact_choices(system, velocity, law)

    def attempt(system: System) -> tuple[System, tuple[Any, ...]]:
        if system.backend.widens_to_inputs:
            system, v = exact_backend_for_velocity(system, velocity)
            if not _holds(system, thresholds):  # a threshold outside the number field: widen it
                values = velocity_numbers(velocity)
                system = system.convert_to(exact_for(source_numbers(system) + values + thresholds))
                v = system.velocity(values)
        else:
            v = system.velocity(velocity)
        ts = system.backend.convert_all(thresholds)
        return system, (v, *_sweeps(system, v, law, ts, _Choices(replay)))

    system, (v, lam, out, steps, outgoing), notes = refining(system, attempt, "a sign of the sequential law")
    return Result(
        system=system,
        rule=rule,
        velocity_in=v,
        exit_velocity=out,
        stop="exit" if outgoing else "max_iterations",
        steps=steps,
        impact_sets=[s.impact_set for s in steps],
        betas=[None] * len(steps),
        max_iterations=law.iterations,
        notes=tuple(notes),
        law="sequential",
        impulses=lam,
        sequential=law,
    )


def _holds(system: System, values: list[Any]) -> bool:
    """Whether the exact backend's number field holds ``values``."""
    try:
        system.backend.convert_all(values)
    except BadNumber:
        return False
    return True
