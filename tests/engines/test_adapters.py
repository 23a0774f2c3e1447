"""The engine adapters (``python -m verify.engines.adapters.ENGINE``): their frame, physical laws, settings, skips.

One table, :data:`ENGINES`, says what differs between the five adapters; the checks they all
share are parametrized over it, each engine run skipped (``pytest.importorskip``) when the
engine is not installed. Every adapter runs the same cases, :data:`CRADLES` and
:data:`CORNERS`, and no engine output is written here beyond physical laws: momentum is
conserved in a cradle, no contact approaches at the exit, a frictionless disk keeps its spin.
Below them: the per-body restitution solvers (pure Python, always run) and MuJoCo's COR to
damping mapping.
"""

from __future__ import annotations

import functools
import importlib
import io
import json
import math
import operator
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

from verify.engines.adapters.mujoco import damping_ratio
from verify.engines.protocol import NOT_INSTALLED, Adapter
from verify.engines.scene import Unsupported
from verify.models.corner import corner_geometry
from verify.models.cradle import cradle_geometry
from verify.records.results import case_record

ROOT = Path(__file__).resolve().parents[2]
SLOPE = Fraction(1, 2)
HALF = Fraction(1, 2)
#: id -> (masses, CORs, velocity): cradles, some of which an engine cannot give its CORs
CRADLES: dict[str, tuple[list[Any], list[Any], list[Any]]] = {
    "cradle-eps-1": ([1, 1, 1], [1, 1], [100, 0, 0]),
    "cradle-121": ([1, 2, 1], [HALF, 1], [3, 0, -3]),
    "cradle-121-slow": ([1, 2, 1], [HALF, 1], [1, 0, -1]),
    "cradle-121-cor-0": ([1, 2, 1], [HALF, 0], [3, 0, -3]),
    "cradle-half-1-half": ([1, 1, 1, 1], [HALF, 1, HALF], [10, 0, 0, 0]),  # not by per-body max
    "cradle-1-half-1": ([1, 1, 1, 1], [1, HALF, 1], [1, 0, 0, 0]),  # per-body products in [0, 1]: all four at 1
    "cradle-1-0-1": ([1, 1, 1, 1], [1, 0, 1], [10, 0, 0, 0]),  # not by per-body products
    "cradle-cor-above-1": ([1, 1, 1], [Fraction(3, 2), 1], [10, 0, 0]),
}
#: id -> (CORs of S1 and S2, velocity (vx, vy, omega)): a disk between the walls of slope SLOPE
CORNERS: dict[str, tuple[list[Any], list[Any]]] = {
    "corner-spin": ([HALF, 1], [10, 1, 5]),
    "corner-spin-slow": ([HALF, 1], [1, Fraction(1, 10), 5]),
}


def _case_text() -> str:
    cases = []
    for case_id, (masses, cors, velocity) in CRADLES.items():
        g, normals = cradle_geometry(masses)
        cases.append(case_record(case_id, g, normals, cors, velocity))
    for case_id, (cors, velocity) in CORNERS.items():
        g, normals = corner_geometry(SLOPE)
        cases.append(case_record(case_id, g, normals, cors, velocity))
    return json.dumps({"cases": cases})


@dataclass(frozen=True)
class Engine:
    """What the shared checks need to know of one adapter."""

    imports: str  #: the engine's module, for pytest.importorskip
    tol: float  #: relative tolerance of the physical laws
    describes: tuple[tuple[str, str], ...]  #: (field, word): words of the description (how restitution combines)
    has: tuple[str, ...]  #: settings that the description must list
    sets: dict[str, float]  #: --set values that the printed settings must show
    bad: tuple[str, ...]  #: out-of-range settings (beyond an unknown name and reverse_order=2)
    skipped: dict[str, str]  #: the cases the adapter cannot build, with a word of each reason
    #: the same with per-body values (--set per_contact=0), for the engines that have that mode
    per_body_skipped: dict[str, str] | None = field(default=None)


