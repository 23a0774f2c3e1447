"""Proofs that the rule never exits, for any number of constraints: a cone that p impulses map into itself.

Write ``b = (p(F_0), ..., p(F_{r-1}))`` for the rates. An impulse on J changes them by

    b -> b - beta sum_{j in J} (1 + e_j) (b_j / G_jj) G[:, j]

with beta = 1 for a single impact, and also for a multiple one whose constraints are mutually
orthogonal (G_JJ diagonal; Sect. 3.5 c). Such an impulse is a *linear* map of the rates,
``M_J``. The certificate is a finite list of generators (rate vectors), some *strict*, and a
number of impulses p. Carry the generators through p impulses, all together: at each impulse,
look at every vector carried so far and split the constraints into

- S, those where every strict vector is ``< 0`` and every other one ``<= 0`` (hit for sure),
- F, those where the vectors disagree (hit or not, depending on the point of the cone),
- the rest, where every vector is ``>= 0`` (not hit);

S must not be empty; the cone is cut at ``x_f = 0`` for each f in F (:func:`split`), and each part
moves on its own impact set J = S + T: by ``M_J`` when the impulse is linear, else with both bounds
of beta over the part (:func:`beta_bounds`), or by the polar values of the impulse's cubic form
(:mod:`verify.proofs.cones.polar`). After p impulses, each vector must be a non-negative
combination of the generators, with a positive weight on a strict generator when it comes from
a strict one. The rates must be a generator (or lie in the cone, :func:`box_seeds`).

Why this proves the rule never exits: a point ``x = sum c_k g_k`` (c >= 0, some weight on a
strict generator) has ``x_i < 0`` on S and ``x_i >= 0`` off S + F, so the rule hits it on
``J = S + T`` for the T of its own negative F-rates; then ``M_J x = sum c_k M_J g_k``, a
combination of vectors carried one impulse further, still with weight on strict ones. After
p impulses the point is again a combination of the generators: by induction the rule hits a
non-empty set at every impulse, forever. Every condition is a finite list of exact signs and
identities; the independent checker repeats them (``tests/certificate_check.py``).

The generators are found from the run: the rates now (and, for rational inputs, a box of
points around the direction the rates tend to), one more point beyond that direction, the unit
vectors of constraints never hit (weak generators: a period leaves them unchanged), then every
carried vector the cone does not contain yet, until the cone is closed.

>>> from verify.models.cradle import cradle_system
>>> s = cradle_system("1/20", 4)
>>> b = s.rates(s.velocity(["0", "1", "0", "-1"]))
>>> period_certificate(s, 2, b, None) is None  # hit on (0, 2) then (1): not yet a cone
True
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Any

from verify import bounds
from verify.dynamics.rates import SearchSystem, beta_from_rates
from verify.dynamics.system import System, on_exact_field
from verify.errors import Undecided
from verify.numbers.backends.base import Backend
from verify.proofs.cones import hull
from verify.proofs.cones.face import HEIGHTS, face_cone
from verify.proofs.cones.lp import Scaled, SearchTooLong, feasible, pivot_budget, solve_columns
from verify.proofs.cones.polar import MAX_VECTORS, extreme, forms, polar_values, pushed
from verify.proofs.cones.shape import exponent, floor_bits, rounded_direction, shaped_seeds
from verify.proofs.cones.stages import Combine, Lift, Outer, product_cone

#: the most generators a cone may have beyond its seeds, the rounds of closing it, and the most vectors
#: carried through a period
MAX_GENERATORS = 24
MAX_ROUNDS = 16
MAX_CARRIED = 400
#: the most pivots of exact linear programming one search may make: a little more than the most that a search which
#: found its cone made in the tests and the ci census (``VERIFY_BOUNDS=FILE`` then ``verify bounds FILE`` measures it);
#: a failing search can take many times more, each pivot slower
MAX_PIVOTS = 6_000
#: the most edges of a carried cone that may cross one hyperplane x_f = 0 (each gives a vector)
MAX_CROSSINGS = 10_000
#: the most vectors whose beta is bounded at a multiple impact (the bound takes every pair)
MAX_BETA_VECTORS = 40
#: exact rational rates longer than this (bits) are replaced by a box of 64-bit rationals that holds them
#: (:func:`rounded_box`): the cone is searched around the box, at the cost of short numbers
MAX_BITS = 512

STATEMENT = (
    "From this state on the rule hits a non-empty set at every impulse, forever: the rates stay in the cone "
    "of the generators, and p impulses map every point of it (carried with every impact set its signs allow) "
    "to a non-negative combination of the generators."
)

Vector = list[Any]


def linear_step(system: SearchSystem, J: Sequence[int]) -> bool:
    """Whether an impulse on J is linear in the rates: a single impact, or constraints mutually
    orthogonal (G_JJ diagonal, where beta = 1); decided exactly.

    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("1/2", 4)
    >>> linear_step(s, (0, 2)), linear_step(s, (0, 1))
    (True, False)
    """
    K, G = system.backend, system.gram
    return len(J) == 1 or all(G[i][j] == K.zero for i, j in itertools.combinations(J, 2))


def step(system: SearchSystem, J: Sequence[int], x: Sequence[Any], beta: Any = None) -> Vector:
    """The rates after an impulse on J with the coefficient beta (default 1, a linear impulse):
    ``x - beta sum_j (1 + e_j)(x_j/G_jj) G[:, j]``.

    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("1/2", 3)
    >>> K = s.backend
    >>> [str(v) for v in step(s, (0,), [K.convert(Fraction(-1)), K.zero])]
    ['1/2', '-3/4']
    """
    a = pushed(system, J, x)
    return [v - (w if beta is None else beta * w) for v, w in zip(x, a)]


def beta_bounds(system: SearchSystem, J: Sequence[int], vectors: Sequence[Vector]) -> list[Any] | None:
    """[beta_lo, beta_hi]: bounds of beta on the cone of the vectors (all hit on J), or None.

    beta = N(x)/D(x), with ``N = sum_j x_j^2 / G_jj`` and ``D = lam^T G_JJ lam`` (lam_j = x_j / G_jj)
    (Sect. 3.5 c). For ``x = sum c_k v_k`` (c >= 0), ``N(x) - t D(x) = sum c_k c_l (N_kl - t D_kl)``
    with the bilinear forms N_kl, D_kl of the vectors: it is >= 0 when every term is. So beta_lo is the
    least N_kl/D_kl over D_kl > 0 and beta_hi the largest, provided the terms with D_kl <= 0 have the
    right sign too. An impulse with beta in between is ``x - beta A x``, which lies between
    ``x - beta_lo A x`` and ``x - beta_hi A x`` with the same weights for every point of the cone:
    carrying each vector with both bounds keeps every point inside the carried cone.
    """
    K = system.backend
    if len(vectors) > MAX_BETA_VECTORS:
        bounds.reached("beta_vectors")
        return None
    bounds.use("beta_vectors", len(vectors))
    N, D = forms(system, J, vectors)
    pairs = [(N[k, l], D[k, l]) for k in range(len(vectors)) for l in range(k, len(vectors))]
    ratios = [n / d for n, d in pairs if K.sign(d) > 0]
    if not ratios:
        return None
    lo = hi = ratios[0]
    for x in ratios[1:]:
        lo = x if K.sign(x - lo) < 0 else lo
        hi = x if K.sign(x - hi) > 0 else hi
    if any(K.sign(d) <= 0 and (K.sign(n - lo * d) < 0 or K.sign(hi * d - n) < 0) for n, d in pairs):
        return None
    return [lo] if lo == hi else [lo, hi]


def _widened(K: Backend, betas: list[Any] | None) -> list[Any] | None:
    """Bounds of beta widened outwards to 64 significant bits (rationals): every beta between the bounds is
    still between them, and the carried vectors keep short numbers (exact bounds, ratios of quadratic forms
    of the carried vectors, grow in size at every impulse)."""
    if betas is None or len(betas) < 2 or not K.rationals:
        return betas
    (lo, _), (hi, unit) = rounded_box(K, betas[:1]), rounded_box(K, betas[1:])
    return [lo[0], hi[0] + unit[0]]  # rounded_box rounds down: lo[0] <= beta_lo, beta_hi < hi[0] + unit[0]


def _classify(K: Backend, carried: Sequence[tuple[Vector, bool]]) -> tuple[list[int], list[int]] | None:
    """(S, F) of the module docstring for the vectors carried so far, or None when S is empty."""
    r = len(carried[0][0])
    S, F = [], []
    for i in range(r):
        signs = [(K.sign(v[i]), strict) for v, strict in carried]
        if all(s >= 0 for s, _ in signs):
            continue
        if all(s < 0 or (s == 0 and not strict) for s, strict in signs):
            S.append(i)
        else:
            F.append(i)
    return (S, F) if S else None


Carried = list[tuple[Vector, bool]]
#: a reduction of carried vectors to fewer with the same cone, or None where it cannot (:func:`carry`)
Prune = Callable[[Backend, Carried], Carried | None]


def _direction(K: Backend, v: Vector) -> tuple[Any, ...]:
    """v scaled by 1/|v_k| at its first non-zero entry k (rationals: positive multiples become equal);
    v itself on other backends, where that sign could cut a parameter's range."""
    if not K.rationals:
        return tuple(v)
    k = next((x for x in v if x != K.zero), None)
    if k is None:
        return tuple(v)
    size = abs(k)
    return tuple(x / size for x in v)


