"""The map of two CORs as exact cells (verify.maps.plane, verify.maps.cells): every rational point of the box
answered by its cell as a single exact run answers it, the cells' areas adding up to the box."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
import sympy as sp

from verify.laws.rule import solve
from verify.maps.backends.plane import FLINT_POLYS, Frac, PlaneBackend, X, Y, polys
from verify.maps.cells import decompose
from verify.maps.plane import PlaneMap, plane_parts
from verify.models.corner import corner_system
from verify.numbers.algebraic import RealAlgebraic

BOX = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
NAMES = ("e1", "e2")
VELOCITY = ["1", "-1/10", "0"]  # docs/examples/corner-map.json


def _corner(K):
    return corner_system("1/2", sp.Symbol("e1"), sp.Symbol("e2"), backend=K)


@pytest.fixture(scope="session")  # once per process: the longest tests run first, apart from the module\'s others
def corner_map() -> PlaneMap:
    return plane_parts(_corner, VELOCITY, BOX, NAMES, 40)


def _on_curves(m: PlaneMap, rng: random.Random, count: int) -> list[tuple[Fraction, Fraction]]:
    """Rational points on the boundaries of the map's cells: on the curves that cut the box, and on the box's own
    edges (the sides of its outer cells); a curve of degree 1 in one parameter is solved for it at a rational value
    of the other."""
    P = m.P
    points: list[tuple[Fraction, Fraction]] = []
    x0, x1, y0, y1 = (sp.Rational(v.numerator, v.denominator) for v in m.box)
    curves = [*m.curves, P.from_expr(X - x0), P.from_expr(X - x1), P.from_expr(Y - y0), P.from_expr(Y - y1)]
    while len(points) < count:
        f = rng.choice(curves)
        t = P.terms(f)
        free = Fraction(rng.randint(0, 997), 997)
        if P.degree_y(f) == 1:  # f = A(x) y + B(x)
            A = sum((c * free**i for (i, j), c in t.items() if j == 1), Fraction(0))
            B = sum((c * free**i for (i, j), c in t.items() if j == 0), Fraction(0))
            point = (free, -B / A) if A else None
        elif max(i for i, _ in t) == 1:  # f = A(y) x + B(y)
            A = sum((c * free**j for (i, j), c in t.items() if i == 1), Fraction(0))
            B = sum((c * free**j for (i, j), c in t.items() if i == 0), Fraction(0))
            point = (-B / A, free) if A else None
        else:
            point = None
        if point is not None and x0 <= point[0] <= x1 and y0 <= point[1] <= y1:
            points.append(point)
    return points


def test_every_point_answered_as_a_single_run(corner_map: PlaneMap) -> None:
    """300 rational points (270 drawn in the box, 30 on the curves between cells): the cell's stop, impact sets
    and exit velocity are those of verify solve's exact run there."""
    rng = random.Random(37)
    points = [(Fraction(rng.randint(0, 10**6), 10**6), Fraction(rng.randint(0, 10**6), 10**6)) for _ in range(270)]
    boundary = _on_curves(corner_map, rng, 30)
    assert any(corner_map.locate(*p).cell.dim < 2 for p in boundary)
    for x, y in points + boundary:
        part, velocity = corner_map.at(x, y)
        run = solve(corner_system("1/2", x, y), VELOCITY, max_iterations=40)
        assert (part.stop, part.impact_sets) == (run.stop, list(run.impact_sets)), (x, y)
        assert velocity == list(run.exit_velocity), (x, y)
        assert all(type(v) is Fraction for v in velocity)


def test_the_cells_fill_the_box(corner_map: PlaneMap) -> None:
    """The exact area bounds of the cells hold the box's area 1, and each cell's sample point is in its cell."""
    low = sum(p.cell.area[0] for p in corner_map.parts)
    high = sum(p.cell.area[1] for p in corner_map.parts)
    assert low <= 1 <= high and high - low < Fraction(1, 20)
    for part in corner_map.parts:
        if part.cell.sample is not None and isinstance(part.cell.sample[1], Fraction):
            assert corner_map.locate(*part.cell.sample) is part
    assert corner_map.area("exit")[1] == 1 and corner_map.area("max_iterations") == (0, 0)


