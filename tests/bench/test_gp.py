"""The paper's loop in PARI/GP (verify/data/gp, verify.bench.gp) against the exact engine.

Skipped where gp is not installed, except the tests of what happens then.
"""

from fractions import Fraction

import pytest

from verify.bench import gp
from verify.bench.throughput import batch, short_batch
from verify.dynamics.system import System
from verify.laws.rule import solve
from verify.models.corner import corner_system
from verify.models.cradle import run_cradle
from verify.numbers.backends import RationalBackend

needs_gp = pytest.mark.skipif(not gp.available(), reason="PARI/GP (gp) is not installed")
F = Fraction


def _kept(result):
    """What GP reports of a run: impact sets, stop, exit velocity (exactly)."""
    K = result.backend
    return list(result.impact_sets), result.stop, tuple(Fraction(K.to_exact(x)) for x in result.exit_velocity)


def _engine_corners(cases, max_impulses=gp.CORNER_MAX_IMPULSES):
    K = RationalBackend()
    return [
        _kept(solve(corner_system(k, e1, e2, backend=K), [xd, yd, 0], max_iterations=max_impulses, trace=False,
                    certify=False))
        for k, xd, yd, e1, e2 in cases
    ]  # fmt: skip


def _gp_kept(runs):
    return list(zip(runs.impact_sets, runs.stops, runs.exit_velocities))


# a few general systems: (mass matrix, normals, CORs, velocity)
ONE3 = [[F(1), 0, 0], [0, F(1), 0], [0, 0, F(1)]]
SYSTEMS = [
    # the three-ball cradle, eps = 1/2 (single impacts)
    (ONE3, [[-1, 1, 0], [0, -1, 1]], [F(1, 2)] * 2, [F(100), 0, 0]),
    # four balls of masses 1, 2, 1, 3, every contact closing at once: |J| = 3
    (
        [[F(1), 0, 0, 0], [0, F(2), 0, 0], [0, 0, F(1), 0], [0, 0, 0, F(3)]],
        [[-1, 1, 0, 0], [0, -1, 1, 0], [0, 0, -1, 1]],
        [F(1, 3), F(0), F(9, 10)],
        [F(3), F(1), F(-1), F(-3)],
    ),
    # a corner with a coupled (non-diagonal) mass matrix and different CORs
    (
        [[F(2), F(1), 0], [F(1), F(2), 0], [0, 0, F(1)]],
        [[F(-1, 3), 1, 0], [F(-1, 3), -1, 0]],
        [F(1, 5), F(1)],
        [F(7), F(1, 2), F(1)],
    ),
    # a two-ball line with one contact and a COR of 0
    ([[F(1), 0], [0, F(5)]], [[-1, 1]], [F(0)], [F(2), F(-1)]),
]


def test_without_gp_it_says_so(monkeypatch):
    monkeypatch.setattr(gp.shutil, "which", lambda _name: None)
    assert not gp.available()
    with pytest.raises(gp.GPError, match="not installed"):
        gp.run_corners(batch(1))


@needs_gp
def test_corner_batch_matches_the_exact_engine():
    cases = batch(200)
    runs = gp.run_corners(cases, repeats=1)
    assert runs.seconds > 0 and runs.loops >= 1 and not runs.real
    assert _gp_kept(runs) == _engine_corners(cases)
    assert {"exit", "max_iterations"} <= set(runs.stops)  # both ends of the batch are covered


@needs_gp
def test_short_batch_matches_the_exact_engine():
    cases = short_batch(100)
    assert _gp_kept(gp.run_corners(cases, repeats=1)) == _engine_corners(cases)


@needs_gp
def test_general_systems_match_the_exact_engine():
    runs = gp.run_systems(SYSTEMS, max_impulses=500, repeats=1)
    K = RationalBackend()
    expected = [
        _kept(solve(System(g, A, e, backend=K), v, max_iterations=500, trace=False, certify=False))
        for g, A, e, v in SYSTEMS
    ]
    assert _gp_kept(runs) == expected
    assert any(len(J) == 3 for sets in runs.impact_sets for J in sets)
    assert runs.exit_velocities[0] == (F(325, 16), F(375, 16), F(225, 4))


@needs_gp
@pytest.mark.parametrize("real", [False, True])
def test_table1_stops_and_counts_match_paper_mode(real):
    runs = gp.run_table1(real=real, repeats=1)
    eps = gp.table1_eps()
    engine = [run_cradle(str(e), mode="paper", trace=False) for e in eps]
    assert [(s, len(J)) for s, J in zip(runs.stops, runs.impact_sets)] == [(r.stop, r.iterations) for r in engine]
    assert runs.impact_sets == [list(r.impact_sets) for r in engine]
    assert runs.stops.count("aeev") == 3
    if real:
        assert runs.precision == 38 and runs.bits == 128  # GP's default precision (64-bit machines)
    else:
        assert runs.exit_velocities == [_kept(r)[2] for r in engine]


@needs_gp
def test_a_wrong_beta_is_caught(tmp_path, monkeypatch):
    """The comparison can fail: beta without the off-diagonal Gram terms (a plausible slip)."""
    for name in ("rule.gp", "table1.gp"):
        text = (gp.GP_DIR / name).read_text(encoding="utf-8")
        (tmp_path / name).write_text(
            text.replace("(lam * vecextract(G, J, J) * lam~)", "sum(a = 1, #J, lam[a]^2 * G[J[a], J[a]])"),
            encoding="utf-8",
        )
    monkeypatch.setattr(gp, "GP_DIR", tmp_path)
    cases = batch(50)
    assert _gp_kept(gp.run_corners(cases, repeats=1)) != _engine_corners(cases)


@needs_gp
def test_a_gp_error_is_raised():
    singular = ([[F(0), 0], [0, F(0)]], [[-1, 1]], [F(1)], [F(1), F(0)])
    with pytest.raises(gp.GPError, match="impossible inverse"):
        gp.run_systems([singular], repeats=1)