def split(K: Backend, vectors: Carried, f: int) -> tuple[Carried, Carried]:
    """The vectors of the two halves of their cone, ``x_f <= 0`` and ``x_f >= 0``: those on each side
    (the ones with ``x_f = 0`` on both), and on both sides, for every pair u (``u_f > 0``), w
    (``w_f < 0``), the point ``-w_f u + u_f w`` where the pair's edge crosses ``x_f = 0`` (strict when
    u or w is). Every point of a half is a non-negative combination of its vectors.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> low, high = split(K, [([K.one, K.one], True), ([K.convert(Fraction(-1)), K.one], False)], 0)
    >>> [([str(x) for x in v], s) for v, s in low]
    [(['-1', '1'], False), (['0', '2'], True)]
    """
    neg = [(v, s) for v, s in vectors if K.sign(v[f]) < 0]
    pos = [(v, s) for v, s in vectors if K.sign(v[f]) > 0]
    zero = [(v, s) for v, s in vectors if v[f] == K.zero]
    cross = [([(K.zero - w[f]) * a + u[f] * b for a, b in zip(u, w)], su or sw) for u, su in pos for w, sw in neg]
    return neg + zero + cross, pos + zero + cross


def _prune(K: Backend, vectors: Carried) -> Carried:
    """The vectors without those that are non-negative combinations of the others (with weight on a strict
    one, for a strict vector): the same cone, fewer vectors to split and carry. Rationals only (elsewhere
    each test would be decided for a whole parameter range)."""
    if not K.rationals or len(vectors) <= len(vectors[0][0]) + 1:
        return vectors
    kept = list(vectors)
    scaled: Scaled = {}  # each vector's integer form, found once for all the tests
    for item in list(vectors):
        others = [x for x in kept if x is not item]
        d = feasible(K, item[0], [v for v, _ in others], scaled=scaled)
        if d is not None and (not item[1] or any(others[k][1] for k in d)):
            kept = others
    return kept


