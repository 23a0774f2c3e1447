"""A small sequential-impulse solver in plain Python floats, written as a physics engine's would be.

It is the worked example of ``docs/oracle.md`` for engine developers: it reads a case file on stdin
and writes a result file on stdout, so that ``verify oracle check CASES.json --law sequential
--threshold 1/2 --impl "python3 examples/sequential_impulses.py"`` checks it and ``verify oracle
explain CASES.json --impl "python3 examples/sequential_impulses.py"`` finds its settings. It imports
nothing from ``verify`` and reads the cases' ``decimal`` numbers (40 digits) with ``float``.

The algorithm is Catto's sequential impulses on one step's contacts: a restitution target taken
once from the rates before the solve (``-e * rate`` for a contact approaching faster than
``--threshold``, else 0), accumulated impulses clamped at 0, ``--sweeps`` sweeps over the contacts
in the order given, no warm start; a case's own ``law_settings`` (sweeps, order,
threshold) replace the options. Like an engine it writes only the velocity after the sweeps;
``--full`` adds the stop, the sweeps that changed an impulse and the accumulated impulses;
``--bug clamp`` or ``--bug target`` plants one of two classic bugs, to see what the oracle says.
"""

from __future__ import annotations

import argparse
import json
import sys
from fractions import Fraction


def solve(A: list[list[float]], b: list[float]) -> list[float]:
    """x with A x = b (Gaussian elimination with partial pivoting)."""
    n = len(A)
    M = [[*row, b[i]] for i, row in enumerate(A)]
    for c in range(n):
        p = max(range(c, n), key=lambda i: abs(M[i][c]))
        M[c], M[p] = M[p], M[c]
        for i in range(c + 1, n):
            f = M[i][c] / M[c][c]
            M[i] = [x - f * y for x, y in zip(M[i], M[c])]
    x = [0.0] * n
    for i in reversed(range(n)):
        x[i] = (M[i][n] - sum(M[i][j] * x[j] for j in range(i + 1, n))) / M[i][i]
    return x


def run(case: dict, sweeps: int, threshold: float, full: bool, bug: str = "") -> dict:
    d = case["decimal"]
    g = [[float(x) for x in row] for row in d["mass_matrix"]]
    a = [[float(x) for x in row] for row in d["normals"]]
    t = [float(x) for x in d.get("time_terms") or ["0"] * len(a)]
    e = [float(x) for x in d["restitution"]]
    v = [float(x) for x in d["velocity"]]
    r = len(a)
    U = [solve(g, row) for row in a]  # the velocity change of a unit impulse on contact i
    G = [sum(x * y for x, y in zip(a[i], U[i])) for i in range(r)]

    def rate(i: int) -> float:
        return t[i] + sum(x * y for x, y in zip(a[i], v))

    own = case.get("law_settings") or {}  # a case may carry its own sweeps, order and threshold
    sweeps = own.get("iterations", sweeps)
    order = own.get("order", range(r))
    given = own.get("threshold", threshold)
    thresholds = [float(Fraction(x)) for x in given] if isinstance(given, list) else [float(Fraction(given))] * r
    target = [-e[i] * rate(i) if -rate(i) > thresholds[i] else 0.0 for i in range(r)]
    lam = [0.0] * r
    changed_sets = []
    for _ in range(sweeps):
        changed = []
        for i in order:
            if bug == "target" and -rate(i) > thresholds[i]:  # deliberate bug: the target from the current rate
                target[i] = -e[i] * rate(i)
            new = lam[i] + (target[i] - rate(i)) / G[i]
            new = new if bug == "clamp" else max(new, 0.0)  # deliberate bug: no clamp at 0
            if new != lam[i]:
                v = [x + (new - lam[i]) * u for x, u in zip(v, U[i])]
                lam[i] = new
                changed.append(i)
        if not changed:
            break
        changed_sets.append(sorted(changed))
    out = {"id": case["id"], "exit_velocity": [repr(x) for x in v]}
    if full:
        out["stop"] = "exit" if all(rate(i) >= 0 for i in range(r)) else "max_iterations"
        out["iterations"] = len(changed_sets)
        out["impact_sets"] = changed_sets
        out["impulses"] = [repr(x) for x in lam]
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sweeps", type=int, default=10, help="sweeps over the contacts (default 10)")
    p.add_argument("--threshold", type=float, default=0.5,
                   help="no restitution for a contact approaching at this speed or slower (default 0.5)")  # fmt: skip
    p.add_argument("--full", action="store_true", help="also write stop, iterations, impact_sets and impulses")
    p.add_argument("--bug", choices=("clamp", "target"), default="",
                   help="a deliberate bug, to see what the oracle says: no clamp at 0, or the target from the "
                        "current rate")  # fmt: skip
    args = p.parse_args()
    cases = json.load(sys.stdin)["cases"]
    results = [run(c, args.sweeps, args.threshold, args.full, args.bug) for c in cases]
    json.dump({"results": results}, sys.stdout, indent=1)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
