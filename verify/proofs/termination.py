"""Proofs that the rule never exits: invariant cones (two constraints) and repeating directions.

A *repeating direction* (any number of constraints): the rates are a positive multiple of
the rates some impulses earlier; the rates evolve on their own and the impulse is
positively homogeneous, so the same cycle of impacts repeats forever
(:func:`repeating_certificate`). The rest of this docstring is about the cones.

Write ``b = (p(F_0), p(F_1))`` for the rates of a velocity. An impulse changes b by a
linear map that depends only on b and the Gram matrix G: a single impact on S_k gives

    N_k(b):  b_k -> -e_k b_k,   b_l -> b_l - (1 + e_k) b_k G_lk / G_kk      (l = 1 - k).

If ``G_01 < 0``, the impact on S_k lowers b_l, so the rule may hit S_0 and S_1 alternately
without end. For ``mu_0, mu_1 > 0`` let

    C_k = { b != 0 : b_k <= 0,  b_l >= 0,  e_l b_k + mu_k b_l <= 0 }.

Every b in C_k has ``b_k < 0 <= b_l``: the impact set is exactly {k}. If the current rates
lie in C_k, ``N_k`` maps C_k into C_l and ``N_l`` maps C_l into C_k, then by induction the
rule alternates single impacts forever: it never exits. Because the cones are convex and
the maps linear, the two inclusions need checking only on the two extreme rays of each
cone, ``(b_k, b_l) = (-1, 0)`` and ``(-mu_k, e_l)``: a finite list of sign conditions.

This module finds such cones: with ``c_k = (1 + e_k) |G_01| / G_kk`` and
``mu_k = lam c_l``, ``mu_l = (1 - lam) c_k``, the inclusions hold when
``lam^2 c_0 c_1 >= e_l`` and ``(1 - lam)^2 c_0 c_1 >= e_k`` (for one COR e and lam = 1/2:
``c_0 c_1 >= 4 e``, the condition for the two-step map to have real eigenvalues). Every
condition is checked here with the backend's exact or certified signs; the certificate
lists what was checked, so that a reader, or a test written without this module, can check
it again.

>>> from verify.models.cradle import cradle_system
>>> s = cradle_system("1/100")
>>> cert = cone_certificate(s, s.rates(s.velocity(["1", "0", "0"])), 0)
>>> cert["kind"], cert["mu"]
('alternating invariant cone', ['101/400', '101/400'])
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from verify import bounds
from verify.dynamics.policy import Halted, StopTest
from verify.dynamics.system import System
from verify.errors import Undecided
from verify.numbers.backends.base import Backend
from verify.proofs.cones.period import period_certificate

STATEMENT = (
    "From this state on the rule applies single impulses to the two constraints alternately, "
    "forever: the rates stay in the cones C_0, C_1, where exactly one constraint is hit."
)


def _apply(system: System, k: int, w: Sequence[Any]) -> list[Any]:
    """N_k(w) for a rate vector w (see the module docstring)."""
    K, G, e = system.backend, system.gram, system.restitution
    l = 1 - k
    out = [K.zero, K.zero]
    out[k] = K.zero - e[k] * w[k]
    out[l] = w[l] - (K.one + e[k]) * w[k] * G[l][k] / G[k][k]
    return out


def _in_cone(system: System, k: int, mu_k: Any, w: Sequence[Any]) -> bool:
    """w in C_k (the closed cone; w != 0 is not asked here)."""
    K, e = system.backend, system.restitution
    l = 1 - k
    return K.nonnegative(K.zero - w[k]) and K.nonnegative(w[l]) and K.nonnegative(K.zero - (e[l] * w[k] + mu_k * w[l]))


def _rays(system: System, k: int, mu_k: Any) -> list[list[Any]]:
    K, e = system.backend, system.restitution
    l = 1 - k
    r1, r2 = [K.zero, K.zero], [K.zero, K.zero]
    r1[k], r1[l] = K.zero - K.one, K.zero
    r2[k], r2[l] = K.zero - mu_k, e[l]
    return [r1, r2]


def _lambda(system: System, cc: Any) -> Any:
    """A weight lam in (0, 1) for the two cones: 1/2 for equal CORs, else found exactly."""
    K, e = system.backend, system.restitution
    half = K.convert(Fraction(1, 2))
    source = system.source["restitution"]
    if source[0] == source[1]:  # the same COR (compared exactly, before conversion)
        return half
    # lam in [sqrt(e_1/cc), 1 - sqrt(e_0/cc)] (for phase 0) found by bisection, from rationals:
    if K.rationals:
        c = K.to_number(cc)
        e0, e1 = K.to_number(e[0]), K.to_number(e[1])
    elif K.encloses and all(isinstance(x, Fraction) for x in source):
        # certified intervals with rational CORs: a lower bound of cc (lam^2 lo >= t then holds
        # for cc too); the cone conditions are verified afterwards, so lam cannot make them unsound
        bounds = K.enclosure(cc, 40)
        if bounds is None:
            return half
        c, (e0, e1) = Fraction(bounds[0]), source
    else:
        return half  # a parameter or approximate backend: try the symmetric weight only
    if c <= 0:
        return half

    def least(t: Fraction) -> Fraction:  # the least lam with lam^2 c >= t, from above, to 2^-60
        lo, hi = Fraction(0), Fraction(1)
        for _ in range(60):
            mid = (lo + hi) / 2
            lo, hi = (lo, mid) if mid * mid * c >= t else (mid, hi)
        return hi

    low, high = least(e1), 1 - least(e0)
    return K.convert((low + high) / 2) if low <= high else half


def cone_parameters(system: System, phase: int) -> list[Any] | None:
    """(mu_0, mu_1) for which N_0 maps C_0 into C_1 and N_1 maps C_1 into C_0, or None.

    Depends only on the system (G and the CORs) and on the constraint hit next; on a
    parameter backend the conditions hold for the whole range, or a split is raised.
    """
    if system.r != 2:
        return None
    K, G, e = system.backend, system.gram, system.restitution
    if K.sign(G[0][1]) >= 0:
        return None
    g = K.zero - G[0][1]
    c = [(K.one + e[k]) * g / G[k][k] for k in (0, 1)]
    lam = _lambda(system, c[0] * c[1])
    j, i = phase, 1 - phase
    mu = [K.zero, K.zero]
    mu[j] = lam * c[i]
    mu[i] = (K.one - lam) * c[j]
    if K.sign(mu[0]) <= 0 or K.sign(mu[1]) <= 0:
        return None
    for k in (0, 1):  # N_k(C_k) in C_l, checked on the extreme rays of C_k
        l = 1 - k
        if not all(_in_cone(system, l, mu[l], _apply(system, k, ray)) for ray in _rays(system, k, mu[k])):
            return None
    return mu


def cone_certificate(
    system: System, rates: Sequence[Any], phase: int, mu: list[Any] | None = None
) -> dict[str, Any] | None:
    """A certificate that the rule never exits from rates ``rates`` about to hit ``phase``.

    Returns None when the cones above do not apply (more than two constraints, G_01 >= 0,
    conditions that fail). On a parameter backend the conditions are decided for the whole
    parameter range, or a :class:`~verify.numbers.backends.symbolic.Split` is raised where they change.
    ``mu`` passes :func:`cone_parameters` when it is already known.
    """
    mu = cone_parameters(system, phase) if mu is None else mu
    if mu is None:
        return None
    K, G, e = system.backend, system.gram, system.restitution
    j = phase
    if not (K.sign(rates[j]) < 0 and _in_cone(system, j, mu[j], rates)):
        return None
    show = K.to_exact if K.is_exact else K.to_decimal
    return {
        "kind": "alternating invariant cone",
        "statement": STATEMENT,
        "rigorous": K.is_rigorous,
        "phase": j,
        "rates": [show(x) for x in rates],
        "gram": [[show(x) for x in row] for row in G],
        "restitution": [show(x) for x in e],
        "mu": [show(x) for x in mu],
        "cones": "C_k = {b != 0 : b_k <= 0, b_l >= 0, e_l*b_k + mu_k*b_l <= 0}, l = 1 - k",
        "map": "N_k: b_k -> -e_k*b_k, b_l -> b_l - (1 + e_k)*b_k*G_lk/G_kk",
        "checked": [
            "mu_0 > 0 and mu_1 > 0",
            "N_0 maps the rays (-1, 0) and (-mu_0, e_1) of C_0 into C_1",
            "N_1 maps the rays (0, -1) and (e_0, -mu_1) of C_1 into C_0",
            f"the rates lie in C_{j}, with b_{j} < 0",
        ],
    }


def repeating_certificate(
    system: System,
    earlier: Sequence[Any],
    now: Sequence[Any],
    impulses_between: int,
    impact_sets: Sequence[Sequence[int]],
) -> dict[str, Any] | None:
    """A certificate that the rule never exits: the rates now are a positive multiple of earlier ones.

    The rates evolve on their own (b -> b + A I(b)) and the impulse is positively homogeneous
    (beta does not change when b is scaled), so rates c*b repeat, scaled by c, the impacts
    that followed b: the same cycle of impact sets forever.
    """
    K = system.backend
    if not K.is_exact or impulses_between < 1:
        return None  # equality needs exact elements (canonical: rationals, number fields, rational functions)
    pivot = next((i for i, x in enumerate(earlier) if x != K.zero), None)
    if pivot is None:
        return None
    c = now[pivot] / earlier[pivot]
    if any(y - c * x != K.zero for x, y in zip(earlier, now)):  # identical, as elements
        return None
    try:
        if K.sign(c) <= 0:
            return None
    except Undecided:  # a factor whose sign changes with a parameter: no certificate, and no cut
        return None
    show = K.to_exact if K.is_exact else K.to_decimal
    return {
        "kind": "repeating direction",
        "statement": (
            "The rates are a positive multiple of the rates some impulses earlier; the rule depends on the rates "
            "alone and is positively homogeneous, so the same cycle of impacts repeats forever."
        ),
        "rigorous": K.is_rigorous,
        "rates_earlier": [show(x) for x in earlier],
        "rates_now": [show(x) for x in now],
        "factor": show(c),
        "cycle": [list(J) for J in impact_sets],
        "gram": [[show(x) for x in row] for row in system.gram],
        "restitution": [show(x) for x in system.restitution],
    }


def non_termination_halt(system: System, memory: int = 8, *, searched: set[tuple[int, int]] | None = None) -> StopTest:
    """A stop test for :func:`verify.laws.rule.solve` that returns ``Halted("non_terminating", certificate)``
    as soon as the run is proved never to exit: rates that repeat their direction (any
    number of constraints, exact backends), rates inside a cone that a period of linear impacts
    maps into itself (three or more constraints: :mod:`verify.proofs.cones.period`; exact, parameter and
    interval backends), or rates inside invariant cones (two constraints). ``searched`` holds the cone
    searches (impulse, period) that an earlier attempt of the same run made in vain (:func:`period_halt`)."""
    cone = cone_halt(system)
    history: list[tuple[int, Any, tuple[int, ...]]] = []  # (impulses so far, rates, impact set taken)
    # the earlier states by the direction of their rates (b / b_pivot): only a state in the same
    # direction can be a positive multiple, so one lookup replaces a scan of the last ``memory``
    directions: dict[tuple[Any, ...], list[int]] = {}

    periodic = period_halt(history, set() if searched is None else searched)

    def halt(system: System, v: Sequence[Any]) -> Halted | None:
        K = system.backend
        b = system.rates(v)
        if not K.is_exact or K.is_parametric:
            # enclosures: equal directions cannot be told (repeating_certificate needs exact elements);
            # rational functions of a parameter: equalities cost too much there; the cones of periods on
            # both when r >= 3, and of two constraints
            found = None
            if system.r >= 3 and (K.is_exact or K.encloses):
                J = tuple(i for i, x in enumerate(b) if K.sign(x) < 0)
                found = periodic(system, b, J)
                history.append((len(history), b, J))
            return found or (cone(system, v) if cone is not None else None)
        count = len(history)
        key = _direction(K, b)
        for w in reversed(directions.get(key, ())):
            if w < count - memory:
                break
            cycle = [J for _, _, J in history[w:]]
            cert = repeating_certificate(system, history[w][1], b, count - w, cycle)
            if cert:
                return Halted("non_terminating", cert)
        J = tuple(i for i, x in enumerate(b) if K.sign(x) < 0)
        found = periodic(system, b, J)
        history.append((count, b, J))
        directions.setdefault(key, []).append(count)
        if found:
            return found
        return cone(system, v) if cone is not None else None

    return StopTest(halt)


#: the longest period of impact sets looked for
MAX_PERIOD = 6
#: on a parameter backend, the impulses after which no cone of a period is looked for: its rational
#: functions grow in degree with every impulse, and so does the cost of a search (``verify cradle-map``)
PARAMETRIC_IMPULSES = 16
#: the impulses after which a cone search may end with a cone around the run's own points
#: (:mod:`verify.proofs.cones.hull`): the costliest search, for runs that switch between impact sets in no period,
#: which the other searches decide early or not at all
SWITCHED_AFTER = 64
#: exact rates of more bits than this are not searched for a cone, unless they are rationals (the search
#: then works on a box of short rationals around them; a run on certified intervals does so too)
MAX_BITS = 512


def period_halt(
    history: list[tuple[int, Any, tuple[int, ...]]], searched: set[tuple[int, int]]
) -> Callable[[System, Sequence[Any], tuple[int, ...]], Halted | None]:
    """A test on the run's ``history`` (impulses so far, rates, impact set) and the current rates b and
    impact set J: ``Halted("non_terminating", certificate)`` when the rates lie in a cone that p impulses map
    into itself (:func:`verify.proofs.cones.period.period_certificate`). Tried when the last three
    periods of p impulses overlap (each impact set shares a constraint with the one p impulses later:
    the same sets, or sets that change only where a rate is near 0), and, after a failure, again once
    the run has gone on as long again. A search that fails is added to ``searched`` as (impulse, period),
    and one found there is not made again: the run repeated at a higher precision, or on intervals after
    an exact run, reaches the same rates (the search boxes long numbers by short rationals)."""
    next_try = [0]

    def test(system: System, b: Sequence[Any], J: tuple[int, ...]) -> Halted | None:
        count = len(history)
        if count < next_try[0] or system.r < 3:  # two constraints: the alternating cones above
            return None
        if system.backend.is_parametric and count > PARAMETRIC_IMPULSES:
            if count == PARAMETRIC_IMPULSES + 1:
                bounds.reached("parametric_impulses")
            return None
        K = system.backend
        if not K.rationals:
            size = max(K.size(x) for x in b)
            if size > MAX_BITS:  # a search on such numbers costs too much (long rationals are boxed by the search)
                bounds.reached("field_bits")
                return None
            bounds.use("field_bits", size)
        sets = [set(h[2]) for h in history] + [set(J)]
        periods = [p for p in range(1, MAX_PERIOD + 1) if count >= 3 * p]
        tails = {p: sets[-3 * p - 1 :] for p in periods}
        same = [p for p in periods if all(tails[p][i] == tails[p][i + p] for i in range(2 * p + 1))]
        near = [p for p in periods if all(tails[p][i] & tails[p][i + p] for i in range(2 * p + 1))]
        tried = list(dict.fromkeys(same[:1] + near[:1]))  # the least exact period first, then the least overlap
        if tried:
            next_try[0] = count + max(8, count)
        for p in tried:
            if (count, p) in searched:
                continue
            cert = period_certificate(system, p, b, history[-p][1], switched=count >= SWITCHED_AFTER)
            if cert:
                bounds.use("period", p)
                if system.backend.is_parametric:
                    bounds.use("parametric_impulses", count)
                return Halted("non_terminating", cert)
            searched.add((count, p))
        return None

    return test


def _direction(K: Backend, b: Sequence[Any]) -> tuple[Any, ...]:
    """The rates divided by their first non-zero entry (and its index): equal for two rate
    vectors exactly when one is a non-zero multiple of the other (exact elements are canonical)."""
    pivot = next((i for i, x in enumerate(b) if x != K.zero), None)
    if pivot is None:
        return ()
    p = b[pivot]
    return (pivot, *(x / p for x in b))


def cone_halt(system: System) -> StopTest | None:
    """A stop test for :func:`verify.laws.rule.solve`: ``Halted("non_terminating", certificate)`` as soon
    as the rates enter an invariant cone (two-constraint systems only; None otherwise)."""
    if system.r != 2:
        return None

    params: dict[tuple[int, int], Any] = {}  # per backend and phase: the cones do not depend on the state

    def halt(system: System, v: Sequence[Any]) -> Halted | None:
        K = system.backend
        b = system.rates(v)
        try:
            for j in (0, 1):
                if K.sign(b[j]) < 0 and K.sign(b[1 - j]) >= 0:
                    key = (id(K), j)
                    if key not in params:
                        params[key] = cone_parameters(system, j)
                    if params[key] is None:
                        return None
                    cert = cone_certificate(system, b, j, params[key])
                    return Halted("non_terminating", cert) if cert else None
        except Undecided as exc:
            if hasattr(exc, "polys"):  # a parameter backend asks to cut its range: let it
                raise
            return None  # an enclosure too wide to decide a condition: no proof, go on
        return None

    return StopTest(halt)