ENGINES: dict[str, Engine] = {
    # Box2D computes in single precision (float32): positions, velocities and impulses carry about
    # 1e-7 relative rounding, so momentum and the exit conditions hold to that, not to double precision.
    "box2d": Engine(
        imports="Box2D",
        tol=1e-6,
        describes=(("combine_rule", "max"),),
        has=("time_step", "velocity_iterations", "overlap", "reverse_order", "per_contact"),
        sets={"time_step": 0.002, "velocity_iterations": 1, "reverse_order": 1},
        bad=("per_contact=2", "time_step=0"),
        skipped={},  # per contact, every COR can be given
        per_body_skipped={"cradle-half-1-half": "combined by max (Box2D)", "cradle-cor-above-1": "in [0, 1] only"},
    ),
    # the others compute in double precision
    "pymunk": Engine(
        imports="pymunk",
        tol=1e-9,
        describes=(("combine_rule", "product"),),
        has=("time_step", "iterations", "overlap", "reverse_order", "per_contact"),
        sets={"time_step": 0.002, "iterations": 1, "reverse_order": 1},
        bad=("per_contact=2", "time_step=0"),
        skipped={},  # per contact, every COR can be given
        per_body_skipped={
            "cradle-1-0-1": "the COR 0",
            "cradle-1-half-1": "every value in [0, 1]",
            "cradle-cor-above-1": "in [0, 1] only",
        },
    ),
    "pybullet": Engine(
        imports="pybullet",
        tol=1e-9,
        describes=(("combine_rule", "product"),),
        has=("time_step", "solver_iterations", "overlap", "reverse_order"),
        sets={"time_step": 0.002, "solver_iterations": 1, "reverse_order": 1},
        bad=("time_step=0",),
        skipped={"cradle-1-0-1": "the COR 0"},  # Bullet takes restitutions above 1: only a 0 between positive CORs
    ),
    "mujoco": Engine(
        imports="mujoco",
        tol=1e-9,
        describes=(("cor_setting", "solref"), ("cor_setting", "e = 0"), ("combine_rule", "no restitution")),
        has=("timestep", "stiffness", "iterations", "overlap", "reverse_order"),
        sets={"timestep": 0.0002, "solimp_dmax": 0.5, "reverse_order": 1},
        bad=("solver=3",),
        skipped={"cradle-cor-above-1": "damping"},
    ),
    "dartpy": Engine(
        imports="dartpy",
        tol=1e-9,
        describes=(("combine_rule", "product"),),
        has=("time_step", "lcp_solver", "pgs_iterations", "overlap", "reverse_order"),
        sets={"time_step": 0.002, "lcp_solver": 1, "reverse_order": 1},
        bad=("lcp_solver=7",),
        skipped={
            "cradle-1-0-1": "the COR 0",
            "cradle-1-half-1": "every value in [0, 1]",
            "cradle-cor-above-1": "in [0, 1] only",
        },
    ),
}
#: (engine, mode): every engine per contact or per body as it can, and per_contact=0 where it is a setting
RUNS = [(name, "default") for name in ENGINES] + [
    (name, "per_body") for name, e in ENGINES.items() if e.per_body_skipped is not None
]


def adapter_class(name: str) -> type[Adapter]:
    """The engine's adapter (importing the adapter module imports no engine)."""
    main = importlib.import_module(f"verify.engines.adapters.{name}").main
    owner: type[Adapter] = main.__self__
    return owner


