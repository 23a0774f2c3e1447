"""Hypothesis strategies that build valid impact problems directly (no filtering).

A drawn case is a :class:`Drawn`: a case record of the contracts (strings only, so a
failing case can be printed, saved and rerun with ``verify solve``), its family and the
rule it is meant for. Every piece is valid by construction:

- mass matrices ``L L^T`` with L lower triangular with a positive diagonal: symmetric
  positive definite; they shrink towards diagonal matrices;
- r independent normals: row i has a non-zero entry in its own pivot column and zeros
  in the other rows' pivot columns; sometimes made Phi-orthogonal (Gram-Schmidt in the
  metric ``g^-1``), so that Proposition 1 (ii) can be exercised;
- CORs in [0, 1], 0 and 1 drawn often: one per constraint (``general``,
  ``asymmetric``), one for all (``symmetric``), all 1 (``ideal``);
- the velocity: a free part, then exact target rates on a chosen set of constraints
  (negative for the hit ones, sometimes exactly 0: grazing), solved for with the Gram
  matrix. At least one constraint is always hit.

Families: ``general`` (r = 1..4 constraints in n = r+1..6 coordinates, the paper's
2 <= r < n plus r = 1; fixed or moving constraints), ``cradle`` (N = 2..5 balls of
rational masses) and ``corner`` (the disk of Sect. 4.2 with a rational slope). The
asymmetric rule (7) is for two constraints: its cases have r = 2.

>>> from hypothesis import find, settings
>>> quiet = settings(database=None, derandomize=True)  # no example database: the same answer every run
>>> d = find(cases("corner", "ideal"), lambda d: True, settings=quiet)  # the simplest corner case
>>> d.record["normals"], d.record["restitution"], d.record["velocity"]
([['-1', '1', '0'], ['-1', '-1', '0']], ['1', '1'], ['1/2', '-1/2', '0'])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from functools import cache
from typing import Any

from hypothesis import strategies as st

from verify.laws.rule import RULES as CORE_RULES
from verify.models.corner import corner_geometry
from verify.models.cradle import cradle_geometry
from verify.models.rates import fractions, metric_inverse_apply, velocity_with_rates
from verify.numbers.backends import RationalBackend
from verify.numbers.linalg import dot, matvec
from verify.records.results import case_record

RULES = (*CORE_RULES[1:], CORE_RULES[0])  # the core's rules in the suite's order: the general rule last
FAMILIES = ("general", "cradle", "corner")
MAX_ITERATIONS = 200  #: the cap of impulses in a drawn case record (a property may raise it: :func:`capped`)

_Q = RationalBackend("python")  # plain Fractions: what the strategies draw and give
#: the fastest installed rationals, for the linear algebra of a draw (its results are given back as Fractions:
#: the same numbers, exactly; a draw is solved thousands of times in a verdict table's searches)
_F = RationalBackend("auto")


@dataclass(frozen=True)
class Drawn:
    """A drawn case: the case record (strings), its family and its rule."""

    family: str
    rule: str
    record: dict[str, Any]

    def values(self, key: str) -> Any:
        """A field of the record as Fractions (every strategy draws rationals)."""
        return fractions(self.record[key])


@cache
def small_rationals(max_denominator: int = 4, bound: int = 3) -> st.SearchStrategy[Fraction]:
    """Rationals p/q with |p/q| <= bound and q <= max_denominator (shrinking to 0, then to integers).

    Built from two integers rather than ``st.fractions``: several times faster to draw.
    """
    return st.builds(
        lambda p, q: min(max(Fraction(p, q), Fraction(-bound)), Fraction(bound)),
        st.integers(-bound * max_denominator, bound * max_denominator),
        st.integers(1, max_denominator),
    )


@cache
def positive_rationals(max_denominator: int = 4, bound: int = 3) -> st.SearchStrategy[Fraction]:
    """Rationals p/q in [1/max_denominator, bound] with q <= max_denominator (shrinking to 1)."""
    return st.builds(
        lambda p, q: min(Fraction(p, q), Fraction(bound)),
        st.integers(1, bound * max_denominator),
        st.integers(1, max_denominator),
    )


@cache
def cors(max_denominator: int = 10) -> st.SearchStrategy[Fraction]:
    """Coefficients of restitution in [0, 1]; 0 and 1 come often (shrinking to 0)."""
    return st.one_of(
        st.just(Fraction(0)),
        st.just(Fraction(1)),
        st.builds(
            lambda p, q: Fraction(min(p, q), q), st.integers(0, max_denominator), st.integers(1, max_denominator)
        ),
    )


_SIGNS = st.sampled_from([Fraction(1), Fraction(-1), Fraction(2), Fraction(-2)])
_ROLES = st.sampled_from(["hit", "graze", "free"])


@st.composite
def spd_matrices(draw: Any, n: int) -> list[list[Fraction]]:
    """Symmetric positive definite n x n matrices ``L L^T``."""
    L = [[Fraction(0)] * n for _ in range(n)]
    for i in range(n):
        L[i][i] = draw(positive_rationals(3, 2))
        for j in range(i):
            L[i][j] = draw(small_rationals(2, 1))
    return _times_transpose(L)


def _times_transpose(L: list[list[Fraction]]) -> list[list[Fraction]]:
    """``L L^T``, exactly: over integers (L scaled by the least common denominator D), then over D^2.

    >>> _times_transpose([[Fraction(1, 2), Fraction(0)], [Fraction(1, 3), Fraction(2)]])
    [[Fraction(1, 4), Fraction(1, 6)], [Fraction(1, 6), Fraction(37, 9)]]
    """
    n = len(L)
    D = math.lcm(*(x.denominator for row in L for x in row))
    M = [[x.numerator * (D // x.denominator) for x in row] for row in L]
    return [[Fraction(sum(M[i][k] * M[j][k] for k in range(n)), D * D) for j in range(n)] for i in range(n)]


@st.composite
def independent_normals(draw: Any, g: list[list[Fraction]], r: int, orthogonal: bool) -> list[list[Fraction]]:
    """r independent covectors in R^n (r <= n); Phi-orthogonal ones if ``orthogonal``."""
    n = len(g)
    pivots = sorted(draw(st.permutations(range(n)))[:r])
    rows: list[list[Fraction]] = []
    for i in range(r):
        row = []
        for col in range(n):
            if col == pivots[i]:
                row.append(draw(_SIGNS))
            elif col in pivots:
                row.append(Fraction(0))
            else:
                row.append(draw(small_rationals(2, 2)))
        rows.append(row)
    if orthogonal:  # Gram-Schmidt for <a, b> = a g^-1 b^T: keeps independence
        U: list[tuple[Any, ...]] = []
        done = [_F.convert_all(row) for row in rows]
        for i in range(r):
            for k in range(i):
                u_k = U[k]
                c = dot(_F, done[i], u_k) / dot(_F, done[k], u_k)
                done[i] = [x - c * y for x, y in zip(done[i], done[k])]
            U.append(metric_inverse_apply(g, done[i]))
        rows = [[_F.to_number(x) for x in row] for row in done]
    return rows


def _restitution(draw: Any, r: int, rule: str) -> list[Fraction]:
    if rule == "ideal":
        return [Fraction(1)] * r
    if rule == "symmetric":
        return [draw(cors())] * r
    return [draw(cors()) for _ in range(r)]


@st.composite
def incoming_velocities(
    draw: Any, g: list[list[Fraction]], normals: list[list[Fraction]], time_terms: list[Fraction]
) -> list[Fraction]:
    """A velocity that hits one or several constraints, maybe grazing others.

    A free part w, then ``v = w + sum_k c_k U_k`` (``U_k = g^-1 a_k``) with the c_k
    solved so that the rates ``p(F_j)`` take drawn values on a chosen set: negative on
    the hit constraints (at least one), 0 on the grazed ones.
    """
    n, r = len(g), len(normals)
    w = [draw(small_rationals(3, 3)) for _ in range(n)]
    roles = [draw(_ROLES) for _ in range(r)]
    if "hit" not in roles:
        roles[draw(st.integers(0, r - 1))] = "hit"
    chosen = [j for j in range(r) if roles[j] != "free"]
    targets = {j: -draw(positive_rationals(3, 3)) if roles[j] == "hit" else Fraction(0) for j in chosen}
    return velocity_with_rates((g, normals, time_terms), w, targets)


@st.composite
def general_cases(draw: Any, rule: str = "general") -> Drawn:
    """A general system: r = 1..4 constraints in n = r+1..6 coordinates (r = 2 for rule (7))."""
    r = 2 if rule == "asymmetric" else draw(st.integers(1, 4))
    n = draw(st.integers(max(2, r + 1), 6))
    g = draw(spd_matrices(n))
    normals = draw(independent_normals(g, r, draw(st.booleans())))
    moving = draw(st.booleans())
    time_terms = [draw(small_rationals(2, 2)) if moving else Fraction(0) for _ in range(r)]
    eps = _restitution(draw, r, rule)
    v = draw(incoming_velocities(g, normals, time_terms))
    return make_drawn("general", rule, (g, normals, time_terms, eps), v)


@st.composite
def cradle_cases(draw: Any, rule: str = "general") -> Drawn:
    """Newton's cradle: N = 2..5 balls of rational masses, contacts S_(i,i+1) (N = 3 for rule (7))."""
    balls = 3 if rule == "asymmetric" else draw(st.integers(2, 5))
    masses = [draw(positive_rationals(3, 3)) for _ in range(balls)]
    g, normals = cradle_geometry(masses)
    time_terms = [Fraction(0)] * (balls - 1)
    eps = _restitution(draw, balls - 1, rule)
    v = draw(incoming_velocities(g, normals, time_terms))
    return make_drawn("cradle", rule, (g, normals, time_terms, eps), v)


