"""The map of any system (``verify map``, :func:`verify.maps.general.eps_map`): checked point by
point against single exact runs, and against the cradle map it generalises."""

from __future__ import annotations

import json
import random
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp

from verify.cli import main
from verify.dynamics.system import System
from verify.errors import InvalidInput
from verify.laws.rule import solve
from verify.maps.cradle import cradle_map, map_json
from verify.maps.general import eps_map, eps_map_json
from verify.maps.line import parts_json
from verify.models.cradle import cradle_system
from verify.numbers.format import format_decimal
from verify.numbers.parse import parse_number, to_number
from verify.records.results import case_from_record

CORNER = Path(__file__).resolve().parents[2] / "docs" / "examples" / "corner-map.json"


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
    code, out, _ = run_cli(capsys, ["map", str(CORNER), "--json", "--grid"])
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


def test_a_system_with_algebraic_numbers_is_mapped_and_others_are_refused(tmp_path, capsys) -> None:
    """Issue 37, item 5: a normal of -sqrt(3)/3 is mapped over Q(sqrt(3)); a number that is not algebraic is
    refused with exit code 2, naming it."""
    case = json.loads(CORNER.read_text())
    case["cases"][0]["normals"][0][0] = "-sqrt(3)/3"
    path = tmp_path / "c.json"
    path.write_text(json.dumps(case))
    code, out, _ = run_cli(capsys, ["map", str(path), "--lines", "2", "--max-impulses", "4", "--json"])
    assert code == 0 and "sqrt(3)" in out
    case["cases"][0]["normals"][0][0] = "-tan(3/10)"
    path.write_text(json.dumps(case))
    code, out, err = run_cli(capsys, ["map", str(path)])
    assert code == 2 and out == "" and "cases[0].normals[0][0] = -tan(3/10) is not an algebraic number" in err, err


def test_the_json_and_the_text_name_the_contacts_and_the_parameter() -> None:
    from verify.maps.text import eps_map_text

    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], ["e", "1"], max_impulses=6)
    data = eps_map_json(m)
    assert data["contacts"] == ["S(1,2)", "S(2,3)"] and data["parameters"] == {"e": ["0", "1"]}
    velocities = [v for p in data["lines"][0]["pieces"] for v in p["exit_velocity"]]
    assert any("e" in v for v in velocities) and not any("eps" in v for v in velocities)
    assert "exit: (S(1,2))(S(2,3))" in eps_map_text(m)


@pytest.mark.parametrize("cors", [["e", "e"], ["e1", "e2"]])
def test_the_map_figure_is_drawn_for_one_and_two_parameters(tmp_path, cors) -> None:
    pytest.importorskip("matplotlib")
    from verify.maps.figures import eps_map_figure

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
    from verify.maps.text import eps_map_text

    m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1]), ["1", "0"], ["e"])
    text = eps_map_text(m)
    assert "--json" not in text and "exact endpoints (in eps_map_json(m))" in text
    code, out, _ = run_cli(capsys, ["map", str(CORNER), "--lines", "2"])
    assert code == 0 and "exact endpoints (in --json)" in out


def test_a_velocity_that_is_not_algebraic_is_named_as_the_velocity_not_as_a_parameter(tmp_path, capsys) -> None:
    """Item 18: ``velocity[0] = sqrt(2)`` was refused as if the parameters were irrational (it is mapped now, over
    Q(sqrt(2)): issue 37); a velocity that is not algebraic is refused as the velocity."""
    system = System([[1, 0], [0, 1]], [[-1, 1]], [1])
    (part,) = eps_map(system, ["sqrt(2)", "0"], ["e"]).lines[0].parts
    assert part.stop == "exit" and "sqrt(2)" in str(part.exit_velocity[0])
    with pytest.raises(InvalidInput) as info:
        eps_map(system, ["pi", "0"], ["e"])
    message = str(info.value)
    assert message == "a map needs algebraic numbers: velocity[0] = pi is not algebraic"
    case = json.loads(CORNER.read_text())
    case["cases"][0]["velocity"][1] = "-pi/10"
    path = tmp_path / "c.json"
    path.write_text(json.dumps(case))
    code, out, err = run_cli(capsys, ["map", str(path)])
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert "cases[0].velocity[1] = -pi/10 is not an algebraic number" in err