@functools.cache
def _output(name: str, mode: str) -> dict[str, Any]:
    args = ["--set", "per_contact=0"] if mode == "per_body" else []
    done = subprocess.run(
        [sys.executable, "-m", f"verify.engines.adapters.{name}", *args],
        input=_case_text(),
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    data: dict[str, Any] = json.loads(done.stdout)  # nothing but the JSON on stdout
    return data


def output(name: str, mode: str = "default") -> dict[str, Any]:
    """The adapter's output for the cases (run once per engine and mode); skipped when not installed."""
    pytest.importorskip(ENGINES[name].imports)
    return _output(name, mode)


def expected_skips(name: str, mode: str) -> dict[str, str]:
    e = ENGINES[name]
    return (e.per_body_skipped or {}) if mode == "per_body" else e.skipped


def velocities(out: dict[str, Any]) -> dict[str, list[float]]:
    return {r["id"]: [float(x) for x in r["exit_velocity"]] for r in out["results"]}


# -- the frame and the laws, for every engine --------------------------------------------------


@pytest.mark.parametrize(("name", "mode"), RUNS)
def test_the_output_has_the_protocol_shape(name: str, mode: str) -> None:
    out = output(name, mode)
    assert set(out) == {"engine", "results", "skipped"}
    engine = out["engine"]
    assert set(engine) == {"name", "package", "version", "combine_rule", "cor_setting", "settings", "alternate",
                           "solver"}  # fmt: skip
    assert engine["solver"]["kind"] in ("sequential", "simultaneous", "soft", "position-based")
    assert engine["solver"]["precision"] in ("float32", "float64")
    assert engine["name"] == engine["package"] == name and engine["version"]
    assert all(word in engine[described] for described, word in ENGINES[name].describes)
    assert set(engine["settings"]) >= {*ENGINES[name].has, *ENGINES[name].sets}
    assert engine["alternate"]["setting"] in engine["settings"]
    if ENGINES[name].per_body_skipped is not None:
        assert engine["settings"]["per_contact"] == (0 if mode == "per_body" else 1)
    skipped = expected_skips(name, mode)
    assert sorted(r["id"] for r in out["results"]) == sorted((set(CRADLES) | set(CORNERS)) - set(skipped))
    for r in out["results"]:
        assert len(r["exit_velocity"]) == (len(CRADLES[r["id"]][0]) if r["id"] in CRADLES else 3)
        assert all(isinstance(x, str) and math.isfinite(float(x)) for x in r["exit_velocity"])


@pytest.mark.parametrize(("name", "mode"), RUNS)
def test_the_cases_an_engine_cannot_build_are_skipped_with_a_reason(name: str, mode: str) -> None:
    skipped = {s["id"]: s["reason"] for s in output(name, mode)["skipped"]}
    expected = expected_skips(name, mode)
    assert set(skipped) == set(expected)
    for case_id, word in expected.items():
        assert word in skipped[case_id], skipped[case_id]


@pytest.mark.parametrize(("name", "mode"), RUNS)
def test_a_cradle_conserves_momentum_and_separates(name: str, mode: str) -> None:
    tol = ENGINES[name].tol
    exits = velocities(output(name, mode))
    checked = 0
    for case_id, (masses, _, before) in CRADLES.items():
        if case_id not in exits:
            continue
        v = exits[case_id]
        p0 = sum(m * x for m, x in zip(masses, before))
        p1 = sum(m * x for m, x in zip(masses, v))
        scale = sum(m * abs(x) for m, x in zip(masses, before))
        assert abs(p1 - p0) <= tol * scale, case_id
        assert all(v[i] <= v[i + 1] + tol * scale for i in range(len(v) - 1)), (case_id, v)  # no contact approaches
        checked += 1
    assert checked >= 5


@pytest.mark.parametrize(("name", "mode"), RUNS)
def test_the_corner_disk_leaves_both_walls_and_keeps_its_spin(name: str, mode: str) -> None:
    tol, k = ENGINES[name].tol, float(SLOPE)
    exits = velocities(output(name, mode))
    for case_id, (_, before) in CORNERS.items():
        vx, vy, omega = exits[case_id]
        scale = float(max(abs(before[0]), abs(before[1])))  # the larger velocity component
        assert k * vx - vy <= tol * scale and k * vx + vy <= tol * scale, case_id  # no approach towards S1 or S2
        assert omega == pytest.approx(float(before[2]), abs=tol * scale), case_id


@pytest.mark.parametrize("name", ENGINES)
def test_describe_prints_the_engine_and_set_changes_its_settings(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    """``--describe`` prints the ``engine`` object of the output, with the ``--set`` values in its settings."""
    engine = output(name)["engine"]
    sets = ENGINES[name].sets
    assert adapter_class(name).main(["--describe", *(f"--set={k}={v!r}" for k, v in sets.items())]) == 0
    described = json.loads(capsys.readouterr().out)
    assert {**described, "settings": engine["settings"]} == engine
    assert described["settings"] == {**engine["settings"], **sets}
    assert all(engine["settings"][k] != v for k, v in sets.items())  # each is a change


@pytest.mark.parametrize("name", ENGINES)
def test_an_unknown_or_out_of_range_setting_exits_2(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    main = adapter_class(name).main
    for setting in ("no_such_setting=1", "reverse_order=2", *ENGINES[name].bad):
        assert main(["--describe", "--set", setting]) == 2, setting
        err = capsys.readouterr().err
        assert err.startswith(f"{name}: ") and setting.partition("=")[0] in err, err


@pytest.mark.parametrize("name", ENGINES)
@pytest.mark.parametrize("args", [["--describe"], []])
def test_an_engine_that_is_not_installed_exits_3_with_one_line(
    name: str, args: list[str], monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    """Runs whether or not the engine is installed: its module is made unimportable."""
    monkeypatch.setitem(sys.modules, ENGINES[name].imports, None)
    monkeypatch.setattr(sys, "stdin", io.StringIO(_case_text()))
    cls = adapter_class(name)
    assert cls.main(args) == NOT_INSTALLED
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.splitlines()
    assert line.startswith(f"{name}: not installed (") and line.endswith(f"pip install {cls.package}")


# -- per-body restitutions through a combine rule -----------------------------------------------

SOLVABLE = ([1.0, 1.0], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0], [1.0, 0.0], [0.9, 0.6, 0.3, 0.2], [0.0, 0.0, 0.0])
#: engine -> (its combine rule, whether its per-body values are at most 1, more solvable CORs, unsolvable CORs)
PER_BODY: dict[str, tuple[Callable[[float, float], float], bool, list[list[float]], list[list[float]]]] = {
    "box2d": (max, True, [[1.0, 0.5, 1.0]], [[0.5, 1.0, 0.5], [0.2, 0.9, 0.4, 0.9, 0.1], [1.5, 1.0], [-0.1, 1.0]]),
    "pymunk": (
        operator.mul,
        True,
        [[0.5, 1.0, 0.5]],
        [[1.0, 0.0, 1.0], [1.0, 0.25, 1.0], [1.0, 0.5, 1.0], [0.5, 0.0, 0.5], [1.5, 1.0], [-0.1, 1.0]],
    ),
    "pybullet": (
        operator.mul,
        False,
        [[1.0, 0.25, 1.0], [1.5, 1.0]],
        [[1.0, 0.0, 1.0], [0.5, 0.0, 0.5, 0.5], [-0.1, 1.0]],
    ),
    "dartpy": (
        operator.mul,
        True,
        [[0.5, 1.0, 0.5]],
        [[1.0, 0.0, 1.0], [1.0, 0.25, 1.0], [1.0, 0.5, 1.0], [0.5, 0.0, 0.5], [1.5, 1.0], [-0.1, 1.0]],
    ),
}


def body_values(name: str, cors: list[float]) -> list[float]:
    """The adapter's per-body values (``per_contact=0`` where that is a setting)."""
    overrides = {"per_contact": 0.0} if "per_contact" in adapter_class(name).settings else {}
    adapter: Any = adapter_class(name)(overrides)
    values: list[float] = adapter.body_values(cors)
    return values


@pytest.mark.parametrize("name", PER_BODY)
def test_per_body_values_combine_to_the_cors(name: str) -> None:
    rule, at_most_1, more, _ = PER_BODY[name]
    for cors in [*SOLVABLE, *more]:
        r = body_values(name, cors)
        assert all(0.0 <= x <= (1.0 if at_most_1 else math.inf) for x in r), (cors, r)
        assert [rule(r[i], r[i + 1]) for i in range(len(cors))] == pytest.approx(cors, rel=1e-15, abs=0)


@pytest.mark.parametrize("name", PER_BODY)
def test_per_body_values_that_do_not_exist_are_unsupported(name: str) -> None:
    for cors in PER_BODY[name][3]:
        with pytest.raises(Unsupported):
            body_values(name, cors)


# -- MuJoCo: a COR as the damping of a spring-damper -------------------------------------------


@pytest.mark.parametrize("e", [1.0, 0.999, 0.5, 0.1, 1e-3])
def test_the_damping_ratio_is_that_of_a_linear_spring_damper(e: float) -> None:
    zeta = damping_ratio(e)
    assert 0 <= zeta < 1
    assert math.exp(-zeta * math.pi / math.sqrt(1 - zeta * zeta)) == pytest.approx(e, rel=1e-12)


def test_a_cor_of_0_maps_to_critical_damping() -> None:
    assert damping_ratio(0.0) == 1.0
