"""The text and JSON of the paper's checks: Table 1 with its AEEV readings (``verify table1``), the corner's
claims (``verify corner-claims``) and the paper's corner over its CORs."""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from verify.laws.outcome import Result
from verify.maps.text import behaviour_lines, eps_map_text
from verify.models.paper import MEASURES, NORMS, PAPER_READING, PAPER_SIGMA_RELATIVE, PAPER_SIGMA_STATED, WHENS
from verify.numbers.format import counted, format_decimal, format_exact
from verify.paper.readings import Search, Window, closed_form
from verify.paper.table1 import (
    ARITHMETICS,
    PARI_PREC,
    READINGS,
    EntryCheck,
    Table1,
    sqrt_decimal,
    threshold_brackets,
)
from verify.records.results import result_record

if TYPE_CHECKING:
    from verify.maps.cradle import CradleMap
    from verify.models.corner import CornerRun
    from verify.paper.corner_claims import Claim, CornerFindings
    from verify.paper.corner_map import CornerMaps


def _iters(result: Result) -> str:
    if result.stop == "aeev":
        return f"AEEV / {result.iterations}"
    if result.stop == "exit":
        return str(result.iterations)
    if result.stop == "non_terminating":
        return "never exits (proof)"
    return f"no exit in {result.iterations}"


def table1_text(table: Table1) -> str:
    """Table 1: printed against recomputed, every entry marked, with reasons; then the readings."""
    lines = [*table1_lines(table), "", *entries_explained_text(table)]
    lines += ["", *aeev_text(table.identification)]
    return "\n".join(lines + table1_differs(table)) + "\n"


def table1_differs(table: Table1) -> list[str]:
    """The rows where the exact run ends otherwise than in paper mode (none: no lines)."""
    differs = [r for r in table.rows if (r.exact.stop, r.exact.iterations) != (r.paper.stop, r.paper.iterations)]
    if not differs:
        return []
    return ["", "Where the exact run differs from paper mode:"] + [
        f"  eps = {r.eps}: paper mode {_iters(r.paper)}, exact {_iters(r.exact)}" for r in differs
    ]


def table1_lines(table: Table1) -> list[str]:
    """Table 1 printed against recomputed, every entry marked; the entries that disagree, with reasons."""
    lines = [
        "Table 1 of Pasquero (2021): Newton's cradle with three unit balls, v0 = 100",
        f"source: {table.source}",
        "",
        "paper mode = the paper's termination (10^4 cap, AEEV stop); exact = stop only at exit"
        f" (or after {counted(table.exact_cap, 'impulse')})",
        "",
        f"{'eps':<8}{'printed v_D1':>14}{'v_D2':>13}{'v_D3':>13}{'iterations':>12}   "
        f"{'paper mode':>11}{'exact':>21}   entries",
    ]
    for row in table.rows:
        n_ok = sum(c.agrees for c in row.checks)
        mark = "all agree" if row.agrees else f"{n_ok}/{len(row.checks)} agree"
        lines.append(
            f"{row.eps:<8}{row.printed[0]:>14}{row.printed[1]:>13}{row.printed[2]:>13}{row.printed[3]:>12}   "
            f"{_iters(row.paper):>11}{_iters(row.exact):>21}   {mark}"
        )
    lines += ["", "Computed exit velocities (paper mode; 12 significant digits, exact values with --json):"]
    for row in table.rows:
        K = row.paper.backend
        lines.append(f"  {row.eps:<8}" + "".join(f"{K.to_decimal(x, 12):>18}" for x in row.paper.exit_velocity))
    bad = [row for row in table.rows if not all(c.explained for c in row.checks)]
    n_bad = sum(not c.explained for r in bad for c in r.checks)
    lines += ["", f"Entries that disagree with the computation under every reading and arithmetic ({n_bad}):"]
    if not bad:
        lines.append("  none")
    tried = {"; ".join(c.tried) for row in bad for c in row.checks if not c.explained and c.tried}
    if len(tried) == 1:  # the same readings for every entry: said once
        lines.append(f"  each tried under: {tried.pop()} (final state and every state of the run)")
    for row in bad:
        for c in row.checks:
            if not c.explained:
                lines.append(
                    f"  eps = {row.eps}, {c.column}: printed {c.printed}, computed {c.computed[:14]}: {c.reason}"
                )
                if c.tried and tried:
                    lines.append(f"    tried: {'; '.join(c.tried)} (final state and every state of the run)")
        for note in row.row_notes:
            lines.append(f"    row {row.eps}: {note}")
    return lines