@st.composite
def corner_cases(draw: Any, rule: str = "general") -> Drawn:
    """The disk in a corner (Sect. 4.2): walls ``kx - y = 0``, ``kx + y = 0``, rational k > 0."""
    k = draw(st.one_of(st.just(Fraction(1)), positive_rationals(6, 6)))  # k = 1: a right angle, orthogonal walls
    g, normals = corner_geometry(k)
    time_terms = [Fraction(0)] * 2
    eps = _restitution(draw, 2, rule)
    v = draw(incoming_velocities(g, normals, time_terms))
    return make_drawn("corner", rule, (g, normals, time_terms, eps), v)


_FAMILIES = {"general": general_cases, "cradle": cradle_cases, "corner": corner_cases}


def cases(family: str, rule: str) -> st.SearchStrategy[Drawn]:
    """The strategy for a family (``general``, ``cradle``, ``corner``) and a rule."""
    if family not in _FAMILIES or rule not in RULES:
        raise ValueError(f"unknown family or rule: {family!r}, {rule!r}")
    return _FAMILIES[family](rule)


def make_drawn(family: str, rule: str, inputs: tuple[Any, ...], v: Any) -> Drawn:
    """Package exact inputs ``(g, normals, time_terms, restitution)`` and a velocity as a
    :class:`Drawn` (the record holds exact strings)."""
    g, normals, time_terms, eps = inputs
    record = case_record(f"{family}-{rule}", g, normals, eps, v, time_terms=time_terms, max_iterations=MAX_ITERATIONS)
    return Drawn(family, rule, record)


def capped(strategy: st.SearchStrategy[Drawn], max_iterations: int) -> st.SearchStrategy[Drawn]:
    """The same cases with another cap of impulses in their records (the draws, and so the cases and
    their shrinking, are unchanged).

    >>> from hypothesis import find
    >>> find(capped(cases("corner", "ideal"), 1000), lambda d: True).record["max_iterations"]
    1000
    """
    return strategy.map(lambda d: Drawn(d.family, d.rule, dict(d.record, max_iterations=max_iterations)))


def rates(d: Drawn, v: list[Fraction] | None = None) -> list[Fraction]:
    """The rates ``p(F_i) = dF_i/dt + dF_i . v`` of a drawn case (default: its velocity)."""
    v = d.values("velocity") if v is None else v
    a = d.values("normals")
    return [t + x for t, x in zip(d.values("time_terms"), matvec(_Q, a, v))]