def test_the_line_through_the_map_is_the_one_parameter_map(corner_map: PlaneMap) -> None:
    """On the line e2 = 1/2 the cells behave as the one-parameter map of that line (verify.maps.line) does: the
    same impact sets at 401 rational e1, and the same part at each end of its pieces."""
    from verify.maps.line import line_parts
    from verify.numbers.backends.symbolic import EPS, Piece

    parts = line_parts(lambda K: corner_system("1/2", EPS, "1/2", backend=K), VELOCITY, Piece.closed(0, 1), 40)
    assert len(parts) > 1  # the line crosses cells of different behaviours
    for k in range(401):
        e1 = Fraction(k, 400)
        line = next(p for p in parts if p.piece.contains(RealAlgebraic.rational(e1)))
        assert corner_map.locate(e1, Fraction(1, 2)).impact_sets == line.impact_sets, e1
    for part in parts:
        for end in (part.piece.lower, part.piece.upper):
            if end.is_rational and part.piece.contains(end):
                assert corner_map.locate(end.rational_value(), Fraction(1, 2)).impact_sets == part.impact_sets


@pytest.mark.skipif(not FLINT_POLYS, reason="python-flint is not installed (the fast extra)")
def test_sympy_polynomials_give_the_same_map() -> None:
    flint_map = plane_parts(_corner, VELOCITY, BOX, NAMES, 40, arithmetic="flint")
    sympy_map = plane_parts(_corner, VELOCITY, BOX, NAMES, 40, arithmetic="sympy")
    shown = [[(str(p.cell.describe(m.P, NAMES)), p.stop, p.impact_sets, [str(v) for v in p.exit_velocity])
              for p in m.parts] for m in (flint_map, sympy_map)]  # fmt: skip
    assert shown[0] == shown[1]


def test_no_float_enters_the_plane_backend() -> None:
    """Elements refuse float(); signs at an algebraic sample point are exact."""
    P = polys()
    K = PlaneBackend(P, (Fraction(1, 2), Fraction(1, 3)), known=set())
    with pytest.raises(TypeError):
        float(K.parameters[0])
    cells = decompose(P, [P.from_expr(sp.Symbol("x") ** 2 + sp.Symbol("y") ** 2 - 1)], BOX)
    arc = next(c for c in cells if c.dim == 1 and c.y_lo.poly is not None)
    K = PlaneBackend(P, arc.sample, known={P.key(arc.y_lo.poly)})
    x, y = K.parameters
    assert K.sign(x * x + y * y - K.one) == 0
    assert isinstance(x * y, Frac)


@pytest.mark.parametrize("name", ["sympy", "flint"])
def test_values_and_signs_at_a_rational_sample_are_exact(name: str) -> None:
    """What a cell reads at its rational sample (a function's value, the sign of a polynomial) is the exact number,
    as SymPy computes it from the expression, in both polynomial arithmetics; at an algebraic sample there is no
    rational value to read."""
    if name == "flint" and not FLINT_POLYS:
        pytest.skip("python-flint is not installed (the fast extra)")
    P = polys(name)
    rng = random.Random(7)
    x, y = sp.symbols("x y")
    for _ in range(30):
        n, d = (sum(rng.randint(-9, 9) * x**i * y**j for i in range(4) for j in range(4) if rng.random() < 0.4) + 1
                for _ in range(2))  # fmt: skip
        at = (Fraction(rng.randint(-30, 30), rng.randint(1, 30)), Fraction(rng.randint(-30, 30), rng.randint(1, 30)))
        exact = (n / d).subs({x: sp.Rational(*at[0].as_integer_ratio()), y: sp.Rational(*at[1].as_integer_ratio())})
        if not exact.is_finite:
            continue
        K = PlaneBackend(P, at, known=set(), point=True)
        f = Frac(P, P.from_expr(n.subs({x: X, y: Y})), P.from_expr(d.subs({x: X, y: Y})))
        assert K.at_sample(f) == Fraction(int(sp.numer(exact)), int(sp.denom(exact)))
        assert isinstance(K.at_sample(f), Fraction)
        assert K.sign(f) == int(sp.sign(exact))
    cells = decompose(P, [P.from_expr(X**2 + Y**2 - 1)], BOX)
    arc = next(c for c in cells if c.dim == 1 and c.y_lo.poly is not None)
    on_arc = PlaneBackend(P, arc.sample, known=set(), point=True)
    assert on_arc.at_sample(on_arc.one) is None


