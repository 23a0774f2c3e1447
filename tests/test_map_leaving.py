"""Every eps above a boundary exits (verify.maps.leaving, ``--leaving``), checked without the code that proves it:
the test's own period matrix has every eigenvalue of modulus eps there, runs of the rule on certified intervals
from points of the proved parts exit (after more impulses than the map's bound), and what stays undecided above
the boundary is a gap below 1e-6."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
import sympy as sp

from tests.test_map_boundary import E, _period
from verify.core.algebraic import RealAlgebraic
from verify.core.backends import get_backend
from verify.maps.cradle import cradle_map
from verify.maps.line import undecided_length
from verify.models.cradle import run_cradle

LAM = sp.Symbol("lam")
CASES = {
    # masses, the interval mapped (the boundary and the first part above it), the boundary
    "four unit balls": ([1, 1, 1, 1], ("0.1715", "0.1729"), 3 - 2 * sp.sqrt(2)),
    "masses 2, 1, 1, 2": ([2, 1, 1, 2], ("0.2679", "0.2681"), 2 - sp.sqrt(3)),
}


@pytest.mark.parametrize("masses", [[1, 1, 1, 1], [2, 1, 1, 2]])
def test_above_the_boundary_every_eigenvalue_of_the_period_has_modulus_eps(masses) -> None:
    """The premise of the proof, from the test's own period (S1,S3)(S2): its characteristic polynomial is
    (lam + eps) q(lam) with q(0) = eps^2 (times q's leading coefficient), and q's roots are not real above the
    boundary, so all three have modulus eps there."""
    M = _period(masses, [[0, 2], [1]])
    p = sp.Poly(M.charpoly(LAM).as_expr(), LAM)
    q, r = sp.div(p, sp.Poly(LAM + E, LAM))
    assert r.is_zero and q.degree() == 2
    a2, a1, a0 = q.all_coeffs()
    assert sp.simplify(a0 / a2 - E**2) == 0
    disc = sp.factor(a1**2 - 4 * a2 * a0)
    star = {"1111": 3 - 2 * sp.sqrt(2), "2112": 2 - sp.sqrt(3)}["".join(map(str, masses))]
    for above in (star + sp.Rational(1, 10**6), star + sp.Rational(1, 100)):
        assert disc.subs(E, above) < 0
    assert disc.subs(E, star - sp.Rational(1, 10**6)) > 0


def _map(system: str):
    masses, (lower, upper), _ = CASES[system]
    return cradle_map(masses=[str(m) for m in masses], velocity=["1", "0", "0", "0"], lower=lower, upper=upper,
                      max_impulses=40, widen=0, leaving=True)  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize("system", list(CASES))
def test_every_eps_above_the_boundary_exits_but_a_gap_below_1e_minus_9(system) -> None:
    masses, _, star = CASES[system]
    m = _map(system)
    proved = [p for p in m.unexplored if p.exits_beyond_bound]
    assert proved and all(p.certificate["kind"] == "leaves and exits" for p in proved)
    boundary = RealAlgebraic.from_number(star)
    assert all(p.piece.lower.cmp(boundary) > 0 for p in proved)
    high = undecided_length(m.parts)[1]
    assert high < F(1, 10**6)
    # the conclusion, from runs of the rule itself: each proved part's middle exits, after more than the bound
    for p in proved:
        lo, hi = p.piece.lower.narrowed(F(1, 10**12))[1], p.piece.upper.narrowed(F(1, 10**12))[0]
        eps = lo + (hi - lo) / 2
        r = run_cradle(eps, v0="1", balls=len(masses), masses=[str(x) for x in masses], trace=False,
                       max_iterations=20000,
                       backend=get_backend("interval", dps=40))  # fmt: skip
        assert r.stop == "exit" and r.iterations > 40
