"""The boundary of never-exits (verify.maps.boundary): found from the pattern's own period, checked without it."""

from __future__ import annotations

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from tests import certificate_check
from verify.maps.boundary import collisions, pattern_map, pattern_of
from verify.maps.cradle import cradle_map
from verify.maps.general import case_map
from verify.models.cradle import cradle_system
from verify.numbers.backends.symbolic import EPS, Piece, RootCache, SymbolicBackend

E = sp.Symbol("e")


def _period(masses: list[int], sets: list[list[int]]) -> sp.Matrix:
    """The test's own period matrix on the rates of a chain of balls: impulses on sets of contacts that do not
    touch the same ball, each b -> b - (1 + e) (b_j / G_jj) G[:, j] (Newton's law on one contact)."""
    n = len(masses)
    N = sp.Matrix(n - 1, n, lambda i, k: -1 if k == i else 1 if k == i + 1 else 0)
    G = N * sp.diag(*[sp.Rational(1, m) for m in masses]) * N.T
    M = sp.eye(n - 1)
    for J in sets:
        A = sp.eye(n - 1)
        for j in J:
            A[:, j] -= (1 + E) / G[j, j] * G[:, j]
        M = A * M
    return M


@pytest.mark.parametrize(
    ("masses", "sets"),
    [([1, 1, 1], [[0], [1]]), ([1, 1, 1, 1], [[0, 2], [1]]), ([2, 1, 1, 2], [[0, 2], [1]])],
)
def test_the_boundary_is_where_the_periods_largest_eigenvalues_meet(masses, sets) -> None:
    K = SymbolicBackend(Piece.closed(0, 1), RootCache())
    system = cradle_system(EPS, len(masses), [str(m) for m in masses], backend=K)
    found = collisions(pattern_map(system, [tuple(J) for J in sets]), Piece.closed(0, 1), RootCache())
    assert len(found) == 1
    star = found[0][0].expr
    M = _period(masses, sets)
    lam = sp.Symbol("lam")
    at = sp.Poly(M.subs(E, star).charpoly(lam).as_expr(), lam)
    # a double eigenvalue at eps*, the largest in modulus
    double = [r for r, m in sp.roots(at).items() if m == 2]
    assert len(double) == 1
    assert all(sp.Abs(r) <= sp.Abs(double[0]) for r in sp.roots(at))
    # all real just below; just above, a non-real pair of the largest modulus
    for shift, real in ((-sp.Rational(1, 10**6), True), (sp.Rational(1, 10**6), False)):
        roots = sp.Poly(M.subs(E, sp.nsimplify(star + shift)).charpoly(lam).as_expr(), lam).nroots(n=40)
        nonreal = [r for r in roots if abs(sp.im(r)) > 1e-30]
        assert (not nonreal) == real
        if nonreal:
            assert max(abs(r) for r in nonreal) > max(abs(r) for r in roots) - 1e-30


def test_a_pattern_is_the_shortest_period_the_impacts_repeat() -> None:
    assert pattern_of([(0,), (1,), (0, 2), (1,), (0, 2), (1,), (0, 2)]).sets == ((1,), (0, 2))
    assert pattern_of([(0,), (1,), (0,), (2,)]) is None


NORMALS4 = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]


def _check_boundary_parts(parts, masses: list[str], restitution: list[str], star: str) -> int:
    """Every part whose certificate reaches the boundary, checked by the independent checker on its whole
    interval (or at its point); the number checked."""
    checked = 0
    for part in parts:
        cert = part.certificate or {}
        if "boundary" not in cert:
            continue
        assert cert["boundary"]["eps"] == star
        piece = part.piece
        if piece.is_point:
            assert str(piece.lower) == star
            at = [str(sp.sympify(x).subs(sp.Symbol("eps"), sp.sympify(star))) for x in restitution]
            assert certificate_check.check_period(cert, masses, NORMALS4, restitution=at) == []
        else:
            interval = (str(piece.lower), str(piece.upper))
            assert certificate_check.check_period(
                cert, masses, NORMALS4, interval=interval, closed=(piece.lower_closed, piece.upper_closed),
                restitution=restitution,
            ) == []  # fmt: skip
        checked += 1
    return checked


