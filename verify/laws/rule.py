"""The iterative impact rule of Pasquero (2021), eqs. (4)-(8), written once.

Given a :class:`~verify.dynamics.system.System` and a left velocity ``p_L^0`` (its components v),
the procedure of Sect. 3.5 is:

b) the impact set J = {i : p(F_i) < 0} (eq. 2; every sign through ``K.sign``);
c) for |J| >= 2 the global orthogonal velocity ``V_J`` and
   ``beta = Phi(V_J, sum V_j) / ||sum V_j||^2``;
d) the impulse (eq. 8): ``-beta sum (1 + eps_j) V_j`` for |J| >= 2,
   ``-(1 + eps_j) V_j`` for J = {j}, 0 for J empty;
e)-f) ``p^{w+1} = p^w + I(p^w)`` until J is empty: that velocity is ``p_R``.

The paper's step e) stops when ``p^{w+1} = p^w``; this happens exactly when J is empty,
because for non-empty J the impulse is never 0 (each ``V_j`` is a non-zero multiple of the
independent ``U_j``, and beta > 0: its numerator is ``sum_j p(F_j)^2 / G_jj``).

Orthogonal components, in terms of the system's ``U_i = g^{-1} dF_i^T`` and Gram matrix G:

- ``V_i(p) = (p(F_i) / G_ii) U_i``: the Phi-orthogonal component of p w.r.t. S_i;
- ``V_J(p) = sum_k mu_k U_k`` with ``G_JJ mu = (p(F_j))_{j in J}``: the component
  orthogonal to the intersection of the S_j (the Gram solve).

The ideal rule (5), the symmetric rule (6) and the asymmetric rule (7) are this rule with
all CORs 1, with equal CORs, and with two constraints: pick one by name in :func:`solve`.

>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
>>> r = solve(s, ["1", "0", "-1"])
>>> [s.backend.to_exact(x) for x in r.exit_velocity], r.impact_sets, r.stop
(['-1', '0', '1'], [(0, 1)], 'exit')
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property, partial
from typing import Any, Literal, get_args

from verify import bounds
from verify.dynamics.policy import Halt, Limits, Run, as_halt
from verify.dynamics.rates import beta_from_rates, coefficients
from verify.dynamics.system import (
    System,
    exact_backend_for_velocity,
    known_zero,
    on_exact_field,
    source_numbers,
    velocity_numbers,
)
from verify.errors import InvalidInput, InvalidSystem, NoConvergence, Undecided
from verify.laws.loops import balls
from verify.laws.loops import integer as fraction_free
from verify.laws.loops import rates as rate_form
from verify.laws.outcome import Result, Step
from verify.laws.sequential import Law, Sequential, solve_sequential
from verify.laws.simultaneous import solve_simultaneous
from verify.numbers.backends import Backend
from verify.numbers.format import counted
from verify.numbers.linalg import ldl, solve_spd
from verify.proofs.termination import non_termination_halt

RuleName = Literal["general", "ideal", "symmetric", "asymmetric"]
RULES: tuple[RuleName, ...] = get_args(RuleName)
#: the impact laws: the paper's iterative rule, the simultaneous law of :mod:`verify.laws.simultaneous`, and the
#: sequential-impulse law of :mod:`verify.laws.sequential` (``law=`` also takes its settings, a ``Sequential``)
LawName = Literal["rule", "simultaneous", "sequential"]
LAWS: tuple[LawName, ...] = get_args(LawName)
DEFAULT_MAX_ITERATIONS = 10_000


@dataclass(frozen=True)
class Budget:
    """Limits on one run, which then stops with ``"budget"`` instead of going on.

    ``bits`` bounds the size of the exact numbers (numerator plus denominator bits of
    the largest velocity component, :meth:`~verify.numbers.backends.Backend.size`): a
    deterministic limit, the same on every machine. ``seconds`` bounds the wall time of
    the iteration: it depends on the machine, so results that hit it are not
    reproducible; prefer ``bits`` where reproducibility matters.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/3", "1/7"])
    >>> r = solve(s, ["100", "0", "0"], budget=Budget(bits=10))
    >>> r.stop, r.iterations
    ('budget', 2)
    """

    seconds: float | None = None
    bits: int | None = None
    #: an exact run that passes ``bits`` is run again on certified intervals (every branch decided
    #: with proof, the precision raised as needed up to ``interval_dps`` digits): its exit, or its proof
    #: that it never exits, is then the result (on the interval backend, with a note); ``"budget"``
    #: remains only when the intervals cannot decide it either
    intervals: bool = False
    interval_dps: int = 400

    def __post_init__(self) -> None:
        for name in ("seconds", "bits", "interval_dps"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or not value > 0):
                raise InvalidSystem(f"budget {name} must be positive, got {value!r}")

    def limits(self, max_iterations: int) -> Limits:
        """The engines' stop policy (:mod:`verify.dynamics.policy`) for this budget and
        ``max_iterations`` impulses."""
        return Limits(max_iterations, bits=self.bits, seconds=self.seconds)


# -- the geometric quantities ------------------------------------------------------------


def impact_set(system: System, v: Sequence[Any]) -> tuple[int, ...]:
    """Step b): the constraints for which the velocity is incoming, ``p(F_i) < 0``."""
    K = system.backend
    return tuple(i for i, b in enumerate(system.rates(v)) if K.sign(b) < 0)


def orthogonal_component(system: System, v: Sequence[Any], i: int) -> tuple[Any, ...]:
    """``V_i(p) = (p(F_i) / G_ii) U_i``, the Phi-orthogonal component w.r.t. S_i.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0], [0, 1]], [[-1, 1]], [1])
    >>> [str(x) for x in orthogonal_component(s, s.velocity(["100", "0"]), 0)]
    ['50', '-50']
    """
    b = system.rates(v)[i]
    return system.combine_normals([(i, b / system.gram_diag[i])])


def global_orthogonal_component(system: System, v: Sequence[Any], J: Sequence[int]) -> tuple[Any, ...]:
    """``V_J(p)``: the component of p orthogonal to the intersection of the S_j, j in J.

    It is ``sum mu_k U_k`` where ``G_JJ mu = (p(F_j))_j`` (the Gram solve), so that
    ``p - V_J`` is tangent to every S_j.
    """
    b = system.rates(v)
    mu = _gram_solve(system, [b[j] for j in J], J)
    return system.combine_normals(list(zip(J, mu)))


def _gram_solve(system: System, rhs: Sequence[Any], J: Sequence[int]) -> tuple[Any, ...]:
    K = system.backend
    G_J = [[system.gram[j][k] for k in J] for j in J]
    return solve_spd(K, ldl(K, G_J), rhs)


def beta(system: System, v: Sequence[Any], J: Sequence[int]) -> Any:
    """The coefficient beta of Sect. 3.5 c) for the impact set J (|J| >= 2).

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    >>> str(beta(s, s.velocity(["1", "0", "-1"]), (0, 1)))
    '2'
    """
    if len(J) < 2:
        raise ValueError("beta is defined for impact sets of two or more constraints")
    return beta_from_rates(system, system.rates(v), J)


def _impulse_from_rates(system: System, b: Sequence[Any], J: Sequence[int]) -> tuple[tuple[Any, ...], Any]:
    """Eq. (8) given the rates p(F_i): returns (impulse, beta or None).

    The impulse is ``sum_j c_j U_j`` with ``c_j = -(1 + e_j) p(F_j) / G_jj`` for a single
    impact and ``c_j = -beta (1 + e_j) p(F_j) / G_jj`` for a multiple one
    (:func:`verify.dynamics.rates.coefficients`).
    """
    pairs, bt = coefficients(system, b, tuple(J))
    return system.combine_normals(pairs), bt


def impulse(system: System, v: Sequence[Any], J: Sequence[int] | None = None) -> tuple[Any, ...]:
    """The reactive impulse I(p) of eq. (8) for the impact set J (default: step b's).

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0], [0, 1]], [[-1, 1]], ["1/2"])
    >>> [str(x) for x in impulse(s, s.velocity(["100", "0"]))]
    ['-75', '75']
    """
    J = impact_set(system, v) if J is None else tuple(J)
    if not J:
        return (system.backend.zero,) * system.n
    return _impulse_from_rates(system, system.rates(v), J)[0]


# -- the iteration ------------------------------------------------------------------------------


def _system_for_rule(system: System, rule: str) -> System:
    if rule == "general":
        return system
    if rule == "ideal":
        return system.with_restitution([1] * system.r)
    if rule == "symmetric":
        e = system.source["restitution"]
        if any(x != e[0] for x in e):
            raise InvalidSystem(f"the symmetric rule (6) needs one COR for all constraints, got {[str(x) for x in e]}")
        return system
    if rule == "asymmetric":
        if system.r != 2:
            raise InvalidSystem(f"the asymmetric rule (7) is for two constraints, the system has {system.r}")
        return system
    raise InvalidSystem(f"unknown rule {rule!r} (choose from {', '.join(RULES)})")


def rule_name(rule: str) -> RuleName:
    """``rule`` as one of :data:`RULES` (:class:`~verify.errors.InvalidSystem` for another name).

    >>> rule_name("symmetric")
    'symmetric'
    """
    for name in RULES:
        if rule == name:
            return name
    raise InvalidSystem(f"unknown rule {rule!r} (choose from {', '.join(RULES)})")


# -- signs that intervals cannot decide: zeros known by structure, or checked exactly ---------------
#
# A rate that is exactly 0 is an interval around 0 on the interval backend, at any precision.
# Two things decide it instead of a chase in precision:
#
# - the structure of the impulse. An impulse ``sum_k c_k U_k`` on J changes the rates by
#   ``p'(F_i) = p(F_i) + sum_k G_ik c_k``. So a single impact on j leaves
#   ``p'(F_j) = -e_j p(F_j)`` (eq. 4: ``c_j = -(1 + e_j) p(F_j) / G_jj``), exactly 0 for a COR
#   of 0; a constraint with ``G_ik = 0`` for every k in J keeps its rate; and a multiple
#   impact whose G_JJ is diagonal has beta = 1, so each j in J gets ``-e_j p(F_j)`` as after a
#   single impact. Beyond that a multiple impact fixes no single rate: with equal CORs e on
#   J only the weighted sum ``sum_j lambda_j p'(F_j) = -e sum_j lambda_j p(F_j)`` (lambda_j =
#   p(F_j) / G_jj) is known, so its rates are left to the arithmetic. These identities are
#   exact, so the rule uses them on every backend (exact ones get the same values).
# - an exact check. When the inputs are rational or algebraic, a rate that stays undecided (in
#   the first impulses of a run at once, later only at the precision limit: see
#   :meth:`_ExactRates.eager`) is
#   recomputed exactly (:class:`_ExactRates`: the run's impact sets replayed on the exact
#   backend, only when asked); an exact 0 then becomes the point 0. A non-zero rate is left
#   to more precision, which separates it from 0. Transcendental inputs (tan(3/10)) have no
#   exact check: a zero that the structure does not explain stays undecided there.


def _couplings(system: System) -> tuple[frozenset[int], ...]:
    """For each constraint i, the k with ``G_ik`` not known to be 0 (i itself included)."""
    K, G, r = system.backend, system.gram, system.r
    return tuple(frozenset(k for k in range(r) if k == i or not known_zero(K, G[i][k])) for i in range(r))


def _structure(couplings: Sequence[frozenset[int]], J: tuple[int, ...]) -> tuple[bool, tuple[int, ...]]:
    """What an impulse on J fixes exactly: (each j in J ends at ``-e_j p(F_j)``, the constraints
    whose rate it leaves unchanged)."""
    hit = frozenset(J)
    diagonal = all(couplings[j] & hit == {j} for j in J)  # G_JJ diagonal: beta = 1 (always for |J| = 1)
    untouched = tuple(i for i, c in enumerate(couplings) if i not in hit and not c & hit)
    return diagonal, untouched


def _rates_after(
    system: System,
    v: tuple[Any, ...],
    b: Sequence[Any],
    J: tuple[int, ...],
    *,
    structure: tuple[Any, ...],
    minus_e: tuple[Any, ...],
) -> tuple[Any, ...]:
    """The rates of the velocity ``v`` after an impulse on J from rates ``b``: those of
    ``system.rates(v)``, except where the structure of the impulse gives them exactly."""
    fresh = system.rates(v)
    diagonal, untouched = structure
    if not diagonal and not untouched:
        return fresh
    out = list(fresh)
    if diagonal:
        for j in J:
            out[j] = minus_e[j] * b[j]
    for i in untouched:
        out[i] = b[i]
    return tuple(out)


#: impulses up to which an undecided rate of algebraic inputs is checked exactly at once
EAGER_EXACT_IMPULSES = 16


class _ExactRates:
    """The exact rates of the states of a run, for signs that its backend leaves undecided.

    Built only when first asked: the system and the velocity on the exact backend (the
    rationals, or the number field of the inputs). A state is reached by replaying the run's
    impact sets (known, since every earlier sign was decided) from the last one asked. With ``bits``,
    a replay whose numbers pass that size (:meth:`~verify.numbers.backends.Backend.size`) gives up: the sign
    stays undecided (the run on intervals after an exact run stopped by the size budget: its replay
    would pass the same budget).
    """

    def __init__(self, system: System, velocity: Sequence[Any], bits: int | None = None):
        self._source = (system, velocity)
        self.bits = bits
        self._exact: tuple[System, tuple[Any, ...]] | None = None
        self.unavailable: str | None = None  #: why no exact check exists (an input that is not algebraic)
        self._state: tuple[int, tuple[Any, ...]] | None = None
        self.limit = False  #: whether the backend is at its precision limit (set by :meth:`at`)

    def at(self, *, limit: bool) -> _ExactRates:
        """Itself, told whether the backend is at its precision limit (see :meth:`eager`)."""
        self.limit = limit
        return self

    def eager(self, impulses: int) -> bool:
        """Whether to check exactly now rather than raise the precision first: when the run is
        short (at most :data:`EAGER_EXACT_IMPULSES` impulses), or at the precision limit.
        Otherwise a tiny non-zero rate is left to more precision first: the exact replay of a long
        run costs as much as the exact run itself (its numbers grow with every impulse), and in a
        number field far more (``verify bench`` measures long interval runs of a rational corner with and
        without the exact checks)."""
        return self.limit or impulses <= EAGER_EXACT_IMPULSES

    @cached_property
    def _values(self) -> list[Any]:
        return velocity_numbers(self._source[1])

    def available(self) -> bool:
        """Whether an exact check exists (every input rational or algebraic); builds it."""
        if self._exact is None and self.unavailable is None:
            system, values = self._source[0], self._values
            try:
                exact = on_exact_field(system, values)
            except InvalidInput:  # BadNumber: an input that is not algebraic
                numbers = source_numbers(system) + values
                bad = next(x for x in numbers if not isinstance(x, Fraction) and x.is_algebraic is not True)
                self.unavailable = f"{bad} is not algebraic"
                return False
            self._exact = (exact, exact.velocity(values))
        return self._exact is not None

    def _built(self) -> tuple[System, tuple[Any, ...]]:
        """The system and left velocity on the exact backend (Undecided when there is none)."""
        self.available()
        if self._exact is None:
            raise Undecided(self.unavailable)
        return self._exact

    def rates(self, impact_sets: Sequence[tuple[int, ...]]) -> tuple[Any, ...]:
        """The exact rates after the impulses on ``impact_sets`` (from the run's left velocity)."""
        system, v0 = self._built()
        done, v = self._state if self._state is not None and self._state[0] <= len(impact_sets) else (0, v0)
        for n, J in enumerate(impact_sets[done:], done + 1):
            if self.bits is not None and _largest_size(system.backend, v) > self.bits:
                raise Undecided(f"the exact check passed {self.bits} bits after {counted(n - 1, 'impulse')}")
            I, _ = _impulse_from_rates(system, system.rates(v), J)
            v = tuple(x + y for x, y in zip(v, I))
            self._state = (n, v)
        return system.rates(v)

    def __call__(self, system: System, impact_sets: Sequence[tuple[int, ...]], i: int, exc: Undecided) -> int:
        """The sign of rate i when it is exactly 0, else Undecided (more precision decides it)."""
        where = f"the rate of {system.names[i]} after {counted(len(impact_sets), 'impulse')}"
        if not self.eager(len(impact_sets)):
            raise Undecided(f"{where}: {exc}") from None
        if not self.available():
            raise Undecided(f"{where}: {exc}") from None
        exact_system = self._built()[0]
        try:
            rates = self.rates(impact_sets)
        except Undecided as why:
            raise Undecided(f"{where}: {exc}; {why}") from None
        if exact_system.backend.sign(rates[i]) == 0:
            return 0
        raise Undecided(f"{where}: {exc}; exact arithmetic finds it non-zero: more precision separates it from 0")


def _impact_set_of(
    system: System, b: tuple[Any, ...], impact_sets: Sequence[tuple[int, ...]], exact: _ExactRates | None
) -> tuple[tuple[int, ...], tuple[Any, ...]]:
    """Step b) on the rates ``b``: (J, the rates, with any zero found exactly made the point 0)."""
    K = system.backend
    try:
        return tuple(i for i, bi in enumerate(b) if K.sign(bi) < 0), b
    except Undecided:
        if exact is None:
            raise
    out, J = list(b), []
    for i, bi in enumerate(b):
        try:
            s = K.sign(bi)
        except Undecided as exc:
            s = exact(system, impact_sets, i, exc)  # 0, or raises
            out[i] = K.zero  # proved 0: the point 0 encloses it
        if s < 0:
            J.append(i)
    return tuple(J), tuple(out)


def _largest_size(K: Backend, v: tuple[Any, ...]) -> int:
    return max(K.size(x) for x in v)


def _iterate(
    system: System,
    v: tuple[Any, ...],
    limits: Limits,
    halts: list[Halt],
    trace: bool,
    *,
    progress: Callable[[int], None] | None = None,
    exact: _ExactRates | None = None,
) -> Run:
    K = system.backend
    limits = limits.start()
    steps: list[Step] = []
    impact_sets: list[tuple[int, ...]] = []
    betas: list[Any] = []
    certificate = None
    couplings = _couplings(system)
    minus_e = tuple(K.zero - e for e in system.restitution)
    structures: dict[tuple[int, ...], tuple[Any, ...]] = {}
    b = system.rates(v)
    after = [h for h in halts if h.after_impulse]  # tested before the exit check
    halts = [h for h in halts if not h.after_impulse]
    doubt = _Doubt(K)
    while True:
        halted = next((r for r in (h(system, v) for h in after) if r is not None), None) if impact_sets else None
        if halted is not None:
            stop, certificate = halted.stop, halted.certificate
            break
        J, b = _impact_set_of(system, b, impact_sets, exact)
        doubt.see(len(impact_sets), b)
        if not J:
            stop = "exit"
            break
        view = rate_form.KnownRates(system, v, b) if halts else system
        halted = next((r for r in (h(view, v) for h in halts) if r is not None), None)
        if halted is not None:
            stop, certificate = halted.stop, halted.certificate
            break
        limit = limits.stop(len(impact_sets), partial(_largest_size, K, v))
        if limit is not None:
            stop = limit
            break
        I, bt = _impulse_from_rates(system, b, J)
        v = tuple(x + y for x, y in zip(v, I))
        impact_sets.append(J)
        betas.append(bt)
        if trace:
            steps.append(Step(J, b, bt, I, v, system))
        if progress is not None:
            progress(len(impact_sets))
        if J not in structures:
            structures[J] = _structure(couplings, J)
        b = _rates_after(system, v, b, J, structure=structures[J], minus_e=minus_e)
    return Run(v, stop, impact_sets, betas, tuple(steps), certificate, doubt.first)


#: a rate closer to 0 than this many units in the last place of the rates' size (at the backend's decimal
#: digits) is below the working precision of a backend that is not rigorous: its sign is noise
DOUBT_UNITS = 10**5


class _Doubt:
    """The first impulse whose impact set a non-rigorous backend (mp, float) decided on a rate below its
    working precision: non-zero and under :data:`DOUBT_UNITS` units in the last place of the largest rate
    seen so far. Rigorous backends decide every sign with proof: nothing is watched there."""

    def __init__(self, K: Backend) -> None:
        self.watch = not K.is_rigorous
        self.digits = 10 ** (K.dps or 0) if self.watch else 1  # the rates' size over this: one unit in the last place
        self.scale: Any = None
        self.first: tuple[int, Any, Any] | None = None

    def see(self, impulses: int, b: Sequence[Any]) -> None:
        """Watch the rates b from which the impact set of impulse ``impulses + 1`` is decided."""
        if not self.watch or self.first is not None:
            return
        sizes = [abs(x) for x in b]
        top = max(sizes, default=0)
        self.scale = top if self.scale is None or top > self.scale else self.scale
        low = min((x for x in sizes if x != 0), default=None)
        if low is not None and low * self.digits <= self.scale * DOUBT_UNITS:
            self.first = (impulses + 1, low, self.scale)


#: impulses on the rationals before a run without trace or stop tests moves to integers
#: (:mod:`verify.laws.loops.integer`): short runs do not repay the integer set-up
FRACTION_FREE_AFTER = 3


def _iterate_untraced(
    system: System, v: tuple[Any, ...], limits: Limits, halts: list[Halt], progress: Callable[[int], None] | None
) -> Run:
    """:func:`_iterate` without a trace, on an exact backend: in rate coordinates
    (:mod:`verify.dynamics.rates`), and on the rationals, when no stop test or progress needs
    the velocity at every impulse, the rest of a long run over integers after the first impulses
    (same values, same deadline)."""
    limits = limits.start()
    if halts or progress is not None or not system.backend.fraction_free:
        return rate_form.iterate(system, v, limits, halts=halts, progress=progress)
    out = rate_form.iterate(system, v, limits, cap=FRACTION_FREE_AFTER)
    if out.stop != "max_iterations" or len(out.impact_sets) == limits.max_iterations:
        return out
    rest = limits.capped(limits.max_iterations - len(out.impact_sets))
    return out.then(fraction_free.iterate(system, out.v, rest))


def _run(
    system: System,
    v0: tuple[Any, ...],
    limits: Limits,
    halts: list[Halt],
    *,
    trace: bool,
    progress: Callable[[int], None] | None,
    exact: _ExactRates | None,
) -> Run:
    """One run at the system's backend: in rate coordinates (and over integers) when the backend
    is exact and nothing is traced; on rate midpoints with one radius on intervals when nothing is
    traced or tested (:mod:`verify.laws.loops.balls`); else the traced loop."""
    K = system.backend
    if K.is_exact and not K.is_parametric and not trace:
        return _iterate_untraced(system, v0, limits, halts, progress)
    checks = exact.at(limit=K.refined() is None) if exact is not None else None
    if K.ball_form and not trace and not halts and progress is None:
        return balls.iterate(system, v0, limits, exact=checks)
    return _iterate(system, v0, limits, halts, trace, progress=progress, exact=checks)


def _result(
    system: System, rule: str, v0: tuple[Any, ...], out: Run, *, max_iterations: int, notes: list[str]
) -> Result:
    """The :class:`Result` of a run (with the note of a run not to be trusted, :class:`_Doubt`)."""
    if out.doubt is not None:
        notes = [*notes, _doubt_note(system.backend, *out.doubt)]
    return Result(
        system=system,
        rule=rule,
        velocity_in=v0,
        exit_velocity=out.v,
        stop=out.stop,
        steps=out.steps,
        impact_sets=out.impact_sets,
        betas=out.betas,
        max_iterations=max_iterations,
        notes=tuple(notes),
        certificate=out.certificate,
        doubtful=out.doubt[0] if out.doubt is not None else None,
    )


def _doubt_note(K: Backend, impulse: int, rate: Any, scale: Any) -> str:
    """The note of a run that is not to be trusted (:class:`_Doubt`)."""
    from mpmath import mpf, nstr

    return (
        f"not to be trusted from impulse {impulse} on: its impact set was decided on a rate of "
        f"{nstr(mpf(rate), 3)}, below the working precision ({K.dps} digits of the rates' size "
        f"{nstr(mpf(scale), 3)}), so its sign may be noise; the exact or the interval backend decides every sign "
        "(--backend exact, --backend interval)"
    )


def _no_convergence(K: Backend, exc: Undecided, exact: _ExactRates) -> NoConvergence:
    """The error for a sign still undecided at the precision limit of ``K``, with the reason."""
    why = (
        "the inputs are exact: use the exact backend, which decides every sign"
        if exact.available()
        else f"the inputs cannot be computed exactly ({exact.unavailable}), so a value that is exactly "
        "0 cannot be told from a tiny one: only the zeros that the structure of the impulses gives "
        "(such as a COR of 0 at a single impact) are known on intervals. The input is valid: this is "
        "a limit of the interval backend"
    )
    return NoConvergence(f"{K.describe()}: a sign stayed undecided at the precision limit ({exc}); {why}")


def law_name(law: Law) -> str:
    """The name of a law as :func:`solve` takes it (a name of :data:`LAWS`, or a ``Sequential``); an unknown
    law is an error.

    >>> law_name("simultaneous"), law_name(Sequential(iterations=3))
    ('simultaneous', 'sequential')
    """
    if isinstance(law, Sequential):
        return law.name
    if law not in LAWS:
        raise InvalidSystem(f"unknown law {law!r} (choose from {', '.join(LAWS)})")
    return law


def solve(
    system: System,
    velocity: Sequence[Any],
    *,
    rule: str = "general",
    law: Law = "rule",
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    halt: Halt | Callable[[Any, Sequence[Any]], Any] | None = None,
    trace: bool = True,
    certify: bool = True,
    budget: Budget | None = None,
    progress: Callable[[int], None] | None = None,
) -> Result:
    """Run the rule from the left velocity ``velocity`` until it exits (or a stop test fires).

    ``rule`` is ``"general"`` (eq. 8, the system's own CORs), ``"ideal"`` (eq. 5, all CORs 1), ``"symmetric"``
    (eq. 6, requires equal CORs) or ``"asymmetric"`` (eq. 7, requires two constraints). ``law="simultaneous"``
    applies the simultaneous law instead (:mod:`verify.laws.simultaneous`) with the CORs that ``rule`` gives,
    ``law="sequential"`` or ``law=Sequential(iterations=..., order=..., threshold=...)`` the sequential-impulse
    law (:mod:`verify.laws.sequential`); the options of the iteration are then unused. ``max_iterations`` caps
    the number of impulses (stop ``"max_iterations"``); ``halt`` is an extra stop test such as the paper's AEEV
    stop. With ``certify``
    (the default) a run also stops, with stop ``"non_terminating"`` and a certificate, as soon as it is
    proved never to exit (:mod:`verify.proofs.termination`). ``budget`` (a :class:`Budget`) ends a run whose
    numbers grow too large or which takes too long with stop ``"budget"`` (or, :attr:`Budget.intervals`,
    decides it on certified intervals). ``progress``, if given, is called with the number of impulses so
    far after every impulse (it should be cheap); a run repeated at higher precision counts again from 1.
    On a backend whose signs can be undecided (intervals) the run is repeated at higher
    precision, and the result's ``notes`` say so; :class:`~verify.errors.NoConvergence` is
    raised when the precision limit is reached. A rate that is exactly 0 is not chased in
    precision: the rule knows the zeros that the impulses make by their structure (a COR of 0
    at a single impact), and, when every input is rational or algebraic, checks any other
    undecided rate exactly (replaying the impact sets on the exact backend).
    ``trace=False`` keeps only impact sets and betas (for long runs).

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    >>> r = solve(s, ["100", "0", "0"], rule="symmetric")
    >>> r.iterations, [s.backend.to_exact(x) for x in r.exit_velocity]
    (3, ['325/16', '375/16', '225/4'])
    """
    if not isinstance(max_iterations, int) or max_iterations < 0:
        raise InvalidSystem(f"max_iterations must be a non-negative integer, got {max_iterations!r}")
    name = law_name(law)
    system = _system_for_rule(system, rule)
    if name == "simultaneous":
        return solve_simultaneous(system, velocity, rule=rule, max_iterations=max_iterations)
    if name == "sequential":
        return solve_sequential(system, velocity, law if isinstance(law, Sequential) else Sequential(), rule=rule)
    options = RunOptions(rule_name(rule), max_iterations, None if halt is None else as_halt(halt), trace, certify)
    return _solve_rule(system, velocity, budget, progress, options, searched=set())


@dataclass(frozen=True)
class RunOptions:
    """The options of one run of the rule (:func:`solve`): its rule, its cap, its extra stop test, whether it
    keeps its trace and whether it looks for a proof that it never exits."""

    rule: RuleName
    max_iterations: int
    halt: Halt | None
    trace: bool
    certify: bool


def _solve_rule(
    system: System,
    velocity: Sequence[Any],
    budget: Budget | None,
    progress: Callable[[int], None] | None,
    options: RunOptions,
    *,
    searched: set[tuple[int, int]],
    exact_bits: int | None = None,
) -> Result:
    """:func:`solve` for the rule (``options``: its rule, max_iterations, halt, trace and certify), repeated at
    higher precision on intervals. ``searched`` holds the cone searches (impulse, period) that failed in an
    earlier attempt of the same run, at a lower precision or exactly: the stop test does not repeat them.
    ``exact_bits`` bounds the exact checks of undecided signs (:class:`_ExactRates`)."""
    limits = budget.limits(options.max_iterations) if budget is not None else Limits(options.max_iterations)
    notes: list[str] = []
    # checks of undecided signs
    exact = _ExactRates(system, velocity, exact_bits) if system.backend.refinable else None
    halt, certify = options.halt, options.certify
    while True:
        try:
            if system.backend.widens_to_inputs:
                system, v0 = exact_backend_for_velocity(system, velocity)
            else:
                v0 = system.velocity(velocity)
            tests = (halt, non_termination_halt(system, searched=searched) if certify else None)
            halts = [h for h in tests if h is not None]
            out = _run(system, v0, limits, halts, trace=options.trace, progress=progress, exact=exact)
            break
        except Undecided as exc:
            K = system.backend
            if not K.refinable:
                raise
            finer = K.refined()
            if finer is None:
                raise _no_convergence(K, exc, exact or _ExactRates(system, velocity)) from None
            notes.append(f"precision raised from {K.dps} to {finer.dps} digits after an undecided sign")
            system = system.convert_to(finer)
    result = _result(system, options.rule, v0, out, max_iterations=options.max_iterations, notes=notes)
    return _decided_on_intervals(result, velocity, budget, options, searched)


def _decided_on_intervals(
    result: Result, velocity: Sequence[Any], budget: Budget | None, options: RunOptions, searched: set[tuple[int, int]]
) -> Result:
    """``result`` itself, or, for an exact run stopped by the size budget with :attr:`Budget.intervals`, the
    same run from the start on certified intervals if they decide it (the rule's system again: the rule's
    CORs are already in it; the cone searches that failed on the exact run are not repeated, and an exact
    check of an undecided sign gives up past the same size budget)."""
    import dataclasses

    from verify.numbers.backends import IntervalBackend

    system = result.system
    if result.stop != "budget" or budget is None or not budget.intervals:
        return result
    if not system.backend.is_exact or system.backend.is_parametric:
        return result
    K = IntervalBackend(max_dps=budget.interval_dps)
    try:
        decided = _solve_rule(
            system.convert_to(K),
            velocity,
            Budget(seconds=budget.seconds),
            None,
            options,
            searched=searched,
            exact_bits=budget.bits,
        )
    except NoConvergence:  # a sign undecided at budget.interval_dps digits
        bounds.reached("run_digits")
        return result
    except InvalidInput:
        return result
    if decided.stop == "budget":
        return result
    bounds.use("run_digits", decided.system.backend.dps or 0)  # an interval backend: its digits
    note = (
        f"the exact numbers passed {budget.bits} bits after {counted(result.iterations, 'impulse')}: run again on "
        f"certified intervals (every branch decided with proof), which end it with {decided.stop}"
    )
    return dataclasses.replace(decided, notes=(*decided.notes, note))


def solve_many(
    system: System,
    velocities: Sequence[Sequence[Any]],
    *,
    restitutions: Sequence[Sequence[Any]] | None = None,
    **options: Any,
) -> list[Result]:
    """Run the rule on many cases over one geometry: case i is ``velocities[i]`` with the CORs
    ``restitutions[i]`` (default: the system's own), each as :func:`solve` runs it with
    ``options``.

    The geometry is built and checked once: a new COR vector shares it
    (:meth:`~verify.dynamics.system.System.with_restitution`), and a COR vector repeated between
    cases is converted once. To run one velocity over many CORs, repeat the velocity.

    >>> from verify.dynamics.system import System
    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
    >>> out = solve_many(s, [["1", "0", "0"]] * 2, restitutions=[[1, 1], ["1/2", "1/2"]], trace=False)
    >>> [[s.backend.to_exact(x) for x in r.exit_velocity] for r in out]
    [['0', '0', '1'], ['13/64', '15/64', '9/16']]
    """
    if restitutions is not None and len(restitutions) != len(velocities):
        raise InvalidSystem(
            f"solve_many: {len(velocities)} velocities but {len(restitutions)} restitution vectors (one per case)"
        )
    systems: dict[tuple[Any, ...], System] = {}
    out = []
    for i, v in enumerate(velocities):
        case = system
        if restitutions is not None:
            cors = tuple(restitutions[i])
            key = tuple((type(x), x) for x in cors)  # equal values of one type share a system
            case = systems.get(key) or systems.setdefault(key, system.with_restitution(cors))
        out.append(solve(case, v, **options))
    return out
