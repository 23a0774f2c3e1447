"""A cone for rates that tend to a face between impact sets: hit rates that tend to 0 against the others.

Some runs never exit while two impact sets take turns that differ by a rate which tends to 0 faster than the
rest: five plastic balls under the symmetric rule hit (1, 2, 3) and (0, 2, 3) in turn, forever, rates 0 and 2
at the first impulse of the period falling far faster than the others (``tests/proofs/test_periodic.py``). The
direction the rates tend to (:mod:`verify.proofs.cones.period` finds it in rounded numbers) then has those rates
exactly 0: it lies on the face where the rule would hit (1, 3) instead. A cone around that direction in which
those rates keep the run's own signs cannot hold the run's later rates (their share there keeps falling), and
a box around it cuts the face.

The cone here is a product: the face, and a wedge across it. Let d be the direction (its largest rate of modulus
1; its rates of at most :data:`ZERO` are taken as 0: Z, those where the run's rates are not 0), x the run's rates at
d's scale (``x_top = d_top`` on d's largest face rate), and t the direction of x's rates on Z (its largest of
modulus 1). Its generators are

- ``d +- a_i e_i`` for each face rate i but d's largest (a cross-polytope around d on the face, each a_i a power
  of 2 at least 4 m times x's distance from d there, m the number of such i, and at least :data:`FACE_WIDTH`), and
- ``d + s (t +- c_k e_k)`` for each k of Z but t's largest (``d + s t`` when Z is one rate): a wedge across the
  face, of height s (the least power of 2 at least twice x's largest rate on Z) and half-widths c_k (powers of 2 at
  least 2 m' times x's distance from t there, m' such k, a quarter of ``|t_k|`` and :data:`FACE_WIDTH`).

Each of x's rates on the face is then within a quarter of the cross-polytope, and its rates on Z within half of the
wedge: x is in the cone, and so is every point of the face near d and every wedge lower than s. Given several
points, the widths hold them all. The cone cannot hold the run in the run's own signs alone: there the share of its
rates on Z keeps falling.

Whether p impulses map such a cone into itself is decided exactly by the search
(:func:`verify.proofs.cones.period.close`, multiple impulses by their polar values; after each impulse but the last,
the vectors are enclosed in such a cone again, around the direction carried as far) and by
``tests/certificate_check.py``. A multiple impulse is continuous across the face: a rate 0 of J adds nothing to the
impulse nor to its beta (Sect. 3.5 c), so a part of the cone on the face is carried alike with or without it.

>>> from verify.numbers.backends.rational import RationalBackend
>>> K = RationalBackend("python")
>>> q = lambda *xs: [K.convert(Fraction(x)) for x in xs]
>>> gens = face_cone(K, q(0, -1, 0, "-1/4"), [0, 1, 2, 3], [q("1/1000", -2, "-1/4000", "-1/2")])
>>> [[str(x) for x in g] for g in gens]  # doctest: +NORMALIZE_WHITESPACE
[['0', '-1', '0', '-1023/4096'], ['0', '-1', '0', '-1025/4096'],
 ['1/512', '-1', '-3/8192', '-1/4'], ['1/512', '-1', '-5/8192', '-1/4']]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.numbers.backends.base import Backend
from verify.proofs.cones.shape import exponent, round_up

Vector = list[Any]

#: a rate of the direction at most this (relative to its largest) is 0 there: the rounding of a rate that fell
#: below the direction's 64 bits (:func:`verify.proofs.cones.shape.rounded_direction` rounds down)
ZERO = Fraction(1, 2**48)
#: the least half-width of the face part, relative to d's largest rate
FACE_WIDTH = Fraction(1, 2**12)
#: the least half-width of the wedge, relative to its direction's rate
WEDGE_WIDTH = Fraction(1, 4)
#: the heights of a snug enclosure's wedge over the vectors' share on Z that a search tries (a higher wedge leaves
#: the face part narrower: the period may draw either in more)
HEIGHTS = (Fraction(2), Fraction(8), Fraction(8, 7))
#: the least half-width of a snug enclosure (relative to the direction's largest rate)
TINY = Fraction(1, 2**40)


def face_cone(
    K: Backend,
    direction: Vector,
    on: Sequence[int],
    points: Sequence[Sequence[Any]],
    center: Sequence[Any] | None = None,
    *,
    snug: Fraction | None = None,
) -> list[Vector] | None:
    """The generators of the module docstring around ``direction`` (its largest rate on ``on`` of modulus 1, the
    constraints the period hits; rationals), wide enough to hold each of ``points`` (the run's rates, or vectors
    carried so far), the wedge turned to ``center``'s rates on Z (default: the first point). None when no rate of
    ``on`` is 0 in the direction but not in the center (no face), or when a point is not on the face's side: a
    largest rate of the opposite sign, or rates on Z where the wedge's direction has none.

    ``snug`` (a height H > 1, for an enclosure of vectors carried so far) makes the cone as narrow as holds them:
    the wedge H times their share on Z, each a_i H/(H - 1) m times their distance from d (8 significant bits, rounded
    up) and each c_k m' times theirs, without the least widths, so that the enclosure widens the cone no more than it
    must (a point's weight on the wedge is then at most 1/H, and the rest is enough for its face part)."""
    center = points[0] if center is None else center
    num = [[Fraction(K.to_number(v)) for v in y] for y in points]
    d = [Fraction(K.to_number(v)) for v in direction]
    small = [i for i in on if abs(d[i]) <= ZERO]
    zeros = [i for i in small if center[i] != K.zero]
    face = [i for i in on if i not in small]
    if not zeros or not face:
        return None
    top = max(face, key=lambda i: abs(d[i]))
    scaled = []
    for y in num:
        if y[top] == 0 or (y[top] > 0) != (d[top] > 0):
            return None
        scaled.append([v * d[top] / y[top] for v in y])
    c = [Fraction(K.to_number(v)) for v in center]
    if c[top] == 0 or (c[top] > 0) != (d[top] > 0):
        return None
    c = [v * d[top] / c[top] for v in c]
    base = [Fraction(0) if i in small else d[i] if i in on else c[i] for i in range(len(c))]
    gens = _face_part(base, face, top, scaled, snug)
    wedge = _wedge(zeros, c, scaled, snug)
    if wedge is None:
        return None
    height, shifts = wedge
    gens += [[b + height * w for b, w in zip(base, u)] for u in shifts]
    return [[K.convert(v) for v in g] for g in gens]


def _face_part(
    base: list[Fraction], face: Sequence[int], top: int, points: Sequence[list[Fraction]], snug: Fraction | None
) -> list[list[Fraction]]:
    """``base +- a_i e_i`` for each face rate i but ``top``, a_i at least 4 m times the points' largest distance from
    base there (m such rates) and FACE_WIDTH (snug H: H/(H - 1) m times it); base itself when there is no such rate."""
    others = [i for i in face if i != top]
    if not others:
        return [list(base)]
    out = []
    for i in others:
        far = max(abs(y[i] - base[i]) for y in points) * len(others)
        a = round_up(max(far * snug / (snug - 1), TINY)) if snug else _power_up(max(4 * far, FACE_WIDTH))
        out += [[v + sign * a if j == i else v for j, v in enumerate(base)] for sign in (1, -1)]
    return out


def _wedge(
    zeros: Sequence[int], center: list[Fraction], points: Sequence[list[Fraction]], snug: Fraction | None
) -> tuple[Fraction, list[list[Fraction]]] | None:
    """(s, the wedge's directions ``t +- c_k e_k``): t the center's rates on Z over their largest modulus (rounded to
    24 bits), each c_k at least 2 m times the points' largest distance from t there (m the rates of Z but t's largest)
    and a quarter of |t_k|, s the least power of 2 at least twice the points' largest rate on t's largest (snug H: c_k
    m times that distance, s H times that rate); None when a point holds rates on Z but not on t's largest, or one of
    the opposite sign."""
    wide = max(zeros, key=lambda i: abs(center[i]))
    unit = Fraction(1, 2**24)
    t = [Fraction(math.floor(center[i] / abs(center[wide]) / unit)) * unit if i in zeros else Fraction(0)
         for i in range(len(center))]  # fmt: skip
    t[wide] = center[wide] / abs(center[wide])
    others = [k for k in zeros if k != wide]
    share, spread = Fraction(0), {k: Fraction(0) for k in others}
    for y in points:
        if all(y[k] == 0 for k in zeros):
            continue
        if y[wide] == 0 or (y[wide] > 0) != (t[wide] > 0):
            return None
        share = max(share, abs(y[wide]))
        for k in others:
            spread[k] = max(spread[k], abs(y[k] / abs(y[wide]) - t[k]))
    share = share or abs(center[wide])
    height = round_up(snug * share) if snug else _power_up(2 * share)
    if not others:
        return height, [t]
    shifts = []
    for k in others:
        far = len(others) * spread[k]
        c = round_up(max(far, TINY)) if snug else _power_up(max(2 * far, abs(t[k]) * WEDGE_WIDTH, FACE_WIDTH))
        shifts += [[v + sign * c if j == k else v for j, v in enumerate(t)] for sign in (1, -1)]
    return height, shifts


def _power_up(q: Fraction) -> Fraction:
    """The least power of 2 at least q (q > 0).

    >>> _power_up(Fraction(3, 1000))
    Fraction(1, 256)
    """
    below = Fraction(2) ** (exponent(q) - 1)  # at most q
    return below if below == q else 2 * below
