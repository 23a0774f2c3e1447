"""The geometry of Sect. 2.3 and 3.2 against hand-worked values.

Systems: the three-ball cradle (unit masses, normals e2 - e1 and e3 - e2) and a disk in a
corner with rational slope k = 1/2 (walls F1 = y - kx >= 0, F2 = -kx - y >= 0, unit mass,
coordinates x, y, theta), whose V_1, V_2, V_12 and beta the paper gives in closed form
(Sect. 4.2).
"""

from __future__ import annotations

from fractions import Fraction as F

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.helpers import assert_exact, assert_exact_vector
from verify.dynamics.system import System
from verify.laws.rule import beta, global_orthogonal_component, impulse, orthogonal_component

CRADLE = System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 1, 0], [0, -1, 1]], [1, 1])
K_SLOPE = F(1, 2)


def corner(k=K_SLOPE, eps=(1, 1)):
    return System([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-k, 1, 0], [-k, -1, 0]], list(eps))


def test_cradle_orthogonal_components_by_hand():
    K = CRADLE.backend
    v = CRADLE.velocity(["100", "0", "0"])
    assert_exact_vector([50, -50, 0], K, orthogonal_component(CRADLE, v, 0))  # the paper's V_(1,2)
    assert_exact_vector([0, 0, 0], K, orthogonal_component(CRADLE, v, 1))
    # G = [[2, -1], [-1, 2]], rates (-100, 0): mu = G^-1 (-100, 0) = (-200/3, -100/3)
    assert_exact_vector([F(200, 3), F(-100, 3), F(-100, 3)], K, global_orthogonal_component(CRADLE, v, (0, 1)))
    assert_exact(1, K, beta(CRADLE, v, (0, 1)))  # one V_j is zero: beta = 1


def test_cradle_second_step_matches_the_paper():
    # p_L^1 = (1-eps)/2 v0, (1+eps)/2 v0, 0 and V_(2,3)(p_L^1) = (1+eps)/4 v0 (e2 - e3), eps = 1/3
    eps = F(1, 3)
    s = CRADLE.with_restitution([eps, eps])
    K = s.backend
    v1 = s.velocity([(1 - eps) / 2 * 100, (1 + eps) / 2 * 100, 0])
    assert_exact_vector([0, (1 + eps) / 4 * 100, -(1 + eps) / 4 * 100], K, orthogonal_component(s, v1, 1))


def test_cradle_double_hit_beta_by_hand():
    # v = (1, 0, -1): rates (-1, -1), lambda = (-1/2, -1/2), W = (1/2, 0, -1/2), ||W||^2 = 1/2,
    # Phi(V_12, W) = sum rate^2 / G_jj = 1, so beta = 2 and I = -beta (2 V_1 + 2 V_2) = (-2, 0, 2)
    K = CRADLE.backend
    v = CRADLE.velocity(["1", "0", "-1"])
    assert_exact_vector([1, 0, -1], K, global_orthogonal_component(CRADLE, v, (0, 1)))
    assert_exact(2, K, beta(CRADLE, v, (0, 1)))
    assert_exact_vector([-2, 0, 2], K, impulse(CRADLE, v))


def paper_corner(k, xd, yd):
    """Sect. 4.2, in the paper's own closed forms."""
    V1 = [k / (1 + k * k) * (k * xd - yd), -1 / (1 + k * k) * (k * xd - yd), 0]
    V2 = [k / (1 + k * k) * (k * xd + yd), 1 / (1 + k * k) * (k * xd + yd), 0]
    V12 = [xd, yd, 0]
    den = k**4 * xd * xd + yd * yd
    b = (1 + k * k) / 2 * (k * k * xd * xd + yd * yd) / den if den else None
    return V1, V2, V12, b


def test_corner_by_hand():
    # k = 1/2, velocity (1, 0): beta = (5/4)/2 * (1/4)/(1/16) = 5/2
    s = corner()
    K = s.backend
    v = s.velocity(["1", "0", "0"])
    # V_1 = k/(1+k^2) (k xd - yd) dx - 1/(1+k^2) (k xd - yd) dy = (2/5)(1/2) dx - (4/5)(1/2) dy
    assert_exact_vector([F(1, 5), F(-2, 5), 0], K, orthogonal_component(s, v, 0))
    assert_exact_vector([F(1, 5), F(2, 5), 0], K, orthogonal_component(s, v, 1))
    assert_exact_vector([1, 0, 0], K, global_orthogonal_component(s, v, (0, 1)))
    assert_exact(F(5, 2), K, beta(s, v, (0, 1)))