def test_four_balls_never_exit_up_to_and_at_3_minus_2_sqrt_2() -> None:
    m = cradle_map(balls=4, lower="0.16", upper="0.175", max_impulses=16, widen=0)
    star = "3 - 2*sqrt(2)"
    assert _check_boundary_parts(m.parts, ["1"] * 4, ["eps"] * 3, star) >= 2
    # the same certificates do not hold past the boundary (the checker is not blind to it)
    cone = next(p for p in m.non_terminating if "boundary" in p.certificate and not p.piece.is_point)
    beyond = (str(cone.piece.lower), "43/250")
    assert certificate_check.check_period(cone.certificate, ["1"] * 4, NORMALS4, interval=beyond,
                                          restitution=["eps"] * 3) != []  # fmt: skip
    point = m.locate(_algebraic(certificate_check.read(star)))
    assert point.stop == "non_terminating" and point.piece.is_point
    # everything below it in the range is decided never to exit; above it, what is left names the boundary
    below = [p for p in m.parts if p.piece.upper.cmp(point.piece.lower) <= 0]
    assert below and all(p.stop == "non_terminating" for p in below)
    above = m.unexplored
    assert above and all(f"boundary eps = {star}" in p.reason for p in above)


def test_the_masses_2_1_1_2_never_exit_up_to_and_at_2_minus_sqrt_3(tmp_path) -> None:
    path = tmp_path / "case.json"
    path.write_text(
        '{"cases": [{"id": "balls-2112", "mass_matrix": [["2","0","0","0"],["0","1","0","0"],["0","0","1","0"],'
        '["0","0","0","2"]], "normals": [["-1","1","0","0"],["0","-1","1","0"],["0","0","-1","1"]], '
        '"restitution": ["eps","eps","eps"], "velocity": ["1","0","0","0"]}]}'
    )
    m = case_map(str(path), None, {"eps": ("0.25", "0.275")}, max_impulses=16, widen=0)
    parts = m.lines[0].parts
    assert _check_boundary_parts(parts, ["2", "1", "1", "2"], ["eps"] * 3, "2 - sqrt(3)") >= 2
    star = certificate_check.read("2 - sqrt(3)")
    assert all(p.stop == "non_terminating" for p in parts if p.piece.upper.cmp(_algebraic(star)) <= 0)


def _algebraic(x):
    from verify.numbers.algebraic import RealAlgebraic

    return RealAlgebraic.from_number(x)


def test_a_boundary_cone_is_not_claimed_where_the_pattern_is_not_linear() -> None:
    K = SymbolicBackend(Piece.closed(0, 1), RootCache())
    system = cradle_system(EPS, 4, backend=K)
    assert pattern_map(system, [(0, 1)]) is None  # contacts 1 and 2 share a ball: beta depends on the rates
    assert pattern_map(system, [(0, 2)]) is not None


def test_above_the_boundary_no_cone_is_mapped_into_itself() -> None:
    """The claim the map prints above eps*: the period's largest eigenvalues are not real and none of its real
    eigenvalues is positive (so its spectral radius is not an eigenvalue); checked here at rational points with
    the test's own period matrix, and refused below eps*."""
    from verify.maps.boundary import without_real_top
    from verify.numbers.algebraic import RealAlgebraic

    cache = RootCache()
    K = SymbolicBackend(Piece.closed(0, 1), cache)
    M = pattern_map(cradle_system(EPS, 4, backend=K), [(0, 2), (1,)])
    ((star, q),) = collisions(M, Piece.closed(0, 1), cache)
    above = Piece(star, RealAlgebraic.rational(sp.Rational(7, 40)), False, True)
    assert without_real_top(M, q, above, cache)
    assert not without_real_top(M, q, Piece.closed("0.16", "0.17"), cache)
    lam = sp.Symbol("lam")
    for eps in (sp.Rational(1716, 10**4), sp.Rational(172, 1000), sp.Rational(7, 40)):
        poly = sp.Poly(_period([1, 1, 1, 1], [[0, 2], [1]]).subs(E, eps).charpoly(lam).as_expr(), lam)
        real = sp.real_roots(poly)
        assert len(real) < poly.degree() and all(r < 0 for r in real)