def test_case_map_of_cells_answers_any_point() -> None:
    """``case_map(..., cells=True)``: the corner of docs/examples/corner-map.json, at a point off every grid line."""
    from verify.maps.general import case_map

    m = case_map("docs/examples/corner-map.json", cells=True, max_impulses=12)
    assert m.layout == "cells" and not m.lines
    part, velocity = m.at({"eps1": "1/7", "eps2": "3/11"})
    run = solve(corner_system("1/2", Fraction(1, 7), Fraction(3, 11)), VELOCITY, max_iterations=12)
    assert (part.stop, part.impact_sets, velocity) == (run.stop, list(run.impact_sets), list(run.exit_velocity))


def _lies_on(m: PlaneMap, cell, f) -> bool:
    """Whether the cell lies on the curve f = 0, as the decomposition names it (a vertical line at a root of f, or
    a section of f)."""
    P = m.P
    if P.degree_y(f) == 0:
        return cell.on_line and cell.x_lo.sign_of(P.in_x(f)) == 0
    return cell.y_lo == cell.y_hi and cell.y_lo.poly is not None and P.key(cell.y_lo.poly) == P.key(f)


def test_a_curve_cuts_only_the_cells_it_meets() -> None:
    """The corner on [0, 1/4] x [1/2, 1] at 4 impulses (the example of docs/cli.md): signs the rule asks on a cell
    may be of curves that do not pass through it (here the box's own edges and two conics); such a curve keeps one
    sign on the cell and does not cut it (verify.maps.cells.meets), so every curve the map lists has a cell on it,
    and the map still answers each drawn point as a single run does."""
    from verify.maps.general import case_map

    m = case_map("docs/examples/corner-map.json", cells=True, max_impulses=4,
                 parameters={"eps1": ("0", "1/4"), "eps2": ("1/2", "1")})  # fmt: skip
    assert m.plane.curves
    for f in m.plane.curves:
        assert any(_lies_on(m.plane, p.cell, f) for p in m.plane.parts), m.P.show(f, NAMES)
    rng = random.Random(14)
    for _ in range(40):
        x, y = Fraction(rng.randint(0, 250), 1000), Fraction(rng.randint(500, 1000), 1000)
        part, velocity = m.at({"eps1": x, "eps2": y})
        run = solve(corner_system("1/2", x, y), VELOCITY, max_iterations=4)
        assert (part.stop, part.impact_sets) == (run.stop, list(run.impact_sets)), (x, y)
        assert run.stop != "exit" or velocity == list(run.exit_velocity), (x, y)


def test_the_text_names_the_contacts_as_the_legend_and_the_line_maps_do() -> None:
    """A map of cells in words names each impact set by the contacts' names (S1, S2), as the figure's legend and
    the one-parameter tables do: each row's sequence is the one of its cell, and the legend's sequences are the
    areas' lines'."""
    from verify.maps.figures import plane_legend
    from verify.maps.general import case_map
    from verify.maps.text import eps_map_text

    m = case_map("docs/examples/corner-map.json", cells=True, max_impulses=4)
    text = eps_map_text(m)
    rows = text.split("Cells (x, then y")[1].splitlines()[1:]
    names = m.system.names
    assert len(rows) == len(m.plane.parts)
    for row, part in zip(rows, m.plane.parts):
        shown = "".join("(" + ",".join(names[j] for j in J) + ")" for J in part.impact_sets)
        assert row.endswith(f"exit after {part.iterations}: {shown}"), row
    areas = text.split("Area of each behaviour")[1].split("Cells (x")[0]
    for _, label in plane_legend(m):
        assert label.split(": ")[1].split(", area")[0] + ":" in areas


