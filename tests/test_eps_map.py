"""The map of any system (``verify map``, :func:`verify.checks.maps.general.eps_map`): checked point by
point against single exact runs, and against the cradle map it generalises."""

from __future__ import annotations

import json
import random
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

from verify.checks.maps.general import eps_map, eps_map_json
from verify.checks.maps.line import parts_json
from verify.checks.paper.cradle_map import cradle_map, map_json
from verify.cli import main
from verify.core.parse import parse_number, to_number
from verify.core.rule import solve
from verify.core.system import System
from verify.errors import InvalidInput
from verify.models.cradle import cradle_system
from verify.records.results import case_from_record

CORNER = Path(__file__).resolve().parents[1] / "docs" / "examples" / "corner-map.json"


def run_cli(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _piece_holds(piece: dict, x: Fraction) -> bool:
    lo, hi = to_number(piece["lower"]), to_number(piece["upper"])
    assert isinstance(lo, Fraction) and isinstance(hi, Fraction)  # the corner's ends are rational here
    above = lo < x or (lo == x and piece["lower_closed"])
    below = x < hi or (x == hi and piece["upper_closed"])
    return above and below


def _points(data: dict, count: int, seed: int) -> list[tuple[dict, dict[str, Fraction]]]:
    """``count`` rational points on the map's lines: random ones, and the rational ends of its pieces."""
    rng = random.Random(seed)
    points = []
    for line in data["lines"]:
        for piece in line["pieces"]:
            for end in ("lower", "upper"):
                points.append((line, {**_fixed(line), line["free"]: to_number(piece[end])}))
    rng.shuffle(points)
    points = points[: count // 5]
    while len(points) < count:
        line = rng.choice(data["lines"])
        lo, hi = (to_number(line["interval"][k]) for k in ("lower", "upper"))
        points.append((line, {**_fixed(line), line["free"]: lo + (hi - lo) * Fraction(rng.randint(0, 997), 997)}))
    return points


def _fixed(line: dict) -> dict[str, Fraction]:
    return {n: to_number(v) for n, v in line["fixed"].items()}


def test_the_corner_map_agrees_with_single_exact_runs_at_100_rational_points(capsys) -> None:
    code, out, _ = run_cli(capsys, ["map", str(CORNER), "--json"])
    assert code == 0
    data = json.loads(out)
    assert data["layout"] == "grid of lines" and data["restitution"] == ["eps1", "eps2"]
    record = json.loads(CORNER.read_text())["cases"][0]
    points = _points(data, 100, seed=1)
    assert len(points) == 100 and len({tuple(sorted(p.items())) for _, p in points}) > 90
    for line, point in points:
        case = case_from_record({**record, "restitution": [str(point["eps1"]), str(point["eps2"])]})
        r = solve(case.system, case.velocity_source)
        x = point[line["free"]]
        (piece,) = [p for p in line["pieces"] if _piece_holds(p, x)]  # the corner exits everywhere here
        assert (r.stop, r.iterations) == ("exit", piece["iterations"]), point
        assert [list(J) for J in r.impact_sets] == piece["impact_sets"], point
        symbol = {line["free"]: sp.Symbol(line["free"])}
        velocity = [parse_number(v, symbols=symbol) for v in piece["exit_velocity"]]
        at = [
            v if isinstance(v, Fraction) else to_number(v.subs(symbol[line["free"]], sp.Rational(x))) for v in velocity
        ]
        assert at == list(r.exit_velocity), point


def test_the_general_map_of_the_cradle_is_the_cradle_map() -> None:
    """One shared eps over the cradle: the same parts as ``verify cradle-map`` (whose pages are made by it)."""
    cmap = cradle_map(max_impulses=10)
    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], max_impulses=10)
    assert m.layout == "interval" and len(m.lines) == 1
    expected = map_json(cmap)
    got = parts_json(m.lines[0].parts)
    for key in ("pieces", "non_terminating"):
        assert got[key] == expected[key], key
    ends = [[p[k] for k in ("lower", "upper", "lower_closed", "upper_closed")] for p in got["unexplored"]]
    assert ends == [[p[k] for k in ("lower", "upper", "lower_closed", "upper_closed")] for p in expected["unexplored"]]
    # what differs: only the three-ball cradle map knows that its unexplored parts exit after more impulses


