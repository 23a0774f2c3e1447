"""The disk in the corner (Sect. 4.2): the paper's cases, claims, termination, sweeps."""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tests import certificate_check
from verify.cli import main
from verify.laws.rule import beta
from verify.models.corner import corner_geometry, corner_system, paper_run, run_corner
from verify.models.wedge import approach_slopes, below_boundary, rebounds_by_slope, symmetric_boundary
from verify.numbers.backends import get_backend
from verify.paper.float_check import float_vs_exact
from verify.paper.sweep import random_corner_cases, sweep
from verify.proofs.termination import cone_parameters

slopes = st.fractions(min_value=F(1, 10), max_value=10, max_denominator=60)
cors = st.fractions(min_value=0, max_value=1, max_denominator=30)
speeds = st.fractions(min_value=F(1, 10), max_value=10, max_denominator=30)


@st.composite
def both_walls(draw):
    """A slope and a velocity that hits both walls at once (|yd| < k xd)."""
    k, xd = draw(slopes), draw(speeds)
    u = draw(st.fractions(min_value=F(-99, 100), max_value=F(99, 100), max_denominator=100))
    return k, xd, u * k * xd


def test_the_papers_example_exactly():
    run = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001")
    r = run.result
    assert run.zones == ["Z12", "Z12", "Z2", "Z0"]  # the repeated multiple impacts of Sect. 4.2
    assert run.repeated_multiple_impacts
    assert r.backend.describe().startswith("exact (number field")
    assert r.backend.to_decimal(r.exit_velocity[0], 30).startswith("-0.0382715991720915118582847")
    # the same case on certified intervals and on mp agree with the exact result
    interval = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001", backend=get_backend("interval"))
    mp = run_corner(alpha="pi/6", phi="pi/12", eps1="0.999", eps2="0.001", backend=get_backend("mp", dps=60))
    assert interval.zones == mp.zones == run.zones
    import sympy as sp

    for x, xi, xm in zip(r.exit_velocity[:2], interval.result.exit_velocity, mp.result.exit_velocity, strict=False):
        exact = r.backend.to_number(x)
        lo, hi = interval.result.backend.enclosure(xi, 60)
        assert sp.Rational(lo) <= exact <= sp.Rational(hi)
        assert abs(sp.Rational(mp.result.backend.to_decimal(xm, 55)) - exact) < sp.Rational(1, 10**45)


def test_angles_without_algebraic_values_run_on_certified_intervals():
    run = run_corner(alpha="3/10", phi="1/10", eps1="0.9", eps2="0.2")
    assert run.result.backend.name == "interval" and run.result.backend.is_rigorous
    assert any("not algebraic" in n for n in run.notes)
    assert run.result.stop == "exit"


@given(both_walls(), cors, cors)
def test_gram_beta_equals_the_papers_closed_form(case, e1, e2):
    """The engine's multiple impulse, with beta from the Gram matrix, is eq. (10)'s first step
    with the paper's closed form of beta: the same velocity after it."""
    k, xd, yd = case
    s = corner_system(k, e1, e2)
    v = s.velocity([xd, yd, 0])
    zones, px, py = paper_run(k, xd, yd, e1, e2, max_iterations=1)
    assert zones[0] == "Z12"
    run = run_corner(slope=k, velocity=[xd, yd], eps1=e1, eps2=e2, max_iterations=1, certify=False)
    K = run.result.backend
    assert [K.to_number(x) for x in run.result.steps[0].velocity[:2]] == [px, py]
    assert K.to_number(run.result.betas[0]) == s.backend.to_number(beta(s, v, (0, 1)))


def test_the_corner_system_is_the_corner_geometry():
    g, normals = corner_geometry(F(1, 3))
    s = corner_system("1/3", "1/2", "1")
    assert s.source["mass_matrix"] == tuple(tuple(row) for row in g)
    assert s.source["normals"] == tuple(tuple(row) for row in normals)
    assert [[str(a) for a in row] for row in normals] == [["-1/3", "1", "0"], ["-1/3", "-1", "0"]]


def test_eq_10_runs_on_fractions_and_on_floats():
    exact = paper_run(F(1, 2), F(2), F(0), F(0), F(1))
    floats = paper_run(0.5, 2.0, 0.0, 0.0, 1.0)
    assert exact[0] == floats[0] == ["Z12", "Z1", "Z0"]
    assert exact[1:] == (F(-8, 5), F(-4, 5))
    assert all(abs(float(x) - y) < 1e-12 for x, y in zip(exact[1:], floats[1:]))  # the floats round
    assert paper_run(F(1, 2), F(2), F(0), F(0), F(1), max_iterations=1)[0] == ["Z12"]  # the cap: no Z0 after it


