"""What a run of an impact law returns: :class:`Result`, with its trace of :class:`Step`.

Both laws (the paper's rule, :mod:`verify.laws.rule`, and the simultaneous law,
:mod:`verify.laws.simultaneous`) return a :class:`Result`; the rule's trace has one step per
impulse, the simultaneous law's one step (its single impulse) or none.

>>> from verify.laws.rule import solve
>>> from verify.dynamics.system import System
>>> r = solve(System([[1, 0], [0, 1]], [[-1, 1]], [1]), ["1", "0"])
>>> r.law, r.iterations, [r.backend.to_exact(x) for x in r.exit_velocity]
('rule', 1, ['0', '1'])
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

from verify.dynamics.policy import Stop
from verify.dynamics.system import System
from verify.numbers.format import counted
from verify.proofs.limits import Limit, alternation_limit


@dataclass(frozen=True)
class Step:
    """One impulse of the iteration: the trace entry of Sect. 3.5 d)-e).

    ``kinetic_energy`` (after the impulse, in the rest frame of the constraints) is
    computed when first asked for: on long exact runs it is the costliest quantity.
    """

    impact_set: tuple[int, ...]
    rates: tuple[Any, ...]  # p(F_i) of the velocity before the impulse, for every constraint
    beta: Any  # None for a single impact
    impulse: tuple[Any, ...]
    velocity: tuple[Any, ...]  # after the impulse
    system: System = field(repr=False, compare=False)
    #: the sequential law: (constraint, change of its accumulated impulse) for each impulse this sweep changed
    changes: tuple[Any, ...] = field(default=(), repr=False, compare=False)

    @cached_property
    def kinetic_energy(self) -> Any:
        return self.system.kinetic_energy(self.velocity)


def velocity_name(stop: Stop) -> str:
    """The one name that the text outputs give the velocity where a run stopped: ``exit velocity``
    when it exits; for a run proved never to exit, the velocity when it was proved (it never exits: there
    is no exit velocity); else ``velocity at the stop`` (stopped by its cap, its budget or the paper's AEEV
    stop, it has not exited). The JSON field is ``exit_velocity`` either way.

    >>> velocity_name("exit"), velocity_name("non_terminating"), velocity_name("max_iterations")
    ('exit velocity', 'velocity when proved never to exit', 'velocity at the stop')
    """
    if stop == "exit":
        return "exit velocity"
    return "velocity when proved never to exit" if stop == "non_terminating" else "velocity at the stop"


def stop_words(stop: Stop, impulses: int, unit: str = "impulse") -> str:
    """A run's length in words: its impulses, or, for a run proved never to exit, that it never ends.

    >>> stop_words("exit", 3), stop_words("non_terminating", 0)
    ('exit after 3 impulses', 'never exits (infinitely many impulses; proved after 0 impulses)')
    """
    if stop == "non_terminating":
        return f"never exits (infinitely many {unit}s; proved after {counted(impulses, unit)})"
    return f"{stop} after {counted(impulses, unit)}"


def energy_words(result: Result, digits: int) -> str:
    """The kinetic energy of a run that never exits: in, when proved, and the limit's when that is proved.

    >>> from verify.laws.rule import solve
    >>> from verify.models.cradle import cradle_system
    >>> energy_words(solve(cradle_system("1/100"), ["100", "0", "0"]), 6)
    '5000 in, 5000 when proved never to exit, tends to 1666.67'
    """
    K = result.backend
    before, after = K.to_decimal(result.kinetic_energy_in, digits), K.to_decimal(result.kinetic_energy_out, digits)
    limit = result.limit
    tends = "" if limit is None else f", tends to {K.to_decimal(limit.kinetic_energy, digits)}"
    return f"{before} in, {after} when proved never to exit{tends}"


@dataclass(frozen=True)
class Result:
    """The outcome of :func:`solve`: exit velocity, stop reason and the full trace."""

    system: System
    rule: str
    velocity_in: tuple[Any, ...]
    exit_velocity: tuple[Any, ...]
    stop: Stop
    steps: tuple[Step, ...]
    impact_sets: list[tuple[int, ...]]
    betas: list[Any]
    max_iterations: int
    notes: tuple[str, ...] = ()
    certificate: dict[Any, Any] | None = field(default=None)
    #: the impact law: ``"rule"`` (the paper's iterative rule), ``"simultaneous"``
    #: (:mod:`verify.laws.simultaneous`) or ``"sequential"`` (:mod:`verify.laws.sequential`)
    law: str = "rule"
    #: the impulse magnitudes lambda_i, one per constraint, of the simultaneous law (or the sequential law's
    #: accumulated impulses); None for the rule
    impulses: tuple[Any, ...] | None = None
    #: on a backend that is not rigorous (mp, float): the first impulse whose impact set was decided on a
    #: rate below the working precision (the run is not to be trusted from there on; a note says so), or None
    doubtful: int | None = None
    #: the sequential law's settings (:class:`verify.laws.sequential.Sequential`); None for the other laws
    sequential: Any = None

    @cached_property
    def kinetic_energy_in(self) -> Any:
        """The kinetic energy before the impact (rest frame of the constraints)."""
        return self.system.kinetic_energy(self.velocity_in)

    @cached_property
    def kinetic_energy_out(self) -> Any:
        """The kinetic energy of the exit velocity."""
        return self.system.kinetic_energy(self.exit_velocity)

    @cached_property
    def limit(self) -> Limit | None:
        """For a run proved never to exit, the velocity it tends to, when that is proved too
        (:func:`verify.proofs.limits.alternation_limit`); None otherwise."""
        if self.stop != "non_terminating":
            return None
        return alternation_limit(self.system, self.exit_velocity, self.certificate)

    @property
    def velocity_name(self) -> str:
        """What the text outputs call :attr:`exit_velocity` (:func:`velocity_name` of the stop).

        >>> from verify.laws.rule import solve
        >>> from verify.dynamics.system import System
        >>> solve(System([[1]], [[1]], [1]), ["-1"]).velocity_name
        'exit velocity'
        """
        return velocity_name(self.stop)

    @property
    def last_velocity(self) -> tuple[Any, ...]:
        """The velocity after the last impulse: the exit velocity when ``stop == "exit"``, else where the run
        stopped (``exit_velocity`` holds it too, under the name of the common case)."""
        return self.exit_velocity

    @property
    def iterations(self) -> int:
        """The number of impulses applied (Table 1's "# Iterations")."""
        return len(self.impact_sets)

    @property
    def backend(self) -> Any:
        return self.system.backend

    def __repr__(self) -> str:
        return (
            f"Result(stop={self.stop!r}, iterations={self.iterations}, law={self.law!r}, rule={self.rule!r}, "
            f"backend={self.backend.name!r})"
        )

    def summary(self, digits: int = 12) -> str:
        """The run in a few lines: how it stopped, the impact sets by contact name, the kinetic energies and
        the exit velocity (for a run that does not exit, the velocity at the stop) in decimals, ``digits`` at most:
        all of them correct on exact backends, only the certified ones on intervals, and marked as not
        certified on mp and float.

        >>> from verify.laws.rule import solve
        >>> from verify.dynamics.system import System
        >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/3", "1/3"],
        ...            names=["left", "right"], coordinates=["x1", "x2", "x3"])
        >>> print(solve(s, ["1", "0", "0"]).summary(digits=6))
        exit after 3 impulses (general rule, exact (rationals, ...), rigorous)
          impact sets: (left)(right)(left)
          kinetic energy: 0.5 -> 0.176269
          exit velocity: x1 = 0.259259, x2 = 0.296296, x3 = 0.444444
        """
        K = self.backend
        names = self.system.names
        words = ["(" + ",".join(names[j] for j in J) + ")" for J in self.impact_sets]
        if len(words) > 12:
            words = [*words[:6], f" ... {len(words) - 9} more ... ", *words[-3:]]
        how = {"exit": "exit", "max_iterations": "still impacting"}
        head = stop_words(self.stop, self.iterations).replace(self.stop, how.get(self.stop, self.stop), 1)
        law = f"{self.rule} rule" if self.law == "rule" else f"{self.law} law, {self.rule} CORs"
        coordinates = self.system.coordinates
        shown = ", ".join(f"{q} = {K.to_decimal(x, digits)}" for q, x in zip(coordinates, self.exit_velocity))
        before, after = K.to_decimal(self.kinetic_energy_in, digits), K.to_decimal(self.kinetic_energy_out, digits)
        energy = f"{before} -> {after}" if self.stop != "non_terminating" else energy_words(self, digits)
        caveat = "" if K.is_rigorous else f" ({K.name}: digits not certified)"
        lines = [
            f"{head} ({law}, {K.describe()})",
            f"  impact sets: {''.join(words) or 'none'}",
            f"  kinetic energy: {energy}",
            f"  {self.velocity_name}: {shown}{caveat}",
        ]
        return "\n".join(lines + [f"  note: {n}" for n in self.notes])
