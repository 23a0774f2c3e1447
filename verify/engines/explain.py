"""Each engine's answers explained by an exact model of its own algorithm.

An engine's exit velocity on a case is compared with exact models, each computed with
:func:`verify.laws.rule.solve` on the case as given:

- the paper's rule, and the simultaneous law (:mod:`verify.laws.simultaneous`);
- the simultaneous law with the engine's documented restitution threshold and COR floor (a
  contact incoming at the threshold's speed or slower, or whose COR is at or below the floor,
  gets the COR 0: what the engine's target then is);
- the sequential law (:mod:`verify.laws.sequential`) with the engine's documented number of
  sweeps and the neighbouring counts (K - 1, K, K + 1), the contacts in the order given and
  reversed, and the engine's threshold and floor;
- for an engine whose step loop has an exact model (its ``solver.step_model``,
  :mod:`verify.engines.models`: DART's, Bullet's, Box2D's), that model with the engine's own settings, first, in
  each of its variants (the solve and the order of the contacts, which the engines do not document).

The engine documents these in its adapter's ``solver`` description
(:class:`verify.engines.protocol.Adapter`): the setting holding the sweeps, the threshold (on the
incoming speed, or on the COR times it), the floor and the engine's precision. An answer is
**explained** when the nearest model is within the engine's precision: ``1e-5`` of the speed for a
``float32`` engine, ``1e-9`` for ``float64`` (``max_i |engine_i - model_i| / max_i |v_in_i|``, the
distance of ``verify engines``, exact on the printed floats and 30-digit decimals of the models).
For the others the record says what differs: an energy gain that no model has, a dropped COR (the
simultaneous or the engine's sequential model with a small COR set to 0 is within precision), a
soft contact (an engine without a coefficient of restitution), or only the nearest model and its
distance.

Thresholds are speeds in the case's units: for a cradle the rate of a contact is the balls'
relative speed; for the corner the rate of wall ``(-k, 1, 0)`` is ``sqrt(1 + k^2)`` times the
disk's normal speed, so the threshold on the rate is ``sqrt(1 + k^2)`` times the engine's (exact).

>>> tolerance_of({"precision": "float32"})
Fraction(1, 100000)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.engines.scene import Unsupported, documented, scene_of, speed_scale
from verify.laws.sequential import Law, Sequential
from verify.numbers.format import format_decimal

#: the tolerance of an explanation by the engine's precision (relative to the entrance speed)
TOLERANCES = {"float32": Fraction(1, 10**5), "float64": Fraction(1, 10**9)}
#: a COR at or below this may be dropped by an engine (the paper's 0.001 on S2)
SMALL_COR = Fraction(1, 100)
#: a relative rise of kinetic energy above which an answer gains energy (the findings of :mod:`verify.engines.run`
#: too)
GAIN = Fraction(1, 10**6)


def tolerance_of(solver: dict[str, Any]) -> Fraction:
    """The tolerance of an explanation for an engine's ``solver`` description."""
    return TOLERANCES.get(str(solver.get("precision")), TOLERANCES["float32"])


@dataclass(frozen=True)
class Model:
    """One exact model of an engine's algorithm: its label, the case's CORs it runs with, its law, and for
    the simultaneous law the rate threshold of each contact at or below which its COR is 0 (None: none)."""

    label: str
    cors: tuple[str, ...]
    law: Law
    thresholds: tuple[str, ...] | None = None
    #: an engine's step model (:mod:`verify.engines.models`) and its variant, run instead of ``law``
    steps: Any = None
    variant: Any = None


def _setting(description: dict[str, Any], value: Any) -> Any:
    """A solver entry that is a number, or the name of the setting holding it."""
    return description["settings"].get(value) if isinstance(value, str) else value