def _reduced(K: Backend, vectors: Carried, prune: Prune | None) -> Carried:
    """The vectors reduced by ``prune`` where it can, else by :func:`_prune`."""
    reduced = prune(K, vectors) if prune is not None else None
    return reduced if reduced is not None else _prune(K, vectors)


def carry(
    system: SearchSystem,
    gens: Sequence[Vector],
    strict: Sequence[bool],
    p: int,
    stages: list[Carried] | None = None,
    *,
    outer: Outer | None = None,
    prune: Prune | None = None,
) -> Carried | None:
    """The vectors after p impulses (the module docstring): at each impulse the cone of the vectors is cut by ``x_f =
    0`` for each f in F (:func:`split`), and each part is carried on its own impact set; ``prune`` reduces them after
    each impulse where it can (else :func:`_prune`, exact linear programming). None when an impulse is not decided: S
    empty, an impact set of a part not linear, too many vectors. With ``stages`` (a list, filled here), a multiple
    impulse whose beta varies is carried by its polar values (:mod:`verify.proofs.cones.polar`) instead of both bounds
    of beta, and the vectors after each impulse but the last are kept, reduced to the corners of their cone (or, with
    ``outer``, replaced by the corners of a larger cone, :func:`verify.proofs.cones.stages.product_cone`, which also
    turns away the vectors of the last impulse that lie outside the generators' cone): the certificate lists them."""
    K = system.backend
    current: Carried = [(list(g), s) for g, s in zip(gens, strict)]
    for n in range(p):
        found = _classify(K, current)
        if found is None:
            return None
        S, F = found
        parts: list[tuple[Carried, tuple[int, ...]]] = [(current, tuple(S))]
        for f in F:
            cut: list[tuple[Carried, tuple[int, ...]]] = []
            for vs, J in parts:
                signs = [K.sign(v[f]) for v, _ in vs]
                if all(x >= 0 for x in signs):
                    cut.append((vs, J))
                elif all(x <= 0 for x in signs):  # x_f = 0 is carried alike with or without f
                    cut.append((vs, (*J, f)))
                else:
                    crossings = sum(x > 0 for x in signs) * sum(x < 0 for x in signs)
                    if crossings > MAX_CROSSINGS:  # a cone too wide to carry: its edges would cross x_f = 0 too often
                        bounds.reached("crossings")
                        return None
                    bounds.use("crossings", crossings)
                    low, high = split(K, vs, f)
                    cut += [(low, (*J, f)), (high, J)]
            parts = cut
        nxt: dict[tuple[Any, ...], bool] = {}  # the vectors, each once (strict if it comes strict from any part)
        for vs, J in parts:
            if stages is not None and not linear_step(system, J):
                if len(vs) > MAX_VECTORS:
                    bounds.reached("polar_vectors")
                    return None
                bounds.use("polar_vectors", len(vs))
                values = polar_values(system, J, vs)
                if values is None:
                    return None
                moved = values
                moved = moved if outer is not None else extreme(K, moved)  # enclosed, or turned away, below
            else:
                betas = [K.one] if linear_step(system, J) else _widened(K, beta_bounds(system, J, [v for v, _ in vs]))
                if betas is None:
                    return None
                moved = [(step(system, J, v, beta), s) for v, s in vs for beta in betas]
            for v, s in moved:
                key = _direction(K, v)
                nxt[key] = nxt.get(key, False) or s
        current = [(list(v), s) for v, s in nxt.items()]
        enclosed = outer(n + 1, current) if outer is not None and stages is not None else None
        if outer is not None and enclosed is None:
            return None  # not enclosed, or outside the generators' cone: not worth the linear programming
        if enclosed is not None and n < p - 1:
            current = enclosed
        elif outer is None:  # with outer, the last impulse's vectors are kept: each has its combination below
            current = extreme(K, current) if stages is not None else _reduced(K, current, prune)
        if outer is not None and n == p - 1:  # each gets its combination from the box, without linear programming
            break
        if len(current) > MAX_CARRIED:
            bounds.reached("carried")
            return None
        bounds.use("carried", len(current))
        if stages is not None and n < p - 1:
            stages.append(current)
    return current


def member(K: Backend, y: Sequence[Any], gens: Sequence[Vector], scaled: Scaled | None = None) -> dict[int, Any] | None:
    """Non-negative coefficients ``{k: d_k}`` with ``y = sum d_k gens[k]``, or None if there are none.

    Exact linear programming (:func:`verify.proofs.cones.lp.feasible`). On a parameter backend the
    basis is found at one rational value of the parameter (a combination for the whole range is one
    there too), then solved for the whole range and its signs decided there (which may cut the range).
    ``scaled`` keeps the generators' integer forms for the next calls (:func:`verify.proofs.cones.lp.feasible`).

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> g = [[K.one, K.zero], [K.one, K.one]]
    >>> sorted((k, str(d)) for k, d in member(K, [K.convert(Fraction(3)), K.one], g).items())
    [(0, '2'), (1, '1')]
    """
    if K.at_sample(K.zero) is None:  # a backend with no sample point of its parameters (every non-parametric one)
        return feasible(K, y, gens, scaled=scaled)
    from verify.numbers.backends.rational import RationalBackend

    at = K.at_sample
    d = feasible(RationalBackend("python"), [at(x) for x in y], [[at(x) for x in g] for g in gens])
    if d is None:
        return None
    cols = sorted(d)
    c = solve_columns(K, [gens[k] for k in cols], y)
    if c is None or any(K.sign(x) < 0 for x in c):
        return None
    return {k: x for k, x in zip(cols, c) if x != K.zero}


def _rule_steps(system: SearchSystem, b: Sequence[Any], p: int) -> Vector | None:
    """The rates after p impulses of the rule from b (None when one finds nothing to hit)."""
    x: Vector | None = list(b)
    for _ in range(p):
        x = _rule_step(system, x) if x is not None else None
    return x


