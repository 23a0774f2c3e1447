"""The property suite on a family of one's own (a Hypothesis strategy or a case file), with public names
only: verdicts, reproducible counterexamples, and the example that takes a rod from its constraint
functions to its map and verdict table."""

from __future__ import annotations

import importlib.util
import itertools
import json
from pathlib import Path

import pytest
from hypothesis import strategies as st

from verify.cli import main
from verify.dynamics.system import System
from verify.errors import InvalidInput
from verify.laws.rule import solve
from verify.properties.own import family_verdicts
from verify.records.results import load_cases

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rod_on_floor.py"


def _example():
    spec = importlib.util.spec_from_file_location("rod_on_floor", EXAMPLE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def rod_verdicts():
    rods = _example().rods()
    chosen = ["kinetic energy does not increase", "the rule exits (termination)"]
    return family_verdicts(rods, "rod", properties=chosen, rules=("general", "symmetric"), examples=30)


def test_a_family_of_rods_gets_a_verdict_row_per_property_and_rule(rod_verdicts) -> None:
    rows = [(v.property, v.rule, v.family) for v in rod_verdicts]
    assert rows == [
        ("kinetic energy does not increase", "general", "rod"),
        ("kinetic energy does not increase", "symmetric", "rod"),
        ("the rule exits (termination)", "general", "rod"),
        ("the rule exits (termination)", "symmetric", "rod"),
    ]
    assert all(v.verdict in ("proved", "holds", "refuted") for v in rod_verdicts)
    termination = [v for v in rod_verdicts if v.property.startswith("the rule exits")]
    assert all(v.census() is not None and sum(v.census().values()) == v.cases for v in termination)


def test_refutations_are_case_records_that_verify_solve_reproduces(rod_verdicts, tmp_path, capsys) -> None:
    refuted = [v for v in rod_verdicts if v.verdict == "refuted"]
    assert refuted, "the rods refute energy under the general rule (different CORs)"
    for v in refuted:
        assert v.counterexample["id"].startswith(f"rod-{v.rule}-")
        path = tmp_path / f"{v.counterexample['id']}.json"
        path.write_text(json.dumps({"cases": [v.counterexample]}))
        assert main(["solve", str(path), "--rule", v.rule, "--json"]) == 0
        (record,) = json.loads(capsys.readouterr().out)["results"]
        if v.property.startswith("the rule exits"):
            assert record["stop"] != "exit"
        else:  # an impulse of the run raises the kinetic energy
            (case,) = load_cases(str(path))
            r = solve(case.system, case.velocity_source, rule=v.rule)
            energies = [r.kinetic_energy_in, *(step.kinetic_energy for step in r.steps)]
            assert any(b > a for a, b in itertools.pairwise(energies)), record


def test_the_same_strategy_gives_the_same_counterexamples(rod_verdicts) -> None:
    again = family_verdicts(_example().rods(), "rod", properties=["kinetic energy"], examples=30)
    first = [v for v in rod_verdicts if v.property.startswith("kinetic") and v.rule == "general"]
    assert [v.counterexample for v in again] == [v.counterexample for v in first]


def test_a_case_file_is_a_family_too(tmp_path) -> None:
    cases = [
        {"id": f"block-{e}", "mass_matrix": [["1"]], "normals": [["1"]], "restitution": [e], "velocity": ["-1"]}
        for e in ("0", "1/2", "1")
    ]
    path = tmp_path / "blocks.json"
    path.write_text(json.dumps({"cases": cases}))
    (v,) = family_verdicts(str(path), "block", properties=["the exit velocity is outgoing"], examples=10)
    assert (v.family, v.verdict) == ("block", "holds")


@pytest.mark.parametrize("part", ["termination", "TERMINATION", "exits (term"])
def test_a_property_is_chosen_by_a_part_of_its_name_as_the_docstring_says(part) -> None:
    """Item 14 of issue 34: "termination" is part of one name only, not its start."""
    wall = st.just((System([[1]], [[1]], ["1/2"]), ["-1"]))
    (v,) = family_verdicts(wall, "block", properties=[part], examples=2)
    assert v.property == "the rule exits (termination)" and v.family == "block"


def test_a_part_of_several_names_is_refused_as_ambiguous() -> None:
    wall = st.just((System([[1]], [[1]], ["1/2"]), ["-1"]))
    with pytest.raises(InvalidInput, match=r"property 'rule' is ambiguous: it is part of \d+ names"):
        family_verdicts(wall, "block", properties=["rule"], examples=2)
    with pytest.raises(InvalidInput, match=r"unknown property 'no such'"):
        family_verdicts(wall, "block", properties=["no such"], examples=2)


def test_a_system_that_is_not_rational_is_refused() -> None:
    def tilted(_: object) -> tuple[System, list[str]]:
        return System([[1, 0], [0, 1]], [["1", "sqrt(2)"]], ["1/2"]), ["-1", "0"]

    with pytest.raises(InvalidInput, match="systems of rational numbers"):
        family_verdicts(st.just(0).map(tilted), "tilted", properties=["the exit velocity is outgoing"], examples=2)


def test_the_rod_example_maps_and_runs() -> None:
    module = _example()
    m = module.rod_map(lines=2)
    assert m.layout == "grid of lines" and m.system.names == ("left", "right")
    part, velocity = m.at({"e_left": "1", "e_right": "1/3"})
    r = module.solve(module.rod(cors=("1", "1/3")), ["0", "-1", "1/4"])
    assert (part.stop, part.iterations, velocity) == (r.stop, r.iterations, list(r.exit_velocity))


def test_a_drawn_case_keeps_the_contacts_names() -> None:
    """A counterexample of a family whose system names its contacts carries the names (a case may name
    them: docs/records.md); a system without names gives a record without the field, as before."""
    from verify.dynamics.system import System
    from verify.properties.own import drawn_case

    named = System([[1, 0], [0, 1]], [[0, 1], [1, 0]], ["1/2", "1/2"], names=["floor", "wall"])
    assert drawn_case("rod", "general", named, ["-1", "-1"]).record["names"] == ["floor", "wall"]
    plain = System([[1, 0], [0, 1]], [[0, 1], [1, 0]], ["1/2", "1/2"])
    assert "names" not in drawn_case("rod", "general", plain, ["-1", "-1"]).record