def models(description: dict[str, Any], case: dict[str, Any]) -> list[Model]:
    """The exact models of an engine (its ``--describe`` description) on a case record, in order of preference:
    the models of the engine's own kind of solver first (its documented sweeps and order first), the paper's rule
    last."""
    solver = description.get("solver") or {}
    cors = list(case["restitution"])
    threshold = documented(_setting(description, solver.get("threshold", 0)) or 0)
    floor = documented(solver.get("cor_floor", 0) or 0)
    exact_cors = [_number(x) for x in cors]
    floored = tuple("0" if floor > 0 and _at_most(e, floor) else str(x) for e, x in zip(exact_cors, cors))
    scale = speed_scale(case)
    # the threshold on each contact's rate: T (or T / e on the COR times the speed, e after the floor), times the
    # rate of a unit speed
    per = []
    for e, s in zip([_number(x) for x in floored], scale):
        t = sp.Rational(threshold.numerator, threshold.denominator) * s
        if solver.get("threshold_of") == "cor_times_speed":
            t = t / _sympy(e) if not _at_most(e, Fraction(0)) else sp.Integer(0)
        per.append(t)
    simultaneous = [Model("the simultaneous law", tuple(cors), "simultaneous")]
    thresholds = tuple(str(t) for t in per)
    if threshold > 0 or floor > 0:
        simultaneous.append(
            Model("the simultaneous law with the engine's threshold", floored, "simultaneous", thresholds)
        )
    sequential: list[Model] = []
    # sweeps of sequential impulses: the engine's count, for a solver of sweeps (a soft solver's iterations are not)
    k0 = _setting(description, solver.get("iterations") or "")
    if solver.get("kind") in ("sequential", "simultaneous") and isinstance(k0, (int, float)) and k0 >= 1:
        r = len(case["normals"])
        for k in dict.fromkeys((int(k0), int(k0) - 1, int(k0) + 1)):
            if k < 1:
                continue
            for name, order in (("as given", None), ("reversed", tuple(reversed(range(r))))):
                if order is not None and r < 2:
                    continue
                label = f"the sequential law, {k} sweeps, order {name}" + (
                    f", threshold {format_decimal(threshold, 6)}" if threshold > 0 else ""
                )
                sequential.append(Model(label, floored, Sequential(k, order, thresholds)))
    # the engine's own kind first: among models within its precision the first is named (they are the same answer
    # to that precision); the paper's rule last
    first, then = (sequential, simultaneous) if solver.get("kind") == "sequential" else (simultaneous, sequential)
    return [*step_models(description, case), *first, *then, Model("the paper's rule", tuple(cors), "rule")]


def step_models(description: dict[str, Any], case: dict[str, Any]) -> list[Model]:
    """The engine's step model (its ``solver.step_model``) with the engine's settings, in each variant."""
    from verify.engines.models import STEP_MODELS

    name = (description.get("solver") or {}).get("step_model")
    if name not in STEP_MODELS:
        return []
    model = STEP_MODELS[name](description.get("settings") or {})
    cors = tuple(str(x) for x in case["restitution"])
    return [Model(model.label(v), cors, "simultaneous", None, model, v) for v in model.variants(len(case["normals"]))]


def _sympy(x: Any) -> Any:
    return sp.Rational(x.numerator, x.denominator) if isinstance(x, Fraction) else x


def _number(text: Any) -> Any:
    from verify.numbers.parse import to_number

    return to_number(text)


def _at_most(a: Any, bound: Fraction) -> bool:
    """Whether the exact number ``a`` (a Fraction or a closed form) is at most ``bound``, decided rigorously."""
    from verify.numbers.numeric import certified_sign

    return a <= bound if isinstance(a, Fraction) else certified_sign(a - _sympy(bound)) <= 0


class Explainer:
    """The exact models' exit velocities, each run once (cases shared between engines)."""

    def __init__(self) -> None:
        self.memo: dict[tuple[str, tuple[str, ...], str], tuple[list[Fraction], Fraction, bool]] = {}

    def exit_of(self, case: dict[str, Any], model: Model) -> tuple[list[Fraction], Fraction, bool]:
        """The model's exit velocity (30-digit decimals, exactly), kinetic energy out, and whether it exits."""
        from verify.laws.rule import solve
        from verify.records.results import case_from_record, result_record

        cors = model.cors if model.thresholds is None else _threshold_cors(case, model)
        law = str(model.law) if model.steps is None else f"{model.label} {sorted(vars(model.steps).items())}"
        key = (case["id"], cors, law)
        if key not in self.memo and model.steps is not None:
            velocity = [Fraction(x) for x in model.steps.run(case, model.variant)]
            self.memo[key] = (velocity, _energy(case, velocity), True)
        if key not in self.memo:
            c = case_from_record(dict(case, restitution=list(cors)), f"case {case['id']}")
            r = solve(c.system, c.velocity_source, law=model.law, max_iterations=c.max_iterations, trace=False)
            rec = result_record(r, c.id)
            self.memo[key] = (
                [Fraction(x) for x in rec["exit_velocity_decimal"]],
                Fraction(format_decimal(r.backend.to_number(r.kinetic_energy_out), 30))
                if r.backend.is_exact and not r.backend.is_parametric
                else Fraction(0),
                r.stop == "exit",
            )
        return self.memo[key]