def test_a_point_off_the_grid_is_refused_and_a_point_on_it_is_exact() -> None:
    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], ["e1", "e2"], {"e2": ("1/2", "1")}, lines=3, max_impulses=8)
    assert m.grid == {"e1": [0, Fraction(1, 2), 1], "e2": [Fraction(1, 2), Fraction(3, 4), 1]}
    part, velocity = m.at({"e1": "1", "e2": "3/4"})
    r = solve(cradle_system(["1", "3/4"], 3), ["1", "0", "0"])
    assert part.iterations == r.iterations and velocity == list(r.exit_velocity)
    with pytest.raises(Exception, match="on no line of the map"):
        m.at({"e1": "1/3", "e2": "2/3"})


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--parameter", "e=0,1"], "parameter 'e' appears in no COR"),
        (["--parameter", "eps1=1,0"], "the interval is reversed"),
        (["--parameter", "eps1=0,2"], "restitution[0] = eps1 is outside [0, 1]"),
        (["--parameter", "eps1"], "--parameter takes NAME=LO,HI"),
        (["--parameter", "eps1=0,pi/4"], "eps1 = pi/4 is not rational: the ends of a parameter's interval must be"),
        (["--case", "nope"], "no case 'nope'"),
    ],
)
def test_bad_map_input_is_one_line_and_exit_2(capsys, extra, message) -> None:
    code, out, err = run_cli(capsys, ["map", str(CORNER), *extra])
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err, err


def test_a_system_with_irrational_numbers_is_refused(tmp_path, capsys) -> None:
    case = json.loads(CORNER.read_text())
    case["cases"][0]["normals"][0][0] = "-sqrt(3)/3"
    path = tmp_path / "c.json"
    path.write_text(json.dumps(case))
    code, _, err = run_cli(capsys, ["map", str(path)])
    assert code == 2 and "a map needs a system of rational numbers" in err, err


def test_the_json_and_the_text_name_the_contacts_and_the_parameter() -> None:
    from verify.views.text import eps_map_text

    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], ["e", "1"], max_impulses=6)
    data = eps_map_json(m)
    assert data["contacts"] == ["S(1,2)", "S(2,3)"] and data["parameters"] == {"e": ["0", "1"]}
    velocities = [v for p in data["lines"][0]["pieces"] for v in p["exit_velocity"]]
    assert any("e" in v for v in velocities) and not any("eps" in v for v in velocities)
    assert "exit: (S(1,2))(S(2,3))" in eps_map_text(m)


@pytest.mark.parametrize("cors", [["e", "e"], ["e1", "e2"]])
def test_the_map_figure_is_drawn_for_one_and_two_parameters(tmp_path, cors) -> None:
    pytest.importorskip("matplotlib")
    from verify.views.figures import eps_map_figure

    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], cors, lines=2, max_impulses=6)
    path = eps_map_figure(m, tmp_path / "map.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 5000


def test_a_parts_exit_velocity_is_written_in_the_parameters_own_name() -> None:
    """Item 18 of issue 34: the library's ``Part.exit_velocity`` was written in ``eps`` whatever the parameter."""
    m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1]), ["1", "0"], ["e_out"])
    (part,) = m.lines[0].parts
    assert part.parameter == "e_out"
    assert {s.name for x in part.exit_velocity for s in sp.sympify(x).free_symbols} == {"e_out"}
    half = sp.Rational(1, 2)
    assert [sp.sympify(x).subs(sp.Symbol("e_out"), half) for x in part.exit_velocity] == [half / 2, 3 * half / 2]
    assert eps_map_json(m)["lines"][0]["pieces"][0]["exit_velocity"] == ["-(e_out - 1)/2", "(e_out + 1)/2"]


def test_the_text_says_where_the_exact_endpoints_are_for_its_caller(capsys) -> None:
    """Item 18: from the library, the text pointed at ``--json``, an option the library has not."""
    from verify.views.text import eps_map_text

    m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1]), ["1", "0"], ["e"])
    text = eps_map_text(m)
    assert "--json" not in text and "exact endpoints (in eps_map_json(m))" in text
    code, out, _ = run_cli(capsys, ["map", str(CORNER), "--lines", "2"])
    assert code == 0 and "exact endpoints (in --json)" in out


def test_an_irrational_velocity_is_named_as_the_velocity_not_as_a_parameter(tmp_path, capsys) -> None:
    """Item 18: ``velocity[0] = sqrt(2)`` was refused as if the parameters were irrational."""
    system = System([[1, 0], [0, 1]], [[-1, 1]], [1])
    with pytest.raises(InvalidInput) as info:
        eps_map(system, ["sqrt(2)", "0"], ["e"])
    message = str(info.value)
    assert message.startswith("velocity[0] = sqrt(2) is not rational: the velocity") and "parameters" not in message
    case = json.loads(CORNER.read_text())
    case["cases"][0]["velocity"][1] = "-sqrt(2)/10"
    path = tmp_path / "c.json"
    path.write_text(json.dumps(case))
    code, out, err = run_cli(capsys, ["map", str(path)])
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "cases[0]: velocity[1] = -sqrt(2)/10 is not rational: the velocity (and every number of the system)" in err
