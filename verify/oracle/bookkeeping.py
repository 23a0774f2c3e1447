"""How the oracle reads a result of the sequential law: the bookkeeping of the sweeps, and hints at a bug.

Under the sequential law (:mod:`verify.laws.sequential`) a result's ``iterations`` counts the sweeps
that changed an accumulated impulse, ``impact_sets`` lists per such sweep the contacts whose impulse
changed, and its ``exit_velocity`` is the velocity after the sweeps, whatever the stop (``exit``: every
rate outgoing; ``max_iterations``: a contact still incoming after the sweeps, which an engine carries
into its next step). A float implementation keeps changing an impulse by residuals of a float's
resolution after the exact impulses have settled, and decides a rate that is exactly 0 by its
rounding. :func:`bookkeeping` tolerates exactly that, and nothing else:

- more sweeps than the exact run's, up to the sweeps allowed, each changing at least the contacts the
  exact sweep changed (extra contacts changed by residuals);
- a stop ``exit`` for ``max_iterations`` or the reverse, when the rate that decides it is within the
  velocity's tolerance of 0.

Both only when the velocity itself agrees within its tolerance (the caller checks that).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from verify.records.results import read_number


def _rates(case: dict[str, Any], velocity: list[Fraction]) -> list[Fraction]:
    """p(F_i) = dF_i . v + time term, from the case's numbers (closed forms to 40 digits)."""
    from verify.properties.formulas import rate

    terms = case.get("time_terms") or ["0"] * len(case["normals"])
    return [rate([read_number(a) for a in row], read_number(t), velocity) for row, t in zip(case["normals"], terms)]


def rate_bounds(case: dict[str, Any], bound: Fraction) -> list[Fraction]:
    """How far each rate of a velocity within ``bound`` (per component) of the exact one can be from the
    exact rate: ``bound * sum_j |dF_ij|``."""
    return [bound * sum((abs(read_number(a)) for a in row), Fraction(0)) for row in case["normals"]]


def stop_tolerated(case: dict[str, Any], exact: dict[str, Any], mine_stop: str, bound: Fraction) -> bool:
    """Whether ``exit`` for ``max_iterations`` (or the reverse) is only a rate within tolerance of 0: the
    exact velocity's rates decide the stop, and each that would have to change sign is within
    :func:`rate_bounds` of 0.

    >>> case = {"normals": [["-1", "1"]], "velocity": ["1", "0"]}
    >>> stop_tolerated(case, {"stop": "exit", "exit_velocity_decimal": ["1", "1"]}, "max_iterations", Fraction(0))
    True
    >>> stop_tolerated(case, {"stop": "exit", "exit_velocity_decimal": ["0", "1"]}, "max_iterations", Fraction(0))
    False
    """
    if {exact["stop"], mine_stop} != {"exit", "max_iterations"}:
        return False
    rates = _rates(case, [read_number(x) for x in exact["exit_velocity_decimal"]])
    slack = rate_bounds(case, bound)
    if exact["stop"] == "exit":  # some rate of the implementation's velocity is negative: one within slack of 0
        return any(w <= s for w, s in zip(rates, slack))
    return all(w >= -s for w, s in zip(rates, slack))  # every negative rate within slack of 0


def sweep_changes(case: dict[str, Any], exact: dict[str, Any]) -> tuple[list[dict[int, Fraction]], Fraction]:
    """The exact run's change of each accumulated impulse in each sweep that changed one (40 digits), and
    the largest accumulated impulse."""
    from verify.laws.rule import solve
    from verify.laws.sequential import law_of_record
    from verify.records.results import bare_case

    c = bare_case(case)
    run = solve(c.system, c.velocity_source, law=law_of_record(dict(exact, law="sequential")), certify=False)
    K = run.backend
    changes = [{i: read_number(K.to_decimal(x, 40)) for i, x in step.changes} for step in run.steps]
    largest = max([abs(read_number(x)) for x in exact.get("impulses") or []] + [Fraction(0)])
    return changes, largest


