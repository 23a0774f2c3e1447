"""The simultaneous impact law: Newton's restitution with complementarity, solved exactly.

This is the law that physics engines implement (or relax): every constraint in contact takes
its impulse at once, in one step, instead of the paper's iteration. On the same
:class:`~verify.dynamics.system.System`, with the pre-impact rates ``w_i = p(F_i)`` of the left
velocity v (eq. 2), an impulse ``sum_i lambda_i U_i`` (``U_i = g^{-1} dF_i^T``) gives the exit
velocity ``v' = v + sum_i lambda_i U_i``, whose rates are ``w' = w + G lambda`` (G the Gram
matrix). The law asks, for every constraint i of the system (all are in contact at the
configuration):

    lambda_i >= 0,   w'_i + e_i min(w_i, 0) >= 0,   lambda_i (w'_i + e_i min(w_i, 0)) = 0.

- An **incoming** constraint (``w_i < 0``) obeys Newton's law ``w'_i >= -e_i w_i``, with
  equality when it takes an impulse (Moreau 1988, Anitescu & Potra 1997, Glocker 2001).
- A constraint that is **not incoming** (``w_i >= 0``: separating, or grazing with a rate of
  exactly 0) gets no restitution: ``w'_i >= 0``, with an impulse only to keep it from being
  penetrated, and it never bounces. The other reading of the standard statement, with
  ``e_i w_i`` on every closed contact, would let a separating contact (``w_i > 0``) leave with
  the penetrating rate ``-e_i w_i < 0``; engines apply restitution only to approaching
  contacts (a velocity bias when the normal velocity is negative), as here. On incoming
  constraints the two readings agree.

So ``lambda`` solves the linear complementarity problem LCP(q, G) with ``q_i = (1 + e_i) w_i``
for an incoming constraint and ``q_i = w_i`` otherwise. The system's normals are independent
(the constructor checks it), so G is positive definite, hence a P-matrix, and the LCP has
exactly one solution for every q (Cottle, Pang & Stone, The Linear Complementarity Problem,
Thm 3.3.7): the exit velocity and the impulses are unique. :func:`complementarity` finds it by
Murty's least-index principal pivoting method, finite for P-matrices, with every sign decided
by ``K.sign`` (exactly on the exact backends). Every exit rate is ``>= 0``: the exit velocity
is outgoing, so the run's stop is ``"exit"``, after one impulse (or none when nothing is
incoming).

>>> from verify.dynamics.system import System
>>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
>>> r = solve_simultaneous(s, ["100", "0", "0"])
>>> [s.backend.to_exact(x) for x in r.exit_velocity], r.impact_sets, [s.backend.to_exact(x) for x in r.impulses]
(['-100/3', '200/3', '200/3'], [(0, 1)], ['400/3', '200/3'])
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from verify.dynamics.system import System, exact_backend_for_velocity, known_zero, source_numbers, velocity_numbers
from verify.errors import BadNumber, NoConvergence, Undecided
from verify.laws.outcome import Result, Step
from verify.numbers.backends import Backend, exact_for
from verify.numbers.linalg import ldl, solve_spd

T = TypeVar("T")


def complementarity(
    K: Backend, G: Sequence[Sequence[Any]], q: Sequence[Any]
) -> tuple[tuple[int, ...], tuple[Any, ...]]:
    """The solution of LCP(q, G) for a positive definite G: the set S of constraints whose
    complementarity equation is active (``(G lambda + q)_i = 0``) and ``lambda`` (0 off S).

    Murty's least-index method: start from S empty; solve ``G_SS lambda_S = -q_S``; if some
    ``lambda_i < 0`` (i in S) or ``(G lambda + q)_i < 0`` (i not in S), move the least such
    index in or out of S, and repeat. For a P-matrix it never cycles (Murty 1974); the 2^r
    bound on pivots only guards against a G that is not one (an error, then).

    >>> from fractions import Fraction
    >>> from verify.numbers.backends import get_backend
    >>> K = get_backend("exact")
    >>> G = [[K.convert(Fraction(2)), K.convert(Fraction(-1))], [K.convert(Fraction(-1)), K.convert(Fraction(2))]]
    >>> S, lam = complementarity(K, G, [K.convert(Fraction(-200)), K.zero])
    >>> S, [str(x) for x in lam]
    ((0, 1), ['400/3', '200/3'])
    """
    r = len(q)
    active: set[int] = set()
    for _ in range(2**r + 1):
        S = tuple(sorted(active))
        lam = [K.zero] * r
        if S:
            G_SS = [[G[i][k] for k in S] for i in S]
            for i, x in zip(S, solve_spd(K, ldl(K, G_SS), [K.zero - q[i] for i in S])):
                lam[i] = x
        wrong = _first_infeasible(K, G, q, S, lam)
        if wrong is None:
            return S, tuple(lam)
        active ^= {wrong}
    raise Undecided(
        "the pivoting of the complementarity problem cycled: its matrix is not a P-matrix, or (on a backend "
        "whose signs are rounded) rounding steered it; use the exact or the interval backend"
    )


def _first_infeasible(
    K: Backend, G: Sequence[Sequence[Any]], q: Sequence[Any], S: tuple[int, ...], lam: list[Any]
) -> int | None:
    """The least index that violates its sign: ``lambda_i < 0`` on S, ``(G lambda + q)_i < 0`` off
    S (the other quantity is 0 by construction, so its sign is never asked); None if none."""
    for i in range(len(q)):
        if i in S:
            if K.sign(lam[i]) < 0:
                return i
            continue
        z = q[i]
        for k in S:
            z = z + G[i][k] * lam[k]
        if K.sign(z) < 0:
            return i
    return None


def incoming(system: System, rates: Sequence[Any]) -> tuple[bool, ...]:
    """Whether each constraint is incoming, ``w_i < 0`` (eq. 2; signs through ``K.sign``)."""
    K = system.backend
    return tuple(K.sign(w) < 0 for w in rates)


def lcp_vector(system: System, rates: Sequence[Any], hits: Sequence[bool] | None = None) -> tuple[Any, ...]:
    """``q_i = (1 + e_i) w_i`` for an incoming constraint (``hits[i]``, by default ``w_i < 0``),
    ``w_i`` otherwise.

    >>> s = System([[1, 0], [0, 1]], [[-1, 1]], ["1/2"])
    >>> [str(x) for x in lcp_vector(s, s.rates(s.velocity(["2", "0"])))]
    ['-3']
    """
    K = system.backend
    hits = incoming(system, rates) if hits is None else hits
    return tuple((K.one + e) * w if hit else w for w, e, hit in zip(rates, system.restitution, hits))


def _on_exact(system: System, velocity: Sequence[Any]) -> tuple[System, tuple[Any, ...]] | None:
    """The system and velocity on their exact backend, or None when an input is not algebraic."""
    values = velocity_numbers(velocity)
    try:
        exact = system.convert_to(exact_for(source_numbers(system) + values))
    except BadNumber:
        return None
    return exact, exact.velocity(values)


def _decide(
    system: System, v: tuple[Any, ...], exact: tuple[System, tuple[Any, ...]] | None
) -> tuple[tuple[bool, ...], tuple[int, ...], tuple[int, ...]]:
    """Which constraints are incoming, the active set, and the constraints of the active set whose
    impulse is not 0: on ``system``'s backend, or exactly when ``exact`` is given (an approximate
    backend with exact inputs: an exact 0 is then never chased, and rounding never steers the
    pivoting)."""
    s, u = exact if exact is not None else (system, v)
    rates = s.rates(u)
    hits = incoming(s, rates)
    S, lam = complementarity(s.backend, s.gram, lcp_vector(s, rates, hits))
    return hits, S, tuple(i for i in S if not known_zero(s.backend, lam[i]))


def _on_active_set(system: System, v: tuple[Any, ...], hits: tuple[bool, ...], S: tuple[int, ...]) -> tuple[Any, ...]:
    """``lambda`` with ``(G lambda + q)_S = 0`` and 0 off S (no sign asked)."""
    K, lam = system.backend, [system.backend.zero] * system.r
    if S:
        q = lcp_vector(system, system.rates(v), hits)
        G_SS = [[system.gram[i][k] for k in S] for i in S]
        for i, x in zip(S, solve_spd(K, ldl(K, G_SS), [K.zero - q[i] for i in S])):
            lam[i] = x
    return tuple(lam)


def solve_simultaneous(
    system: System, velocity: Sequence[Any], *, rule: str = "general", max_iterations: int = 1
) -> Result:
    """The simultaneous law's exit velocity from the left velocity ``velocity`` (one impulse).

    Use it through :func:`verify.laws.rule.solve` with ``law="simultaneous"`` (which also
    applies the ``rule`` variants' CORs). On an approximate backend (interval, mp, float) the
    active set is decided exactly when the inputs are rational or algebraic; else on intervals at
    raised precision (NoConvergence at the limit), on mp and float by their rounded signs.

    >>> s = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], ["1/2", "1/2"])
    >>> [s.backend.to_exact(x) for x in solve_simultaneous(s, ["100", "0", "0"]).exit_velocity]
    ['0', '50', '50']
    """
    exact = _on_exact(system, velocity) if not system.backend.is_exact else None

    def attempt(system: System) -> tuple[System, tuple[Any, ...]]:
        if system.backend.widens_to_inputs:
            system, v = exact_backend_for_velocity(system, velocity)
        else:
            v = system.velocity(velocity)
        hits, S, hit = _decide(system, v, exact)
        return system, (v, hit, _on_active_set(system, v, hits, S))

    system, (v, hit, lam), notes = refining(system, attempt, "the simultaneous law's active set")
    return _result(system, v, hit, lam, rule=rule, max_iterations=max_iterations, notes=notes)


def refining(system: System, attempt: Callable[[System], tuple[System, T]], what: str) -> tuple[System, T, list[str]]:
    """``attempt(system)`` (which returns the system it ran on, perhaps widened, and its value), repeated at higher
    precision while a sign is undecided on a refinable backend (intervals); the notes say so.
    :class:`~verify.errors.NoConvergence` names ``what`` at the precision limit; on other backends the
    :class:`~verify.errors.Undecided` is raised as it is."""
    notes: list[str] = []
    while True:
        try:
            system, value = attempt(system)
            return system, value, notes
        except Undecided as exc:
            finer = system.backend.refined() if system.backend.refinable else None
            if finer is None:
                if system.backend.refinable:
                    raise NoConvergence(f"{system.backend.describe()}: {what} stayed undecided ({exc})") from None
                raise
            notes.append(f"precision raised from {system.backend.dps} to {finer.dps} digits after an undecided sign")
            system = system.convert_to(finer)


def _result(
    system: System,
    v: tuple[Any, ...],
    hit: tuple[int, ...],
    lam: tuple[Any, ...],
    *,
    rule: str,
    max_iterations: int,
    notes: list[str],
) -> Result:
    """The Result of one simultaneous impulse on the constraints ``hit`` (no step when it is empty)."""
    impulse = system.combine_normals([(i, lam[i]) for i in hit])
    exit_velocity = tuple(x + d for x, d in zip(v, impulse)) if hit else v
    steps = (Step(hit, system.rates(v), None, impulse, exit_velocity, system),) if hit else ()
    return Result(
        system=system,
        rule=rule,
        velocity_in=v,
        exit_velocity=exit_velocity,
        stop="exit",
        steps=steps,
        impact_sets=[hit] if hit else [],
        betas=[None] if hit else [],
        max_iterations=max_iterations,
        notes=tuple(notes),
        law="simultaneous",
        impulses=lam,
    )