def _explained_by(c: EntryCheck) -> str:
    """Which arithmetics and readings explain an entry, grouped by the readings."""
    by: dict[tuple[str, ...], list[str]] = {}
    for a in ARITHMETICS:
        found = tuple(f"{e.reading}{'' if e.state is None else f' (state {e.state})'}"
                      for e in c.explained_by if e.arithmetic == a)  # fmt: skip
        by.setdefault(found, []).append(a)
    return "; ".join(f"{' and '.join(arith)}: {', '.join(found) or 'none'}" for found, arith in by.items())


def entries_explained_text(table: Table1) -> list[str]:
    """The entries that only some reading or arithmetic explains, and which."""
    some = [(row, c) for row in table.rows for c in row.checks if c.only_some]
    lines = [
        f"Entries explained only under some readings or arithmetics ({len(some)}; final state unless a state"
        " is named):",
        "  readings: " + "; ".join(f"{k} = {v}" for k, v in READINGS.items()),
        "  arithmetics: " + "; ".join(f"{k} = {v}" for k, v in ARITHMETICS.items()),
    ]
    if not some:
        lines.append("  none")
    groups: dict[str, list[str]] = {}
    for row, c in some:
        groups.setdefault(_explained_by(c), []).append(f"eps {row.eps} {c.column} {c.printed}")
    for by, entries in groups.items():
        lines.append(f"  explained by {by} ({len(entries)}):")
        lines += [f"    {', '.join(entries[i : i + 4])}" for i in range(0, len(entries), 4)]
    return lines


def _window_decimal(w: Window) -> str:
    lo = sqrt_decimal(w.lower_sq, 4)
    if w.upper_sq is None:
        return f"({lo}, infinity)"
    hi = sqrt_decimal(w.upper_sq, 4, up=True)
    return f"({lo}, {hi}]" if w.consistent else f"empty (c > {lo}, c <= {hi})"


def _short_form(q: Fraction | None, limit: int = 44) -> str:
    if q is None:
        return "infinity"
    text = closed_form(q)
    return text if len(text) <= limit else f"<{len(text)} characters: see --json>"


def aeev_text(search: Search) -> list[str]:
    """The search of the readings of the paper's AEEV stop, in words and figures."""
    stated = format_decimal(PAPER_SIGMA_STATED)
    lines = [
        'Identification of the AEEV stop: readings of "the differences of the velocities < sigma = c * norm"',
        f"  tried: {len(MEASURES)} measures x {len(NORMS)} norms x {len(WHENS)} moments = {len(search.windows)}"
        " readings, named measure/norm/when; the stop fires when measure < sigma (strict), so each",
        "  window of c that reproduces every printed count is open below and closed above (ends rounded outward)",
        *[f"    {k:<13} {v}" for k, v in MEASURES.items()],
        "    norms: " + ", ".join(f"{k} = {v}" for k, v in NORMS.items()),
        *[f"    {k:<13} {v}" for k, v in WHENS.items()],
        "",
        f"  {'reading':<26}{'c = ' + stated:<11}{'window of c':<40}{'counts with c = ' + stated:<45}"
        "first row that differs",
        f"  {'':<26}{'reproduces':<11}{'':<40}{'on eps = ' + ', '.join(search.sensitive):<45}with c = {stated}",
    ]
    for w in search.windows:
        verdict = "yes" if w.stated_reproduces else "no"
        counts = ", ".join(w.stated_counts[e] for e in search.sensitive)
        first = "none" if w.first_difference is None else f"{w.first_difference[0]} ({w.first_difference[2]})"
        lines.append(f"  {w.reading.name:<26}{verdict:<11}{_window_decimal(w):<40}{counts:<45}{first}")
    lines.append("")
    good = search.reproducing
    for w in good:
        lines += [
            f"  {w.reading.name} ({w.reading.description}):",
            f"    reproduces every printed count with the printed constant c = {stated};",
            f"    exactly, c in ({_short_form(w.lower_sq)}, {_short_form(w.upper_sq)}]",
        ]
    if not good:
        lines.append(f"  Under the readings tried, c = {stated} reproduces every printed count under none"
                     " (the last column says where each first fails)")  # fmt: skip
    reading = PAPER_READING.name
    lines.append(f"  paper mode uses {reading} with c = {format_decimal(PAPER_SIGMA_RELATIVE)} (other readings: "
                 "verify cradle --mode paper --aeev READING)")  # fmt: skip
    return lines


