"""Maps of systems whose numbers are algebraic (verify.numbers.backends.fieldfunc, NumberFieldBackend.sign_at): the
paper's corner at alpha = pi/6 (docs/examples/paper-corner-map.json) mapped over eps1 with eps2 = 1/1000, each
point answered as a single exact run answers it, and the field's arithmetic giving a rational system's map."""

from __future__ import annotations

import itertools
import json
import random
from fractions import Fraction
from typing import Any

import pytest
import sympy as sp

from tests import certificate_check
from verify.cli import main
from verify.laws.rule import solve
from verify.maps.general import case_map
from verify.maps.line import line_parts
from verify.models.corner import corner_system
from verify.numbers.algebraic import RealAlgebraic, poly_from_coeffs
from verify.numbers.backends import NumberFieldBackend
from verify.numbers.backends.fieldfunc import FieldArithmetic
from verify.numbers.backends.symbolic import EPS, Piece, RootCache, SymbolicBackend

CASE = "docs/examples/paper-corner-map.json"
CAP = 12


def _case() -> dict:
    with open(CASE) as fh:
        return json.load(fh)["cases"][0]


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def paper_map():
    return case_map(CASE, max_impulses=CAP)


@pytest.mark.slow(seconds=23)
def test_hundred_points_as_single_runs(paper_map) -> None:
    """100 rational eps1 in [0, 1] (98 drawn, and both ends): a part that exits or never exits gives verify
    solve's stop, impact sets and exit velocity there (equal in the number field); where the map leaves a part
    unexplored, the single run does not exit within the cap either."""
    case = _case()
    slope = sp.sympify(case["normals"][0][0]) * -1
    e2 = Fraction(case["restitution"][1])
    rng = random.Random(3)
    points = [Fraction(rng.randint(0, 10**6), 10**6) for _ in range(98)] + [Fraction(0), Fraction(1)]
    stops = set()
    for e1 in points:
        part, velocity = paper_map.at({"eps1": e1})
        run = solve(corner_system(slope, e1, e2), case["velocity"], max_iterations=CAP)
        stops.add(part.stop)
        if part.stop == "max_iterations":
            assert run.stop != "exit", e1
            continue
        assert (part.stop, part.impact_sets) == (run.stop, list(run.impact_sets)), e1
        if part.stop == "exit":
            K = run.backend
            assert [K.convert(v) for v in velocity] == list(run.exit_velocity), e1
            assert all(isinstance(v, Fraction) or v.is_algebraic for v in velocity)
    assert stops == {"exit", "non_terminating", "max_iterations"}


def test_the_ends_are_algebraic_and_the_parts_cover_the_interval(paper_map) -> None:
    """The parts' ends are real algebraic numbers over the rationals (irrational ones among them), in order,
    each part starting where the one before ends."""
    parts = paper_map.lines[0].parts
    assert parts[0].piece.lower == RealAlgebraic.rational(Fraction(0))
    assert parts[-1].piece.upper == RealAlgebraic.rational(Fraction(1))
    assert any(not p.piece.upper.is_rational for p in parts)
    for a, b in itertools.pairwise(parts):
        assert a.piece.upper == b.piece.lower and a.piece.upper_closed != b.piece.lower_closed


def test_the_field_gives_a_rational_system_its_map() -> None:
    """The corner of slope 1/2 (rational) mapped with the arithmetic of Q(sqrt(2)) gives the rational map: the same
    pieces, stops, impact sets and exit velocities."""

    def corner(K):
        return corner_system("1/2", EPS, "1/2", backend=K)

    velocity = ["1", "-1/10", "0"]
    plain = line_parts(corner, velocity, Piece.closed(0, 1), 20, RootCache())
    field = line_parts(corner, velocity, Piece.closed(0, 1), 20, RootCache(NumberFieldBackend([sp.sqrt(2)])))
    assert [str(p.piece) for p in plain] == [str(p.piece) for p in field]
    for a, b in zip(plain, field):
        assert (a.stop, a.iterations, a.impact_sets) == (b.stop, b.iterations, b.impact_sets)
        assert all(sp.simplify(x - y) == 0 for x, y in zip(a.exit_velocity, b.exit_velocity))


