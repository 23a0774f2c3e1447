"""A cradle against a fixed wall in the engine adapters: the scene, the closing speed, and Box2D end to end.

The scene and the closing speed are pure Python (always run); Box2D, the one engine of the test
extra, runs a ball against the wall (exit ``-e v``) and two balls against it (the sequential law
with Box2D's 8 sweeps and its 1 m/s threshold), and is skipped when it is not installed.
"""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from verify.engines.common import cradle_closing
from verify.engines.protocol import Adapter
from verify.engines.scene import Cradle, Unsupported, scene_of
from verify.laws.rule import solve
from verify.laws.sequential import Sequential
from verify.models.cradle import cradle_geometry
from verify.records.results import case_from_record, case_record

ROOT = Path(__file__).resolve().parents[2]
HALF = Fraction(1, 2)


def walled(case_id: str, masses: list[Any], cors: list[str], velocity: list[str]) -> dict[str, Any]:
    """A case record of a cradle whose last ball touches a fixed wall."""
    g, normals = cradle_geometry([Fraction(m) for m in masses], wall=True)
    return case_record(case_id, g, normals, cors, velocity)


# -- the scene ---------------------------------------------------------------------------------


def test_a_walled_cradle_is_recognised_with_its_masses_and_cors() -> None:
    s = scene_of(walled("w", [1, 2], ["1/2", "1"], ["3", "0"]))
    assert isinstance(s, Cradle) and s.wall
    assert list(s.masses) == [1, 2] and list(s.cors) == [HALF, 1] and list(s.velocity) == [3, 0]


def test_one_ball_against_a_wall_is_a_cradle() -> None:
    s = scene_of(walled("w1", [3], ["1/2"], ["100"]))
    assert isinstance(s, Cradle) and s.wall
    assert list(s.masses) == [3] and list(s.cors) == [HALF] and list(s.velocity) == [100]


def test_a_cradle_without_its_wall_has_none() -> None:
    g, normals = cradle_geometry([Fraction(1)] * 2)
    s = scene_of(case_record("c", g, normals, ["1"], ["100", "0"]))
    assert isinstance(s, Cradle) and not s.wall


def test_an_adapter_that_builds_no_wall_skips_a_walled_cradle() -> None:
    class NoWalls(Adapter):
        name = "nowalls"

        def cradle(self, scene: Cradle) -> list[float]:
            return [0.0] * len(scene.masses)

    with pytest.raises(Unsupported, match="wall"):
        NoWalls().run(scene_of(walled("w", [1], ["1"], ["1"])))


# -- the closing speed -------------------------------------------------------------------------


def test_the_last_ball_moving_into_the_wall_is_closing() -> None:
    assert cradle_closing([0.0, 1.0]) == -1.0  # the balls part
    assert cradle_closing([0.0, 1.0], wall=True) == 1.0  # but the last one still moves into the wall
    assert cradle_closing([-2.0, -1.0], wall=True) == -1.0  # all leave the wall
    assert cradle_closing([5.0], wall=True) == 5.0  # one ball against the wall
    assert cradle_closing([3.0, 1.0, 2.0], wall=True) == cradle_closing([3.0, 1.0, 2.0]) == 2.0


# -- Box2D end to end --------------------------------------------------------------------------


def box2d(cases: list[dict[str, Any]]) -> dict[str, list[float]]:
    """Box2D's exit velocities for the cases (skipped when Box2D is not installed)."""
    if importlib.util.find_spec("Box2D") is None:
        pytest.skip("Box2D is not installed")
    done = subprocess.run(
        [sys.executable, "-m", "verify.engines.adapters.box2d"],
        input=json.dumps({"cases": cases}),
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert out["skipped"] == []
    return {r["id"]: [float(x) for x in r["exit_velocity"]] for r in out["results"]}


@pytest.mark.parametrize("cor", ["1", "1/2"])
def test_box2d_sends_one_ball_back_from_the_wall_at_minus_e_v(cor: str) -> None:
    (v,) = box2d([walled("w1", [1], [cor], ["100"])])["w1"]
    assert v == pytest.approx(-float(Fraction(cor)) * 100, rel=1e-6)  # float32


@pytest.mark.parametrize("cor", ["1", "1/2"])
def test_box2d_two_balls_against_a_wall_follow_the_sequential_law(cor: str) -> None:
    case = walled("w2", [1, 1], [cor, cor], ["100", "0"])
    got = box2d([case])["w2"]
    c = case_from_record(case)
    exact = solve(c.system, c.velocity_source, law=Sequential(8, threshold=1), trace=False)
    want = [float(Fraction(exact.backend.to_decimal(x, 30))) for x in exact.exit_velocity]
    assert got == pytest.approx(want, rel=1e-5, abs=1e-5 * 100)
