"""The paper's own termination of the cradle runs ("paper mode", Sect. 4.1).

The paper (PARI/GP, floating point) ensured termination "by fixing a maximum number
N = 10^4 of iterations and a minimum threshold sigma = 10^-9 ||v0|| for the differences
of the velocities of the three disks"; rows of Table 1 stopped this way are marked AEEV
("Almost Equal Exit Velocities") "followed by the number of iterations before checking
the almost equalities".

The text leaves open what "the differences of the velocities" measure, which norm sigma
is relative to, and when the test is made. A :class:`Reading` fixes all three:

- ``measure`` (:data:`MEASURES`): the largest pairwise ``|v_i - v_j|``, the Euclidean norm
  of all pairwise differences, the largest or the Euclidean norm of the neighbouring
  differences, the largest distance to the mean or the Euclidean norm of the distances to
  the mean, or the sum of the squares of the pairwise differences (no square root);
- ``norm`` (:data:`NORMS`): ``||v0||`` (the left velocity), ``||v||`` (the velocity being
  tested), or either without the square root (``||v0||^2``, ``||v||^2``);
- ``when`` (:data:`WHENS`): ``before`` each impulse, once an impact is known to remain (a
  row that exits is never AEEV), or ``after`` each impulse, before the exit check.

The stop fires when ``measure < sigma``, strictly, with ``sigma = sigma_relative * norm``
(:func:`aeev_halt`; ``strict=False`` uses ``<=``). It is evaluated exactly, on squares, so
no square root and no float is involved.

:mod:`verify.paper.readings` computes, for every reading of the family, the exact
window of ``sigma_relative`` that reproduces every printed count of Table 1, and the counts
the printed 10^-9 gives (``verify table1`` prints both). Under the readings tried (the 7
measures x 4 norms x 2 moments above), 10^-9 reproduces every printed count under exactly
one: the Euclidean norm of all pairwise differences, relative to the norm of the velocity
being tested, before each impulse (``l2_pair/v/before``). Paper mode uses it,
:data:`PAPER_READING`, with :data:`PAPER_SIGMA_RELATIVE` = 10^-9, the printed constant; a
test checks that it is the one reading the search finds (had there been several, the one
with the fewest operations would have been chosen). The earlier reading,
:data:`MAX_PAIR_READING` (largest pairwise difference, before, ``||v0||``), reproduces
the counts only with sigma / ||v0|| in a window that excludes 10^-9; it stays selectable
(``aeev="max_pair/v0/before"``) and uses :data:`MAX_PAIR_SIGMA_RELATIVE` = 4 * 10^-10,
inside its window.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from verify.dynamics.policy import Halted

PAPER_MAX_ITERATIONS = 10_000
PAPER_SIGMA_STATED = Fraction(1, 10**9)  #: sigma / norm as printed in Sect. 4.1

#: what "the differences of the velocities" can measure
MEASURES = {
    "max_pair": "largest |v_i - v_j| over all pairs",
    "l2_pair": "Euclidean norm of all pairwise differences",
    "max_adjacent": "largest |v_i - v_(i+1)| over neighbours",
    "l2_adjacent": "Euclidean norm of the neighbouring differences",
    "max_mean": "largest |v_i - mean(v)|",
    "l2_mean": "Euclidean norm of v - mean(v)",
    "sumsq_pair": "sum of (v_i - v_j)^2 over all pairs (no square root)",
}
#: what sigma is relative to
NORMS = {"v0": "||v0||", "v": "||v||", "v0^2": "||v0||^2", "v^2": "||v||^2"}
#: when the test is made
WHENS = {
    "before": "before each impulse, once an impact remains",
    "after": "right after each impulse, before the exit check",
}


@dataclass(frozen=True)
class Reading:
    """One reading of the paper's AEEV stop: ``measure < sigma_relative * norm``, tested ``when``.

    >>> Reading.parse("max_pair/v0/before") == MAX_PAIR_READING
    True
    """

    measure: str
    norm: str
    when: str

    def __post_init__(self) -> None:
        for value, allowed, what in ((self.measure, MEASURES, "measure"), (self.norm, NORMS, "norm"),
                                     (self.when, WHENS, "when")):  # fmt: skip
            if value not in allowed:
                raise ValueError(f"unknown AEEV {what} {value!r} (choose from {', '.join(allowed)})")

    @property
    def name(self) -> str:
        return f"{self.measure}/{self.norm}/{self.when}"

    @property
    def description(self) -> str:
        return f"{MEASURES[self.measure]} < sigma, sigma = c {NORMS[self.norm]}, tested {WHENS[self.when]}"

    @classmethod
    def parse(cls, text: str) -> Reading:
        """``"measure/norm/when"`` -> a :class:`Reading`."""
        parts = text.split("/")
        if len(parts) != 3:
            raise ValueError(f"an AEEV reading is measure/norm/when, such as max_pair/v0/before; got {text!r}")
        return cls(*parts)


def all_readings() -> list[Reading]:
    """Every reading of the family, in a fixed order (measure, then norm, then when)."""
    return [Reading(m, n, w) for m in MEASURES for n in NORMS for w in WHENS]


MAX_PAIR_READING = Reading("max_pair", "v0", "before")  #: the earlier reading
MAX_PAIR_SIGMA_RELATIVE = Fraction(4, 10**10)  #: inside the window of the earlier reading
PAPER_READING = Reading("l2_pair", "v", "before")  #: the reading paper mode uses
PAPER_SIGMA_RELATIVE = PAPER_SIGMA_STATED  #: the constant paper mode uses: the printed one


def default_sigma(reading: Reading) -> Fraction:
    """The constant paper mode uses with ``reading``: 4 * 10^-10 for the earlier reading, else 10^-9."""
    return MAX_PAIR_SIGMA_RELATIVE if reading == MAX_PAIR_READING else PAPER_SIGMA_RELATIVE


def squared_terms(v: Sequence[Any], measure: str, n: Any) -> tuple[list[Any], int]:
    """``(terms, d)``: the measure is below ``s >= 0`` iff every term is below ``d * s^2``.

    ``v`` holds exact numbers or backend elements; ``n`` is ``len(v)`` in the same domain
    (distances to the mean are ``(n v_i - sum v) / n``, so ``d = n^2`` and no division is
    made). For ``sumsq_pair`` the single term is the square of the sum of squares.

    >>> squared_terms([3, 1, 0], "max_pair", 3)
    ([4, 9, 1], 1)
    >>> squared_terms([3, 1, 0], "sumsq_pair", 3)
    ([196], 1)
    >>> squared_terms([3, 1, 0], "max_mean", 3)
    ([25, 1, 16], 9)
    """
    k = len(v)
    if measure.endswith("_pair"):
        diffs = [v[i] - v[j] for i in range(k) for j in range(i + 1, k)]
    elif measure.endswith("_adjacent"):
        diffs = [v[i] - v[i + 1] for i in range(k - 1)]
    else:
        total = sum(v[1:], v[0])
        diffs = [n * x - total for x in v]
    squares = [d * d for d in diffs]
    d = k * k if measure.endswith("_mean") else 1
    if measure.startswith("max_"):
        return squares, d
    s = sum(squares[1:], squares[0])
    return ([s * s] if measure == "sumsq_pair" else [s]), d


def norm_term_squared(v: Sequence[Any], v0_squared: Any, norm: str) -> Any:
    """The square of the quantity sigma is relative to (``||v0||^2``, ``||v||^2`` or their squares)."""
    q = v0_squared if norm.startswith("v0") else sum((x * x for x in v[1:]), v[0] * v[0])
    return q * q if norm.endswith("^2") else q


def ratio_squared(v: Sequence[Fraction], v0: Sequence[Fraction], reading: Reading) -> Fraction | None:
    """``(measure / norm)^2`` at the exact velocity ``v`` (None for a zero norm: the stop never fires).

    The stop fires iff ``ratio_squared < sigma_relative^2`` (strictly).

    >>> ratio_squared([Fraction(3), Fraction(1), Fraction(0)], [Fraction(1), 0, 0], MAX_PAIR_READING)
    Fraction(9, 1)
    """
    terms, d = squared_terms(v, reading.measure, len(v))
    q = norm_term_squared(v, sum((Fraction(x) ** 2 for x in v0), Fraction(0)), reading.norm)
    return None if q == 0 else max(terms) / (d * q)


class AeevHalt:
    """The stop of :func:`aeev_halt` (a ``halt`` for :func:`verify.laws.rule.solve`)."""

    def __init__(self, initial_velocity: Sequence[Fraction], sigma_squared: Fraction, reading: Reading,
                 strict: bool) -> None:  # fmt: skip
        self.reading = reading
        self.strict = strict
        self.after_impulse = reading.when == "after"
        self.v0_squared = sum((Fraction(x) * Fraction(x) for x in initial_velocity), Fraction(0))
        self.sigma_squared = Fraction(sigma_squared)
        self.cache: dict[int, tuple[Any, Any, Any]] = {}

    def __call__(self, system: Any, v: Sequence[Any], /) -> Halted | None:
        K = system.backend
        key = id(K)
        if key not in self.cache:
            self.cache.clear()
            self.cache[key] = (K.convert(self.sigma_squared), K.convert(self.v0_squared), K.convert(Fraction(len(v))))
        sigma_sq, v0_sq, n = self.cache[key]
        terms, d = squared_terms(v, self.reading.measure, n)
        bound = sigma_sq * norm_term_squared(v, v0_sq, self.reading.norm)
        if d != 1:
            bound = bound * K.convert(Fraction(d))
        for t in terms:
            s = K.sign(t - bound)
            if s > 0 or (s == 0 and self.strict):
                return None
        return Halted("aeev")


def aeev_halt(
    initial_velocity: Sequence[Fraction],
    sigma_relative: Fraction | None = None,
    *,
    reading: Reading = PAPER_READING,
    strict: bool = True,
    sigma_squared: Fraction | None = None,
) -> AeevHalt:
    """The paper's almost-equal-exit-velocities stop, as a ``halt`` for :func:`verify.laws.rule.solve`.

    Fires (returns ``Halted("aeev")``) when the ``reading``'s measure of the differences of the
    velocities is strictly below ``sigma = sigma_relative * norm`` (``strict=False``: ``<=``),
    tested before each impulse once an impact remains, or right after each impulse
    (``reading.when``). ``sigma_relative`` defaults to :func:`default_sigma`;
    ``sigma_squared`` gives its square instead (to test at an irrational end of a window).

    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("0")
    >>> halt = aeev_halt([Fraction(100), 0, 0])
    >>> halt(s, s.velocity(["100", "0", "0"])) is None
    True
    >>> halt(s, s.velocity(["1/3", "1/3", "1/3"]))
    Halted(stop='aeev', certificate=None)
    """
    if sigma_squared is None:
        sigma = default_sigma(reading) if sigma_relative is None else Fraction(sigma_relative)
        sigma_squared = sigma * sigma
    elif sigma_relative is not None:
        raise ValueError("give sigma_relative or sigma_squared, not both")
    return AeevHalt(initial_velocity, sigma_squared, reading, strict)
