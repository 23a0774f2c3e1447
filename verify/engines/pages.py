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
    its largest kinetic-energy gain, and its median distance to the paper's rule and to the simultaneous law."""
    from verify.engines.explain import GAIN
    from verify.engines.run import median_distance
    from verify.numbers.format import format_decimal

    lines = [
        f"| engine | precision | explained by an exact model | most by | largest energy gain (above {GAIN}) | "
        "median distance to the paper's rule | to the simultaneous law |",
        "|---|---|---|---|---|---|---|",
    ]
    for e in record["engines"]:
        s = e.get("explained") or {"explained": 0, "cases": len(e["cases"]), "models": {}, "precision": "?"}
        top = max(s["models"].items(), key=lambda kv: (kv[1], kv[0]))[0] if s["models"] else "-"
        gains = [Fraction(c["energy_change"]) for c in e["cases"] if c["energy_change"]]
        gain = format_decimal(max(gains), 3) if gains and max(gains) > GAIN else "none"
        lines.append(
            f"| {e['name']} | {s['precision']} | {s['explained']} of {s['cases']} | {top} | {gain} | "
            f"{median_distance(e, 'distance_to_rule')} | {median_distance(e, 'distance_to_simultaneous')} |"
        )
    return lines


def engines_tables(record: dict[str, Any]) -> list[str]:
    """The engines page's tables: the engines, the exact references, and each engine's cases."""
    lines = ["## The engines", "", "| engine | version | combines restitution | one COR per contact | settings |",
             "|---|---|---|---|---|"]  # fmt: skip
    for e in record["engines"]:
        settings = ", ".join(f"{k} = {v:g}" for k, v in e["settings"].items())
        lines.append(f"| {e['name']} | {e['version']} | {e['combine_rule']} | {e['cor_setting']} | {settings} |")
    lines += [f"- **{s['name']}** was not run: {s['reason']}" for s in record["skipped"]]
    ids = {c["id"] for e in record["engines"] for c in e["cases"]}
    lines += ["", "## The exact references", "", "| case | paper's rule | simultaneous law |", "|---|---|---|"]
    rows = {c["id"]: c for e in record["engines"] for c in e["cases"]}
    for case in record["cases"]:
        if case["id"] in ids:
            r = rows[case["id"]]
            rule = _v(r["rule_exit_velocity"]) if r["rule_exit_velocity"] else f"no exit ({r['rule_stop']})"
            lines.append(f"| `{case['id']}` | {rule} | {_v(r['simultaneous_exit_velocity'])} |")
    for e in record["engines"]:
        lines += ["", f"## {e['name']} {e['version']}, default settings", "",
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


def engines_page_text(record: dict[str, Any]) -> str:
    """The engines page for a record of :func:`verify.engines.run.engines_record`."""
    from verify.engines.run import AGREES, findings

    names = ", ".join(e["name"] for e in record["engines"]) or "none"
    head = [
        "# Physics engines against the paper's rule and the simultaneous law",
        "",
        "Each engine runs as a subprocess adapter (`python -m verify.engines.adapters.NAME`, the `verify oracle check",
        "--impl` protocol) with gravity and friction off, on the cradles and corners below; its exit velocity",
        "stands beside the exact ones of the paper's rule and of the simultaneous law (Newton's restitution with",
        "complementarity, all contacts at once: `verify solve --law simultaneous`). The distances are relative:",
        "`max_i |engine_i - exact_i| / max_i |v_in_i|`. Written by `verify engines --report` (record:",
        "`engines.json`, beside this page); `verify report` renders the record and runs no engine. Floats of an",
        "engine are read exactly as printed.",
        "",
        f"Engines that ran: {names}.",
        "",
        "## Findings (measured on the record)",
        "",
        *[f"- {line}" for line in findings(record)],
        "",
        f"An engine agrees with a law on a case when the relative distance is at most {AGREES}.",
        "",
    ]
    if record["engines"]:
        head += [
            "## Each engine explained",
            "",
            "Each answer of an engine at its default settings is compared with exact models of its own algorithm:",
            "the paper's rule, the simultaneous law (also with the engine's documented",
            "restitution threshold), and the sequential law (`verify solve --law sequential`: projected Gauss-Seidel",
            "sweeps, exactly) with the engine's documented sweeps, the neighbouring counts, both contact orders and",
            "its threshold. An answer is explained when a model is within the engine's precision (float32: 1e-5 of",
            "the speed; float64: 1e-9); when several are, they give the same answer to that precision, and the first",
            "of the engine's own kind of solver is named. The last columns are medians over the cases where the law",
            "exits.",
            "",
            *explained_table(record),
            "",
            "![The three-ball cradle against eps: the rule, the simultaneous law and each engine](engines-cradle.png)",
            "",
        ]
    return "\n".join(head + engines_tables(record)) + "\n"


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