def _rule_step(system: SearchSystem, x: Sequence[Any]) -> Vector | None:
    """One impulse of the rule from the rates x: on the incoming set, with its own beta."""
    K = system.backend
    J = [i for i, v in enumerate(x) if K.sign(v) < 0]
    if not J:
        return None
    if linear_step(system, J):
        return step(system, J, x)
    return step(system, J, x, beta_from_rates(system, x, J))


def _growth(K: Backend, earlier: Sequence[Any], now: Sequence[Any]) -> Any | None:
    """now_i / earlier_i on the first rate that is non-zero in both (the growth over a period)."""
    for a, b in zip(earlier, now):
        if K.zero not in (a, b):
            return b / a
    return None


Found = tuple[list[Vector], list[bool], list[tuple[Vector, dict[int, Any]]], list[Carried]]


def close(
    system: SearchSystem,
    p: int,
    seeds: Sequence[Vector],
    extra: Sequence[Vector],
    rounds: int = 8,
    *,
    polar: bool = False,
    inflate: Vector | None = None,
    outer: Outer | None = None,
    combine: Combine | None = None,
    prune: Prune | None = None,
) -> Found | None:
    """A cone of the seeds (strict), the ``extra`` strict vectors and the weak unit vectors of the
    constraints no seed is hit on in p impulses, closed under p impulses: (generators, strict flags, the
    vectors carried through p impulses with their combinations, the stages of :func:`carry` when
    ``polar``), or None. With ``inflate`` (a vector inside the cone, rationals), a carried vector y the cone
    lacks is added as ``y + (y - s c) / 64`` (s c: ``inflate`` at y's scale), so that y itself lies inside
    the cone, not on an edge: the cone then holds for parameters near these ones too. ``prune`` reduces the carried
    vectors (:func:`carry`)."""
    K, r = system.backend, system.r
    gens = [list(g) for g in (*seeds, *extra)]
    strict = [True] * len(gens)
    hit = {i for g in seeds for i in _hit(system, g, p)}
    never = [i for i in range(r) if i not in hit]
    for m in never:
        gens.append([K.one if i == m else K.zero for i in range(r)])
        strict.append(False)
    start = len(gens)
    limit = start + MAX_GENERATORS
    scaled: Scaled = {}  # the generators' integer forms (the list only grows: each stays alive, unchanged)
    for done in range(1, rounds + 1):
        stages: list[Carried] | None = [] if polar else None
        inner = _inside(K, gens, strict, len(seeds), combine)
        carried = carry(system, [g for i, g in enumerate(gens) if i not in inner],
                        [s for i, s in enumerate(strict) if i not in inner], p, stages, outer=outer,
                        prune=prune)  # fmt: skip
        if carried is None:
            return None
        out, missing = [], []
        for y, s in carried:
            d = combine(y, len(seeds), gens) if combine is not None else None
            d = d if d is not None else member(K, y, gens, scaled)
            if d is None or (s and not any(strict[k] for k in d)):
                missing.append((y, s))
            else:
                out.append((y, d))
        if not missing:
            bounds.use("generators", len(gens) - start)
            bounds.use("rounds", done)
            return gens, strict, out, stages or []
        if len(gens) + len(missing) > limit:
            bounds.reached("generators")
            return None
        for y, s in missing:
            gens.append(_inflated(K, y, inflate) if inflate is not None else y)
            strict.append(s)
    if rounds == MAX_ROUNDS:
        bounds.reached("rounds")
    return None


def _inside(
    K: Backend, gens: Sequence[Vector], strict: Sequence[bool], seeds: int, combine: Combine | None
) -> set[int]:
    """The seeds that ``combine`` writes as combinations of the other generators with weight on a strict one: the
    same cone without them, so they are not carried (the values of a multiple impulse are trilinear: a seed's
    lie in the cone of the others')."""
    if combine is None:
        return set()
    out = set()
    for i in range(seeds):
        d = combine(gens[i], seeds, gens)
        if d is not None and i not in d and any(strict[k] and K.sign(w) > 0 for k, w in d.items()):
            out.add(i)
    return out


def _inflated(K: Backend, y: Vector, center: Vector) -> Vector:
    """y pushed away from ``center`` (scaled to y's size) by 1/64 of their difference (exact rationals)."""
    top = max(abs(Fraction(K.to_number(x))) for x in center)
    scale = K.convert(max(abs(Fraction(K.to_number(x))) for x in y) / top) if top else K.zero
    step = K.convert(Fraction(1, 64))
    return [a + (a - scale * c) * step for a, c in zip(y, center)]


def box_seeds(K: Backend, center: Sequence[Any], radius: Sequence[Any]) -> list[Vector]:
    """Points ``center +- a_i e_i`` whose cone contains the box ``center +- radius`` (each a_i at least
    k radius_i, k the number of non-zero radii; the center alone when they are all 0).

    Every point ``center + t`` of the box is ``(1/k) sum_i ((1/2 + k t_i / (2 a_i)) (center + a_i e_i)
    + (1/2 - k t_i / (2 a_i)) (center - a_i e_i))``, with non-negative weights. Each a_i is twice
    k radius_i, or ``|center_i| 2^-30`` when that is larger (a rounder cone).

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> center, radius = [K.convert(Fraction(-1)), K.convert(Fraction(2))], [K.zero, K.convert(Fraction(1, 8))]
    >>> [[str(x) for x in v] for v in box_seeds(K, center, radius)]
    [['-1', '9/4'], ['-1', '7/4']]
    """
    wide = [i for i, w in enumerate(radius) if w != K.zero]
    if not wide:
        return [list(center)]
    k = K.convert(Fraction(len(wide)))
    out = []
    for i in wide:
        a = max(k * radius[i] * 2, abs(center[i]) / 2**30)  # exact rationals here: abs and max are exact
        for sign in (1, -1):
            out.append([x + sign * a if j == i else x for j, x in enumerate(center)])
    return out