def _reading_record(w: Window) -> dict[str, Any]:
    r = w.reading
    return {
        "reading": r.name,
        "measure": r.measure,
        "norm": r.norm,
        "when": r.when,
        "description": r.description,
        "c_squared_lower": str(w.lower_sq),
        "c_squared_upper": None if w.upper_sq is None else str(w.upper_sq),
        "c_lower": closed_form(w.lower_sq),
        "c_upper": None if w.upper_sq is None else closed_form(w.upper_sq),
        "c_lower_decimal": sqrt_decimal(w.lower_sq, 10),
        "c_upper_decimal": None if w.upper_sq is None else sqrt_decimal(w.upper_sq, 10, up=True),
        "consistent": w.consistent,
        "impossible": w.impossible,
        "stated_inside": w.stated_inside,
        "stated_reproduces_every_count": w.stated_reproduces,
        "counts_with_stated": w.stated_counts,
        "first_difference_with_stated": None
        if w.first_difference is None
        else dict(zip(("eps", "printed", "obtained"), w.first_difference)),
    }


def aeev_json(search: Search) -> dict[str, Any]:
    """The search of the readings as JSON (exact windows, as squares and closed forms)."""
    return {
        "comparison": "measure < c * norm (strict): the window of c is (c_lower, c_upper]",
        "stated_c": str(PAPER_SIGMA_STATED),
        "sensitive_rows": search.sensitive,
        "readings": [_reading_record(w) for w in search.windows],
        "reproducing_with_stated_c": [w.reading.name for w in search.reproducing],
        "paper_mode": {"reading": PAPER_READING.name, "c": str(PAPER_SIGMA_RELATIVE)},
    }


def table1_json(table: Table1) -> dict[str, Any]:
    """Table 1 as JSON: printed entries, result records of both runs, checks and notes."""
    ident = table.identification
    return {
        "source": table.source,
        "v0": str(table.v0),
        "exact_cap": table.exact_cap,
        "rows": [
            {
                "eps": row.eps,
                "printed": dict(zip(["v_D1", "v_D2", "v_D3", "iterations"], row.printed)),
                "paper": result_record(row.paper, f"table1-paper-{row.eps}"),
                "exact": result_record(row.exact, f"table1-exact-{row.eps}"),
                "checks": [
                    {
                        "column": c.column,
                        "printed": c.printed,
                        "computed": c.computed,
                        "agrees": c.agrees,
                        "reason": c.reason or None,
                        "explained": c.explained,
                        "explained_by": [
                            {"arithmetic": e.arithmetic, "reading": e.reading, "state": e.state} for e in c.explained_by
                        ],
                        "readings_tried": c.tried,
                    }
                    for c in row.checks
                ],
                "notes": row.row_notes,
                "momentum_ranges": {
                    r: None if span is None else [str(span[0]), str(span[1])] for r, span in row.momentum_ranges.items()
                },
            }
            for row in table.rows
        ],
        "readings": READINGS,
        "arithmetics": ARITHMETICS,
        "binary_precision_bits": PARI_PREC,
        "inconsistent_entries": [
            {"eps": row.eps, "column": c.column, "printed": c.printed, "readings_tried": c.tried}
            for row in table.rows
            for c in row.checks
            if not c.explained
        ],
        "aeev_identification": aeev_json(ident),
    }