@given(slopes, speeds, st.fractions(min_value=-10, max_value=10, max_denominator=30), cors, cors)
@settings(max_examples=60)
def test_engine_equals_eq_10(k, xd, yd, e1, e2):
    run = run_corner(slope=k, velocity=[xd, yd], eps1=e1, eps2=e2, max_iterations=200, certify=False)
    zones, px, py = paper_run(k, xd, yd, e1, e2, max_iterations=run.result.iterations)
    assert zones[: run.result.iterations] == run.zones[: run.result.iterations]
    if run.result.stop == "exit":
        K = run.result.backend
        assert [K.to_number(x) for x in run.result.exit_velocity[:2]] == [px, py]


@given(slopes, speeds, st.fractions(min_value=-10, max_value=10, max_denominator=30), cors, cors)
@settings(max_examples=60)
def test_mirror_symmetry(k, xd, yd, e1, e2):
    a = run_corner(slope=k, velocity=[xd, yd], eps1=e1, eps2=e2, max_iterations=200, certify=False)
    b = run_corner(slope=k, velocity=[xd, -yd], eps1=e2, eps2=e1, max_iterations=200, certify=False)
    swap = {"Z1": "Z2", "Z2": "Z1"}
    assert [swap.get(z, z) for z in a.zones] == b.zones
    Ka, Kb = a.result.backend, b.result.backend
    (x, y), (mx, my) = ([K.to_number(c) for c in r.result.exit_velocity[:2]] for K, r in ((Ka, a), (Kb, b)))
    assert (x, y) == (mx, -my)


@given(both_walls())
def test_ideal_corner_one_multiple_impact_and_exit(case):
    k, xd, yd = case
    run = run_corner(slope=k, velocity=[xd, yd], eps1=1, eps2=1, max_iterations=10_000)
    assert run.result.stop == "exit"
    assert sum(1 for J in run.result.impact_sets if len(J) == 2) <= 1


@given(both_walls(), cors)
def test_symmetric_corner_multiple_impacts_at_most_once(case, e):
    k, xd, yd = case
    run = run_corner(slope=k, velocity=[xd, yd], eps1=e, eps2=e, max_iterations=2000)
    assert sum(1 for J in run.result.impact_sets if len(J) == 2) <= 1


def test_asymmetric_corner_repeats_multiple_impacts():
    run = run_corner(slope="49/422", velocity=["478/47", "-105399/247925"], eps1="0", eps2="363/401")
    assert sum(1 for J in run.result.impact_sets if len(J) == 2) >= 2


def test_non_termination_in_the_wedge_is_certified_and_checked_independently():
    run = run_corner(slope="1/5", velocity=["1", "3/10"], eps1="1/4", eps2="1/4")
    r = run.result
    assert r.stop == "non_terminating"
    rates = r.certificate["rates"]
    failures = certificate_check.check(
        r.certificate, ["1", "1", "1"], [["-1/5", "1", "0"], ["-1/5", "-1", "0"]], rates=rates
    )
    assert failures == []
    # an asymmetric corner too (the cone weights are not 1/2 there)
    run = run_corner(slope="1/10", velocity=["1", "1/20"], eps1="1/10", eps2="1/50")
    assert run.result.stop == "non_terminating"
    assert (
        certificate_check.check(run.result.certificate, ["1", "1", "1"], [["-1/10", "1", "0"], ["-1/10", "-1", "0"]])
        == []
    )


def test_the_symmetric_boundary_is_derived():
    import sympy as sp

    k_star, alpha_star = symmetric_boundary()
    eps = sp.Symbol("eps", positive=True)
    assert k_star.subs(eps, sp.Rational(1, 4)) == sp.Rational(1, 3)
    assert sp.simplify(sp.tan(alpha_star) - k_star) == 0


@given(
    st.fractions(min_value=F(1, 50), max_value=F(99, 100), max_denominator=100),
    st.fractions(min_value=F(1, 100), max_value=F(99, 100), max_denominator=100),
)
def test_cones_exist_exactly_below_the_boundary(k, e):
    s = corner_system(k, e, e)
    assert (cone_parameters(s, 0) is not None) == below_boundary(k, e)


def test_narrower_corners_mean_more_rebounds():
    runs = rebounds_by_slope("1/4", ["1", "3/10"], approach_slopes(F(1, 4), 4))
    counts = [r["iterations"] for r in runs]
    assert all(r["stop"] == "exit" for r in runs)
    assert counts == sorted(counts) and counts[-1] > 150
    below = rebounds_by_slope("1/4", ["1", "3/10"], ["3/10", "1/5"])
    assert all(r["stop"] == "non_terminating" for r in below)


def test_sweep_in_parallel_gives_the_serial_results():
    cases = random_corner_cases(300, seed=7)
    assert sweep(cases, workers=2, chunk=40, progress=False) == sweep(cases, workers=1, progress=False)


def test_sweep_on_a_local_dask_cluster():
    distributed = pytest.importorskip("dask.distributed")
    cases = random_corner_cases(100, seed=11)
    local = "127.0.0.1:0"  # Dask's HTTP server on a free port: other tests may run a cluster at the same time
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=local)
    with cluster, distributed.Client(cluster) as client:
        results = sweep(cases, executor=client.get_executor(), chunk=20, progress=False)
    assert results == sweep(cases, workers=1, progress=False)


