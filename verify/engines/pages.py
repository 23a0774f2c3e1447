"""The report page of the physics engines: the record of ``verify engines --report``, rendered."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path
from typing import Any


def _v(values: list[str] | None, digits: int = 6) -> str:
    """A velocity's components to ``digits`` significant digits (a closed form evaluated), or "-"."""
    from verify.engines.run import short_decimal

    return "-" if values is None else "(" + ", ".join(short_decimal(x, digits) for x in values) + ")"


def explained_table(record: dict[str, Any]) -> list[str]:
    """Per engine: the share of its default answers an exact model explains (and the model that explains most),
    the law it is nearer, and its median distance to each law over the cases where both laws exit."""
    from verify.engines.run import AGREES, both_exit, median_distance, nearer_law
    from verify.numbers.format import format_decimal

    lines = [
        "| engine | precision | explained by an exact model | most by | nearer | cases where both laws exit | "
        f"median distance to the rule | to the simultaneous law | within {format_decimal(AGREES)} of the "
        "simultaneous law |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for e in record["engines"]:
        s = e.get("explained") or {"explained": 0, "cases": len(e["cases"]), "models": {}, "precision": "?"}
        top = max(s["models"].items(), key=lambda kv: (kv[1], kv[0]))[0] if s["models"] else "-"
        agree = sum(Fraction(c["distance_to_simultaneous"]) <= AGREES for c in e["cases"])
        lines.append(
            f"| {e['name']} | {s['precision']} | {s['explained']} of {s['cases']} | {top} | {nearer_law(e)} | "
            f"{len(both_exit(e))} | {median_distance(e, 'distance_to_rule')} | "
            f"{median_distance(e, 'distance_to_simultaneous')} | {agree} of {len(e['cases'])} |"
        )
    return lines


def _departures_table(record: dict[str, Any]) -> list[str]:
    """Per engine, one row of where it departs: from both laws, in kinetic energy, with the speed, on the small
    COR, and under its other settings."""
    from verify.engines.run import AGREES, SLOW_TWINS, energy_gains, moved, off_both, small_cor, speed_twins
    from verify.numbers.format import format_decimal

    def d(x: Fraction) -> str:
        return format_decimal(x, 2)

    cases = {c["id"]: c for c in record["cases"]}
    twins = " | ".join(f"`{slow}` x {ratio} against `{fast}`" for slow, fast, ratio in SLOW_TWINS)
    lines = [
        f"| engine | departs from both laws by more than {d(AGREES)} | gains kinetic energy | {twins} | "
        "COR 0.001 on S2 of the paper's corner | another setting moves the answers by |",
        "|---|---|---|---|---|---|---|",
    ]
    for e in record["engines"]:
        n, c = off_both(e)
        off = "none" if c is None else f"{n} cases; most on `{c['id']}`"
        n, c = energy_gains(e)
        gain = "none" if c is None else f"{n} cases; up to {c['energy_change']} on `{c['id']}`"
        speed = {slow: f"{d(x)}: " + ("differs" if x > AGREES else "agrees") for slow, _, _, x in speed_twins(e)}
        small = small_cor(e, cases)
        kept = "-" if small is None else small[2].split(":")[0]
        moves = "; ".join(f"{v['label']}: {d(moved(e, v, cases)[0])}" for v in e["variants"])
        speeds = " | ".join(speed.get(slow, "-") for slow, _, _ in SLOW_TWINS)
        lines.append(f"| {e['name']} | {off} | {gain} | {speeds} | {kept} | {moves} |")
    return lines


def _engines_list(record: dict[str, Any]) -> list[str]:
    """Each engine: its version, how it combines two restitutions, how one COR per contact is set, its settings."""
    from verify.views.pages import wrapped

    lines = []
    for e in record["engines"]:
        settings = ", ".join(f"{k} = {v:g}" for k, v in e["settings"].items())
        text = (f"**{e['name']} {e['version']}**. Restitution combined: {e['combine_rule']}. One COR per contact: "
                f"{e['cor_setting']}. Settings: {settings}.")  # fmt: skip
        lines += wrapped(text, bullet="- ")
    return lines + [f"- **{s['name']}** was not run: {s['reason']}" for s in record["skipped"]]


def case_tables(record: dict[str, Any]) -> list[str]:
    """The exact references of every case, then each engine's answer on each case (``verify engines --cases``)."""
    ids = {c["id"] for e in record["engines"] for c in e["cases"]}
    lines = ["The exact references", "", "| case | paper's rule | simultaneous law |", "|---|---|---|"]
    rows = {c["id"]: c for e in record["engines"] for c in e["cases"]}
    for case in record["cases"]:
        if case["id"] in ids:
            r = rows[case["id"]]
            stop = "never exits (infinitely many impulses)" if r["rule_stop"] == "non_terminating" else r["rule_stop"]
            rule = _v(r["rule_exit_velocity"]) if r["rule_exit_velocity"] else f"no exit: {stop}"
            lines.append(f"| `{case['id']}` | {rule} | {_v(r['simultaneous_exit_velocity'])} |")
    for e in record["engines"]:
        lines += ["", f"{e['name']} {e['version']}, default settings", "",
                  "| case | engine exit velocity | to the rule | to the simultaneous law | kinetic energy in -> out | "
                  "nearest exact model (distance) |",
                  "|---|---|---|---|---|---|"]  # fmt: skip
        for c in e["cases"]:
            energy = f"{c['kinetic_energy_in']} -> {c['kinetic_energy_out']}"
            model = "-" if "nearest_model" not in c else (
                f"{c['nearest_model']} ({c['model_distance']})" + ("" if c.get("model") else f"; not within "
                                                                  f"precision: {c.get('why', '')}"))  # fmt: skip
            lines.append(f"| `{c['id']}` | {_v(c['engine_exit_velocity'])} | {c['distance_to_rule'] or 'no exit'} | "
                         f"{c['distance_to_simultaneous']} | {energy} | {model} |")  # fmt: skip
        lines += [f"- skipped `{s['id']}`: {s['reason']}" for s in e["skipped_cases"]]
    return lines


def _found(record: dict[str, Any]) -> list[str]:
    """The page's opening: what the engines run, as exact models explain it, and where they depart."""
    from verify.engines.explain import GAIN
    from verify.engines.run import AGREES, energy_gains, nearer_law, speed_twins
    from verify.numbers.format import format_decimal
    from verify.views.pages import wrapped

    def ruled(e: dict[str, Any]) -> list[dict[str, Any]]:
        return [c for c in e["cases"] if c["distance_to_rule"] is not None]

    def on_rule(e: dict[str, Any]) -> int:
        return sum(Fraction(c["distance_to_rule"]) <= AGREES for c in ruled(e))

    engines = record["engines"]
    sim = [e["name"] for e in engines if nearer_law(e) == "simultaneous law"]
    rule = [e["name"] for e in engines if nearer_law(e) == "paper's rule"]
    best = max(engines, key=on_rule)

    def top(e: dict[str, Any]) -> str:
        s = e.get("explained") or {"models": {}, "explained": 0, "cases": len(e["cases"])}
        if not s["models"]:
            return f"{e['name']} (0 of {s['cases']})"
        label, n = max(s["models"].items(), key=lambda kv: (kv[1], kv[0]))
        return f"{e['name']} ({s['explained']} of {s['cases']}; {n} of them by {label})"

    gains = [(e["name"], energy_gains(e)[1]) for e in engines]
    gainers = [f"{name} (up to {row['energy_change']})" for name, row in gains if row is not None]
    speed = [e["name"] for e in engines if any(d > AGREES for *_, d in speed_twins(e))]
    text = [
        f"**What was found.** Of the {len(engines)} engines, {len(sim)} are nearer the simultaneous law than the "
        f"paper's rule on most cases where both exit ({', '.join(sim) or 'none'}); {len(rule)} nearer the paper's "
        f"rule ({', '.join(rule) or 'none'})."
        + (
            f" No engine is within {format_decimal(AGREES)} of the paper's rule on every case where the rule exits; "
            f"the most is {best['name']}, on {on_rule(best)} of {len(ruled(best))}."
            if on_rule(best) < len(ruled(best))
            else f" {best['name']} is within {format_decimal(AGREES)} of the paper's rule on every case where it exits."
        ),
        "Exact models of the engines' own algorithms explain (to the engine's precision) "
        + "; ".join(top(e) for e in engines)
        + ".",
        f"{len(gainers)} engines gain kinetic energy (by more than {format_decimal(GAIN)}, relative) on some case: "
        f"{', '.join(gainers) or 'none'}. "
        f"{len(speed)} answer differently at a low speed, scaled (a restitution velocity threshold, or a soft "
        f"contact): {', '.join(speed) or 'none'}.",
    ]
    return [line for paragraph in text for line in [*wrapped(paragraph), ""]]


def per_engine_tables(record: dict[str, Any]) -> list[str]:
    """One table per engine: how many of its default answers each exact model explains (the contact orders a
    model was found in counted, not listed), the answers left and what the record says of them, and the kinetic
    energy its answers gain."""
    from verify.engines.explain import GAIN, tolerance_of, unordered
    from verify.numbers.format import format_decimal

    lines: list[str] = []
    for e in record["engines"]:
        s = e.get("explained") or {"explained": 0, "cases": len(e["cases"])}
        tolerance = format_decimal(tolerance_of(e.get("solver") or {}), 3)
        head = f"**{e['name']}** ({s.get('precision', '?')}, within {tolerance} of the speed)"
        lines += [f"{head}: {s['explained']} of {s['cases']} answers explained.", "", "| answers | explained by |"]
        lines.append("|---|---|")
        models: dict[str, list[str]] = {}
        left: dict[str, list[str]] = {}
        for row in e["cases"]:
            if row.get("model"):
                models.setdefault(unordered(row["model"]), []).append(row["model"])
            else:
                left.setdefault((row.get("why") or "no model").split(" (")[0], []).append(f"`{row['id']}`")
        for name, found in sorted(models.items(), key=lambda kv: -len(kv[1])):
            orders = len({label for label in found if label != name})
            where = f" (in {orders} contact order{'s' if orders > 1 else ''})" if orders else ""
            lines.append(f"| {len(found)} | {name}{where} |")
        for why, ids in sorted(left.items(), key=lambda kv: -len(kv[1])):
            named = ", ".join(ids[:3]) + (f" and {len(ids) - 3} more" if len(ids) > 3 else "")
            lines.append(f"| {len(ids)} left | {why}: {named} |")
        gains = [Fraction(r["energy_change"]) for r in e["cases"] if r.get("energy_change") is not None]
        gained = [g for g in gains if g > GAIN]
        energy = (
            f"Kinetic energy: gained on {len(gained)} answers, up to {format_decimal(max(gained), 3)} of it."
            if gained
            else "Kinetic energy: no answer gains it."
        )
        lines += ["", energy, ""]
    return lines


def engines_page_text(record: dict[str, Any]) -> str:
    """The engines page for a record of :func:`verify.engines.run.engines_record`."""
    from verify.engines.run import AGREES
    from verify.numbers.format import format_decimal
    from verify.views.pages import wrapped

    names = ", ".join(e["name"] for e in record["engines"]) or "none"
    how = (
        "Each engine runs through an adapter (the protocol of `verify oracle check --impl`) with gravity and "
        f"friction off, on the {len(record['cases'])} cases of the record. Its exit velocity is compared with "
        "the exact ones of the paper's rule and of the simultaneous law (Newton's restitution with "
        "complementarity, all contacts at once: `verify solve --law simultaneous`), and with exact models of "
        "its own algorithm: the paper's rule, the simultaneous law (also with the engine's documented "
        "restitution threshold) and the sequential law (`verify solve --law sequential`: projected "
        "Gauss-Seidel sweeps, exactly) with the engine's documented sweeps, the neighbouring counts, both "
        "contact orders and its threshold; for DART, Bullet and Box2D first of all an exact model of the "
        "engine's own step loop with its settings, stepping the gaps as the engine does (docs/engines.md, "
        "'Step models'). `verify engines --from engines.json --explain` explains the record again, running no "
        "engine. An answer "
        "is explained when a model is within the engine's precision (float32: 1e-5 of the speed; float64: "
        "1e-9). Distances are relative, `max_i |engine_i - exact_i| / max_i |v_in_i|`; an engine agrees with a "
        f"law when the distance is at most {format_decimal(AGREES)}. Floats of an engine are read exactly as "
        "printed. Measured by `verify engines --report` (record: `engines.json`, beside this page); `verify "
        "report` renders the record and runs no engine."
    )
    lines = ["# Physics engines against the paper's rule and the simultaneous law", ""]
    if record["engines"]:
        lines += _found(record)
    lines += [*wrapped(how), "", f"Engines that ran: {names}.", ""]
    if record["engines"]:
        lines += [
            "## How each engine's answers are explained",
            "",
            "Each engine's answers at its default settings, by the exact model that reproduces them within the "
            "engine's precision (`verify engines --from reports/engines.json --explain` recomputes them), and "
            "those no model reproduces, with what the record says of them.",
            "",
            *per_engine_tables(record),
            "## What each engine runs",
            "",
            "The medians are over the cases where both laws exit (their number is given); the last column is over",
            "every case the engine ran.",
            "",
            *explained_table(record),
            "",
            "![The three-ball cradle against eps: the rule, the simultaneous law and each engine](engines-cradle.png)",
            "",
            "## Where each engine departs",
            "",
            "Relative distances. A slow case is run at 1/200 of its twin's speed and scaled back: an engine",
            "without a velocity threshold or a soft contact gives the same answer. On the paper's corner, the COR",
            "0.001 of S2 is either kept or dropped (the answer nearer the simultaneous law with that COR set to 0).",
            "",
            *_departures_table(record),
            "",
        ]
    lines += ["## The engines", "", *_engines_list(record), "", "## Every case", ""]
    lines += wrapped(
        "Each engine's answer on every case, beside the exact answers of both laws and the nearest exact model, is "
        "in the record `engines.json`: `verify engines --from reports/engines.json --cases` prints the tables "
        "(`--engine NAME` for one engine)."
    )
    return "\n".join(lines) + "\n"


def engines_page(out: Path) -> str:
    """The page of ``out/engines.json`` (copied there from ``reports/engines.json`` when missing); draws its figure."""
    import json

    from verify.engines.figures import engines_cradle
    from verify.records.files import write_atomic

    saved = out / "engines.json"
    source = saved if saved.exists() else Path("reports") / "engines.json"
    if not source.exists():
        return (
            '# Physics engines\n\nNo engines record yet: `pip install ".[engines]"`, then `verify engines --report`.\n'
        )
    data = source.read_bytes()
    if source != saved:
        write_atomic(saved, data)
    record = json.loads(data)
    if record["engines"]:
        engines_cradle(record, out / "engines-cradle.png")
    return engines_page_text(record)