def table1_summary(table: Table1) -> str:
    """A few lines for ``verify all``."""
    agree = [r for r in table.rows if r.agrees]
    bad = [r for r in table.rows if not r.agrees]
    counts_ok = all(r.checks[-1].agrees for r in table.rows)
    lines = [
        f"  Table 1: {len(agree)} of {len(table.rows)} rows agree in every printed entry; "
        f"printed iteration counts {'all reproduced' if counts_ok else 'NOT all reproduced'} in paper mode",
    ]
    for r in bad:
        wrong = ", ".join(c.column for c in r.checks if not c.agrees)
        why = r.row_notes[0] if r.row_notes else ""
        lines.append(f"    disagrees with the paper: eps = {r.eps} ({wrong}): {why}")
    for hi, lo, inside in threshold_brackets(table):
        where = "lies" if inside else "does NOT lie"
        lines.append(
            f"    3 -> 4 iterations between eps = {hi} and {lo}; the paper's threshold 3 - 2*sqrt(2) {where} "
            "between them (decided exactly)"
        )
    search = table.identification
    stated = format_decimal(PAPER_SIGMA_STATED)
    good = [w.reading.name for w in search.reproducing]
    tried = f"{len(search.windows)} readings tried"
    if good:
        lines.append(f"    AEEV stop: the printed sigma = {stated} * norm reproduces every printed count under "
                     f"{', '.join(good)} (of {tried}; paper mode uses {PAPER_READING.name})")  # fmt: skip
    else:
        lines.append(f"    AEEV stop: under the {tried}, the printed sigma = {stated} * norm "
                     "reproduces the printed counts under none (verify table1 lists why)")  # fmt: skip
    return "\n".join(lines) + "\n"


def corner_claims_text(found: CornerFindings) -> str:
    """The corner's claims, the wedge's termination boundary and float-vs-exact, in words."""
    claims, boundary, eps, rebounds, floats = found.claims, found.boundary, found.eps, found.rebounds, found.floats
    lines = ["The disk in the corner (Sect. 4.2): the paper's claims, checked exactly", ""]
    for c in claims:
        lines.append(f"  [{c.verdict}] {c.name}")
        lines.append(f"      {c.cases} cases; {c.note}")
        if c.counterexample:
            lines.append(f"      counterexample: {c.counterexample}")
        for e in c.examples[:3]:
            velocity = ", ".join(e["velocity"])
            lines.append(f"      example: slope {e['slope']}, velocity ({velocity}), eps {e['eps1']}, {e['eps2']}")
    k_star, alpha_star = boundary
    lines += [
        "",
        "Termination in the wedge (symmetric corner, one COR eps):",
        f"  invariant cones exist, so that the entrances that reach them never leave, iff tan(alpha) <= {k_star},",
        f"  i.e. alpha <= {alpha_star} (derived: the alternating two-step map has real eigenvalues);",
        "  above it the map rotates every alternating run out of the corner.",
        f"  Narrower corners, more rebounds: eps = {eps}, entrance velocity (1, 3/10), exact runs:",
        f"  {'slope k':>18}  {'impulses':>8}  {'stop':<16} below the boundary",
    ]
    for r in rebounds:
        lines.append(f"  {r['slope']:>18}  {r['iterations']:>8}  {r['stop']:<16} {r['below_boundary']}")
    lines += [
        "",
        f"Float against exact ({floats['cases']} random rational cases, the paper's eq. (10) in Python floats):",
        f"  {floats['differing']} cases take another branch; reasons: "
        + ", ".join(f"{why} on {n}" for why, n in floats["reasons"].items())
        + "; "
        f"{floats['differing_with_a_cor_of_0']} of them have a COR of 0",
    ]
    for e in floats["examples"][:3]:
        case = e["case"]
        velocity = ", ".join(case["velocity"])
        lines.append(
            f"  e.g. slope {case['slope']}, velocity ({velocity}), eps {case['eps1']}, {case['eps2']}: "
            f"exact {'-'.join(e['exact_zones'])}, float {'-'.join(e['float_zones'])} ({e['reason']})"
        )
    return "\n".join(lines) + "\n"


def corner_claims_json(found: CornerFindings) -> dict[str, Any]:
    """The same as :func:`corner_claims_text`, as JSON."""
    claims, boundary, eps, rebounds, floats = found.claims, found.boundary, found.eps, found.rebounds, found.floats
    return {
        "claims": [
            {
                "claim": c.name,
                "verdict": c.verdict,
                "cases": c.cases,
                "note": c.note,
                "counterexample": c.counterexample,
                "examples": c.examples,
            }
            for c in claims
        ],
        "symmetric_boundary": {"slope": str(boundary[0]), "alpha": str(boundary[1])},
        "rebounds": {"eps": eps, "velocity": ["1", "3/10"], "runs": rebounds},
        "float_vs_exact": floats,
    }