def test_signs_at_algebraic_points_against_high_precision() -> None:
    """NumberFieldBackend.sign_at: polynomials over Q(sqrt(3)) at roots of rational quadratics, the sign exactly 0
    where the point is a root (built so), else the sign of a 60-digit evaluation."""
    F = NumberFieldBackend([sp.sqrt(3)])
    x = sp.Symbol("x")
    rng = random.Random(11)
    zeros = 0
    for _ in range(60):
        a, b = rng.randint(-9, 9), rng.randint(1, 30)
        roots = RealAlgebraic.roots_in(poly_from_coeffs([1, a, -b]))  # x^2 + a x - b: two real roots
        r = rng.choice(roots)
        q = sum(sp.Rational(rng.randint(-5, 5), rng.randint(1, 4)) * sp.sqrt(3) ** rng.randint(0, 1) * x**k
                for k in range(rng.randint(1, 4)))  # fmt: skip
        if rng.random() < 0.3:
            q = sp.expand(q * (x**2 + a * x - b))
            zeros += 1
        if q == 0:
            continue
        got = F.sign_at(sp.Poly(q, x, domain=F.field), r)
        value = sp.N(q.subs(x, r.expr), 60)
        expected = 0 if abs(value) < sp.Float(10) ** -40 else (1 if value > 0 else -1)
        assert got == expected, (q, r)
    assert zeros > 5


@pytest.mark.parametrize("generators", [[sp.sqrt(2), sp.sqrt(3)], [sp.cbrt(2)]], ids=["real conjugates", "complex"])
def test_signs_at_roots_of_the_norm_by_conjugates_as_by_the_square_free_part(generators) -> None:
    """At a real root r of the norm of p, r is a root of p or of one of its conjugates: the sign read from interval
    values of the conjugates (every conjugate real: Q(sqrt(2), sqrt(3))) equals the one of the square-free part over
    the field, and a 60-digit evaluation's; Q(2^(1/3)) has complex conjugates and takes the square-free part. Both
    outcomes, 0 and not 0, are met over the real field (over Q(2^(1/3)) a real root of the norm is one of p: its
    conjugates have no real roots here)."""
    F = NumberFieldBackend(generators)
    x = sp.Symbol("x")
    g = sum(generators)
    rng = random.Random(12)
    outcomes = set()
    for _ in range(12):
        q = sp.expand(sum(sp.Rational(rng.randint(-5, 5), rng.randint(1, 3)) * g ** rng.randint(0, 2) * x**k
                          for k in range(rng.randint(2, 3))))  # fmt: skip
        if sp.Poly(q, x).degree() < 1:
            continue
        p = sp.Poly(q, x, domain=F.field)
        for r in RealAlgebraic.roots_in(sp.Poly(F.norm(p).sqf_part().as_expr(), x, domain="QQ")):
            got = F.sign_at(p, r)
            value = sp.N(q.subs(x, r.expr), 60)
            expected = 0 if abs(value) < sp.Float(10) ** -40 else (1 if value > 0 else -1)
            assert got == F.sign_at(p, r, conjugates=False) == expected, (q, r)
            outcomes.add(got == 0)
    assert outcomes == ({True, False} if len(generators) == 2 else {True})


def test_no_float_enters_the_field_arithmetic() -> None:
    """Elements refuse float(); a run over the field on a symbolic backend keeps them exact."""
    F = NumberFieldBackend([sp.sqrt(3)])
    A = FieldArithmetic.over(F)
    x = A.from_expr(sp.sqrt(3) * EPS / 3)
    with pytest.raises(TypeError):
        float(x)
    K = SymbolicBackend(Piece.closed(Fraction(1, 2), Fraction(1, 2)), RootCache(F))
    r = solve(corner_system("sqrt(3)/3", EPS, "1/2", backend=K), ["1", "2 - sqrt(3)", "0"], max_iterations=6)
    assert all(type(v).__name__ == "FieldFunc" for v in r.exit_velocity)