def _hit(system: SearchSystem, b: Sequence[Any], p: int) -> list[int]:
    """The constraints the rule hits in p impulses from b."""
    K = system.backend
    x: Vector | None = list(b)
    hit: set[int] = set()
    for _ in range(p):
        if x is None:
            break
        hit |= {i for i, v in enumerate(x) if K.sign(v) < 0}
        x = _rule_step(system, x)
    return sorted(hit)


def _limit(system: SearchSystem, b: Sequence[Any], p: int, periods: int = 400) -> tuple[Vector, list[int]] | None:
    """The direction the rates tend to (rationals only), and the constraints hit (H), or None.

    The rates of H evolve on their own, so the direction is found on them alone: p-impulse steps of the
    rule from b's H-rates (the others kept at 0), scaled and rounded after each."""
    K = system.backend
    on = _hit(system, b, p)
    if not on or all(b[i] == K.zero for i in on):
        return None
    v = rounded_direction(K, [x if i in on else K.zero for i, x in enumerate(b)], on)
    step = _on_step(system, on)
    for _ in range(periods):
        w: Vector | None = v
        for _ in range(p):  # the other rates are kept at 0: an impulse on H would make them incoming
            w = step(w) if w is not None else None
        if w is None or all(w[i] == K.zero for i in on):
            return None
        v = rounded_direction(K, w, on)
    return v, on


def limit_cone(system: SearchSystem, p: int, b: Sequence[Any], bits: int) -> Found | None:
    """A cone closed under p impulses around the direction the rates b tend to (rationals), seeded with that
    direction +- 2^-bits of the rates' scale along each rate hit (:func:`_around`; b itself is not a seed), or
    None."""
    limit = _limit(system, b, p)
    if limit is None:
        return None
    seeds = _around(system.backend, b, *limit, bits)
    return close(system, p, seeds, [], MAX_ROUNDS, inflate=seeds[0])


def rates_after(system: SearchSystem, b: Sequence[Any], n: int) -> Vector | None:
    """The rates after n impulses of the rule from b (None when one of them finds nothing to hit)."""
    return _rule_steps(system, b, n)


def _around(K: Backend, b: Sequence[Any], v: Vector, on: list[int], bits: int = 12) -> list[Vector]:
    """Points around the direction v (:func:`_limit`), with b's own scale: v and v +- 2^-bits times each unit
    vector of H, scaled to b's H-rates, with b's other rates (the weak generators add to those what the cone
    needs)."""
    scale = max(abs(Fraction(K.to_number(b[i]))) for i in on)
    size = K.convert(scale)
    delta = K.convert(scale / 2**bits)
    base = [v[i] * size if i in on else b[i] for i in range(len(b))]
    out = [base]
    for i in on:
        if v[i] == K.zero:  # a rate 0 in that direction (a COR of 0): moving it would change the impact sets
            continue
        for sign in (1, -1):
            out.append([x + sign * delta if j == i else x for j, x in enumerate(base)])
    return out


def _beyond(system: SearchSystem, p: int, guide: tuple[Sequence[Any], Sequence[Any] | None]) -> list[Vector]:
    """``2 P b - lam b``: past the direction the rates tend to, from (b, the rates p impulses before)."""
    K = system.backend
    b, earlier = guide
    lam = _growth(K, earlier, b) if earlier is not None else None
    ahead = _rule_steps(system, b, p) if lam is not None and K.sign(lam) > 0 else None
    return [[a + a - lam * x for a, x in zip(ahead, b)]] if ahead is not None else []


def cone_search(
    system: SearchSystem,
    p: int,
    seeds: Sequence[Vector],
    guide: tuple[Sequence[Any], Sequence[Any] | None],
    *,
    switched: bool = True,
) -> Found | None:
    """A closed cone containing the seeds: first with one point beyond the direction the rates tend to
    (``2 P b - lam b``, from ``guide`` = (b, the rates one period before)), then (rational backends)
    with points around that direction (:func:`_limit`, :func:`_around`), then, when that direction draws the
    rates in, with a polytope around it shaped by the period's linear part there and multiple impulses carried
    by their polar values (:func:`_shaped`, a search with pivots of its own; lifted along the rates the run holds
    positive off the period when the hit rates tend to 0 against them, :func:`_lift`), and last, when some hit rates
    tend to 0 against the other hit rates (the direction on a face between impact sets), with a cone of that face and
    a wedge across it (:func:`_face`). Last, with ``switched``, for runs that switch between impact sets, a cone
    around the run's own points pushed out by a slack (:func:`_hull`)."""
    K = system.backend
    b, _ = guide
    found = close(system, p, seeds, _beyond(system, p, guide))
    if found is None and K.rationals:
        limit = _limit(system, b, p)
        try:
            if limit is not None:
                found = close(system, p, seeds, _around(K, b, *limit), MAX_ROUNDS)
        except SearchTooLong:  # the pivots of the search spent: the polytope below has pivots of its own
            bounds.reached("pivots")
        if found is None and limit is not None:
            found = _shaped(system, p, seeds, limit)
        if found is None and limit is not None:
            found = _face(system, p, seeds, limit)
        if found is None and switched:
            found = _hull(system, p, seeds, b)
    return found