def test_cells_from_the_command_line(tmp_path, capsys) -> None:
    """``verify map``: with two parameters, cells by default (as ``--cells``): JSON with every cell, a figure; one
    parameter is refused with exit code 2 under ``--cells``, as is ``--cell-cones`` with a grid of lines, and
    ``--cells`` with ``--grid``; ``--lines`` asks for the grid."""
    import json

    from verify.cli import main

    assert main(["map", "docs/examples/corner-map.json", "--cells", "--json", "--max-impulses", "8"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["layout"] == "cells" and len(out["cells"]["cells"]) > 10
    assert {c["stop"] for c in out["cells"]["cells"]} <= {"exit", "not_run"}
    one = tmp_path / "one.json"
    one.write_text(json.dumps({"cases": [{"id": "a", "mass_matrix": [["1", "0"], ["0", "1"]], "normals": [["-1", "1"]],
                                          "restitution": ["e"], "velocity": ["1", "0"]}]}))  # fmt: skip
    assert main(["map", str(one), "--cells"]) == 2
    assert "two parameters" in capsys.readouterr().err
    assert main(["map", "docs/examples/corner-map.json", "--json", "--max-impulses", "8"]) == 0
    assert json.loads(capsys.readouterr().out) == out, "cells are the default with two parameters"
    assert main(["map", "docs/examples/corner-map.json", "--json", "--max-impulses", "8", "--lines", "2"]) == 0
    assert json.loads(capsys.readouterr().out)["layout"] == "grid of lines"
    assert main(["map", "docs/examples/balls-2112-cors.json", "--cell-cones", "--grid"]) == 2
    captured = capsys.readouterr()
    assert "--cell-cones is for a map of cells" in captured.err and not captured.out
    assert main(["map", str(one), "--cell-cones"]) == 2, "one parameter: no cells to try cones on"
    assert "cell cones are tried on a map of cells" in capsys.readouterr().err
    assert main(["map", "docs/examples/corner-map.json", "--cells", "--lines", "3"]) == 2
    captured = capsys.readouterr()
    assert "--cells and --grid (or --lines)" in captured.err and not captured.out
    figure = tmp_path / "m.png"
    assert (
        main(["map", "docs/examples/corner-map.json", "--cells", "--max-impulses", "8", "--figure", str(figure)]) == 0
    )
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_budget_leaves_the_rest_unexplored() -> None:
    """A size budget of 5 cells: the map stops, says why, and the cells not run are unexplored with that reason;
    their areas and the others' still hold the box."""
    from verify.maps.line import Watch

    watch = Watch(max_parts=5)
    m = plane_parts(_corner, VELOCITY, BOX, NAMES, 40, watch=watch)
    assert m.stopped == "the size budget of 5 parts was reached" and watch.parts == 5
    done = [p for p in m.parts if not p.reason.startswith("not explored")]
    left = [p for p in m.parts if p.reason == f"not explored: {m.stopped}"]
    assert len(done) == 5 and left and all(p.stop == "max_iterations" for p in left)
    low, high = sum(p.cell.area[0] for p in m.parts), sum(p.cell.area[1] for p in m.parts)
    assert low <= 1 <= high
    part, velocity = m.at(Fraction(1, 2), Fraction(1, 2))
    assert velocity is None or part in done


@pytest.mark.slow(seconds=10)
def test_four_balls_each_drawn_point_as_a_single_run() -> None:
    """Four balls of masses 2, 1, 1, 2 with CORs (e_out, e_mid, e_out) (docs/examples/balls-2112-cors.json) at 8
    impulses: at 300 rational points (270 drawn in the box, 30 on the curves between cells), a cell that exits
    gives verify solve's impact sets and exit velocity, and where a cell is unexplored the single run does not exit
    within the cap either. The cells that are rational points are decided as verify solve decides them: where it
    proves never-exits (e_out = 0 with e_mid = 0 or 1, and (1/2, 0)), the cell carries the certificate, and the
    tests' own checker passes it."""
    from tests import certificate_check
    from verify.dynamics.system import System
    from verify.maps.general import case_map

    m = case_map("docs/examples/balls-2112-cors.json", cells=True, max_impulses=8)
    rng = random.Random(2112)
    masses = [["2", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "2"]]
    normals = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]
    stops = set()
    points = [(Fraction(0), Fraction(0)), (Fraction(0), Fraction(1)), (Fraction(1, 2), Fraction(0))]
    points += [(Fraction(rng.randint(0, 10**6), 10**6), Fraction(rng.randint(0, 10**6), 10**6)) for _ in range(270)]
    boundary = _on_curves(m.plane, rng, 30)
    assert any(m.plane.locate(*p).cell.dim < 2 for p in boundary)
    for x, y in points + boundary:
        part, velocity = m.at({"e_out": x, "e_mid": y})
        run = solve(System(masses, normals, [x, y, x]), ["1", "0", "0", "0"], max_iterations=8)
        stops.add(part.stop)
        if part.stop == "exit":
            assert (part.impact_sets, velocity) == (list(run.impact_sets), list(run.exit_velocity)), (x, y)
        elif part.stop == "non_terminating":
            assert part.cell.dim == 0 and run.stop == "non_terminating", (x, y)
            assert (part.iterations, part.certificate["kind"]) == (run.iterations, run.certificate["kind"])
            assert part.certificate["kind"] == "repeating direction"
            assert certificate_check.check_repeating(part.certificate, ["2", "1", "1", "2"], normals) == [], (x, y)
        else:
            assert part.stop == "max_iterations" and run.stop in ("max_iterations", "non_terminating"), (x, y)
    assert stops == {"exit", "max_iterations", "non_terminating"}
    assert [p.cell.sample for p in m.plane.parts if p.stop == "non_terminating"] == points[:3]
    for part in m.plane.parts:  # every cell that is a rational point: proved exactly where a single exact run is
        if part.cell.dim == 0 and part.cell.sample is not None and isinstance(part.cell.sample[1], Fraction):
            x, y = part.cell.sample
            run = solve(System(masses, normals, [x, y, x]), ["1", "0", "0", "0"], max_iterations=8)
            assert (part.stop == "non_terminating") == (run.stop == "non_terminating"), (x, y)


def test_a_cell_run_past_the_deadline_stops() -> None:
    """The wall-clock budget is checked at every sign of a cell's run, not only between cells: past its deadline a
    sign raises OutOfTime, and the map leaves that cell unexplored with the budget's reason."""
    from verify.maps.backends.plane import OutOfTime
    from verify.maps.line import Watch

    K = PlaneBackend(polys(), (Fraction(1, 2), Fraction(1, 3)), known=set(), deadline=0.0)
    with pytest.raises(OutOfTime):
        K.sign(K.parameters[0])

    class LateWatch(Watch):  # lets the first cell start, then says the budget ran out (as after a long run)
        calls = 0

        def check(self) -> bool:
            self.calls += 1
            return self.calls > 1 and super().check()

    watch = LateWatch(seconds=1e-9)
    m = plane_parts(_corner, VELOCITY, BOX, NAMES, 40, watch=watch)
    assert m.stopped.startswith("the wall-clock budget") and watch.calls == 2
    assert {p.reason for p in m.parts} == {f"not explored: {m.stopped}"}


def test_cells_proved_never_to_exit_carry_a_certificate_that_holds_at_their_points() -> None:
    """The corner of slope 1/10 entered at (1, 1/20, 0) (the geometry of the golden case
    corner-slope-1/10-never-exits) over [0, 1]^2 at 4 impulses: cells proved never to exit carry an alternating
    invariant cone, written in the parameters. At every drawn rational point that lands in one, the certificate
    with the point's values passes the tests' own checker (tests/certificate_check.py), and a single exact run
    there does not exit within 200 impulses; the golden case's point (1/10, 1/50) lies in such a cell."""
    from tests import certificate_check
    from verify.maps.general import eps_map

    system = corner_system("1/10", "1", "1")
    m = eps_map(system, ["1", "1/20", "0"], ["e1", "e2"], max_impulses=4, cells=True)
    proved = [p for p in m.plane.parts if p.stop == "non_terminating"]
    assert proved and all(p.certificate["kind"] == "alternating invariant cone" for p in proved)
    masses = ["1", "1", "1"]
    normals = [["-1/10", "1", "0"], ["-1/10", "-1", "0"]]
    rng = random.Random(110)
    points = [(Fraction(1, 10), Fraction(1, 50))]
    points += [(Fraction(rng.randint(0, 400), 1000), Fraction(rng.randint(0, 500), 1000)) for _ in range(60)]
    checked = 0
    for x, y in points:
        part, _ = m.at({"e1": x, "e2": y})
        if part.stop != "non_terminating":
            assert (x, y) != points[0]
            continue
        cert = certificate_check.at_point(part.certificate, {"e1": x, "e2": y})
        assert certificate_check.check(cert, masses, normals) == [], (x, y)
        run = solve(corner_system("1/10", x, y), ["1", "1/20", "0"], max_iterations=200)
        assert run.stop != "exit", (x, y)
        checked += 1
    assert checked >= 10


def test_cells_of_three_contacts_proved_never_to_exit_carry_a_period_cone_that_holds_at_their_points() -> None:
    """Four balls of masses 2, 1, 1, 2 with CORs (e_out, e_mid, e_out) on [0, 1/4]^2 at 8 impulses: the runs repeat
    (S2)(S1,S3), a period linear in the rates; cells still impacting at the cap where its two largest eigenvalues are
    real get the boundary cone built over Q(e_out, e_mid) and checked on the whole cell (verify.maps.cell_cones).
    At every drawn rational point of such a cell, the certificate with the point's values passes the tests' own
    checker with the rates of a single exact run there, and that run does not exit within 200 impulses."""
    from tests import certificate_check
    from verify.dynamics.system import System
    from verify.maps.general import case_map

    m = case_map("docs/examples/balls-2112-cors.json", cells=True, max_impulses=8, cell_cones=True,
                 parameters={"e_out": ("0", "1/4"), "e_mid": ("0", "1/4")})  # fmt: skip
    proved = [p for p in m.plane.parts if p.stop == "non_terminating" and p.cell.dim == 2]
    assert proved and all(p.certificate["kind"] == "invariant cone of a period" for p in proved)
    masses = [["2", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "2"]]
    normals = [["-1", "1", "0", "0"], ["0", "-1", "1", "0"], ["0", "0", "-1", "1"]]
    rng = random.Random(2112)
    checked = 0
    for _ in range(40):
        x, y = Fraction(rng.randint(0, 250), 1000), Fraction(rng.randint(0, 250), 1000)
        part, _ = m.at({"e_out": x, "e_mid": y})
        if part.stop != "non_terminating":
            continue
        system = System(masses, normals, [x, y, x])
        start = solve(system, ["1", "0", "0", "0"], max_iterations=part.iterations, trace=False)
        rates = [str(sum((Fraction(n) * v for n, v in zip(row, start.exit_velocity)), Fraction(0))) for row in normals]
        cert = certificate_check.at_point(part.certificate, {"e_out": x, "e_mid": y})
        assert certificate_check.check_period(cert, ["2", "1", "1", "2"], normals, rates=rates,
                                              restitution=[str(x), str(y), str(x)]) == [], (x, y)  # fmt: skip
        assert solve(system, ["1", "0", "0", "0"], max_iterations=200).stop != "exit", (x, y)
        checked += 1
    assert checked >= 10


def test_the_cone_search_on_cells_decides_membership_at_the_sample_point(monkeypatch) -> None:
    """On a plane of two CORs the cone search solves its linear programs in rationals at the cell's sample point,
    then checks the combination on the whole cell: a linear program runs on the plane's functions only where the
    plane has no sample point (one on the plane's functions would cut the cell at every sign it asks, and split
    this map of 37 parts into 161)."""
    from verify.cli import main
    from verify.proofs.cones import period

    seen: list[tuple[str, bool]] = []
    original = period.feasible

    def recording(K, *args, **kwargs):
        seen.append((type(K).__name__, K.at_sample(K.zero) is not None))
        return original(K, *args, **kwargs)

    monkeypatch.setattr(period, "feasible", recording)
    argv = ["map", "docs/examples/balls-2112-cors.json", "--cells", "--cell-cones", "--max-impulses", "8",
            "--parameter", "e_out=0,1/4", "--parameter", "e_mid=0,1/4", "--json", "--quiet"]  # fmt: skip
    assert main(argv) == 0
    assert ("RationalBackend", False) in seen, "the guard: the map searched cones at sample points"
    assert (PlaneBackend.__name__, True) not in seen