def test_the_command_line_maps_the_paper_corner(tmp_path, capsys) -> None:
    """verify map on the paper's corner: JSON with algebraic ends; and its cells, at 2 impulses on the square
    [1/2, 1]^2, with exit velocities over the field."""
    assert main(["map", CASE, "--json", "--max-impulses", "6"]) == 0
    out = json.loads(capsys.readouterr().out)
    pieces = out["lines"][0]["pieces"]
    assert "sqrt" in json.dumps(out["velocity"]) and any("CRootOf" in p["upper"] for p in pieces)
    case = _case()
    case["restitution"] = ["eps1", "eps2"]
    path = tmp_path / "plane.json"
    with open(path, "w") as fh:
        json.dump({"cases": [case]}, fh)
    box = ["--parameter", "eps1=1/2,1", "--parameter", "eps2=1/2,1"]  # where the cells exit, few curves
    assert main(["map", str(path), "--cells", "--max-impulses", "2", "--json", *box]) == 0
    cells = json.loads(capsys.readouterr().out)["cells"]
    assert any("sqrt" in v for c in cells["cells"] for v in c["exit_velocity"])


# -- two parameters over a number field: cells (verify.maps.backends.tower) ----------------------------------------

SQRT3_CORNER = {"mass_matrix": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
                "normals": [["-sqrt(3)/3", "1", "0"], ["-sqrt(3)/3", "-1", "0"]],
                "restitution": ["e1", "e2"]}  # fmt: skip


def _cells_against_single_runs(velocity: list[str], cap: int, seed: int, m: Any = None) -> tuple[set[str], Any]:
    """The corner of slope sqrt(3)/3 over (e1, e2) in [0, 1]^2 as cells, from ``velocity``: 100 rational points (90
    drawn, 10 on the curves between cells) give a single exact run's stop, impact sets and exit velocity where the
    cell exits, a certificate that the tests' checker passes at the point where it never exits, and a single run
    that does not exit within the cap where it is unexplored or never exits. ``m``: that map if already made (its
    two parameters under any names)."""
    from tests.maps.test_plane import _on_curves
    from verify.maps.general import eps_map

    if m is None:
        m = eps_map(corner_system("sqrt(3)/3", "1", "1"), velocity, ["e1", "e2"], max_impulses=cap, cells=True)
    names = list(m.parameters)
    rng = random.Random(seed)
    points = [(Fraction(rng.randint(0, 1000), 1000), Fraction(rng.randint(0, 1000), 1000)) for _ in range(90)]
    points += _on_curves(m.plane, rng, 10)
    stops = set()
    for x, y in points:
        part, at = m.at(dict(zip(names, (x, y))))
        run = solve(corner_system("sqrt(3)/3", x, y), velocity, max_iterations=cap)
        stops.add(part.stop)
        if part.stop == "exit":
            assert (part.impact_sets, run.stop) == (list(run.impact_sets), "exit"), (x, y)
            assert [run.backend.convert(v) for v in at] == list(run.exit_velocity), (x, y)
        elif part.stop == "non_terminating":  # its certificate at the point, by the tests' own checker
            cert = certificate_check.at_point(part.certificate, dict(zip(names, (x, y))))
            assert certificate_check.check(cert, ["1", "1", "1"], SQRT3_CORNER["normals"]) == [], (x, y)
            assert run.stop != "exit", (x, y)
        else:
            assert part.stop == "max_iterations" and run.stop != "exit", (x, y)
    low = sum(p.cell.area[0] for p in m.plane.parts)
    high = sum(p.cell.area[1] for p in m.plane.parts)
    assert low <= 1 <= high
    return stops, m


def test_cells_of_an_algebraic_corner_as_single_runs() -> None:
    """The corner of slope sqrt(3)/3 entered at (1, -1/10, 0): every cell exits within 4 impulses."""
    assert _cells_against_single_runs(["1", "-1/10", "0"], 4, 41)[0] == {"exit"}


