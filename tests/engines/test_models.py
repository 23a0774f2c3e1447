"""The engines' step models (verify.engines.models): each recomputes a known engine answer of the committed record
from the engine's own settings, exactly (no float in the path), and verify oracle explain names the same model."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest

from verify.engines.models import STEP_MODELS, orders
from verify.engines.models.dart import Dart

RECORD = json.loads((Path(__file__).resolve().parents[2] / "reports" / "engines.json").read_text(encoding="utf-8"))
CASES = {c["id"]: c for c in RECORD["cases"]}
ENGINES = {e["name"]: e for e in RECORD["engines"]}
F64 = Fraction(1, 10**9)


def _row(engine: str, case_id: str) -> dict:
    return next(r for r in ENGINES[engine]["cases"] if r["id"] == case_id)


def _distance(case: dict, got: list[str], model: list[str]) -> Fraction:
    scale = max(abs(Fraction(x)) for x in case["velocity"])
    return max(abs(Fraction(a) - Fraction(b)) for a, b in zip(got, model)) / scale


def _no_float(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(self: Fraction) -> float:
        raise AssertionError("a float was taken of an exact value")

    monkeypatch.setattr(Fraction, "__float__", refuse)


@pytest.mark.parametrize(
    ("engine", "key", "case_id", "variant"),
    [
        ("dartpy", "dart", "cradle-3-eps-1", ("dantzig", None)),  # one LCP with CFM, then ERP closes a gap
        ("dartpy", "dart", "cradle-4-eps-1", ("pgs first", (0, 2, 1))),  # DART's PGS fallback at the first step
        ("pybullet", "bullet", "cradle-3-eps-1", (1, 0)),  # slop, warm start and the residual stop
        ("pybullet", "bullet", "wall-2-balls-one-moving", (1, 0)),  # a plane's speculative contact
    ],
)
def test_a_step_model_recomputes_the_engines_answer_exactly(engine, key, case_id, variant, monkeypatch):
    case, row = CASES[case_id], _row(engine, case_id)
    model = STEP_MODELS[key](ENGINES[engine]["settings"])
    _no_float(monkeypatch)
    exit_velocity = model.run(case, variant)
    assert _distance(case, row["engine_exit_velocity"], exit_velocity) <= F64
    assert row["model"] == model.label(variant)


def test_the_model_is_not_the_simultaneous_law():
    """The model differs from the law by what DART adds (CFM 1e-5): a wrong engine answer is not explained."""
    case = CASES["cradle-3-eps-1"]
    exit_velocity = Dart().run(case, ("dantzig", None))
    assert _distance(case, ["-33.333333333333336", "66.66666666666667", "66.66666666666667"], exit_velocity) > F64


def test_a_cradle_of_an_irrational_radius_starts_from_the_engines_float_gaps():
    """pybullet's five balls at the floats i * 2 sqrt(5/2): the third pair overlaps, the fourth does not touch."""
    from verify.engines.models.steps import _cradle_gaps

    gaps = _cradle_gaps(5, 2.5**0.5, wall=False)
    assert gaps[0] == gaps[1] == 0 and gaps[2] < 0 < gaps[3]
    assert _cradle_gaps(5, 1.0, wall=True) == [0, 0, 0, 0, 0]


def test_orders():
    assert len(orders(5)) == 120 and orders(6) == [(0, 1, 2, 3, 4, 5), (5, 4, 3, 2, 1, 0)]


def test_oracle_explain_names_the_model_verify_engines_names():
    from verify.engines.explain import engine_velocities
    from verify.oracle.explain import Grid, explain

    ids = ["cradle-3-eps-1", "cradle-4-eps-1/2"]
    results = [{"id": i, "exit_velocity": _row("dartpy", i)["engine_exit_velocity"]} for i in ids]
    e = explain(
        [CASES[i] for i in ids], results, Grid(sweeps=(1,), thresholds=(Fraction(0),), more=(engine_velocities,))
    )
    for i, row in zip(ids, e.rows):
        assert _row("dartpy", i)["model"] in row.explained_by