def _hull(system: SearchSystem, p: int, seeds: Sequence[Vector], b: Sequence[Any]) -> Found | None:
    """A cone of the seeds closed around the run's own points every p impulses from b, pushed out by a slack
    (:mod:`verify.proofs.cones.hull`): for runs that switch between impact sets with no direction to tend to. Where b
    holds positive rates off the constraints the run hits (H, over its next 16 periods), the points are those of the
    rates of H alone (the others kept at 0: they evolve by those of H, not the reverse), and the cone is lifted along
    b's rates off H as :func:`_lift` lifts a box. A search with :data:`MAX_PIVOTS` of its own, each slack of
    :data:`~verify.proofs.cones.hull.SLACKS` in turn."""
    if not hull.available():
        return None
    K = system.backend
    rule = lambda x: _rule_step(system, x)  # noqa: E731
    trail = hull.orbit(K, rule, b, 1, hull.HIT_PERIODS * p)  # rounded: exact rates would grow at every impulse
    if trail is None:  # the run exits
        return None
    on = sorted({i for x in trail[:-1] for i, v in enumerate(x) if K.sign(v) < 0})
    if all(b[i] == K.zero for i in on):
        return None
    start = [x if i in on else K.zero for i, x in enumerate(b)]
    lift = _lift(system, p, b, (hull.rounded_point(K, start), on))
    step = rule if lift is None else _on_step(system, on)
    points = hull.orbit(K, step, b if lift is None else start, p)
    if points is None:  # the run exits
        return None

    lifted = (lambda gens: gens) if lift is None else (lambda gens: _lifted(K, gens, *lift))

    def carried(gens: list[Vector]) -> list[Vector] | None:
        moved = carry(system, lifted(gens), [True] * len(gens), p, prune=hull.extreme_rays)
        if moved is None:
            return None
        return [y if lift is None else [x if i in on else K.zero for i, x in enumerate(y)] for y, _ in moved]

    def search() -> Found | None:
        for slack in hull.SLACKS:
            gens = hull.grown_cone(K, points, slack, carried) or hull.pushed_cone(K, points, slack)
            found = None if gens is None else close(system, p, seeds, lifted(gens), MAX_ROUNDS, prune=hull.extreme_rays)
            if found is not None:
                return found
        return None

    return _own_pivots(search)


def _lifted(K: Backend, gens: list[Vector], u: Vector, height: Fraction) -> list[Vector]:
    """Each generator plus ``height`` times u (:func:`_lift`)."""
    return [[x + K.convert(height) * y for x, y in zip(g, u)] for g in gens]


def _shaped(system: SearchSystem, p: int, seeds: Sequence[Vector], limit: tuple[Vector, list[int]]) -> Found | None:
    """A cone of the seeds closed around a polytope shaped by the period at the direction of ``limit``, multiple
    impulses carried by polar values: for four rates or more, boxes carried stage by stage
    (:func:`verify.proofs.cones.stages.product_cone`), else the corners of
    :func:`verify.proofs.cones.shape.shaped_seeds`; a search with :data:`MAX_PIVOTS` of its own. Where the rates lie
    by a face of the outgoing ones (:func:`_lift`), the boxes, lifted, in a chart of two dimensions too."""
    K = system.backend
    lift = _lift(system, p, seeds[0], limit)
    step = (lambda x: _rule_step(system, x)) if lift is None else _on_step(system, limit[1])
    staged = product_cone(K, *limit, step, p=p, points=seeds, lift=lift)
    shaped = shaped_seeds(K, *limit, lambda x: _rule_steps(system, x, p), seeds) if staged is None and not lift else []
    if staged is None and not shaped:
        return None
    if staged is not None:
        return _own_pivots(
            lambda: close(system, p, seeds, staged[0], 2, polar=True, outer=staged[1], combine=staged[2])
        )
    return _own_pivots(lambda: close(system, p, seeds, shaped, 2, polar=True))


def _own_pivots(search: Callable[[], Found | None]) -> Found | None:
    """``search()`` with :data:`MAX_PIVOTS` of its own, or None when it spends them (the bound ``pivots`` reached)."""
    try:
        with pivot_budget(MAX_PIVOTS) as left:
            found = search()
    except SearchTooLong:
        bounds.reached("pivots")
        return None
    if found is not None:
        bounds.use("pivots", MAX_PIVOTS - left[0])
    return found


def _face(system: SearchSystem, p: int, seeds: Sequence[Vector], limit: tuple[Vector, list[int]]) -> Found | None:
    """A cone of the seeds closed around the face that ``limit``'s direction lies on, where rates the period hits
    tend to 0 against the others (:mod:`verify.proofs.cones.face`), multiple impulses carried by polar values: the
    seeds lie in the cone of the face's generators and are not carried, and after each impulse but the last the
    vectors are enclosed in such a cone around the direction and the run carried as far (:func:`_face_stages`). A
    search with :data:`MAX_PIVOTS` of its own."""
    K = system.backend
    direction, on = limit
    gens = face_cone(K, direction, on, seeds)
    if gens is None:
        return None

    def combine(y: Vector, first: int, generators: Sequence[Vector]) -> dict[int, Any] | None:
        d = feasible(K, y, generators[first:])
        return None if d is None else {first + k: c for k, c in d.items()}

    def search() -> Found | None:
        if any(combine(s, 0, gens) is None for s in seeds):
            return None
        for height in HEIGHTS:  # the enclosures' wedges, higher or lower against their face parts
            outer = _face_stages(system, p, seeds[0], limit, height)
            found = (
                None if outer is None else close(system, p, seeds, gens, 2, polar=True, outer=outer, combine=combine)
            )
            if found is not None:
                return found
        return None

    return _own_pivots(search)