@pytest.mark.slow(seconds=34)
def test_cells_of_the_paper_corner_at_three_impulses_as_single_runs(paper_corner_maps) -> None:
    """The paper's corner (alpha = pi/6) entered in the direction phi = pi/12 as the corner report maps it,
    (1, tan(pi/12), 0): at 3 impulses, cells that exit and cells still impacting, each as single runs answer; and
    at 12 of the points, single runs from the paper's own velocity (cos(pi/12), sin(pi/12), 0) have the same impact
    sets and stop, and the exit velocity times cos(pi/12) (the rule is positively homogeneous). The cells still
    impacting cover 0.3 % of the square, which 100 drawn points may miss: the sample point of each of its open
    cells is run too. The map is the corner report's (``corner_maps``, shared with tests/report/test_reports.py)."""
    from verify.models.corner import direction_of, velocity_of

    direction = [str(v) for v in direction_of("pi/12")]
    m = paper_corner_maps.plane
    normals = [[str(a) for a in row] for row in corner_system("sqrt(3)/3", "1", "1").normals]
    assert ([str(v) for v in m.velocity], m.max_impulses, [[str(a) for a in row] for row in m.system.normals]) == (
        direction, 3, normals)  # fmt: skip
    assert m.parameters == {"eps1": (0, 1), "eps2": (0, 1)}
    stops, m = _cells_against_single_runs(direction, 3, 42, m)
    assert "exit" in stops
    still = [p for p in m.plane.parts if p.stop == "max_iterations" and p.cell.dim == 2]
    assert still
    for p in still:
        x, y = p.cell.sample
        assert m.at({"eps1": x, "eps2": y})[0].stop == "max_iterations"
        assert solve(corner_system("sqrt(3)/3", x, y), direction, max_iterations=3).stop != "exit", (x, y)
    rng = random.Random(43)
    cos = sp.cos(sp.pi / 12)
    for _ in range(12):
        x, y = Fraction(rng.randint(0, 100), 100), Fraction(rng.randint(0, 100), 100)
        part, at = m.at({"eps1": x, "eps2": y})
        run = solve(corner_system("sqrt(3)/3", x, y), velocity_of("pi/12", "1"), max_iterations=3)
        assert (run.stop, list(run.impact_sets)) == (part.stop, part.impact_sets), (x, y)
        if run.stop == "exit":
            assert [run.backend.convert(sp.expand(cos * v)) for v in at] == list(run.exit_velocity), (x, y)


def test_the_paper_statement_on_repeated_multiple_impacts_has_its_exact_boundary() -> None:
    """verify.paper.corner_map: on eps2 = 1/1000 the first two impulses are both multiple impacts exactly for
    eps1 above 1513/6500 + 2013*sqrt(3)/6500 (0.76917...); single exact runs on either side of it agree, and the
    paper's eps1 = 0.999 is inside."""
    from verify.models.corner import run_corner
    from verify.paper.corner_map import corner_maps, repeated

    found = corner_maps(line_impulses=4, plane_impulses=2)
    (piece,) = found.repeated_pieces()
    boundary = (1513 + 2013 * sp.sqrt(3)) / 6500
    assert sp.simplify(piece.lower.expr - boundary) == 0 and not piece.lower_closed and piece.upper_closed
    for e1, inside in (("0.769172", False), ("0.769173", True), ("0.999", True), ("0.5", False)):
        r = run_corner(alpha="pi/6", phi="pi/12", eps1=e1, eps2="0.001")
        assert repeated(list(r.result.impact_sets)) is inside, e1
    low, high = found.repeated_area()
    assert 0 < low <= high < Fraction(1, 100)


def test_a_new_curve_over_a_number_field_is_named_in_its_message() -> None:
    """The message of NewCurves for a function over a number field writes the function (it read a rational
    fraction's numerator, which the tower's functions do not have)."""
    from verify.maps.backends.plane import NewCurves, PlaneBackend, polys
    from verify.maps.backends.tower import Tower

    P = polys()
    K = PlaneBackend(
        P, (Fraction(1, 2), Fraction(1, 3)), known=set(), tower=Tower.over(P, NumberFieldBackend([sp.sqrt(3)]))
    )
    with pytest.raises(NewCurves) as info:
        K.sign(K.convert(sp.sqrt(3) * sp.Symbol("x")) - K.parameters[1])
    assert str(info.value).startswith("the sign of sqrt(3)*x - y is read on a cell that no curve")