def _threshold_cors(case: dict[str, Any], model: Model) -> tuple[str, ...]:
    """The CORs of the simultaneous law under a threshold: 0 for each contact incoming at its threshold's rate or
    slower (its target is then 0, as the engine's), the model's CORs otherwise. Signs exact (the rates of the
    case's velocity against the thresholds, in the number field of both)."""
    from verify.dynamics.system import System
    from verify.numbers.backends import exact_for

    numbers = [_number(x) for x in model.thresholds or ()]
    velocity = [_number(x) for x in case["velocity"]]
    normals = [[_number(x) for x in row] for row in case["normals"]]
    K = exact_for([x for row in normals for x in row] + velocity + numbers)
    g = [[_number(x) for x in row] for row in case["mass_matrix"]]
    s = System(g, normals, [_number(x) for x in model.cors], case.get("time_terms"), backend=K)
    out = []
    for w, t, e in zip(s.rates(s.velocity(velocity)), numbers, model.cors):
        slow = K.sign(w) < 0 and K.sign(K.zero - w - K.convert(t)) <= 0
        out.append("0" if slow else str(e))
    return tuple(out)


def _scale(case: dict[str, Any]) -> Fraction:
    """The speed a distance is relative to: the case's largest entrance speed (1 if it is at rest)."""
    return max(abs(_approx(x)) for x in case["velocity"]) or Fraction(1)


def _distance(a: Sequence[Fraction], b: Sequence[Fraction], scale: Fraction) -> Fraction:
    return max(abs(x - y) for x, y in zip(a, b)) / scale


def _energy(case: dict[str, Any], v: Sequence[Fraction]) -> Fraction:
    g = [[_approx(x) for x in row] for row in case["mass_matrix"]]
    return sum((g[i][j] * v[i] * v[j] for i in range(len(v)) for j in range(len(v))), Fraction(0)) / 2


def _approx(text: Any) -> Fraction:
    from verify.oracle.reference import approx

    return approx(str(text))


def explain_case(
    explainer: Explainer, description: dict[str, Any], case: dict[str, Any], engine_velocity: Sequence[str]
) -> dict[str, Any]:
    """One case of one engine: the model that explains the answer (of those within the engine's precision, the first
    of :func:`models`), else the nearest model, its distance and why it does not explain it.

    >>> from verify.engines.run import engine_cases
    >>> case = next(c for c in engine_cases() if c["id"] == "cradle-3-eps-1")
    >>> d = {"settings": {"k": 1}, "solver": {"kind": "sequential", "iterations": "k", "precision": "float64"}}
    >>> row = explain_case(Explainer(), d, case, ["0.0", "50.0", "50.0"])
    >>> row["model"], row["model_distance"]
    ('the sequential law, 1 sweeps, order as given', '0')
    """
    try:
        candidates = models(description, case)
    except Unsupported:
        return {"model": None, "nearest_model": None, "model_distance": None, "why": "not a cradle or a corner"}
    v = [Fraction(x) for x in engine_velocity]
    scale, tol = _scale(case), tolerance_of(description.get("solver") or {})
    scored = []
    for m in candidates:
        exit_velocity, energy, _ = explainer.exit_of(case, m)
        scored.append((_distance(v, exit_velocity, scale), m, energy))
    within = [t for t in scored if t[0] <= tol]  # the same answer to the engine's precision: the first is named
    distance, nearest, model_energy = within[0] if within else min(scored, key=lambda t: t[0])
    row: dict[str, Any] = {
        "nearest_model": nearest.label,
        "model_distance": format_decimal(distance, 3),
        "model": nearest.label if distance <= tol else None,
    }
    if distance > tol:
        row["why"] = _why(explainer, description, case, v, scale=scale, tol=tol, model_energy=model_energy)
        if nearest.steps is not None:
            row["why"] = f"{row['why']}: {STEP_NEAREST}"
    return row


#: what an answer no model explains gets when the nearest model is the engine's step model
STEP_NEAREST = (
    "its step model is the nearest (the record holds the exit velocities only, so the step where the engine "
    "departs is not measured)"
)