def test_explain_without_a_saved_record_is_a_usage_error(capsys):
    from verify.cli import main

    assert main(["engines", "--explain"]) == 2
    assert "--explain" in capsys.readouterr().err


def test_explain_again_recomputes_a_saved_record_without_any_engine(tmp_path, capsys):
    import copy

    from verify.cli import main

    expected = _row("dartpy", "cradle-3-eps-1")["model"]
    one = copy.deepcopy(dict(RECORD, engines=[dict(ENGINES["dartpy"], cases=[_row("dartpy", "cradle-3-eps-1")])]))
    one["engines"][0]["cases"][0].pop("model")
    path = tmp_path / "engines.json"
    path.write_text(json.dumps(one), encoding="utf-8")
    assert main(["engines", "--from", str(path), "--explain", "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["engines"][0]["cases"][0]["model"] == expected


def test_box2d_steps_recompute_the_float32_answer_with_warm_starting():
    """The three-ball cradle with e = 0: Box2D's warm start leaves it apart (33.3323, 33.3323, 33.3354), one
    solve does not; the step model recomputes the engine's float32 answer within 1e-5."""
    from verify.engines.models.box2d import Box2D

    case, row = CASES["cradle-3-eps-0"], _row("box2d", "cradle-3-eps-0")
    settings = ENGINES["box2d"]["settings"]
    assert _distance(case, row["engine_exit_velocity"], Box2D(settings).run(case, (1, 0))) <= Fraction(1, 10**5)
    cold = Box2D(dict(settings, warm_starting=0)).run(case, (1, 0))
    assert _distance(case, row["engine_exit_velocity"], cold) > Fraction(1, 10**5)


def test_an_answer_no_step_model_explains_names_the_nearest_step_model():
    from verify.engines.explain import Explainer, explain_case

    case_id = "wall-chain-5-eps-1"
    row = explain_case(Explainer(), ENGINES["box2d"], CASES[case_id], _row("box2d", case_id)["engine_exit_velocity"])
    assert row["model"] is None and row["nearest_model"].startswith("Box2D's steps")
    assert row["why"].endswith("the step where the engine departs is not measured)")


def test_box2d_continuous_collision_is_what_explains_the_five_ball_cradle():
    """Without the time of impact the five-ball cradle (e = 1) is 0.02 off Box2D's answer; with it, within 1e-5."""
    from verify.engines.models.box2d import Box2D

    case, row = CASES["cradle-5-eps-1"], _row("box2d", "cradle-5-eps-1")
    settings = ENGINES["box2d"]["settings"]
    order = (3, 2, 1, 0)
    assert _distance(case, row["engine_exit_velocity"], Box2D(settings).run(case, order)) <= Fraction(1, 10**5)
    discrete = Box2D(dict(settings, bullet=0)).run(case, order)
    assert _distance(case, row["engine_exit_velocity"], discrete) > Fraction(1, 10**3)


@pytest.mark.parametrize(
    ("key", "variant"),
    [("dart", ("pgs", (0, 1))), ("dart", ("pgs first", None)), ("dart", (1, 0)), ("bullet", (0,)),
     ("bullet", (0, 1, 2)), ("box2d", ("dantzig", None))],
)  # fmt: skip
def test_a_variant_that_is_not_one_is_refused(key, variant):
    with pytest.raises(ValueError, match=r"order|variant"):
        STEP_MODELS[key]().run(CASES["cradle-3-eps-1"], variant)


def test_every_explained_answer_of_the_record_has_no_reason_left():
    """A row an exact model explains carries no ``why`` (docs/json-outputs.md): a re-explained record drops it."""
    for engine in RECORD["engines"]:
        for row in engine["cases"]:
            assert (row["model"] is None) == ("why" in row), (engine["name"], row["id"])