def _face_stages(
    system: SearchSystem, p: int, point: Sequence[Any], limit: tuple[Vector, list[int]], height: Fraction
) -> Outer | None:
    """The ``outer`` of :func:`carry` for :func:`_face`: after impulse n < p, the generators of a face cone
    (:func:`verify.proofs.cones.face.face_cone`) around the limit's direction carried n impulses on its own
    constraints, turned to ``point`` carried n impulses by the rule, that holds every vector (exact linear
    programming; None when one lies outside), snug with the wedge's ``height``; after impulse p, the vectors
    themselves."""
    K = system.backend
    direction, on = limit
    step = _on_step(system, on)
    directions, points = [direction], [list(point)]
    for _ in range(p - 1):
        d, x = step(directions[-1]), _rule_step(system, points[-1])
        if d is None or x is None or all(d[i] == K.zero for i in on):
            return None
        directions.append(rounded_direction(K, d, on))
        points.append(x)

    def outer(n: int, vectors: Carried) -> Carried | None:
        if n == p:
            return vectors
        gens = face_cone(K, directions[n], on, [v for v, _ in vectors], points[n], snug=height)
        if gens is None or any(feasible(K, v, gens) is None for v, _ in vectors):
            return None
        return [(g, True) for g in gens]

    return outer


def _lift(system: SearchSystem, p: int, point: Sequence[Any], limit: tuple[Vector, list[int]]) -> Lift | None:
    """The lift of :func:`verify.proofs.cones.stages.product_cone` when ``point`` (the run's rates) holds positive rates
    off H (the constraints a period hits), which a period moves but never hits: u is the point's rates off H over
    their largest a, and L a power of 2 at most half of a over the point's size on H in the units of the direction
    of ``limit`` (so that the point stays in the lifted cone); else None. Without it the corners, 0 off H, may be
    hit there (rates by a face of the outgoing ones: the rates of H tend to 0 against those off H, which the period
    lowers), and the weak unit vectors off H make the cone's vectors too many for linear programming."""
    K = system.backend
    direction, on = limit
    off = [i for i in range(system.r) if i not in on and K.sign(point[i]) > 0]
    if not off:
        return None
    top = max(on, key=lambda i: abs(Fraction(K.to_number(direction[i]))))
    a = max(Fraction(K.to_number(point[i])) for i in off)
    size = abs(Fraction(K.to_number(point[top])) / Fraction(K.to_number(direction[top])))
    if size == 0:
        return None
    u = [point[i] / K.convert(a) if i in off else K.zero for i in range(system.r)]
    return u, Fraction(2) ** (exponent(a / size) - 2)  # 2^(e-1) <= a / size: half of that


def _on_step(system: SearchSystem, on: list[int]) -> Callable[[Vector], Vector | None]:
    """One impulse of the rule on the rates of ``on`` alone, the others kept at 0 (they evolve by the rates of
    ``on``, not the reverse): the direction of :func:`_limit`, the shapes of a lifted box."""

    def step(x: Vector) -> Vector | None:
        y = _rule_step(system, x)
        return None if y is None else [v if i in on else system.backend.zero for i, v in enumerate(y)]

    return step


class _Sampled:
    """A system on a parameter backend, at the parameter's sample value (rationals): what the cone
    search reads of a system."""

    def __init__(self, system: SearchSystem):
        from verify.numbers.backends.rational import RationalBackend

        sample = system.backend.at_sample
        self.backend = K = RationalBackend("auto")  # the fastest installed: the same exact numbers

        def at(x: Any) -> Any:
            return K.convert(sample(x))

        self.gram = [[at(x) for x in row] for row in system.gram]
        self.restitution = [at(x) for x in system.restitution]
        self.inverse_gram_diag = [K.one / self.gram[i][i] for i in range(system.r)]
        self.r = system.r
        self.at = at


def _at_sample(system: SearchSystem, p: int, b: Sequence[Any], earlier: Sequence[Any] | None) -> bool:
    """Whether the search for the whole range can succeed: it succeeds at the sample value of the parameter
    (the same search in rationals; a point of the range, where the backend has none, passes)."""
    if system.backend.at_sample(system.backend.zero) is None:
        return True
    q = _Sampled(system)
    bq = [q.at(x) for x in b]
    guide = (bq, [q.at(x) for x in earlier] if earlier is not None else None)
    try:
        return close(q, p, [bq], _beyond(q, p, guide)) is not None
    except Undecided:
        return False


def period_certificate(
    system: System, p: int, b: Sequence[Any], earlier: Sequence[Any] | None, *, switched: bool = True
) -> dict[str, Any] | None:
    """A certificate that the rule never exits from rates ``b``, with a cone that p impulses map into
    itself, or None. ``earlier`` are the rates p impulses before (they guide the search only). Every
    sign is the backend's, so on a parameter backend a :class:`~verify.numbers.backends.symbolic.Split`
    may ask to cut the range.

    On certified intervals (rational inputs), the cone is built in exact rationals around the box
    that encloses the rates (:func:`box_seeds`): the certificate is exact, and it holds for every
    point of the box, the true rates among them. ``switched`` (default True) lets the search end with a cone around
    the run's own points (:func:`_hull`), the costliest search, for runs with no direction to tend to.
    """
    K = system.backend
    box: tuple[Vector, Vector] | None = None
    guide: tuple[Sequence[Any], Sequence[Any] | None]
    if K.is_parametric and not _at_sample(system, p, b, earlier):
        return None
    size = max(K.size(x) for x in b) if K.is_exact else 0
    if K.is_exact and K.rationals and size > MAX_BITS:
        bounds.reached("cone_bits")
        # long exact rationals: the cone is built around a box of short ones that holds the rates exactly
        exact, box = system, rounded_box(K, b)
        seeds = box_seeds(K, *box)
        guide = (box[0], rounded_box(K, earlier)[0] if earlier is not None else None)
    elif K.is_exact:
        bounds.use("cone_bits", size)
        exact, seeds, guide = system, [list(b)], (b, earlier)
    elif K.encloses and K.is_rigorous:
        exact = on_exact_field(system, [])
        if not exact.backend.rationals:
            return None
        Q = exact.backend
        box = enclosing_box(Q, [K.bounds(x) for x in b])
        seeds = box_seeds(Q, *box)
        guide = (box[0], enclosing_box(Q, [K.bounds(x) for x in earlier])[0] if earlier is not None else None)
    else:
        return None
    left = [MAX_PIVOTS, MAX_PIVOTS]
    try:
        with pivot_budget(MAX_PIVOTS) as left:
            found = cone_search(exact, p, seeds, guide, switched=switched)
    except Undecided as exc:  # SearchTooLong among them
        if isinstance(exc, SearchTooLong):
            bounds.reached("pivots")
        if hasattr(exc, "polys"):
            raise
        bounds.use("pivots_failed", MAX_PIVOTS - max(left[0], 0))
        return None
    bounds.use("pivots" if found else "pivots_failed", MAX_PIVOTS - max(left[0], 0))
    return certificate_of(exact, p, found, b if K.is_exact else None, box) if found else None