def bookkeeping(case: dict[str, Any], exact: dict[str, Any], mine: dict[str, Any], rtol: Fraction) -> str | None:
    """Why the sweeps' counts differ only by float residuals, or None when they differ otherwise (or not at
    all). A sweep may change more contacts than the exact one (residuals), or leave out a contact whose exact
    change is at most ``rtol`` times the largest accumulated impulse (below what the velocity's tolerance
    sees), and the sweeps may go on to the number allowed.

    >>> case = {"id": "c", "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    ...         "normals": [["-1", "1", "0"], ["0", "-1", "1"]], "restitution": ["1", "1"],
    ...         "velocity": ["100", "0", "0"]}
    >>> exact = {"iterations": 2, "impact_sets": [[0, 1], [0, 1]], "impulses": ["100", "50"],
    ...          "law_settings": {"iterations": 2, "order": [0, 1], "threshold": ["0", "0"]}}
    >>> bookkeeping(case, exact, {"iterations": 2, "impact_sets": [[0, 1], [0, 1]]}, Fraction(1, 10**8)) is None
    True
    >>> bookkeeping(case, exact, {"iterations": 1, "impact_sets": [[0, 1]]}, Fraction(1, 10**8)) is None
    True
    """
    sets_e = exact["impact_sets"]
    sets_m = [sorted(J) for J in mine["impact_sets"]] if "impact_sets" in mine else None
    n = mine.get("iterations", len(sets_m) if sets_m is not None else None)
    if n is None or (n == exact["iterations"] and (sets_m is None or sets_m == sets_e)):
        return None
    allowed = int((exact.get("law_settings") or {}).get("iterations", n))
    r = len(case["normals"])
    if n > allowed or (sets_m is not None and (len(sets_m) != n or any(not 0 <= i < r for J in sets_m for i in J))):
        return None
    changes, largest = sweep_changes(case, exact)
    small = rtol * largest
    for k in range(max(n, len(changes))):
        left_out = set(changes[k]) if k < len(changes) else set()
        if sets_m is not None and k < n:
            left_out -= set(sets_m[k])
        elif k < n:  # only the count is given: a sweep it made may change anything
            left_out = set()
        if any(abs(changes[k][i]) > small for i in left_out):
            return None
    what = (
        f"impulses changing in {n} sweeps where the exact ones change in {exact['iterations']}"
        if n != exact["iterations"]
        else "other contacts changing in a sweep than the exact run's"
    )
    return f"{what} (tolerated: changes of at most {_tiny(rtol)} of the largest impulse, float residuals)"


def _tiny(x: Fraction) -> str:
    from verify.numbers.format import format_decimal

    return format_decimal(x, 3)


def _numbers(values: Any) -> list[Fraction] | None:
    try:
        return [read_number(str(x)) for x in values]
    except Exception:  # a bad number in the implementation's impulses: no hint from them
        return None


def hint(
    case: dict[str, Any],
    exact: dict[str, Any],
    mine: dict[str, Any],
    rtol: Fraction = Fraction(1, 10**8),
    lead: str = "the exact run",
) -> str:
    """Where a sequential run's answer departs: the targets of the restitution, the exact accumulated
    impulses and the implementation's (when it gives ``impulses``), the first contact whose impulse differs
    by more than ``rtol`` of the largest (one below 0 first: what a missing clamp leaves); ``lead`` names the
    run at the end of the sweeps.

    >>> case = {"id": "c", "mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
    ...         "normals": [["-1", "1", "0"], ["0", "-1", "1"]], "restitution": ["1", "1"],
    ...         "velocity": ["100", "0", "0"]}
    >>> exact = {"impulses": ["100", "50"], "law_settings": {"iterations": 1, "order": [0, 1], "threshold": ["0", "0"]}}
    >>> hint(case, exact, {"impulses": ["100", "-50"]})
    '; the exact run: targets t = (100, 0), accumulated impulses (100, 50); yours (100, -50): contact 1 differs \
(exact 50, yours -50, below 0: the law clamps an accumulated impulse at 0)'
    """
    from verify.numbers.format import format_decimal

    targets = restitution_targets(case, exact)
    lam = exact.get("impulses") or []
    text = f"; {lead}: targets t = ({', '.join(targets)}), accumulated impulses ({', '.join(_short(x) for x in lam)})"
    theirs = _numbers(mine.get("impulses") or [])
    if not theirs or len(theirs) != len(lam):
        return text + ' (give "impulses" in the result to compare yours)'
    exact_values = [read_number(x) for x in lam]
    text += f"; yours ({', '.join(format_decimal(x, 6) for x in theirs)})"
    scale = max([abs(x) for x in exact_values] + [Fraction(1, 10**30)])
    far = [i for i, (a, b) in enumerate(zip(exact_values, theirs)) if abs(a - b) > rtol * scale]
    if not far:
        return text
    i = next((k for k in far if theirs[k] < 0), far[0])  # a negative impulse first: what a missing clamp leaves
    below = ", below 0: the law clamps an accumulated impulse at 0" if theirs[i] < 0 else ""
    exact_text = format_decimal(exact_values[i], 6)
    return text + f": contact {i} differs (exact {exact_text}, yours {format_decimal(theirs[i], 6)}{below})"


def restitution_targets(case: dict[str, Any], exact: dict[str, Any]) -> list[str]:
    """The target rate of each contact, exactly as the law takes it: ``-e_i w_i`` for a contact incoming
    faster than its threshold (``w_i`` its rate before the solve), else 0."""
    from verify.laws.sequential import Sequential, law_of_record
    from verify.laws.sequential import restitution_targets as targets
    from verify.records.results import bare_case

    c = bare_case(case)
    law = law_of_record(dict(exact, law="sequential"))
    assert isinstance(law, Sequential)
    system, values = targets(c.system, c.velocity_source, law)
    K = system.backend
    return [_short(K.to_exact(x)) for x in values]


def _short(text: str) -> str:
    """An exact number string when short (24 characters), else ``~`` and 6 significant digits."""
    if len(text) <= 24:
        return text
    from verify.numbers.format import format_decimal

    return "~" + format_decimal(read_number(text), 6)