@given(
    st.fractions(min_value=F(1, 20), max_value=20, max_denominator=50),
    st.fractions(min_value=-10, max_value=10, max_denominator=50),
    st.fractions(min_value=-10, max_value=10, max_denominator=50),
    st.fractions(min_value=-5, max_value=5, max_denominator=9),
)
def test_corner_matches_the_papers_closed_forms(k, xd, yd, spin):
    s = corner(k)
    K = s.backend
    v = s.velocity([xd, yd, spin])
    V1, V2, V12, b = paper_corner(k, xd, yd)
    assert_exact_vector(V1, K, orthogonal_component(s, v, 0))
    assert_exact_vector(V2, K, orthogonal_component(s, v, 1))
    assert_exact_vector(V12, K, global_orthogonal_component(s, v, (0, 1)))
    if xd != 0 or yd != 0:
        assert_exact(b, K, beta(s, v, (0, 1)))


# -- Proposition 1 ---------------------------------------------------------------------


def _vec(K, x):
    return [K.to_number(c) for c in x]


@given(
    st.fractions(min_value=-10, max_value=10, max_denominator=30),
    st.fractions(min_value=-10, max_value=10, max_denominator=30),
)
def test_proposition_1_holds_for_orthogonal_constraints(xd, yd):
    # slope k = 1: the walls are orthogonal, Phi(U_1, U_2) = 0
    s = corner(F(1))
    K = s.backend
    v = s.velocity([xd, yd, 0])
    V1, V2 = _vec(K, orthogonal_component(s, v, 0)), _vec(K, orthogonal_component(s, v, 1))
    V12 = _vec(K, global_orthogonal_component(s, v, (0, 1)))
    sums = [a + b for a, b in zip(V1, V2, strict=True)]
    assert sums == V12  # (ii)
    assert (V12 == V1) == all(c == 0 for c in V2)  # (i)
    if any(c != 0 for c in V1) and any(c != 0 for c in V2):
        assert_exact(1, K, beta(s, v, (0, 1)))  # the codimension-2 reflection rule


def test_proposition_1_i_is_refuted_for_non_orthogonal_constraints():
    """Prop. 1 (i) claims V_12 = V_i iff V_j = 0. Both directions fail for the cradle,
    whose normals are not orthogonal (Phi(U_1, U_2) = -1): exact counterexamples."""
    K = CRADLE.backend
    # V_2 = 0 but V_12 != V_1: the cradle's own first impact, v = (100, 0, 0)
    v = CRADLE.velocity(["100", "0", "0"])
    assert _vec(K, orthogonal_component(CRADLE, v, 1)) == [0, 0, 0]
    assert _vec(K, global_orthogonal_component(CRADLE, v, (0, 1))) != _vec(K, orthogonal_component(CRADLE, v, 0))
    # V_12 = V_1 but V_2 != 0: rates (-100, 50), i.e. v = (100, 0, 50)
    v = CRADLE.velocity(["100", "0", "50"])
    assert _vec(K, global_orthogonal_component(CRADLE, v, (0, 1))) == _vec(K, orthogonal_component(CRADLE, v, 0))
    assert _vec(K, orthogonal_component(CRADLE, v, 1)) != [0, 0, 0]


@pytest.mark.parametrize("velocity", [["100", "0", "0"], ["0", "0", "-7/3"], ["5", "5", "0"]])
def test_beta_is_one_when_one_component_vanishes(velocity):
    # what the paper's remark after eq. (5) needs, and what does hold: beta = 1 when V_j = 0
    K = CRADLE.backend
    v = CRADLE.velocity(velocity)
    assert_exact(1, K, beta(CRADLE, v, (0, 1)))


def test_beta_gram_form_equals_the_definition_with_vectors():
    # beta = Phi(V_J, sum V_j) / ||sum V_j||^2, evaluated with vectors and the mass matrix
    s = System(
        [["2", "1/2", "0", "0"], ["1/2", "3", "1", "0"], ["0", "1", "1", "0"], ["0", "0", "0", "5/2"]],
        [["1", "-1", "0", "2"], ["0", "1", "-3", "1"], ["1", "0", "1", "-1"]],
        ["1/3", "0", "1"],
    )
    K = s.backend
    v = s.velocity(["-1", "2", "3", "-2"])
    J = (0, 1, 2)
    VJ = global_orthogonal_component(s, v, J)
    W = [sum((orthogonal_component(s, v, j)[m] for j in J), K.zero) for m in range(s.n)]
    assert K.to_number(beta(s, v, J)) == K.to_number(s.phi(VJ, W) / s.phi(W, W))
    # and V_J really is the orthogonal component: p - V_J is tangent to every S_j in J
    assert all(K.sign(x) == 0 for x in s.rates([a - b for a, b in zip(v, VJ, strict=True)]))