@given(
    st.fractions(min_value=-100, max_value=100, max_denominator=10**6),
    st.fractions(min_value=-100, max_value=100, max_denominator=10**6),
    st.sampled_from([2, 3, 5, 6]),
)
def test_the_checkers_sign_of_a_quadratic_irrational_is_exact(a, b, d) -> None:
    from tests.certificate_check import _Quadratic

    x = sp.Rational(a.numerator, a.denominator) + sp.Rational(b.numerator, b.denominator) * sp.sqrt(d)
    expected = 0 if a == b == 0 else int(sp.sign(sp.N(x, 200)))  # a + b sqrt(d) is 0 only when a = b = 0
    assert _Quadratic(x).sign() == expected


NORMALS5 = [["-1" if j == i else "1" if j == i + 1 else "0" for j in range(5)] for i in range(4)]


def test_five_balls_boundary_is_over_q_sqrt_5_where_the_periods_largest_eigenvalues_meet() -> None:
    """The period (S1,S3)(S2,S4) of five unit balls: its quartic factor splits over Q(sqrt(5))(eps) only, and
    its boundary is where the test's own period matrix has a double eigenvalue of modulus eps, beside a complex
    pair of the same modulus (so no polyhedral cone reaches it, and the map's cones stop short of it)."""
    from verify.maps.turning import extension, field_collisions

    K = SymbolicBackend(Piece.closed(0, 1), RootCache())
    M = pattern_map(cradle_system(EPS, 5, backend=K), [(0, 2), (1, 3)])
    assert collisions(M, Piece.closed(0, 1), RootCache()) == []  # nothing over Q(eps)
    assert extension(M) == sp.sqrt(5)
    found = field_collisions(M, sp.sqrt(5), Piece.closed(0, 1))
    assert len(found) == 1
    star = found[0][0]
    # eps* is the root of eps^2 - (22 - 8 sqrt(5)) eps + 1 in (0, 1)
    expected = 11 - 4 * sp.sqrt(5) - sp.sqrt((11 - 4 * sp.sqrt(5)) ** 2 - 1)
    assert abs(sp.N(star.expr - expected, 50)) < sp.Float("1e-45")
    lam = sp.Symbol("lam")
    P = _period([1] * 5, [[0, 2], [1, 3]])
    for shift in (-sp.Rational(1, 10**6), sp.Rational(1, 10**6)):
        at = sp.nsimplify(sp.N(expected, 60) + shift, rational=True)
        roots = sp.Poly(P.subs(E, at).charpoly(lam).as_expr(), lam).nroots(n=40)
        top = max(abs(r) for r in roots)
        if shift < 0:  # below: one real eigenvalue larger than every other modulus
            largest = [r for r in roots if abs(r) > top - sp.Float("1e-30")]
            assert len(largest) == 1 and abs(sp.im(largest[0])) < 1e-30
        else:  # above: none is real, all of modulus eps
            assert all(abs(sp.im(r)) > 1e-30 and abs(abs(r) - at) < 1e-25 for r in roots)
    at = sp.N(expected, 80)
    roots = sp.Poly(P.subs(E, at).charpoly(lam).as_expr(), lam).nroots(n=40, maxsteps=1000)
    assert all(abs(abs(r) - at) < 1e-15 for r in roots)  # at eps*: all four of modulus eps* (a double root)


_X = sp.Symbol("x")
STAR5 = sp.CRootOf(_X**4 - 44 * _X**3 + 166 * _X**2 - 44 * _X + 1, 1)  #: the boundary of five unit balls


