"""Hard cases where the simultaneous and the sequential laws branch (``verify oracle generate --law``).

- the sequential law: a contact incoming exactly at the restitution threshold (which the law does
  not restitute: "at this speed or slower") and 10^-k faster or slower; two contacts incoming at
  the same speed, swept in either order (an order tie: the answer after a few sweeps depends on
  the order); contacts whose normals differ in scale by 10^6 (Gauss-Seidel's diagonal is then
  badly scaled). The threshold and order cases carry their own ``law_settings`` (threshold, order,
  sweeps); the scaled ones run with the command's settings.
- the simultaneous law: a three-ball cradle whose third ball leaves at exactly the speed at which
  the second contact's impulse becomes 0 (the boundary of the active set), and 10^-k on each side.

>>> [c["id"] for c in law_cases(1, "simultaneous")][:2]
['sim-active-set-e1/2-at', 'sim-active-set-e1/2-plus-1e-12']
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.models.cradle import cradle_geometry
from verify.records.results import case_record

#: the distances 10^-k of the cases beside a boundary, per level
DISTANCES = {1: (12, 6), 2: (15, 12, 9, 6), 3: (30, 15, 12, 9, 6, 3)}
CAP = 10_000


def _cradle(
    case_id: str, eps: Any, velocity: list[Any], why: str, settings: dict[str, Any] | None = None
) -> dict[Any, Any]:
    g, normals = cradle_geometry([1] * len(velocity))
    record = case_record(case_id, g, normals, [eps] * (len(velocity) - 1), velocity, max_iterations=CAP)
    record["why"] = why
    if settings:
        record["law_settings"] = settings
    return record


def _beside(level: int) -> list[tuple[str, Fraction]]:
    """The signed distances of the cases beside a boundary, with their id suffix."""
    out = []
    for k in DISTANCES[level]:
        out += [(f"plus-1e-{k}", Fraction(1, 10**k)), (f"minus-1e-{k}", -Fraction(1, 10**k))]
    return out


def sequential_cases(level: int) -> list[dict[Any, Any]]:
    """Thresholds, order ties and badly scaled contacts of the sequential law."""
    out = []
    for t in (Fraction(1, 2), Fraction(1)) if level > 1 else (Fraction(1, 2),):
        settings = {"threshold": str(t)}
        why = f"contact S(1,2) incoming at exactly the threshold {t}: no restitution ('at this speed or slower')"
        out.append(_cradle(f"seq-threshold-{t}-at", 1, [t, 0, 0], why, settings))
        for suffix, d in _beside(level):
            side = "faster" if d > 0 else "slower"
            why = f"contact S(1,2) incoming {abs(d)} {side} than the threshold {t}"
            out.append(_cradle(f"seq-threshold-{t}-{suffix}", 1, [t + d, 0, 0], why, settings))
    for name, order in (("given", [0, 1]), ("reversed", [1, 0])):
        for sweeps in (1, 2):
            why = f"both contacts incoming at speed 1: {sweeps} sweeps in the order {order} (the answer depends on it)"
            own: dict[str, Any] = {"order": order, "iterations": sweeps}
            out.append(_cradle(f"seq-order-tie-{name}-{sweeps}-sweeps", "1/2", [1, 0, -1], why, own))
    g, normals = cradle_geometry([1, 1, 1])
    for scale in (10**6, Fraction(1, 10**6)):
        scaled = [[x * scale for x in normals[0]], normals[1]]
        record = case_record(f"seq-scaled-contacts-{scale}", g, scaled, ["1/2", "1/2"], [1, 0, 0], max_iterations=CAP)
        record["why"] = f"the normal of S(1,2) scaled by {scale}: the sweeps' diagonal G_ii badly scaled"
        out.append(record)
    return out


def simultaneous_cases(level: int) -> list[dict[Any, Any]]:
    """The boundary of the simultaneous law's active set in a three-ball cradle with COR e: with contact
    S(1,2) alone the middle ball leaves at (1 + e)/2, so a third ball leaving at exactly that speed takes
    no impulse from S(2,3), and 10^-k slower it takes one."""
    out = []
    for e in (Fraction(1, 2), Fraction(1)) if level > 1 else (Fraction(1, 2),):
        x = (1 + e) / 2
        out.append(_cradle(f"sim-active-set-e{e}-at", e, [1, 0, x], f"ball 3 leaves at exactly (1 + e)/2 = {x}: "
                           "the impulse of S(2,3) is exactly 0 (the boundary of the active set)"))  # fmt: skip
        for suffix, d in _beside(level):
            what = (
                "faster than (1 + e)/2: no impulse on S(2,3)"
                if d > 0
                else "slower than (1 + e)/2: an impulse on S(2,3)"
            )
            out.append(_cradle(f"sim-active-set-e{e}-{suffix}", e, [1, 0, x + d], f"ball 3 leaves {abs(d)} {what}"))
    return out


def law_cases(level: int, law: str) -> list[dict[Any, Any]]:
    """The hard cases of a law (none for the paper's rule: :mod:`verify.oracle.hardcases` holds those)."""
    if law == "sequential":
        return sequential_cases(level)
    if law == "simultaneous":
        return simultaneous_cases(level)
    return []
