"""DART's step loop, exactly: one boxed LCP per step with constraint-force mixing and error reduction.

What DART 6 does at each step (``dart/constraint/ContactConstraint.cpp``, ``BoxedLcpConstraintSolver.cpp``,
``PgsBoxedLcpSolver.cpp``), with its compile-time constants:

- every contact whose gap is at most 0 is in the step's LCP (DART solves one LCP per group of connected
  skeletons: on a cradle or a corner, whose touching contacts form one chain, that is one LCP; where they
  fall apart into groups the model still solves one) ``A x = b + w``, ``x >= 0``, ``w >= 0``,
  ``x . w = 0``, ``A`` the contacts' Delassus matrix with each diagonal entry times ``1 + CFM``
  (``DART_CFM = 1e-5``, ``getVelocityChange(..., withCfm)``);
- ``b`` is the approach speed plus a target: ``ERP / time_step`` times the penetration, at most
  ``MAX_ERV`` (``DART_ERP = 0.01``, ``DART_MAX_ERV = 1e-3``), replaced by ``e`` times the approach speed when
  that is larger and above ``0.1`` (``DART_BOUNCING_VELOCITY_THRESHOLD``), capped at ``100``, and only when
  ``e > 1e-3`` (``DART_RESTITUTION_COEFF_THRESHOLD``);
- the LCP is solved by Dantzig's pivoting (here: exactly, by its unique solution, ``A`` being positive
  definite); where Dantzig stops early, DART's fallback is PGS (``PgsBoxedLcpSolver``: 30 sweeps from 0 at
  most, stopping when every change is within ``1e-6`` in the first sweep or within ``1e-3`` of the value
  in a later one), whose answer depends on the order in which the detector lists the contacts;
- the bodies then move by ``time_step`` times their new velocities, and the next step detects again, until
  no impulse is applied and no contact approaches (the adapter's stop) or ``max_steps``.

A solve is named by its variant: ``dantzig`` (every step by pivoting), ``pgs first`` (PGS at the first
step, as DART 6.20 was measured to fall back on the cradles' first step with three or more contacts) and
``pgs 3+`` (PGS at every step with three or more contacts), with the contact order of PGS.

>>> from verify.models.cradle import cradle_geometry
>>> from verify.records.results import case_record
>>> g, normals = cradle_geometry([1, 1, 1])
>>> v = Dart().run(case_record("c", g, normals, ["1", "1"], ["100", "0", "0"]), ("dantzig", None))
>>> [x[:12] for x in v]
['-33.33111115', '66.665548916', '66.665562236']
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from itertools import combinations
from typing import Any

from verify.engines.adapters.dartpy import RADIUS
from verify.engines.models.steps import Contacts, check_order, contacts_of, orders
from verify.numbers.linalg import ldl, solve_spd

CFM = Fraction(1, 10**5)  #: DART_CFM
ERP = Fraction(1, 100)  #: DART_ERP
MAX_ERV = Fraction(1, 1000)  #: DART_MAX_ERV
COR_FLOOR = Fraction(1, 1000)  #: DART_RESTITUTION_COEFF_THRESHOLD: bounce only when e is above it
BOUNCE_MIN = Fraction(1, 10)  #: DART_BOUNCING_VELOCITY_THRESHOLD: bounce only when e times the approach is above it
BOUNCE_MAX = Fraction(100)  #: DART_MAX_BOUNCING_VELOCITY
#: PgsBoxedLcpSolver::Option's defaults but the sweeps (the adapter's pgs_iterations): first-sweep change,
#: relative change, and the diagonal below which a row is skipped
PGS_DELTA, PGS_RELATIVE, PGS_EPSILON = Fraction(1, 10**6), Fraction(1, 1000), Fraction(1, 10**9)

Variant = tuple[str, tuple[int, ...] | None]


class Dart:
    """DART's steps (``dartpy``; nimblephysics keeps Dantzig with CFM 0 and no fallback at these sizes).

    ``settings``: an engine's settings as the record holds them (``time_step``, ``pgs_iterations``,
    ``max_steps``, ``overlap``; DART's defaults otherwise). A variant is ``("dantzig", None)`` or
    ``(solver, order)`` with ``solver`` "pgs first" or "pgs 3+" and ``order`` a permutation of the case's
    contacts (:meth:`variants` lists them). :meth:`run` returns the exit velocity as 30-digit decimals of the
    exact one; the record's ``model`` label of an engine answer names the variant (:meth:`label`).
    """

    name = "DART's steps"
    solvers = ("dantzig", "pgs first", "pgs 3+")

    def __init__(self, settings: dict[str, Any] | None = None):
        from verify.engines.scene import documented

        s = settings or {}
        self.dt = documented(s.get("time_step", 0.001))
        self.sweeps = int(s.get("pgs_iterations", 30))
        self.max_steps = int(s.get("max_steps", 1000))
        self.overlap = float(s.get("overlap", 0.0))

    def label(self, variant: Variant) -> str:
        """The model in words, with its settings."""
        from verify.numbers.format import format_decimal

        solver, order = variant
        how = {"dantzig": "Dantzig", "pgs first": "PGS at the first step", "pgs 3+": "PGS on 3 or more contacts"}
        where = "" if order is None else f" ({self.sweeps} sweeps), contact order {', '.join(map(str, order))}"
        dt = format_decimal(self.dt, 6)
        return f"{self.name}: boxed LCP, CFM 1e-5, ERP 0.01, time step {dt}, {how[solver]}{where}"

    def variants(self, r: int) -> list[Variant]:
        """The solves to try on ``r`` contacts: pivoting, and PGS in each order
        (:func:`~verify.engines.models.orders`)."""
        solvers = self.solvers[1:] if r >= 3 else self.solvers[1:2]  # "pgs 3+" is Dantzig below 3 contacts
        return [("dantzig", None)] + [(s, o) for o in orders(r) for s in solvers]

    def run(self, case: dict[str, Any], variant: Variant) -> list[str]:
        """The exit velocity (30-digit decimals of the exact one) of the model on a case record."""
        c = contacts_of(case, radius=RADIUS, overlap=self.overlap)
        solver, order = variant
        if solver not in self.solvers or (solver == "dantzig") != (order is None):
            raise ValueError(
                f"a DART variant is ('dantzig', None) or (one of {self.solvers[1:]}, an order), got {variant!r}"
            )
        if order is not None:
            check_order(order, c.system.r)
        K = c.K
        v = c.velocity
        for step in range(self.max_steps):
            touching = [i for i in range(c.system.r) if K.sign(c.gaps[i]) <= 0]
            pushed = False
            if touching:
                solver, order = variant
                pgs = (solver == "pgs first" and step == 0) or (solver == "pgs 3+" and len(touching) >= 3)
                x = self._solve(c, v, touching, order if pgs else None, pgs)
                for i, xi in zip(touching, x):
                    if K.sign(xi) != 0:
                        v, pushed = c.push(v, i, xi), True
            c.move(v, K.convert(self.dt))
            if not pushed and all(K.sign(w) >= 0 for w in c.system.rates(v)):
                break
        return [K.to_decimal(x, 30) for x in v]

    def _solve(
        self, c: Contacts, v: Sequence[Any], rows: list[int], order: tuple[int, ...] | None, pgs: bool
    ) -> list[Any]:
        K, s = c.K, c.system
        rates = s.rates(v)
        cv = K.convert
        b = []
        for i in rows:
            approach, depth = K.zero - rates[i], K.zero - c.gaps[i]
            target = K.zero
            if K.sign(depth) > 0:
                target = depth * cv(ERP) / cv(self.dt)
                target = cv(MAX_ERV) if K.sign(target - cv(MAX_ERV)) > 0 else target
            e = s.restitution[i]
            bounce = approach * e
            if K.sign(e - cv(COR_FLOOR)) > 0 and K.sign(bounce - cv(BOUNCE_MIN)) > 0 and K.sign(bounce - target) > 0:
                target = cv(BOUNCE_MAX) if K.sign(bounce - cv(BOUNCE_MAX)) > 0 else bounce
            b.append(approach + target)
        A = [[s.gram[i][j] * (K.one + cv(CFM)) if i == j else s.gram[i][j] for j in rows] for i in rows]
        if not pgs:
            return _lcp(K, A, b)
        at = {i: k for k, i in enumerate(rows)}
        p = [at[i] for i in (order or range(s.r)) if i in at]
        y = _pgs(K, [[A[i][j] for j in p] for i in p], [b[i] for i in p], self.sweeps)
        x = [K.zero] * len(rows)
        for k, i in enumerate(p):
            x[i] = y[k]
        return x


def _lcp(K: Any, A: list[list[Any]], b: list[Any]) -> list[Any]:
    """The unique solution of the LCP ``A x - b = w`` (``A`` positive definite), found exactly: the active
    set whose solution is non-negative and leaves every other row non-negative."""
    n = len(b)
    for size in range(n, -1, -1):
        for active in combinations(range(n), size):
            x = [K.zero] * n
            if active:
                xs = solve_spd(K, ldl(K, [[A[i][j] for j in active] for i in active]), [b[i] for i in active])
                if any(K.sign(t) < 0 for t in xs):
                    continue
                for i, t in zip(active, xs):
                    x[i] = t
            rest = [i for i in range(n) if i not in active]
            if all(K.sign(sum((A[i][j] * x[j] for j in range(n)), K.zero) - b[i]) >= 0 for i in rest):
                return x
    raise ArithmeticError("no solution of the step's LCP")  # not reached: A is positive definite


def _pgs(K: Any, A: list[list[Any]], b: list[Any], sweeps: int) -> list[Any]:
    """DART's PgsBoxedLcpSolver on a normal-only LCP (lower bound 0, no upper), exactly."""
    n, cv = len(b), K.convert
    x = [K.zero] * n

    def size(t: Any) -> Any:
        return t if K.sign(t) >= 0 else K.zero - t

    def update(i: int, a: list[Any], bi: Any) -> Any:
        new = bi
        for j in range(n):
            if j != i:
                new = new - a[j] * x[j]
        return new

    rows = [i for i in range(n) if K.sign(A[i][i] - cv(PGS_EPSILON)) >= 0]
    done = True
    for i in rows:
        new = update(i, A[i], b[i]) / A[i][i]
        old, x[i] = x[i], new if K.sign(new) > 0 else K.zero
        done = done and K.sign(size(x[i] - old) - cv(PGS_DELTA)) <= 0
    if done:
        return x
    b = [b[i] / A[i][i] for i in range(n)]
    A = [[a / row[i] for a in row] for i, row in enumerate(A)]
    for _ in range(1, sweeps):
        done = True
        for i in rows:
            new = update(i, A[i], b[i])
            old, x[i] = x[i], new if K.sign(new) > 0 else K.zero
            if done and K.sign(size(x[i]) - cv(PGS_EPSILON)) > 0:
                done = K.sign(size(x[i] - old) - cv(PGS_RELATIVE) * size(x[i])) <= 0
        if done:
            break
    return x
