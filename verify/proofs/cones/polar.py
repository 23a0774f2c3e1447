"""Multiple impulses carried exactly through a cone: the polar values of the impulse's cubic form.

A multiple impulse on J moves the rates by ``x -> x - beta(x) A x`` with ``A x = sum_{j in J} (1 + e_j)
(x_j / G_jj) G[:, j]`` and ``beta = N(x) / D(x)``, ``N(x) = sum_j x_j^2 / G_jj``, ``D(x) = lam^T G_JJ lam``
(lam_j = x_j / G_jj; Sect. 3.5 c). Multiplied by ``D(x) > 0`` (lam != 0 wherever J is hit), the new rates
point along the cubic form

    C(x) = D(x) x - N(x) A x.

For ``x = sum_k c_k v_k`` with ``c >= 0``, ``C(x) = sum c_k c_l c_m P(v_k, v_l, v_m)`` over all triples,
where P is the symmetric trilinear (polar) form of C, here three times it:

    P(u, v, w) = D(u, v) w + D(v, w) u + D(u, w) v - N(u, v) A w - N(v, w) A u - N(u, w) A v

(D(u, v), N(u, v) the bilinear forms). So every point of the cone of the v_k is carried into the cone of the
polar values, with weight ``c_k^3 > 0`` on ``P(v_k, v_k, v_k) = 3 C(v_k)`` when c_k > 0. Unlike the two
bounds of beta (:func:`verify.proofs.cones.period.beta_bounds`), which widen a cone of width w by a first-order
amount, the polar values lie within O(w^2) of the image: a cone around a direction that the period map draws
in slowly (a spiral, whose contraction is close to 1) can close under them.

:func:`verify.proofs.cones.shape.shaped_seeds` gives such a cone: a polytope around the direction the rates tend
to, shaped by the linear part of the period map there.

>>> from verify.models.cradle import cradle_system
>>> s = cradle_system("0", 4)
>>> K = s.backend
>>> x = [K.convert(Fraction(-1)), K.convert(Fraction(-2)), K.one]
>>> [str(v) for v in pushed(s, (0, 1), x)]
['0', '-3/2', '1']
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.numbers.backends.base import Backend
from verify.proofs.cones.lp import Scaled, feasible

Vector = list[Any]
Carried = list[tuple[Vector, bool]]

#: the most vectors whose polar values a search takes at once (48 give 19,600 values)
MAX_VECTORS = 48


def pushed(system: Any, J: Sequence[int], x: Sequence[Any]) -> Vector:
    """``A x = sum_{j in J} (1 + e_j) (x_j / G_jj) G[:, j]``: what an impulse on J with beta = 1 takes off
    the rates x (the doctest of the module)."""
    K, G, e = system.backend, system.gram, system.restitution
    out = [K.zero] * system.r
    for j in J:
        if x[j] == K.zero:
            continue
        c = (K.one + e[j]) * x[j] / G[j][j]
        for i in range(system.r):
            if G[i][j] != K.zero:
                out[i] = out[i] + c * G[i][j]
    return out


def forms(system: Any, J: Sequence[int], vs: Sequence[Vector]) -> tuple[dict[Any, Any], dict[Any, Any]]:
    """The bilinear forms of beta's numerator and denominator on every pair of the vectors, ``N[k, l] =
    sum_j v_k[j] lam_l[j]`` and ``D[k, l] = lam_k^T G_JJ lam_l`` (lam_j = v[j] / G_jj), each pair computed once
    and stored both ways (the forms are symmetric).

    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("0", 4)
    >>> K = s.backend
    >>> N, D = forms(s, (0, 1), [[K.convert(Fraction(-1)), K.convert(Fraction(-2)), K.one]])
    >>> str(N[0, 0] / D[0, 0])  # beta of the doctest of polar_values
    '5/3'
    """
    K, G = system.backend, system.gram
    lam = [[v[j] / G[j][j] for j in J] for v in vs]
    glam = [[sum((G[i][j] * lv[t] for t, j in enumerate(J)), K.zero) for i in J] for lv in lam]
    N: dict[tuple[int, int], Any] = {}
    D: dict[tuple[int, int], Any] = {}
    for a in range(len(vs)):
        for b in range(a, len(vs)):
            N[a, b] = N[b, a] = sum((vs[a][j] * lam[b][t] for t, j in enumerate(J)), K.zero)
            D[a, b] = D[b, a] = sum((x * y for x, y in zip(lam[a], glam[b])), K.zero)
    return N, D


def polar_values(system: Any, J: Sequence[int], vectors: Carried) -> Carried | None:
    """The polar values ``P(v_k, v_l, v_m)`` of the vectors (module docstring), each triple once, the zero
    ones left out; a value is strict when its three vectors are: a point with weight c_k > 0 on a strict v_k
    has weight c_k^3 on ``P(v_k, v_k, v_k)``, so that value carries its strictness. None when that value is
    0 for a strict v_k (the point v_k itself would lose every rate). A value with a vector that is not strict
    stays weak: a weak vector on which the impulse does nothing (a constraint off the period, 0 on J) gives
    values along itself, which need not be hit.

    >>> from verify.models.cradle import cradle_system
    >>> s = cradle_system("0", 4)
    >>> K = s.backend
    >>> x = [K.convert(Fraction(-1)), K.convert(Fraction(-2)), K.one]
    >>> [([str(v) for v in y], t) for y, t in polar_values(s, (0, 1), [(x, True)])]
    [(['-9/2', '9/4', '-3'], True)]

    One vector's value is ``3 D(x) = 9/2`` times the rates after the rule's own impulse (beta = 5/3):

    >>> from verify.proofs.cones.period import _rule_step
    >>> [str(v) for v in _rule_step(s, x)]
    ['-1', '1/2', '-2/3']
    """
    K = system.backend
    vs = [v for v, _ in vectors]
    pushes = [pushed(system, J, v) for v in vs]
    N, D = forms(system, J, vs)
    out: Carried = []
    for a, b, c in itertools.combinations_with_replacement(range(len(vs)), 3):
        y = [
            D[a, b] * vs[c][i] + D[b, c] * vs[a][i] + D[a, c] * vs[b][i]
            - N[a, b] * pushes[c][i] - N[b, c] * pushes[a][i] - N[a, c] * pushes[b][i]
            for i in range(system.r)
        ]  # fmt: skip
        strict = vectors[a][1] and vectors[b][1] and vectors[c][1]
        if any(x != K.zero for x in y):
            out.append((y, strict))
        elif strict and a == b == c:
            return None
    return out


def extreme(K: Backend, vectors: Carried) -> Carried:
    """The vectors whose cone is the same, fewer: for rates of three constraints (a polygon seen from the
    origin) the corners of the exact convex hull in a plane that cuts every vector; otherwise each vector
    is kept unless it is a combination of those kept before it (strict vectors first). A dropped strict
    vector must be a combination with weight on a strict kept one; else it is kept.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> square = [[1, 1, 2], [1, -1, 2], [-1, -1, 2], [-1, 1, 2], [0, 0, 2], [1, 0, 2]]
    >>> [v for v, _ in extreme(K, [([K.convert(Fraction(x)) for x in v], True) for v in square])] == [
    ...     [K.convert(Fraction(x)) for x in v] for v in square[:4]]
    True
    """
    if len(vectors) <= 3:
        return list(vectors)
    corners = _hull3(K, vectors) if len(vectors[0][0]) == 3 else None
    scaled: Scaled = {}  # the kept vectors' integer forms, found once for all the tests
    if corners is None:
        kept: Carried = []
        for v, s in sorted(vectors, key=lambda item: not item[1]):
            d = feasible(K, v, [g for g, _ in kept], scaled=scaled) if kept else None
            if d is None or (s and not any(kept[k][1] for k in d)):
                kept.append((v, s))
        return kept
    kept = [vectors[i] for i in corners]
    if all(s for _, s in kept):
        return kept
    for i, (v, s) in enumerate(vectors):
        if s and i not in corners:
            d = feasible(K, v, [g for g, _ in kept], scaled=scaled)
            if d is None or not any(kept[k][1] for k in d):
                kept.append((v, s))
    return kept


def _hull3(K: Backend, vectors: Carried) -> list[int] | None:
    """The indices of the vectors on the corners of the cone's section by the plane ``h . x = 1`` (exact
    signs, the backend's rationals), with h the sum of the vectors each scaled to a largest entry of 1 and
    rounded to 16 bits; None when h is not positive on every vector (then the section does not show the
    cone). Each turn of the hull is decided by :func:`_turn`: in floating point where its error bound decides
    it, else exactly."""
    exact = K.rationals  # the elements are rationals themselves: no conversion to Fraction
    units = [0, 0, 0]  # h in units of 2^-16
    for v, _ in vectors:
        q = v if exact else [Fraction(K.to_number(x)) for x in v]
        top = max(abs(x) for x in q)
        # int(): gmpy2's floor is an mpz, which Fraction keeps and the backends do not convert
        units = [a + int(math.floor(x * 2**16 / top)) for a, x in zip(units, q)]  # noqa: RUF046
    h = [Fraction(a, 2**16) for a in units]
    hk = [K.convert(x) for x in h]
    heights = [sum((a * b for a, b in zip(hk, v)), K.zero) for v, _ in vectors]
    if any(K.sign(t) <= 0 for t in heights):
        return None
    k = max(range(3), key=lambda i: abs(h[i]))
    axes = [i for i in range(3) if i != k]  # the section seen along e_k: a projection, corners kept
    points = sorted((v[axes[0]] / t, v[axes[1]] / t, n) for n, ((v, _), t) in enumerate(zip(vectors, heights)))
    near = {pt[2]: _near(K, pt) for pt in points}

    def turn(o: tuple[Any, ...], a: tuple[Any, ...], b: tuple[Any, ...]) -> int:
        return _turn(K, near, o, a, b)

    lower: list[tuple[Any, ...]] = []
    upper: list[tuple[Any, ...]] = []
    for chain, seq in ((lower, points), (upper, points[::-1])):
        for pt in seq:
            while len(chain) >= 2 and turn(chain[-2], chain[-1], pt) <= 0:
                chain.pop()
            chain.append(pt)
    corners = {pt[2] for pt in lower[:-1] + upper[:-1]}
    return sorted(corners) if len(corners) >= 3 else None


#: the relative error of a rational rounded to a float (one unit in the last place: a rounding that truncates
#: errs by up to one, to nearest by half)
_ULP = 2.0**-52
#: floats beyond these magnitudes are not used (over- and underflow would void the error bound)
_LARGEST, _SMALLEST = 2.0**500, 2.0**-500


def _near(K: Backend, point: tuple[Any, ...]) -> tuple[float, float] | None:
    """The point's coordinates as floats, each within a relative :data:`_ULP` of the exact one (None when
    a coordinate is too large, or too small but not 0, for the error bound of :func:`_turn`)."""
    out = []
    for x in point[:2]:
        try:
            f = float(K.to_number(x)) if not K.rationals else float(x)
        except (OverflowError, TypeError, ValueError):
            return None
        if not (f == 0 and x == K.zero) and not _SMALLEST < abs(f) < _LARGEST:
            return None
        out.append(f)
    return out[0], out[1]


def _turn(K: Backend, near: dict[int, Any], o: tuple[Any, ...], a: tuple[Any, ...], b: tuple[Any, ...]) -> int:
    """The sign of the cross product ``(a - o) x (b - o)`` of three points (exact rationals (x, y, n), with their
    floats ``near[n]`` from :func:`_near` or None). In floating point when the rounded product is farther
    from 0 than a bound on its error, else exactly.

    Each float coordinate errs by at most u |c| (u = :data:`_ULP`), a difference of two by u (|c| + |c'|) from
    the inputs and its own rounding, half an ulp of the result; each of the two products then by about
    2 u (|a_x| + |o_x|)(|b_y| + |o_y|), and the final difference adds half an ulp of its own. So
    16 u (P + Q), with P and Q those products of sums of magnitudes, bounds the error with room to spare.

    >>> from verify.numbers.backends.rational import RationalBackend
    >>> K = RationalBackend("python")
    >>> pts = [(Fraction(0), Fraction(0), 0), (Fraction(1), Fraction(0), 1), (Fraction(1), Fraction(1, 10**30), 2)]
    >>> near = {p[2]: _near(K, p) for p in pts}
    >>> [_turn(K, near, *pts), _turn(K, {}, pts[0], pts[2], pts[1])]
    [1, -1]
    """
    fo, fa, fb = near.get(o[2]), near.get(a[2]), near.get(b[2])
    if fo is not None and fa is not None and fb is not None:
        dax, day, dbx, dby = fa[0] - fo[0], fa[1] - fo[1], fb[0] - fo[0], fb[1] - fo[1]
        cross = dax * dby - day * dbx
        bound = 16 * _ULP * ((abs(fa[0]) + abs(fo[0])) * (abs(fb[1]) + abs(fo[1]))
                             + (abs(fa[1]) + abs(fo[1])) * (abs(fb[0]) + abs(fo[0])))  # fmt: skip
        if bound > _SMALLEST and abs(cross) > bound:
            return 1 if cross > 0 else -1
    return int(K.sign((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])))
