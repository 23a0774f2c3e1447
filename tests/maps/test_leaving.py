"""Every eps above a boundary exits (verify.maps.leaving, ``--leaving``), checked without the code that proves it:
the test's own period matrix has every eigenvalue of modulus eps there, runs of the rule on certified intervals
from points of the proved parts exit (after more impulses than the map's bound), and what stays undecided above
the boundary is a gap below 1e-6."""

from __future__ import annotations

from fractions import Fraction as F

import pytest
import sympy as sp

from tests.maps.test_boundary import E, _period
from verify.maps.cradle import cradle_map
from verify.maps.line import undecided_length
from verify.models.cradle import run_cradle
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends import get_backend

LAM = sp.Symbol("lam")
CASES = {
    # masses, the interval mapped (the boundary and the first part above it), the boundary
    "four unit balls": ([1, 1, 1, 1], ("0.1715", "0.1729"), 3 - 2 * sp.sqrt(2)),
    "masses 2, 1, 1, 2": ([2, 1, 1, 2], ("0.2679", "0.2681"), 2 - sp.sqrt(3)),
}


@pytest.mark.parametrize("system", list(CASES))
def test_above_the_boundary_every_eigenvalue_of_the_period_has_modulus_eps(system) -> None:
    """The premise of the proof, from the test's own period (S1,S3)(S2): its characteristic polynomial is
    (lam + eps) q(lam) with q(0) = eps^2 (times q's leading coefficient), and q's roots are not real above the
    boundary, so all three have modulus eps there."""
    masses, _, star = CASES[system]
    M = _period(masses, [[0, 2], [1]])
    p = sp.Poly(M.charpoly(LAM).as_expr(), LAM)
    q, r = sp.div(p, sp.Poly(LAM + E, LAM))
    assert r.is_zero and q.degree() == 2
    a2, a1, a0 = q.all_coeffs()
    assert sp.simplify(a0 / a2 - E**2) == 0
    disc = sp.factor(a1**2 - 4 * a2 * a0)
    for above in (star + sp.Rational(1, 10**6), star + sp.Rational(1, 100)):
        assert disc.subs(E, above) < 0
    assert disc.subs(E, star - sp.Rational(1, 10**6)) > 0


def _map(system: str, leaving: bool | None = None):
    """The map of ``system`` over its interval; by default the proof of exits is tried where nothing else decides
    (``leaving=None``, as ``verify cradle-map`` does by default)."""
    masses, (lower, upper), _ = CASES[system]
    return cradle_map(masses=[str(m) for m in masses], velocity=["1", "0", "0", "0"], lower=lower, upper=upper,
                      max_impulses=40, widen=0, leaving=leaving)  # fmt: skip


@pytest.mark.slow(seconds=44)
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
    without = undecided_length(_map(system, leaving=False).parts)[0]
    assert without > F(1, 10**4) > high, "the default decides what the map without the proof leaves undecided"
    # the conclusion, from runs of the rule itself: each proved part's middle exits, after more than the bound
    for p in proved:
        lo, hi = p.piece.lower.narrowed(F(1, 10**12))[1], p.piece.upper.narrowed(F(1, 10**12))[0]
        eps = lo + (hi - lo) / 2
        r = run_cradle(eps, v0="1", balls=len(masses), masses=[str(x) for x in masses], trace=False,
                       max_iterations=20000,
                       backend=get_backend("interval", dps=40))  # fmt: skip
        assert r.stop == "exit" and r.iterations > 40


def _rates_to_velocity(masses: list[int], z: sp.Matrix) -> list[sp.Expr]:
    """A velocity of the chain of balls whose normal rates are z (v = M^-1 N^T G^-1 z)."""
    n = len(masses)
    N = sp.Matrix(n - 1, n, lambda i, k: -1 if k == i else 1 if k == i + 1 else 0)
    Minv = sp.diag(*[sp.Rational(1, m) for m in masses])
    return list(Minv * N.T * (N * Minv * N.T).inv() * z)