# -- item 20 of issue 34: the figure's legend, `verify map --figure`, contacts named by the case -----------------


def _named_cradle(tmp_path: Path, names: list | None, cors: tuple[str, str] = ("e", "e")) -> Path:
    """A three-ball cradle case file whose CORs name ``e``, its contacts named by ``names`` (when given)."""
    unit = [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]]
    case = {"id": "cradle", "mass_matrix": unit, "normals": [["-1", "1", "0"], ["0", "-1", "1"]],
            "restitution": list(cors), "velocity": ["1", "0", "0"]}  # fmt: skip
    if names is not None:
        case["names"] = names
    path = tmp_path / "cradle.json"
    path.write_text(json.dumps({"cases": [case]}))
    return path


def test_the_one_parameter_figure_has_a_legend_entry_for_never_exits_and_unexplored() -> None:
    """The figure drew "never exits" and "unexplored" as lines at impulses = 0, with no legend entry: now
    they are shaded bands over their intervals, each named in the legend."""
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Patch

    from verify.maps.figures import eps_map_plot

    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], max_impulses=8)
    stops = {p.stop for p in m.lines[0].parts}
    assert {"non_terminating", "max_iterations", "exit"} <= stops  # the three kinds are there to be drawn
    fig = eps_map_plot(m)
    try:
        ax = fig.axes[0]
        legend = ax.get_legend()
        assert legend is not None
        entries = dict(zip([t.get_text() for t in legend.get_texts()], legend.legend_handles, strict=True))
        never, unexplored = entries["never exits (proved)"], entries["unexplored: still impacting after 8 impulses"]
        assert isinstance(never, Patch) and isinstance(unexplored, Patch) and "exit after k impulses" in entries
        assert never.get_facecolor() != unexplored.get_facecolor()
        bands = {(round(b.get_x(), 12), round(b.get_x() + b.get_width(), 12)): b.get_facecolor() for b in ax.patches}
        for part in m.lines[0].parts:  # each part that does not exit is a band over its interval, as in the legend
            if part.stop != "exit":
                ends = tuple(round(float(format_decimal(x, 17)), 12) for x in (part.piece.lower, part.piece.upper))
                assert bands[ends] == (never if part.stop == "non_terminating" else unexplored).get_facecolor()
        heights = {
            y for c in ax.collections if isinstance(c, LineCollection) for s in c.get_segments() for y in s[:, 1]
        }
        assert heights and 0 not in heights  # nothing is drawn at impulses = 0
    finally:
        plt.close(fig)


def test_the_grid_figure_names_never_exits_and_unexplored_in_its_legend() -> None:
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from verify.maps.figures import eps_map_plot

    m = eps_map(cradle_system("1", 3), ["1", "0", "0"], ["e1", "e2"], lines=2, max_impulses=6)
    fig = eps_map_plot(m)
    try:
        labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        assert labels == ["never exits (proved)", "unexplored: still impacting after 6 impulses"]
    finally:
        plt.close(fig)


def test_verify_map_draws_its_figure_with_the_contacts_names(tmp_path, capsys) -> None:
    pytest.importorskip("matplotlib")
    path = _named_cradle(tmp_path, ["ball 1-2", "ball 2-3"])
    figure = tmp_path / "out" / "map.png"
    figure.parent.mkdir()
    code, out, err = run_cli(capsys, ["map", str(path), "--max-impulses", "6", "--figure", str(figure)])
    assert code == 0 and err == f"figure written to {figure}\n", err
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and sorted(p.name for p in figure.parent.iterdir()) == [
        "map.png"
    ]
    assert "CORs ball 1-2 = e, ball 2-3 = e" in out and "exit: (ball 1-2)(ball 2-3)(ball 1-2)" in out


def test_verify_map_figure_refuses_a_bad_path_in_one_line(tmp_path, capsys) -> None:
    path = _named_cradle(tmp_path, None)
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    for bad, message in ((str(blocker / "map.png"), "is a file"), (str(tmp_path / "map.svg"), "ending in .png")):
        code, out, err = run_cli(capsys, ["map", str(path), "--figure", bad])
        assert code == 2 and out == "" and err.count("\n") == 1, err
        assert "--figure" in err and message in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a-file", "cradle.json"]


