"""Physics engines through the oracle: each engine's exit velocities beside both laws' exact ones.

:func:`engine_cases` is the case set (cradles of 3 to 5 balls at several eps, eps = 0 included,
the 3-ball cradle on a grid of eps for the figure, a slow cradle that probes restitution
thresholds, and every golden case that an engine can build, the paper's two examples among
them). :func:`engines_record` runs every adapter of :data:`ENGINES` (``python -m
verify.engines.adapters.NAME``, the ``verify oracle check --impl`` protocol) on them, under its default
settings, under its second setting of the parameter that matters most, and, for the engines
whose contact order can be reversed, in reverse order; an engine that is not installed is
listed as skipped. Each case row holds the engine's exit velocity (its floats as printed), the
exact exit velocities of the paper's rule and of the simultaneous law
(:mod:`verify.laws.simultaneous`), the relative distance to each (``max_i |engine_i - exact_i|
/ max_i |v_in_i|``, the oracle's measure, computed exactly from the printed floats) and the
kinetic energies. :func:`findings` reads the record: which law each engine is closest to, and
where it departs from both, each with the case and settings that show it.

>>> [c["id"] for c in engine_cases()][:2]
['cradle-3-eps-0', 'cradle-3-eps-1/10']
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction
from typing import Any

from verify.engines import ENGINES
from verify.engines.explain import GAIN, Explainer, explain_case, explained_summary, unordered, within
from verify.engines.protocol import NOT_INSTALLED
from verify.engines.scene import Unsupported, documented, scene_of
from verify.models.corner import corner_geometry, slope_of, velocity_of
from verify.models.cradle import cradle_geometry
from verify.numbers.format import format_decimal
from verify.oracle.reference import approx, golden_cases, golden_results
from verify.records.results import case_record

#: the eps of the 3-ball cradle's grid (the figure's points)
GRID = tuple(Fraction(k, 10) for k in range(11))
#: a relative distance under which an engine is said to agree with a law
AGREES = Fraction(1, 10**3)
TIMEOUT = 600.0


def _cradle(case_id: str, eps: Sequence[Any], velocity: Sequence[Any], *, wall: bool = False) -> dict[str, Any]:
    g, normals = cradle_geometry([Fraction(1)] * len(velocity), wall=wall)
    return case_record(case_id, g, normals, list(eps), list(velocity))


def documented_thresholds() -> dict[str, Fraction]:
    """Each engine's documented restitution threshold on the incoming speed (its adapter's ``solver``; for a
    threshold on the COR times the speed, the speed at COR 1), for the engines that have one.

    >>> documented_thresholds()["box2d"]
    Fraction(1, 1)
    """
    import importlib

    from verify.engines.protocol import Adapter

    out = {}
    for name, path in ENGINES.items():
        module = importlib.import_module(path)
        adapter = next(
            v for v in vars(module).values() if isinstance(v, type) and issubclass(v, Adapter) and v.name == name
        )
        t = adapter.solver.get("threshold", 0)
        t = adapter.settings.get(t, 0) if isinstance(t, str) else t
        if t:
            out[name] = documented(t)
    return out


def reported_cases() -> list[dict[str, Any]]:
    """The cases that engines' users report (docs/engines.md cites each report): two balls and a wall in
    contact at once with one ball moving; chains of balls against a wall; a 5-ball cradle with one COR per
    contact; and the 3-ball cradle at 9/10 and 11/10 of each engine's restitution threshold.

    >>> [c["id"] for c in reported_cases()][:2]
    ['wall-2-balls-one-moving', 'wall-chain-3-eps-1']
    """
    out = [_cradle("wall-2-balls-one-moving", [1, 1], [100, 0], wall=True)]
    for balls, eps in ((3, 1), (5, 1), (5, Fraction(1, 2))):
        out.append(_cradle(f"wall-chain-{balls}-eps-{eps}", [eps] * balls, [100] + [0] * (balls - 1), wall=True))
    out.append(_cradle("cradle-5-cors-1-1/2-9/10-1/5", [1, Fraction(1, 2), Fraction(9, 10), Fraction(1, 5)],
                       [100, 0, 0, 0, 0]))  # fmt: skip
    speeds = sorted({t * k for t in documented_thresholds().values() for k in (Fraction(9, 10), Fraction(11, 10))})
    out += [_cradle(f"slow-cradle-3-eps-1-v0-{v}", [1, 1], [v, 0, 0]) for v in speeds]
    return out


def engine_cases() -> list[dict[str, Any]]:
    """The case records run through the engines, in a fixed order."""
    out = [_cradle(f"cradle-3-eps-{e}", [e, e], [100, 0, 0]) for e in GRID]
    for balls in (4, 5):
        out += [
            _cradle(f"cradle-{balls}-eps-{e}", [e] * (balls - 1), [100] + [0] * (balls - 1))
            for e in (0, Fraction(1, 2), 1)
        ]
    out.append(_cradle("slow-cradle-3-eps-1-v0-1/2", [1, 1], [Fraction(1, 2), 0, 0]))
    g, normals = corner_geometry(slope_of(alpha="pi/6"))
    out.append(case_record("slow-paper-corner-v0-1/2", g, normals, ["0.999", "0.001"], velocity_of("pi/12", "1/2")))
    for case in golden_cases():
        try:
            scene_of(case)
        except Unsupported:
            continue
        out.append(case)
    return out + reported_cases()


# -- running the adapters -----------------------------------------------------------------------


def installed() -> list[str]:
    """The engines whose Python package is installed (found, not imported: an adapter's module
    imports its engine only when it runs).

    >>> set(installed()) <= set(ENGINES)
    True
    """
    import importlib
    from importlib.util import find_spec

    from verify.engines.protocol import Adapter

    out = []
    for name, path in ENGINES.items():
        module = importlib.import_module(path)
        adapter = next(
            v for v in vars(module).values() if isinstance(v, type) and issubclass(v, Adapter) and v.name == name
        )
        if find_spec(adapter.module) is not None:
            out.append(name)
    return out


def run_adapter(
    name: str, case_text: str, overrides: dict[str, float] | None = None, *, python: str | None = None
) -> dict[str, Any]:
    """One adapter run: its output (``engine``, ``results``, ``skipped``), or ``{"not_installed":
    reason}`` when its engine cannot be imported (or cannot run here). A failure of the adapter is an error
    (RuntimeError). ``python`` runs the adapter with another interpreter (an environment of its own, for an
    engine whose pins conflict with another's; ``verify`` must be importable there)."""
    argv = [python or sys.executable, "-m", ENGINES[name]]
    for key, value in (overrides or {}).items():
        argv += ["--set", f"{key}={value!r}"]
    done = subprocess.run(argv, input=case_text, capture_output=True, text=True, timeout=TIMEOUT, check=False)
    if done.returncode == NOT_INSTALLED:
        return {"not_installed": done.stderr.strip() or f"{name} is not installed"}
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise RuntimeError(f"the {name} adapter exited with code {done.returncode}: {last}")
    output: dict[str, Any] = json.loads(done.stdout)
    return output


def _variants(description: dict[str, Any]) -> list[tuple[str, dict[str, float]]]:
    """The settings each engine is run under: its defaults, its alternate, and reversed order."""
    out: list[tuple[str, dict[str, float]]] = [("default", {})]
    name, value = description["alternate"]["setting"], description["alternate"]["value"]
    if name:
        out.append((f"{name} = {value:g}", {name: value}))
    if "reverse_order" in description["settings"]:
        out.append(("reverse_order = 1", {"reverse_order": 1}))
    return out


# -- the exact references and the comparison ------------------------------------------------------


def references(cases: Sequence[dict[str, Any]]) -> dict[str, dict[str, dict[str, Any]]]:
    """Each case's exact result records under both laws: ``{id: {"rule": ..., "simultaneous": ...}}``."""
    rule = golden_results(list(cases))
    simultaneous = golden_results(list(cases), law="simultaneous")
    return {c["id"]: {"rule": r, "simultaneous": s} for c, r, s in zip(cases, rule, simultaneous)}


def short_decimal(text: str, digits: int = 6) -> str:
    """A number string to ``digits`` significant digits (for tables).

    >>> short_decimal("-100/3"), short_decimal("0.1")
    ('-33.3333', '0.1')
    """
    return format_decimal(approx(text), digits)


def _distance(engine: Sequence[Fraction], exact: dict[str, Any], scale: Fraction) -> str | None:
    if exact["stop"] != "exit":
        return None
    diff = max(abs(a - approx(b)) for a, b in zip(engine, exact["exit_velocity"]))
    return format_decimal(diff / scale, 3)


def _energy(case: dict[str, Any], v: Sequence[Fraction]) -> Fraction:
    g = [[approx(x) for x in row] for row in case["mass_matrix"]]
    return sum((g[i][j] * v[i] * v[j] for i in range(len(v)) for j in range(len(v))), Fraction(0)) / 2


def case_row(case: dict[str, Any], engine_velocity: Sequence[str], refs: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """One case of one engine: its exit velocity beside both laws', distances and energies."""
    v = [Fraction(x) for x in engine_velocity]  # a float's shortest string, read exactly
    scale = max(abs(approx(x)) for x in case["velocity"]) or Fraction(1)
    rule, sim = refs["rule"], refs["simultaneous"]
    e_in = approx(rule["kinetic_energy_in"])
    e_out = _energy(case, v)
    return {
        "id": case["id"],
        "engine_exit_velocity": list(engine_velocity),
        "rule_exit_velocity": rule["exit_velocity"] if rule["stop"] == "exit" else None,
        "rule_stop": rule["stop"],
        "simultaneous_exit_velocity": sim["exit_velocity"],
        "distance_to_rule": _distance(v, rule, scale),
        "distance_to_simultaneous": _distance(v, sim, scale),
        "kinetic_energy_in": rule["kinetic_energy_in"],
        "kinetic_energy_out": format_decimal(e_out, 12),
        "energy_change": format_decimal((e_out - e_in) / e_in, 3) if e_in else None,
    }


def _engine_entry(
    name: str, cases: list[dict[str, Any]], refs: dict[str, Any], text: str, python: str | None = None
) -> dict[str, Any]:
    """One engine's record: description, default run's cases, and the other settings' runs."""
    first = run_adapter(name, text, python=python)
    if "not_installed" in first:
        return {"name": name, "skipped": first["not_installed"]}
    d = first["engine"]
    keys = ("name", "package", "version", "combine_rule", "cor_setting", "settings", "alternate", "solver")
    entry: dict[str, Any] = {key: d[key] for key in keys}
    by_id = {c["id"]: c for c in cases}
    runs = []
    for label, overrides in _variants(d):
        out = first if not overrides else run_adapter(name, text, overrides, python=python)
        rows = [case_row(by_id[r["id"]], r["exit_velocity"], refs[r["id"]]) for r in out["results"]]
        runs.append({"label": label, "settings": out["engine"]["settings"], "cases": rows, "skipped": out["skipped"]})
    entry["cases"] = runs[0]["cases"]
    entry["skipped_cases"] = runs[0]["skipped"]
    entry["variants"] = runs[1:]
    return entry


def engines_record(
    names: Sequence[str] | None = None,
    *,
    progress: Callable[[str], None] | None = None,
    workers: int = 2,
    pythons: dict[str, str] | None = None,
) -> dict[str, Any]:
    """The ``verify engines --json`` record: every engine (or ``names``) on :func:`engine_cases`; ``pythons``
    maps an engine to the interpreter that runs its adapter (default: this one)."""
    cases = engine_cases()
    if progress:
        progress(f"exact references: {len(cases)} cases, the rule and the simultaneous law")
    refs = references(cases)
    text = json.dumps({"cases": cases})
    chosen = list(names) if names else list(ENGINES)

    def one(name: str) -> dict[str, Any]:
        entry = _engine_entry(name, cases, refs, text, (pythons or {}).get(name))
        if progress:
            progress(
                f"{name}: " + ("skipped, " + entry["skipped"] if "skipped" in entry else f"{len(entry['cases'])} cases")
            )
        return entry

    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        entries = list(pool.map(one, chosen))
    explain(entries, cases, progress)
    return {
        "engines": [e for e in entries if "skipped" not in e],
        "skipped": [{"name": e["name"], "reason": e["skipped"]} for e in entries if "skipped" in e],
        "cases": cases,
    }


def explain(entries: list[dict[str, Any]], cases: list[dict[str, Any]], progress: Callable[[str], None] | None) -> None:
    """Each engine's default answers explained by the nearest exact model of its algorithm
    (:mod:`verify.engines.explain`): each case row gets ``nearest_model``, ``model_distance``, ``model`` (or
    None) and, unexplained, ``why``; each engine its ``explained`` summary."""
    by_id = {c["id"]: c for c in cases}
    explainer = Explainer()
    for entry in entries:
        if "skipped" in entry:
            continue
        for row in entry["cases"]:
            row.pop("why", None)  # a saved row's reason, from an explanation before
            row.update(explain_case(explainer, entry, by_id[row["id"]], row["engine_exit_velocity"]))
        _name_the_common_variant(explainer, entry, by_id)
        entry["explained"] = explained_summary(entry, entry["cases"])
        if progress:
            s = entry["explained"]
            progress(f"{entry['name']}: {s['explained']} of {s['cases']} cases explained by an exact model")


def _name_the_common_variant(explainer: Explainer, entry: dict[str, Any], by_id: dict[str, Any]) -> None:
    """Among the contact orders of the named model that explain an answer (the engines do not document theirs,
    and several orders often give the same answer), the one that explains most of the engine's answers is
    named; which model is named is :func:`~verify.engines.explain.explain_case`'s choice."""
    found = {row["id"]: within(explainer, entry, by_id[row["id"]], row) for row in entry["cases"] if row.get("model")}
    counts: dict[str, int] = {}
    for labels in found.values():
        for label in labels:
            counts[label] = counts.get(label, 0) + 1
    for row in entry["cases"]:
        if row["id"] in found:
            same = [label for label in found[row["id"]] if unordered(label) == unordered(row["model"])]
            row["model"] = row["nearest_model"] = max(same, key=lambda label: counts[label])


def explain_again(record: dict[str, Any], progress: Callable[[str], None] | None = None) -> None:
    """A saved record's answers explained again (:func:`explain`), each engine's ``solver`` description first
    brought up to date from ``engines.toml`` (its exact models may have changed since the engines ran)."""
    from verify.engines.protocol import Adapter, description

    for entry in record["engines"]:
        table = description(entry["name"]).get("solver") or {}
        entry["solver"] = {**Adapter.solver, **(entry.get("solver") or {}), **table}
    explain(record["engines"], record["cases"], progress)


# -- the findings, measured on the record ---------------------------------------------------------


def _f(text: str | None) -> Fraction | None:
    return None if text is None else Fraction(text)


def _median(values: list[Fraction]) -> Fraction:
    s = sorted(values)
    return s[len(s) // 2] if len(s) % 2 else (s[len(s) // 2 - 1] + s[len(s) // 2]) / 2


def _d(x: Fraction) -> str:
    return format_decimal(x, 2)


def both_exit(entry: dict[str, Any]) -> list[dict[str, Any]]:
    """An engine's cases where both laws exit: the one case set its medians are taken over.

    >>> both_exit({"cases": [{"distance_to_rule": "0.1", "distance_to_simultaneous": "0"},
    ...                      {"distance_to_rule": None, "distance_to_simultaneous": "0"}]})
    [{'distance_to_rule': '0.1', 'distance_to_simultaneous': '0'}]
    """
    return [
        c for c in entry["cases"] if c["distance_to_rule"] is not None and c["distance_to_simultaneous"] is not None
    ]


def median_distance(entry: dict[str, Any], key: str) -> str:
    """The median of an engine's distances ``key`` over the cases where both laws exit (``-`` if none).

    >>> rows = [{"r": "0.1", "s": "0.5"}, {"r": None, "s": "9"}, {"r": "0.3", "s": "0.7"}]
    >>> median_distance({"cases": [{"distance_to_rule": r["r"], "distance_to_simultaneous": r["s"]} for r in rows]},
    ...                 "distance_to_simultaneous")
    '0.6'
    """
    values = [Fraction(c[key]) for c in both_exit(entry)]
    return _d(_median(values)) if values else "-"


def closest_law(entry: dict[str, Any]) -> str:
    """Which law the engine's default run is closest to, over the cases where both laws exit."""
    both = [(Fraction(c["distance_to_rule"]), Fraction(c["distance_to_simultaneous"])) for c in both_exit(entry)]
    if not both:
        return f"**{entry['name']}**: no case where both laws exit"
    sim = sum(s < r for r, s in both)
    agree = sum(Fraction(c["distance_to_simultaneous"]) <= AGREES for c in entry["cases"])
    return (
        f"**{entry['name']}** is closest to the {nearer_law(entry)}: closer to the simultaneous law on {sim} of the "
        f"{len(both)} cases where both laws exit; median relative distance "
        f"{median_distance(entry, 'distance_to_simultaneous')} to the simultaneous law, "
        f"{median_distance(entry, 'distance_to_rule')} to the rule (over those {len(both)}); within {_d(AGREES)} "
        f"of the simultaneous law on {agree} of {len(entry['cases'])} cases."
    )


def nearer_law(entry: dict[str, Any]) -> str:
    """``simultaneous law``, ``paper's rule`` or ``neither law``: nearer on most cases where both laws exit.

    >>> nearer_law({"cases": [{"distance_to_rule": "0.3", "distance_to_simultaneous": "0.01"}]})
    'simultaneous law'
    """
    both = both_exit(entry)
    sim = sum(Fraction(c["distance_to_simultaneous"]) < Fraction(c["distance_to_rule"]) for c in both)
    return "simultaneous law" if 2 * sim > len(both) else "paper's rule" if 2 * sim < len(both) else "neither law"


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _off_both(c: dict[str, Any]) -> Fraction:
    """The distance to the nearer law (the simultaneous law when the rule does not exit)."""
    return min(Fraction(x) for x in (c["distance_to_rule"], c["distance_to_simultaneous"]) if x is not None)


def off_both(entry: dict[str, Any]) -> tuple[int, dict[str, Any] | None]:
    """How many cases the engine departs from both laws on (by more than :data:`AGREES`), and the farthest.

    >>> rows = [{"id": "a", "distance_to_rule": "0.5", "distance_to_simultaneous": "0.2"},
    ...         {"id": "b", "distance_to_rule": None, "distance_to_simultaneous": "0.0001"}]
    >>> n, row = off_both({"cases": rows}); n, row["id"]
    (1, 'a')
    """
    off = [(_off_both(c), c) for c in entry["cases"] if _off_both(c) > AGREES]
    return len(off), (max(off, key=lambda sc: sc[0])[1] if off else None)


def energy_gains(entry: dict[str, Any]) -> tuple[int, dict[str, Any] | None]:
    """How many cases the engine gains kinetic energy on (a relative rise above GAIN), and the largest gain.

    >>> n, row = energy_gains({"cases": [{"id": "a", "energy_change": "0.02"}, {"id": "b", "energy_change": None}]})
    >>> n, row["id"]
    (1, 'a')
    """
    gains = [(Fraction(c["energy_change"]), c) for c in entry["cases"]
             if c["energy_change"] and Fraction(c["energy_change"]) > GAIN]  # fmt: skip
    return len(gains), (max(gains, key=lambda sc: sc[0])[1] if gains else None)


def departures(entry: dict[str, Any], cases: dict[str, dict[str, Any]]) -> list[str]:
    """Where the engine departs from both laws, gains energy, or moves with speed or settings."""
    name, out = entry["name"], []
    n, c = off_both(entry)
    if c is not None:
        out.append(
            f"{name} departs from both laws (by more than {_d(AGREES)}) on {_count(n, 'case')}; the most on "
            f"`{c['id']}`: {c['distance_to_simultaneous']} from the simultaneous law, "
            + (f"{c['distance_to_rule']} from the rule." if c["distance_to_rule"] else "and the rule does not exit.")
        )
    n, c = energy_gains(entry)
    if c is not None:
        out.append(
            f"{name} gains kinetic energy (a relative rise above {_d(GAIN)}) on {_count(n, 'case')}; the most on "
            f"`{c['id']}`: {c['kinetic_energy_in']} -> {c['kinetic_energy_out']} ({c['energy_change']})."
        )
    for slow, fast, ratio, d in speed_twins(entry):
        what = (
            "differs: the answer depends on the speed (a restitution velocity threshold, or a soft contact)"
            if d > AGREES
            else "agrees: no dependence on the speed between these two"
        )
        out.append(f"{name}: `{slow}` scaled by {ratio} against `{fast}`, relative difference {_d(d)}: {what}.")
    small = small_cor(entry, cases)
    if small is not None:
        d_given, d_zero, verdict = small
        cor = cases[SMALL_COR_CASE]["restitution"][1]
        out.append(
            f"{name} on `{SMALL_COR_CASE}` (COR {cor} on S2): {_d(d_given)} from the simultaneous law as given, "
            f"{_d(d_zero)} with that COR set to 0: {verdict}."
        )
    for variant in entry["variants"]:
        worst, where = moved(entry, variant, cases)
        out.append(
            f"{name} under {variant['label']}: "
            + (
                f"the answers move by up to {_d(worst)} (relative), on `{where}`."
                if where
                else "the same answers as under its default settings, on every case."
            )
        )
    return out


#: the case whose small COR (0.001 on wall S2) an engine may drop
SMALL_COR_CASE = "paper-corner-pi6-pi12"


def small_cor(entry: dict[str, Any], cases: dict[str, dict[str, Any]]) -> tuple[Fraction, Fraction, str] | None:
    """Whether the engine's answer on the paper's corner is nearer the simultaneous law with the small
    COR 0.001 as given, or with it set to 0 (both exact): a nearer 0 shows the COR dropped. The two
    distances and the verdict (None without that case)."""
    row = next((c for c in entry["cases"] if c["id"] == SMALL_COR_CASE), None)
    if row is None or SMALL_COR_CASE not in cases:
        return None
    case = cases[SMALL_COR_CASE]
    zero = dict(case, restitution=[case["restitution"][0], "0"])
    as_given, dropped = (references([c])[c["id"]]["simultaneous"] for c in (case, zero))
    got = [Fraction(x) for x in row["engine_exit_velocity"]]
    scale = max(abs(approx(x)) for x in case["velocity"])
    d_given = Fraction(_distance(got, as_given, scale) or "0")
    d_zero = Fraction(_distance(got, dropped, scale) or "0")
    if min(d_given, d_zero) > abs(d_given - d_zero):
        verdict = "too far from both to tell"
    else:
        verdict = "nearer the COR set to 0: the engine drops it" if d_zero < d_given else "nearer the COR as given"
    return d_given, d_zero, verdict


#: the slow cases, their fast twins and the speed ratio between them
SLOW_TWINS = (
    ("slow-cradle-3-eps-1-v0-1/2", "cradle-3-eps-1", 200),
    ("slow-paper-corner-v0-1/2", "paper-corner-pi6-pi12", 200),
)


def speed_twins(entry: dict[str, Any]) -> list[tuple[str, str, int, Fraction]]:
    """The slow cases against their fast twins, scaled: (slow, fast, ratio, relative difference); a
    difference shows a velocity threshold.

    >>> rows = [{"id": "slow-cradle-3-eps-1-v0-1/2", "engine_exit_velocity": ["0", "0", "0.5"]},
    ...         {"id": "cradle-3-eps-1", "engine_exit_velocity": ["0", "0", "100"]}]
    >>> speed_twins({"cases": rows})
    [('slow-cradle-3-eps-1-v0-1/2', 'cradle-3-eps-1', 200, Fraction(0, 1))]
    """
    rows = {c["id"]: c for c in entry["cases"]}
    out = []
    for slow, fast, ratio in SLOW_TWINS:
        if slow not in rows or fast not in rows:
            continue
        a = [Fraction(x) * ratio for x in rows[slow]["engine_exit_velocity"]]
        b = [Fraction(x) for x in rows[fast]["engine_exit_velocity"]]
        d = max(abs(x - y) for x, y in zip(a, b)) / (max(abs(x) for x in b) or Fraction(1))
        out.append((slow, fast, ratio, d))
    return out


def moved(entry: dict[str, Any], variant: dict[str, Any], cases: dict[str, dict[str, Any]]) -> tuple[Fraction, str]:
    """How far another setting moves the engine's answers from its default run: the largest relative move
    and its case (``""`` when nothing moves).

    >>> entry = {"cases": [{"id": "c", "engine_exit_velocity": ["1", "0"]}]}
    >>> variant = {"cases": [{"id": "c", "engine_exit_velocity": ["1/2", "0"]}]}
    >>> moved(entry, variant, {"c": {"velocity": ["2", "0"]}})
    (Fraction(1, 4), 'c')
    """
    base = {c["id"]: c for c in entry["cases"]}
    worst, where = Fraction(0), ""
    for c in variant["cases"]:
        if c["id"] not in base:
            continue
        a = [Fraction(x) for x in c["engine_exit_velocity"]]
        b = [Fraction(x) for x in base[c["id"]]["engine_exit_velocity"]]
        scale = max(abs(approx(x)) for x in cases[c["id"]]["velocity"]) or Fraction(1)
        d = max(abs(x - y) for x, y in zip(a, b)) / scale
        if d > worst:
            worst, where = d, c["id"]
    return worst, where


def explained_line(entry: dict[str, Any]) -> str:
    """How many of an engine's default answers an exact model explains, by which, and what differs on the rest."""
    s = entry.get("explained")
    if not s:
        return f"{entry['name']}: not explained (a record made before the exact models)"
    models = "; ".join(f"{label} on {n}" for label, n in s["models"].items()) or "none"
    rest = "; ".join(f"{why} on {n}" for why, n in s["unexplained"].items())
    return (
        f"{entry['name']} ({s['precision']}): an exact model explains {s['explained']} of {s['cases']} answers "
        f"to within {s['tolerance']} of the speed: {models}" + (f". The others: {rest}." if rest else ".")
    )


def findings(record: dict[str, Any]) -> list[str]:
    """Every measured statement of the engines page, from a record of :func:`engines_record`."""
    cases = {c["id"]: c for c in record["cases"]}
    out = []
    for entry in record["engines"]:
        out.append(closest_law(entry))
        out.append(explained_line(entry))
        out += departures(entry, cases)
    return out


def grid_rows(record: dict[str, Any]) -> tuple[list[Any], list[Any], dict[str, list[Any]]]:
    """The 3-ball cradle at every eps of :data:`GRID`, as Fractions: the rule's exit velocities
    (None where it does not exit) and the simultaneous law's, computed exactly, and each engine's
    from the record (None where it skipped the case)."""
    ids = [f"cradle-3-eps-{e}" for e in GRID]
    cases = {c["id"]: c for c in record["cases"]}
    refs = references([cases[cid] for cid in ids])

    def exit_of(r: dict[str, Any]) -> list[Fraction] | None:
        return [approx(x) for x in r["exit_velocity"]] if r["stop"] == "exit" else None

    rule = [exit_of(refs[cid]["rule"]) for cid in ids]
    sim = [exit_of(refs[cid]["simultaneous"]) for cid in ids]
    engines = {}
    for entry in record["engines"]:
        rows = {c["id"]: c["engine_exit_velocity"] for c in entry["cases"]}
        engines[entry["name"]] = [[Fraction(x) for x in rows[cid]] if cid in rows else None for cid in ids]
    return rule, sim, engines