def test_float_takes_other_branches_only_where_an_exact_rate_is_zero():
    report = float_vs_exact(random_corner_cases(600, seed=0), workers=1)
    assert report["differing"] > 0
    assert report["reasons"] == {"exact rate 0": report["differing"]}
    assert report["differing_with_a_cor_of_0"] == report["differing"]


def test_cli_corner_json():
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main(["corner", "--alpha", "pi/6", "--phi", "pi/12", "--eps1", "0.999", "--eps2", "0.001", "--json"])
    rec = json.loads(out.getvalue())
    assert code == 0
    assert rec["zones"] == ["Z12", "Z12", "Z2", "Z0"] and rec["impact_sets"] == [[0, 1], [0, 1], [1]]
    assert rec["repeated_multiple_impacts"] is True and rec["rigorous"] is True


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--alpha", "0"], "alpha = 0 must lie in (0, pi/2)"),
        (["--alpha", "pi/2"], "must lie in (0, pi/2)"),
        (["--alpha", "2"], "must lie in (0, pi/2)"),
        (["--alpha=-pi/6"], "must lie in (0, pi/2)"),
        (["--slope", "-1"], "slope = -1 must be positive"),
        (["--alpha", "inf"], 'not a number: "inf"'),
        (["--alpha", "nan"], 'not a number: "nan"'),
        (["--alpha", "pi/6", "--eps1", "1.5"], "eps1 = 1.5 is outside [0, 1]"),
        (["--alpha", "pi/6", "--eps2", "-0.5"], "eps2 = -0.5 is outside [0, 1]"),
        (["--alpha", "sin("], 'not a number: "sin("'),
        (["--alpha", "__import__('os')"], "unknown name '__import__'"),
        (["--alpha", "pi/6", "--v0", "0"], "v0 = 0 must be positive"),
        (["--alpha", "pi/6", "--slope", "1"], "not allowed with argument"),
    ],
)
def test_corner_bad_input(argv, message, capsys):
    full = ["corner", *argv]
    for flag, value in (("--phi", "pi/12"), ("--eps1", "0.5"), ("--eps2", "0.5")):
        if flag not in full:
            full += [flag, value]
    assert main(full) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_repeated_multiple_impacts_forever_are_certified():
    """alpha = pi/6, phi = pi/12 (the paper's example) with eps1 = 1, eps2 = 0: every impulse is a
    multiple impact that sends the velocity back along its own direction, scaled down: it never exits."""
    run = run_corner(alpha="pi/6", phi="pi/12", eps1="1", eps2="0")
    cert = run.result.certificate
    assert run.result.stop == "non_terminating" and cert["kind"] == "repeating direction"
    k = "-sqrt(3)/3"
    assert certificate_check.check_repeating(cert, ["1", "1", "1"], [[k, "1", "0"], [k, "-1", "0"]]) == []
    tampered = dict(cert, factor="1/2")
    assert certificate_check.check_repeating(tampered, ["1", "1", "1"], [[k, "1", "0"], [k, "-1", "0"]])


def test_corner_figures(tmp_path):
    pytest.importorskip("matplotlib")
    from verify.paper import figures

    for figure, n in ((figures.MULTIPLE_IMPACTS, 4), (figures.WEDGE, 5), (figures.ITERATIONS, 3)):
        path = figure.make(tmp_path / figure.file, workers=1, n=n)
        assert path.read_bytes()[:4] == b"\x89PNG"


def test_corner_claims_cli(capsys):
    assert main(["corner-claims", "--cases", "60", "--workers", "1"]) == 0
    out = capsys.readouterr().out
    assert "[holds] mirror symmetry" in out and "Float against exact" in out


@given(both_walls(), cors)
@settings(max_examples=40)
def test_symmetric_corner_is_the_symmetric_and_ideal_rule(case, e):
    """eq. (7) with eps1 = eps2 is eq. (6), and with eps1 = eps2 = 1 it is eq. (5): the named rules agree."""
    k, xd, yd = case
    general = run_corner(slope=k, velocity=[xd, yd], eps1=e, eps2=e, max_iterations=500)
    symmetric = run_corner(slope=k, velocity=[xd, yd], eps1=e, eps2=e, max_iterations=500, rule="symmetric")
    assert general.zones == symmetric.zones
    ideal = run_corner(slope=k, velocity=[xd, yd], eps1=e, eps2=e, rule="ideal")
    one = run_corner(slope=k, velocity=[xd, yd], eps1=1, eps2=1)
    K = ideal.result.backend
    assert ideal.zones == one.zones
    assert [K.to_number(x) for x in ideal.result.exit_velocity] == [
        one.result.backend.to_number(x) for x in one.result.exit_velocity
    ]