def test_verify_map_figure_is_written_whole_or_not_at_all(tmp_path, capsys, monkeypatch) -> None:
    """A write that fails half-way (a full disk) leaves neither a half figure nor a temporary file."""
    pytest.importorskip("matplotlib")
    import builtins
    import errno

    from verify.records import files

    class FullDisk:
        """A file that takes the first 100 bytes, then finds the disk full."""

        def __init__(self, name, mode) -> None:
            self.name, self.fh = name, builtins.open(name, mode)  # noqa: SIM115 (closed by __exit__)

        def __enter__(self):
            return self

        def __exit__(self, *exc) -> None:
            self.fh.close()

        def write(self, data) -> None:
            self.fh.write(data[:100])
            raise OSError(errno.ENOSPC, "No space left on device", str(self.name))

    def full_disk(name, mode="r", *args, **kwargs):
        if "w" in mode and str(name).endswith(".png" + files.TMP_SUFFIX):
            return FullDisk(name, mode)
        return builtins.open(name, mode, *args, **kwargs)

    monkeypatch.setattr(files, "open", full_disk, raising=False)
    path = _named_cradle(tmp_path, None)
    figure = tmp_path / "map.png"
    code, _, err = run_cli(capsys, ["map", str(path), "--max-impulses", "4", "--figure", str(figure)])
    assert code == 2 and err.count("\n") == 1 and "--figure" in err and "No space left on device" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cradle.json"]


def test_a_case_names_its_contacts_and_the_results_maps_and_figures_use_the_names(tmp_path, capsys) -> None:
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from verify.maps.figures import eps_map_plot
    from verify.maps.general import case_map
    from verify.records.results import load_cases

    named = _named_cradle(tmp_path, ["ball 1-2", "ball 2-3"], cors=("1/2", "1/2"))
    (case,) = load_cases(str(named))
    assert case.system.names == ("ball 1-2", "ball 2-3")
    code, out, _ = run_cli(capsys, ["solve", str(named)])
    assert code == 0 and "impact sets: {ball 1-2} {ball 2-3} {ball 1-2}" in out, out
    unnamed = _named_cradle(tmp_path, None, cors=("1/2", "1/2"))
    code, out, _ = run_cli(capsys, ["solve", str(unnamed)])
    assert code == 0 and "impact sets: {0} {1} {0}" in out, out  # unnamed: the 0-based indices, as before
    m = case_map(str(_named_cradle(tmp_path, ["left pair", "right pair"], cors=("e", "1/2"))), max_impulses=6)
    assert eps_map_json(m)["contacts"] == ["left pair", "right pair"]
    fig = eps_map_plot(m)
    try:
        assert "left pair = e, right pair = 1/2" in fig.axes[0].get_title()
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    ("names", "message"),
    [
        (["a", "a"], 'cases[0].names: "a" appears twice'),
        (["a"], "cases[0].names: expected 2 names (one per row of normals), got 1"),
        (["a", ""], "cases[0].names[1]: empty"),
        (["a", " "], "cases[0].names[1]: expected a non-empty string, got ' '"),
        (["a", 3], "cases[0].names[1]: expected a string, got 3"),
        ("a,b", 'cases[0].names: expected a list, got "a,b"'),
    ],
)
@pytest.mark.parametrize("command", ["solve", "map"])
def test_bad_contact_names_are_refused_in_one_line(tmp_path, capsys, names, message, command) -> None:
    path = _named_cradle(tmp_path, names, cors=("e", "e") if command == "map" else ("1/2", "1/2"))
    code, out, err = run_cli(capsys, [command, str(path)])
    assert code == 2 and out == "" and err.count("\n") == 1 and message in err, err


def test_system_checks_the_names_it_is_given() -> None:
    with pytest.raises(InvalidInput, match=r"names\[1\] = 'x' repeats names\[0\]"):
        System([[1, 0], [0, 1]], [[-1, 1], [0, 1]], [1, 1], names=["x", "x"])
    with pytest.raises(InvalidInput, match=r"names\[0\]: expected a non-empty string, got 7"):
        System([[1, 0], [0, 1]], [[-1, 1]], [1], names=[7])
