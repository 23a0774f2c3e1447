"""Per-body restitutions that an engine's combine rule turns into the contacts' CORs.

An engine that gives each body (shape, fixture) one restitution and combines the two of a
contact by a rule needs, for a case's CORs, per-body values whose combination is each
contact's COR. The bodies here lie on a path, contact ``i`` between bodies ``i`` and ``i + 1``
(a cradle's balls; wall S1, the disk, wall S2), so ``len(cors) + 1`` values. When no such
values exist the case is :class:`~verify.engines.scene.Unsupported`, with the reason, and
never run with other CORs. ``who`` names the values and the rule in that reason
(``"per-body elasticities multiplied (Chipmunk)"``).

- :func:`max_rule_values`: the larger of the two (Box2D's ``b2MixRestitution``);
- :func:`product_rule_values`: the product (Chipmunk/Pymunk, Bullet, DART). A COR of 0 needs a
  body of value 0, whose other contact then has COR 0 too; each run of positive CORs is
  solved along the chain, ``r_(i+1) = cors[i] / r_i``, from one free first value: with
  ``bounded`` (values in [0, 1]) one body at 1, trying each body in turn; without, the first
  value that makes the largest value as small as it can be.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from verify.engines.scene import Unsupported


def check_range(cors: Sequence[float], who: str, *, bounded: bool) -> None:
    """:class:`Unsupported` unless every COR is at least 0 (and at most 1 when ``bounded``)."""
    if any(c < 0 or (bounded and c > 1) for c in cors):
        span = "[0, 1]" if bounded else "[0, inf)"
        raise Unsupported(f"CORs {list(cors)!r}: {who} give CORs in {span} only")


def max_rule_values(cors: Sequence[float], who: str) -> list[float]:
    """Values ``r`` in [0, 1] with ``max(r[i], r[i+1]) == cors[i]``; :class:`Unsupported` if none.

    Body ``i`` takes the smallest COR of its contacts: it fails exactly when an interior
    contact's COR is larger than both neighbours'.

    >>> max_rule_values([0.5, 1.0], "max")
    [0.5, 0.5, 1.0]
    >>> max_rule_values([0.5, 1.0, 0.5], "per-body restitutions combined by max (Box2D)")
    Traceback (most recent call last):
    ...
    verify.engines.scene.Unsupported: per-body restitutions combined by max (Box2D) cannot give contact 2 ...
    """
    check_range(cors, who, bounded=True)
    n = len(cors) + 1
    r = [min(cors[j] for j in (i - 1, i) if 0 <= j < len(cors)) for i in range(n)]
    for i, c in enumerate(cors):
        if max(r[i], r[i + 1]) != c:
            raise Unsupported(
                f"{who} cannot give contact {i + 1} the COR {c!r}: "
                "it is larger than the CORs of both neighbouring contacts"
            )
    return r


def product_rule_values(cors: Sequence[float], who: str, *, bounded: bool, slack: float = 0.0) -> list[float]:
    """Values ``r`` with ``r[i] * r[i+1] == cors[i]`` (to within roundings); :class:`Unsupported` if none.

    ``bounded``: every value in [0, 1], a value up to ``1 + slack`` counting as 1 (and given
    as 1); else any value >= 0.

    >>> product_rule_values([0.5, 0.5], "product", bounded=True)
    [1.0, 0.5, 1.0]
    >>> product_rule_values([0.25, 0.25], "product", bounded=False)
    [0.5, 0.5, 0.5]
    >>> product_rule_values([0.0, 1.0], "product", bounded=True)
    [0.0, 1.0, 1.0]
    >>> product_rule_values([1.0, 0.0, 1.0], "per-body elasticities multiplied (Chipmunk)", bounded=True)
    Traceback (most recent call last):
    ...
    verify.engines.scene.Unsupported: per-body elasticities multiplied (Chipmunk) cannot give contact 2 the COR 0 ...
    """
    check_range(cors, who, bounded=bounded)
    m = len(cors)
    for j, c in enumerate(cors):
        if c == 0 and 0 < j < m - 1 and cors[j - 1] > 0 and cors[j + 1] > 0:
            raise Unsupported(
                f"{who} cannot give contact {j + 1} the COR 0 while both its bodies have another contact "
                "with a COR above 0"
            )
    r = [0.0] * (m + 1)  # a body every contact of which has COR 0 keeps 0
    i = 0
    while i < m:
        if cors[i] == 0:
            i += 1
            continue
        j = i
        while j < m and cors[j] > 0:
            j += 1
        run = list(cors[i:j])  # bodies i..j, contacts i..j-1, all CORs above 0
        values = unit_run(run, slack) if bounded else balanced_run(run)
        if values is None:
            raise Unsupported(f"{who} cannot give contacts {i + 1}..{j} the CORs {run!r} with every value in [0, 1]")
        r[i : j + 1] = values
        i = j
    return r


def unit_run(cors: list[float], slack: float = 0.0) -> list[float] | None:
    """Values in [0, 1] for a run of positive CORs with one body at 1 (each tried in turn), or None.

    If any values in [0, 1] exist, some have a 1 (the largest first value allowed)."""
    n = len(cors) + 1
    for pivot in range(n):
        r = [1.0] * n
        for q in range(pivot, n - 1):
            r[q + 1] = cors[q] / r[q]
        for q in range(pivot, 0, -1):
            r[q - 1] = cors[q - 1] / r[q]
        if max(r) <= 1 + slack:
            return [min(x, 1.0) for x in r]
    return None


def balanced_run(cors: list[float]) -> list[float]:
    """Values >= 0 for a run of positive CORs whose largest is as small as it can be.

    From a first value of 1, even-indexed values scale with the first value ``t`` and
    odd-indexed ones with ``1/t``: ``t`` balances the largest of each (equal CORs give
    ``sqrt(e)`` for every body)."""
    c = [1.0]
    for e in cors:
        c.append(e / c[-1])
    t = math.sqrt(max(c[1::2]) / max(c[0::2]))
    return [cm * t if m % 2 == 0 else cm / t for m, cm in enumerate(c)]