def within(explainer: Explainer, description: dict[str, Any], case: dict[str, Any], row: dict[str, Any]) -> list[str]:
    """The models (labels, in :func:`models`' order) within the engine's precision of a row's answer, from the
    explainer's runs (:func:`explain_case` ran them): the engine's summary picks among them the one that
    explains most of its answers (a contact order the engine does not document is then named once)."""
    v = [Fraction(x) for x in row["engine_exit_velocity"]]
    scale, tol = _scale(case), tolerance_of(description.get("solver") or {})
    return [m.label for m in models(description, case) if _distance(v, explainer.exit_of(case, m)[0], scale) <= tol]


def _why(
    explainer: Explainer,
    description: dict[str, Any],
    case: dict[str, Any],
    v: Sequence[Fraction],
    *,
    scale: Fraction,
    tol: Fraction,
    model_energy: Fraction,
) -> str:
    """What differs when no model is within precision."""
    e_in = _energy(case, [_approx(x) for x in case["velocity"]])
    e_out = _energy(case, v)
    if e_in and (e_out - e_in) / e_in > GAIN and (model_energy - e_in) / e_in <= GAIN:
        return f"an energy gain no model has ({format_decimal((e_out - e_in) / e_in, 3)} of the kinetic energy)"
    cors = [_number(x) for x in case["restitution"]]
    small = [i for i, e in enumerate(cors) if isinstance(e, Fraction) and 0 < e <= SMALL_COR]
    if small:
        dropped = tuple("0" if i in small else str(x) for i, x in enumerate(case["restitution"]))
        for m in models(description, dict(case, restitution=list(dropped))):
            if m.steps is not None:  # the step models run on the case's own CORs
                continue
            exit_velocity, _, _ = explainer.exit_of(case, Model(m.label, dropped, m.law))
            if _distance(v, exit_velocity, scale) <= tol:
                return f"a dropped COR (COR {case['restitution'][small[0]]} acts as 0: {m.label})"
    kind = (description.get("solver") or {}).get("kind")
    if kind == "soft":
        return "soft contact: the engine has no coefficient of restitution, no exact model"
    if kind not in ("sequential", "simultaneous"):
        return f"a {kind} solver: no exact model of its algorithm here"
    if step_models(description, case):
        return "no model within the engine's precision"
    return (
        "no model within the engine's precision (the models are one solve: the engine's later steps, "
        "position correction and warm starting are not in them)"
    )


def unordered(label: str) -> str:
    """A model's label without its contact order (the engines do not document theirs).

    >>> unordered("Bullet's steps: sequential impulses, contact order 1, 0")
    "Bullet's steps: sequential impulses"
    """
    return label.partition(", contact order ")[0]


def explained_summary(description: dict[str, Any], rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Per engine: the tolerance, how many cases a model explains and which, and what differs on the rest."""
    solver = description.get("solver") or {}
    by_model: dict[str, int] = {}
    why: dict[str, int] = {}
    for row in rows:
        if row.get("model"):  # a model in all its contact orders counted once
            key = unordered(row["model"])
            by_model[key] = by_model.get(key, 0) + 1
        elif row.get("why"):
            key = row["why"].split(" (")[0]
            why[key] = why.get(key, 0) + 1
    return {
        "precision": solver.get("precision"),
        "tolerance": format_decimal(tolerance_of(solver), 3),
        "cases": len(rows),
        "explained": sum(by_model.values()),
        "models": dict(sorted(by_model.items(), key=lambda kv: -kv[1])),
        "unexplained": dict(sorted(why.items(), key=lambda kv: -kv[1])),
    }


def engine_velocities(case: dict[str, Any]) -> dict[Any, list[Fraction] | None]:
    """Each engine step model's exit velocity on a case, with the engine's default settings, in each variant,
    keyed as :mod:`verify.oracle.explain` keys its models (none on a case that is not a cradle or a corner):
    what ``verify oracle explain`` adds to its grid.

    >>> from verify.oracle.reference import golden_cases
    >>> case = next(c for c in golden_cases() if c["id"] == "paper-table1-eps-1")
    >>> any(s.label().startswith("DART's steps") for s in engine_velocities(case))
    True
    """
    from verify.engines.protocol import descriptions
    from verify.oracle.explain import Settings

    try:
        scene_of(case)
    except Unsupported:
        return {}
    out: dict[Any, list[Fraction] | None] = {}
    for table in descriptions().values():
        for m in step_models(table, case):
            out[Settings("engine", model=m.label)] = [Fraction(x) for x in m.steps.run(case, m.variant)]
    return out