@pytest.mark.slow(seconds=14)
def test_five_balls_never_exit_up_to_and_at_their_boundary() -> None:
    """Five unit balls on [1/4, 0.26]: the map proves that every eps up to and with eps* (the boundary of
    (S1,S3)(S2,S4), where the period's largest eigenvalues meet beside a turning pair) never exits, with one
    "dominant growth" certificate (verify.maps.growth), which the tests' checker confirms on the whole closed interval
    from the masses and normals; its rates are the test's own impulses from the velocity. Above eps* nothing is
    proved never to exit. A certificate that is wrong fails the checker: stretched above eps* (where the
    eigenvalues on W turn complex), or with the rates turned around."""
    m = cradle_map(balls=5, lower="1/4", upper="0.26", max_impulses=12)
    grown = [p for p in m.non_terminating if (p.certificate or {}).get("kind") == "dominant growth"]
    assert len(grown) == 1
    part, cert = grown[0], grown[0].certificate
    assert str(part.piece.upper.expr) == str(STAR5) and part.piece.upper_closed
    assert cert["boundary"]["reached"] is True and cert["boundary"]["eps"] == str(STAR5)
    assert all(p.piece.lower.cmp(part.piece.upper) >= 0 for p in m.unexplored)  # all below eps* is decided
    # the rates: the test's own impulses (singles and pairs on contacts that share no ball) from ball 1 at speed 1
    G = certificate_check.gram([1] * 5, [[certificate_check.read(x) for x in row] for row in NORMALS5])
    b = [sp.Integer(-1), sp.Integer(0), sp.Integer(0), sp.Integer(0)]
    for J in part.impact_sets:
        b = certificate_check._step(G, [EPS] * 4, list(J), b)
    assert [sp.cancel(x - certificate_check.read(y)) for x, y in zip(b, cert["rates"])] == [0] * 4
    lo = sp.Rational(part.piece.lower.lo) if part.piece.lower.is_rational else None
    assert lo is not None
    masses = ["1"] * 5
    assert certificate_check.check_growth(cert, masses, NORMALS5, interval=(lo, STAR5)) == []
    assert certificate_check.check_growth(cert, masses, NORMALS5, interval=(lo, sp.Rational(2597, 10000))) != []
    turned = dict(cert, rates=[str(-certificate_check.read(x)) for x in cert["rates"]])
    assert certificate_check.check_growth(turned, masses, NORMALS5, interval=(lo, STAR5)) != []


@given(
    st.lists(st.integers(-20, 20), min_size=1, max_size=4),
    st.lists(st.integers(-20, 20), min_size=1, max_size=4),
    st.lists(st.integers(-20, 20), min_size=1, max_size=3),
    st.sampled_from([2, 3, 5]),
)
def test_the_growth_arguments_signs_over_a_quadratic_field_are_exact(a, b, c, d) -> None:
    """verify.maps.growth decides the sign of (a + sqrt(d) b)/c on [-2, 2] (a, b, c polynomials with integer
    coefficients) part by part, cut at the real roots of the norms; each part's sign is the sign of the function at
    that part's points, compared here with a 60-digit evaluation at its ends' neighbourhood (strictly inside an
    interval part, at a point part itself), and a root of c is a pole (None)."""
    from verify.maps.growth import signs_on
    from verify.numbers.algebraic import RealAlgebraic

    root = sp.sqrt(d)
    poly = lambda cs: sum((k * EPS**i for i, k in enumerate(cs)), sp.Integer(0))  # noqa: E731
    expr = (poly(a) + root * poly(b)) / poly(c)
    D = sp.QQ.algebraic_field(root).frac_field(EPS)
    if poly(c) == 0:
        return
    x = D.from_sympy(sp.together(expr))
    found = signs_on(x, Piece.closed(-2, 2))
    reduced = D.to_sympy(x)  # in lowest terms: no 0/0 at a common root of a + sqrt(d) b and c
    denominator = sp.Poly(poly(c), EPS)
    c_roots = [t for t in sp.real_roots(denominator) if -2 <= t <= 2] if denominator.degree() > 0 else []
    if found is None:
        assert c_roots, "a pole was reported where the denominator has no root"
        return
    for part, sign in found:
        at = part.lower if part.is_point else RealAlgebraic.rational(part.sample())
        value = sp.N(reduced.subs(EPS, at.expr), 60)
        if sign == 0:
            assert abs(value) < sp.Float("1e-40")
        else:
            assert value * sign > 0