def rounded_box(K: Backend, b: Sequence[Any], bits: int = 64) -> tuple[Vector, Vector]:
    """(center, radius): each rate rounded down to ``bits`` significant bits (exact rationals), with a radius
    of one unit in its last place, so that ``center_i <= b_i < center_i + radius_i`` (0 for a rate of 0).

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> center, radius = rounded_box(K, [K.convert(Fraction(1, 3)), K.zero], bits=4)
    >>> [str(x) for x in center], [str(x) for x in radius]
    (['5/16', '0'], ['1/32', '0'])
    """
    center, radius = [], []
    for x in b:
        q = Fraction(K.to_number(x))
        if q == 0:
            center.append(K.zero)
            radius.append(K.zero)
            continue
        low, unit = floor_bits(q, bits)  # q down to its bits-th significant bit, and a unit of that bit
        center.append(K.convert(low))
        radius.append(K.convert(unit))
    return center, radius


def enclosing_box(K: Backend, ends: Sequence[tuple[Fraction, Fraction]], bits: int = 64) -> tuple[Vector, Vector]:
    """(center, radius) of short rationals whose box holds each interval ``[lo, hi]`` of ``ends``: its ends
    rounded outwards to multiples of a unit of the ``bits``-th significant bit of max(|lo|, |hi|). A search
    on the intervals' own ends, of thousands of bits at a high precision, costs far more and finds no more:
    the seeds of :func:`box_seeds` are already |center_i| 2^-30 wide.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> center, radius = enclosing_box(K, [(Fraction(1, 3), Fraction(1, 3) + Fraction(1, 10**40)), (0, 0)], bits=4)
    >>> [str(x) for x in center], [str(x) for x in radius]
    (['21/64', '0'], ['1/64', '0'])
    """
    center, radius = [], []
    for lo, hi in ends:
        top = max(abs(Fraction(lo)), abs(Fraction(hi)))
        if top == 0:
            center.append(K.zero)
            radius.append(K.zero)
            continue
        unit = Fraction(2) ** (exponent(top) - bits)
        a, b = Fraction(math.floor(Fraction(lo) / unit)) * unit, Fraction(math.ceil(Fraction(hi) / unit)) * unit
        center.append(K.convert((a + b) / 2))
        radius.append(K.convert((b - a) / 2))
    return center, radius


def certificate_of(
    system: SearchSystem,
    p: int,
    found: Found,
    b: Sequence[Any] | None,
    box: tuple[Vector, Vector] | None = None,
) -> dict[str, Any]:
    """The certificate (a JSON-ready dict) of a cone found by :func:`close` for the rates ``b`` (or for a box
    of them), in the exact numbers of ``system``'s backend."""
    K = system.backend
    gens, strict, carried, stages = found
    show = K.to_exact
    where: dict[str, Any] = {"rates": [show(x) for x in b]} if b is not None else {}
    if stages:  # the vectors after each impulse of the period but the last (polar values)
        where["stages"] = [
            {"vectors": [[show(x) for x in v] for v, _ in st], "strict": [t for _, t in st]} for st in stages
        ]
    if box is not None:
        where["box"] = {"center": [show(x) for x in box[0]], "radius": [show(x) for x in box[1]]}
    return {
        "kind": "invariant cone of a period",
        "statement": STATEMENT,
        "rigorous": K.is_rigorous,
        "impulses": p,
        **where,
        "gram": [[show(x) for x in row] for row in system.gram],
        "restitution": [show(x) for x in system.restitution],
        "generators": [[show(x) for x in g] for g in gens],
        "strict": strict,
        "carried": [
            {"vector": [show(x) for x in y], "combination": {str(k): show(d) for k, d in sorted(c.items())}}
            for y, c in carried
        ],
        "multiple impulses": "polar values" if stages else "beta bounds",
        "map": "b -> b - beta sum_{j in J} (1 + e_j) (b_j / G_jj) G[:, j] for J = S + T, T any subset of F",
        "checked": [
            "at each of the p impulses, S (every strict vector carried so far < 0, the others <= 0) is not empty; "
            "the cone is cut by x_f = 0 for each f in F (the constraints where the vectors disagree)",
            "a part hit on one constraint, or on mutually orthogonal ones, moves with beta = 1; else "
            + (
                "by the polar values of the cubic form D(x) x - N(x) A x of its vectors (every triple), and the "
                "vectors after each impulse but the last lie in the cone of the listed stage"
                if stages
                else "each vector moves with both bounds of beta over the part (from the pairwise forms N_kl, D_kl)"
            ),
            "each generator's vectors after p impulses are the listed ones",
            "each listed vector is sum_k combination[k] * generator k, coefficients >= 0, with a positive "
            "coefficient on a strict generator when it comes from a strict one",
            "the rates are generator 0, which is strict"
            if box is None
            else "the rates lie in the box center +- radius ("
            + ("exactly: the listed rates" if b is not None else "certified intervals")
            + "), and the first generators are "
            "center +- a_i e_i with a_i >= k radius_i (k the number of non-zero radii): the box lies in the cone",
        ],
    }