def corner_summary(example: CornerRun, claims: Sequence[Claim]) -> str:
    """A few lines on the corner for ``verify all``."""
    r = example.result
    K = r.backend
    lines = [
        f"  the paper's example (alpha = pi/6, phi = pi/12, eps = 0.999, 0.001): zones {' -> '.join(example.zones)}, "
        f"{r.velocity_name} {', '.join(K.to_decimal(x, 12) for x in r.exit_velocity[:2])} (computed exactly)",
    ]
    for c in claims:
        lines.append(f"    [{c.verdict}] {c.name} ({c.cases} cases)")
    return "\n".join(lines) + "\n"


def corner_map_text(found: CornerMaps) -> str:
    """The paper's corner mapped over its CORs (:func:`verify.paper.corner_map.corner_maps`): the line
    eps2 = 1/1000, where its runs have repeated multiple impacts, and the area of the square where they do."""
    from sympy import total_degree

    from verify.maps.plane import describe_area

    pieces = " and ".join(str(p) for p in found.repeated_pieces()) or "no value"
    velocity = ", ".join(format_exact(v) for v in found.plane.velocity)
    plane = found.cells
    sides = [side.poly for p in found.repeated_plane for side in (p.cell.y_lo, p.cell.y_hi)
             if getattr(side, "poly", None) is not None]  # fmt: skip
    curves = sorted({(plane.P.show(q, plane.names), total_degree(plane.P.expr(q, plane.names))) for q in sides})
    return (
        eps_map_text(found.line, exact_in="the --json of verify map")
        + f"\nRepeated multiple impacts (the first two impulses both on both walls) on this line: exactly for eps1 in "
        f"{pieces}.\n\nBoth CORs over [0, 1]^2 as exact cells, up to "
        f"{counted(found.plane.max_impulses, 'impulse')}, from "
        f"velocity ({velocity}) (the paper's direction; the speed changes no "
        f"impact set or stop): {len(plane.parts)} cells; the first two impulses (two decide it) are multiple impacts "
        f"on {len(found.repeated_plane)} of "
        f"them, of area {describe_area(found.repeated_area())} (exact bounds), for eps1 from "
        f"{min((p.cell.x_lo for p in found.repeated_plane), default='-')} to "
        f"{max((p.cell.x_hi for p in found.repeated_plane), default='-')}, bounded below and above by "
        + (
            "; ".join(
                f"{c} = 0" if len(c) <= 80 else f"a curve of degree {d} (its polynomial in the --json of verify map)"
                for c, d in curves
            )
            or "the box"
        )
        + ".\n\n"
        + "\n".join(behaviour_lines(plane, found.plane.system.names))
        + "\n"
    )


def cradle_map_summary(cmap: CradleMap) -> str:
    """A few lines of the cradle map for ``verify all``."""
    from verify.maps.cradle import termination_boundaries, threshold_between
    from verify.paper.cradle_map import aeev_rows_explained

    lines = [f"  exact map: {len(cmap.pieces)} pieces with an exit, up to {counted(cmap.max_impulses, 'impulse')}"]
    t34 = threshold_between(cmap, 4, 3)
    if t34 is not None:
        lines.append(f"    3 -> 4 impulses at eps = {t34} (derived from the map, as the paper states)")
    for b in termination_boundaries(cmap):
        above = [p for p in cmap.parts if p.piece.lower >= b and p.stop != "non_terminating"]
        rest = (
            "exits for every larger eps"
            if all(p.stop == "exit" or p.exits_beyond_bound for p in above)
            else ("larger eps not all decided")
        )
        lines.append(f"    never exits for eps <= {b} = {format_decimal(b, 12)} (certified); {rest}")
    for row in aeev_rows_explained(cmap):
        lines.append(f"    paper's row eps = {row['eps']} ({row['printed']}): {row['verdict']}")
    return "\n".join(lines) + "\n"