@pytest.mark.parametrize("system", list(CASES))
def test_from_points_of_the_ellipses_the_run_exits_where_it_leaves_the_period(system) -> None:
    """Fact 2 of the proof at rational points, with the test's own algebra: at a rational eps above the boundary,
    the rates (S1,S3)(S2) starts from, scaled by eps per period, lie on the ellipses Q(w) = Q(w_0) +- c u of the
    test's own period matrix; from points of them (rational slopes t) a run that follows one period then exits
    within one impulse or follows it again. And the ellipses are what the runs' rates do lie on."""
    from verify.dynamics.system import System
    from verify.laws.rule import solve

    masses, (lower, upper), _ = CASES[system]
    sets = [[0, 2], [1]]
    n = len(masses)
    normals = [["-1" if k == i else "1" if k == i + 1 else "0" for k in range(n)] for i in range(n - 1)]
    mass = [[str(masses[i]) if i == k else "0" for k in range(n)] for i in range(n)]
    for eps in (F(lower) + (F(upper) - F(lower)) / 3, F(upper)):
        e = sp.Rational(eps.numerator, eps.denominator)
        M = _period(masses, sets).subs(E, e)
        system_ = System(mass, normals, [str(eps)] * (n - 1))
        start = solve(system_, ["1"] + ["0"] * (n - 1), max_iterations=2, trace=False)
        assert [list(J) for J in start.impact_sets] == [[0], [1]]  # the period starts after (S1)(S2)
        x0 = sp.Matrix([sp.Rational(str(r)) for r in system_.rates(start.exit_velocity)])
        # W: the plane of the non-real pair, the kernel of q(M), q the characteristic polynomial over (lam + e)
        p = sp.Poly(M.charpoly(LAM).as_expr(), LAM)
        q = sp.div(p, sp.Poly(LAM + e, LAM))[0]
        a2, a1, a0 = q.all_coeffs()
        W = sp.Matrix.hstack(*(a2 * M * M + a1 * M + a0 * sp.eye(n - 1)).nullspace())
        u = (M + e * sp.eye(n - 1)).nullspace()[0]
        coords = sp.Matrix.hstack(W, u).solve(x0)
        A = (W.pinv() * M * W) / e
        h = (A[1, 1] - A[0, 0]) / 2
        Q = sp.Matrix([[A[1, 0], h], [h, -A[0, 1]]])
        assert sp.simplify(A.T * Q * A - Q) == sp.zeros(2, 2) and Q.det() > 0
        w0, c = sp.Matrix(coords[:2]), coords[2]
        # the run's own rates after k periods, scaled by e^k, lie on the ellipses
        x = x0
        for k in range(1, 4):
            x = M * x
            wk = sp.Matrix.hstack(W, u).solve(x / e**k)
            assert (sp.Matrix(wk[:2]).T * Q * sp.Matrix(wk[:2]))[0] == (w0.T * Q * w0)[0]
            assert wk[2] == (-1) ** k * c
        seen = {"leaves": 0, "follows": 0}
        for t in [sp.Rational(k, 8) for k in range(-8, 9)]:
            for d in (sp.Matrix([1, t]), sp.Matrix([t, 1])):
                w = w0 - 2 * (w0.T * Q * d)[0] / (d.T * Q * d)[0] * d
                for sign in (1, -1):
                    z = W * w + sign * c * u
                    r = solve(system_, _rates_to_velocity(masses, z), max_iterations=4, trace=False, certify=False)
                    runs = [list(J) for J in r.impact_sets]
                    if runs[:2] != sets:
                        continue
                    assert (r.stop == "exit" and len(runs) <= 3) or runs[2:4] == sets
                    seen["follows" if runs[2:4] == sets else "leaves"] += 1
        assert seen["leaves"] and seen["follows"], seen  # both branches of fact 2 are met


@pytest.mark.parametrize(("flags", "leaving"), [([], None), (["--leaving"], True), (["--no-leaving"], False)])
def test_the_command_tries_the_proof_where_the_map_leaves_parts_undecided(monkeypatch, flags, leaving) -> None:
    """``verify cradle-map`` by default tries the proof of exits on what the map leaves undecided (``leaving=None``,
    tested above); ``--leaving`` everywhere, ``--no-leaving`` nowhere."""
    import verify.maps.cradle
    from verify.cli import main
    from verify.errors import InvalidInput

    seen = []

    def record(*args, **kwargs):
        seen.append(kwargs["leaving"])
        raise InvalidInput("stopped here")  # nothing to compute: the command's choice is what is tested

    monkeypatch.setattr(verify.maps.cradle, "cradle_map", record)
    assert main(["cradle-map", "--balls", "4", *flags]) == 2
    assert seen == [leaving]
