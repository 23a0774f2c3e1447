"""Text and JSON views of results for the command line (no arithmetic happens here).

>>> from verify.models.cradle import run_cradle
>>> print(cradle_text(run_cradle("1"), eps=["1"], mode="exact").splitlines()[0])
Newton's cradle: 3 balls (masses 1, 1, 1), eps = 1 for every contact
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from verify.checks.paper.readings import Search, Window, closed_form
from verify.checks.paper.table1 import (
    ARITHMETICS,
    PARI_PREC,
    READINGS,
    EntryCheck,
    Table1,
    sqrt_decimal,
    threshold_brackets,
)
from verify.core.format import counted, format_decimal, format_exact
from verify.core.rule import Result
from verify.core.system import default_names
from verify.models.paper import MEASURES, NORMS, PAPER_READING, PAPER_SIGMA_RELATIVE, PAPER_SIGMA_STATED, WHENS
from verify.records.results import result_record, value_string

TRACE_LIMIT = 40


def _join(values: list[str]) -> str:
    return ", ".join(values)


def cradle_text(result: Result, *, eps: list[str], mode: str, full_trace: bool = False) -> str:
    """The human-readable report of one cradle run."""
    K = result.backend
    s = result.system
    masses = [K.to_decimal(s.g[i][i], 12) for i in range(s.n)]
    eps_text = (
        f"eps = {eps[0]} for every contact"
        if len(eps) == 1
        else "eps = " + _join([f"{e} for {name}" for e, name in zip(eps, s.names)])
    )
    lines = [
        f"Newton's cradle: {s.n} balls (masses {_join(masses)}), {eps_text}",
        f"left velocity: {_join([value_string(K, x) for x in result.velocity_in])}",
        f"backend: {K.describe()}; mode: {mode}",
        *law_lines(result),
    ]
    lines += [f"note: {n}" for n in result.notes]
    if result.steps:
        lines += ["", *trace_lines(result, full_trace), ""]
    label = result.velocity_name
    if K.is_exact:
        lines.append(f"{label} (exact): {_join([_short_exact(K, x) for x in result.exit_velocity])}")
    lines.append(f"{label} ({_decimal_label(K)}): {_join([K.to_decimal(x, 30) for x in result.exit_velocity])}")
    stop = {
        "exit": "exit (no constraint is hit any more)",
        "aeev": "aeev (the paper's almost-equal-exit-velocities stop)",
        "max_iterations": (
            f"max_iterations (still incoming after {result.max_iterations} sweeps)"
            if result.law == "sequential"
            else f"max_iterations (no exit within {counted(result.max_iterations, 'impulse')})"
        ),
        "non_terminating": "non_terminating (proved never to exit: the certificate is in --json)",
    }.get(result.stop, result.stop)
    which = " (sweeps that changed an impulse)" if result.law == "sequential" else ""
    lines.append(f"iterations: {result.iterations}{which}; stop: {stop}")
    lines.append(
        f"kinetic energy: {K.to_decimal(result.kinetic_energy_in, 12)} -> "
        f"{K.to_decimal(result.kinetic_energy_out, 12)} (12 significant digits)"
    )
    return "\n".join(lines) + "\n"


def trace_lines(
    result: Result, full_trace: bool = False, indent: str = "", names: Sequence[str] | None = None
) -> list[str]:
    """The trace of a run: one line per impulse (a sweep under the sequential law) with its impact set, beta
    (under the sequential law the changes of the accumulated impulses), the velocity after it and the kinetic
    energy; the first and last lines only beyond ``TRACE_LIMIT`` unless ``full_trace``. The constraints are
    named by ``names`` (default the system's)."""
    K, s, steps = result.backend, result.system, result.steps
    shown_names = list(names or s.names)
    sequential = result.law == "sequential"
    unit = "sweep" if sequential else "impulse"
    chosen: list[tuple[int, Any] | None] = list(enumerate(steps, 1))
    if not full_trace and len(chosen) > TRACE_LIMIT:
        chosen = [*chosen[: TRACE_LIMIT - 5], None, *chosen[-5:]]
    rows: list[tuple[int, str, str, str, str] | None] = []
    for item in chosen:
        if item is None:
            rows.append(None)
            continue
        w, st = item
        impact = "{" + ", ".join(shown_names[j] for j in st.impact_set) + "}"
        if sequential:
            middle = ", ".join(K.to_decimal(x, 6) for _, x in sorted(st.changes, key=lambda c: c[0]))
        else:
            middle = "-" if st.beta is None else K.to_decimal(st.beta, 8)
        vel = _join([K.to_decimal(x, 12) for x in st.velocity])
        rows.append((w, impact, middle, vel, K.to_decimal(st.kinetic_energy, 12)))
    head = "changes of lambda" if sequential else "beta"
    widths = [max([len(str(r[k])) for r in rows if r] + [len(h)]) for k, h in ((1, "impact set"), (2, head), (3, ""))]
    widths = [max(widths[0], 16), max(widths[1], 20 if sequential else 14), max(widths[2], 48)]
    title = f"{unit:>7}  {'impact set':<{widths[0]}} {head:<{widths[1]}} {'velocity after (12 digits)':<{widths[2]}}"
    lines = [indent + title + " kinetic energy"]
    for row in rows:
        if row is None:
            lines.append(f"{indent}{'...':>7}  ({len(steps) - TRACE_LIMIT + 1} {unit}s not shown; --trace shows all)")
            continue
        w, impact, middle, vel, energy = row
        lines.append(f"{indent}{w:>7}  {impact:<{widths[0]}} {middle:<{widths[1]}} {vel:<{widths[2]}} {energy}")
    return lines


def law_lines(result: Result, indent: str = "") -> list[str]:
    """The lines that name the simultaneous or the sequential law and its impulses (none for the paper's rule)."""
    if result.law == "rule":
        return []
    K = result.backend
    lam = _join([K.to_decimal(x, 12) for x in result.impulses or ()])
    if result.sequential is not None:
        what = f"sequential ({result.sequential.describe(result.system.names)})"
        label = "accumulated impulses lambda"
    else:
        what = "simultaneous (Newton's restitution with complementarity, all constraints at once)"
        label = "impulses lambda"
    return [f"{indent}law: {what}", f"{indent}{label} (12 digits): {lam}"]


def solve_text(case_id: str, result: Result, trace: bool = False) -> str:
    """A few lines per solved case; the impact sets by the contacts' names when the case names them
    (``names``), else by their 0-based indices.

    >>> from verify.core.rule import solve
    >>> from verify.core.system import System
    >>> print(solve_text("a", solve(System([[1, 0], [0, 1]], [[-1, 1]], [1], names=["spring"]), [1, 0])))
    a: exit after 1 impulse (...)
      impact sets: {spring}
    ...
    """
    K = result.backend
    s = result.system
    shown = [str(j) for j in range(s.r)] if s.names == default_names(s.r) else s.names
    sets = " ".join("{" + ",".join(shown[j] for j in J) + "}" for J in result.impact_sets[:20])
    if result.iterations > 20:
        sets += f" ... ({result.iterations - 20} more)"
    lines = [
        f"{case_id}: {result.stop} after "
        f"{counted(result.iterations, 'sweep' if result.law == 'sequential' else 'impulse')} "
        f"({K.describe()})",
        f"  impact sets: {sets or '-'}",
        *law_lines(result, "  "),
    ]
    if trace and result.steps:  # verify solve --trace
        lines += trace_lines(result, True, "  ", names=shown)
    if K.is_exact:
        lines.append(f"  {result.velocity_name}: {_join([_short_exact(K, x) for x in result.exit_velocity])}")
    lines.append(f"  {_decimal_label(K)}: {_join([K.to_decimal(x, 20) for x in result.exit_velocity])}")
    lines.append(
        f"  kinetic energy: {K.to_decimal(result.kinetic_energy_in, 12)} -> "
        f"{K.to_decimal(result.kinetic_energy_out, 12)}"
        f" ({len(s.names)} constraints, {s.n} coordinates)"
    )
    lines += [f"  note: {n}" for n in result.notes]
    return "\n".join(lines) + "\n"


def _decimal_label(K: Any) -> str:
    """What the decimals are: interval backends print only the digits their enclosures certify
    (:meth:`verify.core.backends.IntervalBackend.to_decimal`), so fewer than asked for."""
    return "decimal, certified digits only" if K.encloses else "decimal"


def _short_exact(K: Any, x: Any, limit: int = 60) -> str:
    text = K.to_exact(x)
    if len(text) <= limit:
        return text
    return f"<a fraction of {len(text)} characters: see --json>"


def _iters(result: Result) -> str:
    if result.stop == "aeev":
        return f"AEEV / {result.iterations}"
    if result.stop == "exit":
        return str(result.iterations)
    if result.stop == "non_terminating":
        return "never exits (proof)"
    return f"no exit in {result.iterations}"


def table1_text(table: Table1) -> str:
    """Table 1: printed against recomputed, every entry marked, with reasons."""
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
    for row in bad:
        for c in row.checks:
            if not c.explained:
                lines.append(
                    f"  eps = {row.eps}, {c.column}: printed {c.printed}, computed {c.computed[:14]}: {c.reason}"
                )
                if c.tried:
                    lines.append(f"    tried: {'; '.join(c.tried)} (final state and every state of the run)")
        for note in row.row_notes:
            lines.append(f"    row {row.eps}: {note}")
    lines += ["", *entries_explained_text(table)]
    lines += ["", *aeev_text(table.identification)]
    rows_exit_differs = [
        r for r in table.rows if (r.exact.stop, r.exact.iterations) != (r.paper.stop, r.paper.iterations)
    ]
    if rows_exit_differs:
        lines += ["", "Where the exact run differs from paper mode:"]
        for r in rows_exit_differs:
            lines.append(f"  eps = {r.eps}: paper mode {_iters(r.paper)}, exact {_iters(r.exact)}")
    return "\n".join(lines) + "\n"


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
    lines.append(f"  paper mode uses {reading} with c = {format_decimal(PAPER_SIGMA_RELATIVE)} (see "
                 "verify/models/paper.py; other readings: verify cradle --mode paper --aeev READING)")  # fmt: skip
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


def approach_table(rows: Sequence[tuple[Fraction, int | str]]) -> list[str]:
    """The lines of the table of :func:`approach_counts` (a blank line first; none for no rows).

    A count is shown only for a run that exits; any other row says what happened in words,
    and a ratio is shown only between two consecutive rows that both exit.

    >>> rows = [(Fraction(1, 10), 8), (Fraction(1, 100), 24), (Fraction(1, 1000), "> 30 (budget)")]
    >>> print("\\n".join(approach_table(rows)))
    <BLANKLINE>
    Impulses until exit just above the boundary (certified interval runs):
                         eps  impulses   ratio to the row above
                         0.1         8
                        0.01        24                        3
                       0.001  > 30 (budget)
      (each row is about ten times closer to the boundary; ...)
    """
    if not rows:
        return []
    lines = [
        "",
        "Impulses until exit just above the boundary (certified interval runs):",
        f"  {'eps':>22}  {'impulses':>8}  {'ratio to the row above':>23}",
    ]
    previous = None
    for eps, n in rows:
        if isinstance(n, int):
            ratio = "" if previous is None else format_decimal(Fraction(n, previous), 4)
            lines.append(f"  {format_decimal(eps, 16):>22}  {n:>8}  {ratio:>23}")
            previous = n
        else:  # no count: no ratio from this row, nor to the next one
            lines.append(f"  {format_decimal(eps, 16):>22}  {n}")
            previous = None
    lines.append(
        "  (each row is about ten times closer to the boundary; a ratio near sqrt(10) means a count "
        "growing like (eps - boundary)^(-1/2))"
    )
    return lines


def _stopped_line(stopped: str) -> list[str]:
    """The line that says a map stopped early (none for a complete map)."""
    if not stopped:
        return []
    return [f"Stopped early: {stopped}. Below is what was decided; the rest is unexplored, saying so."]


def cradle_map_text(
    cmap: Any,
    *,
    aeev_rows: list[dict[str, Any]],
    approach: Sequence[tuple[Fraction, int | str]],
    exact_in: str = "map_json(cmap)",
) -> str:
    """The cradle map in words and tables. ``exact_in`` says where every exact endpoint and
    certificate is (the command line passes ``"--json"``)."""
    from verify.maps.cradle import termination_boundaries, threshold_between, undecided_measure
    from verify.models.cradle import cradle_system

    masses = ", ".join(format_exact(m) for m in cmap.masses)
    lines = [
        f"Newton's cradle, {cmap.balls} balls (masses {masses}), left velocity "
        f"({', '.join(format_exact(v) for v in cmap.velocity)}), one COR eps for every contact",
        f"eps in {cmap.domain}; explored up to {counted(cmap.max_impulses, 'impulse')}; exact endpoints, "
        "decimals rounded to 12 digits",
        *_stopped_line(cmap.stopped),
        "",
        *parts_table(cmap.parts, contacts=cradle_system("1", cmap.balls).names),
    ]
    points = [cmap.parts[0].piece.lower] + [p.piece.upper for p in cmap.parts]
    lines += ["", f"Exact endpoints (polynomials of degree 4 or less; all of them, as CRootOf, in {exact_in}):"]
    seen: list[Any] = []
    for x in points:
        if (x.is_rational or x.poly.degree() <= 4) and not any(x is y for y in seen):
            seen.append(x)
            lines.append(f"  {format_decimal(x, 12):>16} = {x}")
    t34 = threshold_between(cmap, 4, 3)
    if t34 is not None:
        lines += ["", f"The threshold between 3 and 4 impulses, derived: eps = {t34} = {format_decimal(t34, 20)}"]
    bounds = termination_boundaries(cmap)
    for part in cmap.non_terminating:
        cert = part.certificate or {}
        if "mu" in cert:
            how = f"invariant cones (mu = {', '.join(cert['mu'])})"
        elif cert.get("kind") == "repeating direction":
            cycle = len(cert.get("cycle", []))
            after = counted(cycle, "impulse")
            how = f"a direction of the rates that repeats after {after} (verify solve's run at that point)"
        elif cert.get("kind") == "dominant growth":
            how = (f"the growth of the rates on the plane of the two eigenvalues of the period {cert['pattern']} that "
                   f"meet at the boundary, against the turning pair beside them (verify.maps.growth), from the rates "
                   f"after {counted(cert['impulses'] or 0, 'impulse')}")  # fmt: skip
        else:
            gens, impulses = len(cert.get("generators", [])), cert.get("impulses")
            how = f"a cone of {gens} generators that {impulses} impulses map into itself"
            if "boundary" in cert:
                how += f" (built from the period of the repeating impacts {cert['boundary']['pattern']})"
        checker = "tests/test_map_boundary.py" if "boundary" in cert else "tests/test_cradle_map.py"
        lines += [
            "",
            f"Never exits for eps in {part.piece}: proved by {how};",
            f"  the certificate is in {exact_in}; {checker} checks it without the code that found it.",
        ]
    for bound in bounds:
        lines.append(f"Termination boundary: eps = {bound} = {format_decimal(bound, 20)}")
    lines += boundary_lines(cmap.parts, "eps")
    for part in cmap.unexplored:
        lines += ["", f"Unexplored {part.piece}: {part.reason}"]
    lo, hi = undecided_measure(cmap)
    if hi > 0:
        middle, error = format_decimal((lo + hi) / 2, 12), format_decimal((hi - lo) / 2, 2)
        lines += ["", f"Undecided in all: a set of eps of length {middle} (+- {error})"]
    lines += approach_table(approach)
    if aeev_rows:
        lines += ["", "The paper's AEEV rows (Table 1), read off the map:"]
        for row in aeev_rows:
            lines.append(f"  eps = {row['eps']:<7} printed {row['printed']:<10} -> {row['verdict']}")
    return "\n".join(lines) + "\n"


def parts_table(parts: Sequence[Any], name: str = "eps", contacts: Sequence[str] | None = None) -> list[str]:
    """The lines of a map's table: each part's interval of the parameter ``name`` (decimals rounded to 12
    digits), its impulses and what happens; impact sets by index, or by the ``contacts``' names."""
    lines = [f"{name + ' from':>16} {'to':>16}  {'impulses':>8}  what happens"]
    for part in parts:
        a, b = format_decimal(part.piece.lower, 12), format_decimal(part.piece.upper, 12)
        left = "[" if part.piece.lower_closed else "("
        right = "]" if part.piece.upper_closed else ")"
        if part.stop == "exit":
            what = "exit: " + _sequence(part.impact_sets, contacts)
        elif part.stop == "non_terminating" and (part.certificate or {}).get("kind") == "repeating direction":
            what = "never exits (certificate: repeating direction)"
        elif part.stop == "non_terminating" and (part.certificate or {}).get("kind") == "dominant growth":
            what = "never exits (certificate: dominant growth)"
        elif part.stop == "non_terminating":
            what = "never exits (certificate: invariant cones)"
        else:
            what = "unexplored"
        count = str(part.iterations) if part.stop == "exit" else "-"
        lines.append(f"{left}{a:>15} {b:>16}{right} {count:>8}  {what}")
    return lines


def _sequence(impact_sets: list[tuple[int, ...]], contacts: Sequence[str] | None = None) -> str:
    """``(0)(1)(0)`` with runs folded: ``(0)(1) x 5``; the contacts' names instead of indices when given."""
    words = ["(" + ",".join(contacts[j] if contacts else str(j) for j in J) + ")" for J in impact_sets]
    if len(words) > 8 and len(set(words[0::2])) == 1 and len(set(words[1::2])) == 1:
        return f"{words[0]}{words[1]} alternating, {len(words)} impulses"
    return "".join(words)


def cradle_map_summary(cmap: Any) -> str:
    """A few lines of the cradle map for ``verify all``."""
    from verify.checks.paper.cradle_map import aeev_rows_explained
    from verify.maps.cradle import termination_boundaries, threshold_between

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


def corner_text(run: Any, *, alpha: str | None, slope: str | None, phi: str, v0: str, eps1: str, eps2: str) -> str:
    """The human-readable report of one corner run, with its inputs as given (``alpha`` or ``slope``)."""
    r = run.result
    K = r.backend
    angle = f"alpha = {alpha}" if alpha is not None else f"slope k = {slope}"
    lines = [
        f"Disk in a corner: {angle} (k = {format_exact(run.slope)}), entrance direction phi = {phi}, "
        f"v0 = {v0}, eps1 = {eps1} (S1), eps2 = {eps2} (S2)",
        f"entrance velocity: {', '.join(format_exact(v) for v in run.velocity[:2])}",
        f"backend: {K.describe()}",
        *law_lines(r),
    ]
    lines += [f"note: {n}" for n in run.notes]
    lines.append(f"zones visited: {' -> '.join(run.zones)}")
    if run.repeated_multiple_impacts:
        lines.append(f"repeated multiple impacts: {sum(1 for J in r.impact_sets if len(J) == 2)}")
    lines.append("")
    for w, st in enumerate(r.steps, 1):
        if w > TRACE_LIMIT:
            lines.append(f"  ... ({len(r.steps) - TRACE_LIMIT} more impulses)")
            break
        beta = "" if st.beta is None else f", beta = {K.to_decimal(st.beta, 12)}"
        wall = "+".join(r.system.names[j] for j in st.impact_set)
        lines.append(f"  impulse {w}: {wall}{beta}; velocity {', '.join(K.to_decimal(x, 12) for x in st.velocity[:2])}")
    label = r.velocity_name
    if K.is_exact:
        lines.append(f"{label} (exact): {', '.join(_short_exact(K, x, 120) for x in r.exit_velocity[:2])}")
    lines.append(f"{label} ({_decimal_label(K)}): {', '.join(K.to_decimal(x, 30) for x in r.exit_velocity[:2])}")
    if K.encloses:
        for name, x in zip(("xd", "yd"), r.exit_velocity[:2]):
            lo, hi = K.enclosure(x, 20)
            lines.append(f"  {name} in [{lo}, {hi}]")
    lines.append(f"iterations: {r.iterations}; stop: {r.stop}")
    lines.append(f"kinetic energy: {K.to_decimal(r.kinetic_energy_in, 12)} -> {K.to_decimal(r.kinetic_energy_out, 12)}")
    return "\n".join(lines) + "\n"


def corner_claims_text(claims: Any, boundary: Any, eps: str, rebounds: Any, floats: Any) -> str:
    """The corner's claims, the wedge's termination boundary and float-vs-exact, in words."""
    lines = ["The disk in the corner (Sect. 4.2): the paper's claims, checked exactly", ""]
    for c in claims:
        lines.append(f"  [{c.verdict}] {c.name}")
        lines.append(f"      {c.cases} cases; {c.note}")
        if c.counterexample:
            lines.append(f"      counterexample: {c.counterexample}")
        for e in c.examples[:3]:
            lines.append(f"      example: slope {e['slope']}, velocity {e['velocity']}, eps {e['eps1']}, {e['eps2']}")
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
        f"  {floats['differing']} cases take another branch; reasons: {floats['reasons']}; "
        f"{floats['differing_with_a_cor_of_0']} of them have a COR of 0",
    ]
    for e in floats["examples"][:3]:
        case = e["case"]
        lines.append(
            f"  e.g. slope {case['slope']}, velocity {case['velocity']}, eps {case['eps1']}, {case['eps2']}: "
            f"exact {'-'.join(e['exact_zones'])}, float {'-'.join(e['float_zones'])} ({e['reason']})"
        )
    return "\n".join(lines) + "\n"


def corner_claims_json(claims: Any, boundary: Any, eps: str, rebounds: Any, floats: Any) -> dict[str, Any]:
    """The same as :func:`corner_claims_text`, as JSON."""
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


def corner_summary(example: Any, claims: Any) -> str:
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


def properties_text(profile: str, found: list) -> str:
    """The verdict table of ``verify properties`` (a row per property, law, rule and family; for
    the simultaneous law the rule column names the CORs), then every refutation with its case.

    >>> from types import SimpleNamespace as Row
    >>> print(properties_text("dev", [Row(property="p", law="simultaneous", rule="ideal", family="corner",
    ...                                   verdict="holds", cases=25)]), end="")
    Property suite, profile dev: 1 row (property x law x rule x family)
    <BLANKLINE>
      property  law           rule        family   verdict   cases
      p         simultaneous  ideal       corner   holds     25
    <BLANKLINE>
      0 proved, 1 holds, 0 refuted
    """
    import json

    lines = [f"Property suite, profile {profile}: {counted(len(found), 'row')} (property x law x rule x family)", ""]
    width = max((len(v.property) for v in found), default=10)
    lines.append(f"  {'property':{width}}  {'law':12}  {'rule':10}  {'family':7}  {'verdict':8}  cases")
    for v in found:
        lines.append(f"  {v.property:{width}}  {v.law:12}  {v.rule:10}  {v.family:7}  {v.verdict:8}  {v.cases}")
    counts = {k: sum(v.verdict == k for v in found) for k in ("proved", "holds", "refuted")}
    lines += ["", "  " + ", ".join(f"{n} {k}" for k, n in counts.items())]
    lines += census_lines(found)
    for v in found:
        if v.verdict != "refuted":
            continue
        which = f"{v.rule} rule" if v.law == "rule" else f"{v.law} law, {v.rule} CORs"
        lines += [
            "",
            f"REFUTED: {v.property} ({which}, {v.family})",
            f"  {v.note}",
            "  counterexample (case file):",
        ]
        lines.append("    " + json.dumps({"cases": [v.counterexample]}, sort_keys=True))
    return "\n".join(lines) + "\n"


def census_lines(found: list) -> list[str]:
    """The census of the termination rows: how each row's runs end (empty without such rows).

    >>> from types import SimpleNamespace as Row
    >>> row = Row(property="t", law="rule", rule="ideal", family="corner", cases=3,
    ...           census=lambda: {"exit": 2, "non_terminating": 1, "max_iterations": 0, "budget": 0})
    >>> for line in census_lines([row]):
    ...     print(line)
    <BLANKLINE>
    Census: how the runs of each termination row end (a refuted row's census is a separate sample)
    <BLANKLINE>
      law           rule        family   cases  exit  non_terminating  max_iterations  budget
      rule          ideal       corner       3     2                1               0       0
    """
    rows = [(v, c) for v in found if (c := getattr(v, "census", lambda: None)()) is not None]
    if not rows:
        return []
    stops = list(dict.fromkeys(k for _, c in rows for k in c))
    lines = ["", "Census: how the runs of each termination row end (a refuted row's census is a separate sample)", ""]
    lines.append(f"  {'law':12}  {'rule':10}  {'family':7}  {'cases':>5}  " + "  ".join(stops))
    for v, c in rows:
        counts = "  ".join(f"{c.get(k, 0):>{len(k)}}" for k in stops)
        lines.append(f"  {v.law:12}  {v.rule:10}  {v.family:7}  {v.cases:>5}  {counts}")
    return lines


def graded_lines(comparison: Any) -> list[str]:
    """The graded verdicts: one line per case that does not pass, the count per class, and the
    cases that need the largest tolerance (:mod:`verify.checks.grading`)."""
    from verify.checks.grading import PASSING, hardest
    from verify.core.format import format_decimal

    lines = [f"{g.cls.upper()} {g.case_id}: {g.detail}" for g in comparison.grades if g.cls not in PASSING]
    lines += [f"WITHIN_TOLERANCE {g.case_id}: {g.detail}" for g in comparison.grades
              if g.cls == "within_tolerance" and g.detail]  # fmt: skip
    lines += ["", "  class                count"] if lines else ["  class                count"]
    lines += [f"  {cls:20} {n}" for cls, n in comparison.classes().items()]
    worst = hardest(comparison.grades, 3)
    if worst:
        lines += ["", "largest tolerance needed (relative to the exit speed; binary64 ulps of the exact value):"]
        lines += [f"  {g.case_id}: {format_decimal(g.needed_speed or 0, 3)} ({g.needed_ulps} ulps)" for g in worst]
    return [*lines, ""]


def ulps_text(n: int) -> str:
    """A count of ulps: all its digits below a million, else its first three digits (truncated).

    >>> ulps_text(4049), ulps_text(938012345678901234567890123456)
    ('4049', '9.38e+29')
    """
    digits = str(n)
    if n < 10**6:
        return digits
    return f"{digits[0]}.{digits[1:3]}e+{len(digits) - 1}"


def error_table_text(rows: Sequence[Any]) -> str:
    """``verify oracle table``: one row per implementation, the count per class and the worst errors."""
    from verify.checks.grading import CLASSES

    used = [c for c in CLASSES if any(c in r.counts for r in rows)]
    width = max([len(r.name) for r in rows] + [14])
    head = f"  {'implementation':{width}}  {'law':12}" + "".join(f"  {c:>{max(len(c), 5)}}" for c in used)
    lines = [head + "  worst relative error (case)"]
    for r in rows:
        counts = "".join(f"  {r.counts.get(c, 0):>{max(len(c), 5)}}" for c in used)
        worst = "-" if r.worst_speed is None else f"{format_decimal(r.worst_speed[0], 3)} ({r.worst_speed[1]})"
        ulp_text = "" if r.worst_ulps is None else f"; {ulps_text(r.worst_ulps[0])} ulps ({r.worst_ulps[1]})"
        lines.append(f"  {r.name:{width}}  {r.law:12}{counts}  {worst}{ulp_text}")
    return "\n".join(lines) + "\n"


def oracle_text(comparison: Any, report: Any = None) -> str:
    """Every mismatch of ``verify oracle check``, then a summary table; the last lines count the cases as
    ``--junit`` reports them (``report``: its ``--junit-as``)."""
    from verify.views.junit import junit_counts

    lines = []
    for m in comparison.mismatches:
        lines.append(f"MISMATCH {m.case_id}: {m.field}: {m.detail}")
    fields: dict[str, int] = {}
    for m in comparison.mismatches:
        key = m.field.split("[")[0]
        fields[key] = fields.get(key, 0) + 1
    lines += ["", "  what                 count", f"  cases checked        {comparison.checked}",
              f"  cases agreeing       {comparison.agreeing}"]  # fmt: skip
    lines += [f"  {k:20} {v}" for k, v in sorted(fields.items())]
    if comparison.skipped:
        lines.append(f"  skipped by the implementation: {len(comparison.skipped)}")
    lines.append("")
    for name, lacking in comparison.unchecked.items():
        lines.append(f"not checked: {name} (left out of {counted(lacking, 'result')}: velocity-only)")
    if comparison.unchecked:
        lines.append("")
    for cid, reason in comparison.skipped.items():
        lines.append(f"SKIPPED {cid}: {reason}")
    lines += graded_lines(comparison)
    if comparison.tolerance:
        lines += [f"tolerance: {comparison.tolerance}", ""]
    counts = junit_counts(comparison.grades, report)
    graded = {g.case_id for g in comparison.grades}
    if any(m.case_id not in graded for m in comparison.mismatches):  # results of no case: a test of their own
        counts = dict(counts, tests=counts["tests"] + 1, failures=counts["failures"] + 1)
    lines.append(f"as tests (--junit): {counts['passed']} passed, {counts['failures']} failed, "
                 f"{counts['skipped']} skipped of {counts['tests']}")  # fmt: skip
    agree = "every case agrees" if not comparison.skipped else "every case that the implementation ran agrees"
    if comparison.limited:
        agree += (f" as far as the exact runs went ({len(comparison.limited)} limited by the budget: --junit counts "
                  "them as failures unless --junit-as limited=passed)")  # fmt: skip
    lines.append(f"OK: {agree}" if comparison.ok else counted(len(comparison.mismatches), "mismatch"))
    return "\n".join(lines) + "\n"


def all_summary(
    table: Table1, cmap: Any, example: Any, claims: Any, *, profile: str, found: list, oracle_ok: bool
) -> tuple[str, bool]:
    """The closing summary of ``verify all`` (Table 1, the cradle map, the corner example and claims,
    the property verdicts of ``profile``, the oracle's self-check), and whether the program
    contradicted itself."""
    from verify.maps.cradle import termination_boundaries

    lines = ["", "Summary", "======="]
    bad = [(row.eps, c.column) for row in table.rows for c in row.checks if not c.agrees]
    lines.append(f"Table 1: {counted(len(table.rows), 'row')} recomputed; {counted(len(bad), 'printed entry')} "
                 f"{'disagrees' if len(bad) == 1 else 'disagree'} "
                 f"({', '.join(f'eps {e} {c}' for e, c in bad)}); see reports/table1.md")  # fmt: skip
    bounds = termination_boundaries(cmap)
    three = next((p for p in cmap.parts if p.stop == "exit" and p.iterations == 3), None)
    lines.append(f"Cradle: threshold 3 -> 4 impulses at eps = {three.piece.lower if three else '?'} (derived); "
                 f"never exits for eps <= {bounds[0] if bounds else '?'}; see reports/cradle-map.md")  # fmt: skip
    impulses = counted(example.result.iterations, "impulse")
    lines.append(f"Corner example: {impulses}, stop {example.result.stop}; claims: "
                 + ", ".join(f"{c.verdict}" for c in claims))  # fmt: skip
    refuted = [v for v in found if v.verdict == "refuted"]
    lines.append(f"Properties ({profile}): {sum(v.verdict == 'proved' for v in found)} proved, "
                 f"{sum(v.verdict == 'holds' for v in found)} hold, {len(refuted)} refuted:")  # fmt: skip
    for name in dict.fromkeys(v.property for v in refuted):
        rows = [f"{v.rule}/{v.family}" + ("" if v.law == "rule" else f" ({v.law} law)") for v in refuted
                if v.property == name]  # fmt: skip
        lines.append(f"  - {name}: {', '.join(rows)}")
    contradictions = [v for v in refuted if v.note.startswith("contradicts the proof")]
    lines.append("Oracle self-check: " + ("passed" if oracle_ok else "FAILED"))
    failed = bool(contradictions) or not oracle_ok
    if contradictions:
        wrong = counted(len(contradictions), "row")
        lines.append(f"PROGRAM ERROR: {wrong} {'contradicts' if len(contradictions) == 1 else 'contradict'} a SymPy "
                     "proof (see reports/properties.md)")  # fmt: skip
    return "\n".join(lines) + "\n", failed


def boundary_lines(parts: Sequence[Any], name: str) -> list[str]:
    """A paragraph for each boundary of never-exits that the parts reach with a cone of their repeating impacts
    (:mod:`verify.maps.boundary`): the exact point, what holds up to it and what is known above it."""
    from verify.core.algebraic import RealAlgebraic
    from verify.core.parse import parse_number

    seen: dict[str, dict[str, Any]] = {}
    highest: dict[str, Any] = {}
    for part in parts:
        b = (part.certificate or {}).get("boundary")
        if b is not None and b["eps"] not in seen:
            seen[b["eps"]] = b
        if b is not None:
            highest[b["eps"]] = part.piece.upper
    out = []
    for star, b in seen.items():
        value = format_decimal(RealAlgebraic.from_number(parse_number(star)), 20)
        if b.get("reached") is False:  # turning cones (verify.maps.turning) stop short of the boundary
            out += [
                "",
                f"Boundary of the repeating impacts {b['pattern']}: {name} = {star} = {value}, where the two largest "
                "eigenvalues of their period meet beside a complex pair of the same modulus (over "
                f"Q({b.get('extension', 'sqrt(d)')})). Cones that the period turns into themselves prove never-exits "
                f"up to {format_decimal(highest[star], 12)}; no polyhedral cone holds at the boundary itself, and the "
                "rest below it stays undecided.",
            ]
            continue
        proof = "the cones above"
        if "extension" in b:  # reached beside a turning pair: by the growth argument (verify.maps.growth)
            proof = (f"the growth of the rates where the two largest eigenvalues of their period meet, against the "
                     f"complex pair of the same modulus beside them, over Q({b['extension']}): "
                     "verify.maps.growth")  # fmt: skip
        out += [
            "",
            f"Boundary of never-exits: {name} = {star} = {value}: up to and at it the impacts {b['pattern']} repeat",
            f"forever ({proof})"
            + (
                "; beyond it the two eigenvalues of their period that meet there are not real and its spectral "
                "radius is not an eigenvalue: no cone is mapped into itself by it."
                if b["no_cone_beyond"]
                else "."
            ),
        ]
    return out


#: the most curves a map of cells lists in its text (all of them are in its JSON)
SHOWN_CURVES = 12


def behaviour_lines(m: Any, contacts: Sequence[str] | None = None) -> list[str]:
    """The area of each behaviour of a map of cells (:class:`verify.maps.plane.PlaneMap`), exact bounds: one line
    per stop and impact sequence (what :func:`plane_lines` shows before its cells); impact sets by index, or by
    the ``contacts``' names."""
    from verify.maps.plane import describe_area

    out = ["Area of each behaviour (exact bounds):"]
    kinds: dict[tuple, list[Any]] = {}
    for p in m.parts:
        if p.stop == "exit":
            key = (p.stop, p.iterations, tuple(p.impact_sets), "")
        else:
            kind = (p.certificate or {}).get("kind", "") if p.stop == "non_terminating" else p.reason
            key = (p.stop, 0, (), kind)
        kinds.setdefault(key, []).append(p)
    for (stop, n, sets, kind), parts in kinds.items():
        low, high = m.bounds_of(parts)
        what = {"exit": f"{stop} after {counted(n, 'impulse')} {_sequence(list(sets), contacts)}",
                "non_terminating": f"never exits (proved on each cell: {kind})",
                "max_iterations": f"unexplored ({kind})"}.get(stop, f"not run ({kind})")  # fmt: skip
        out.append(f"  {what}: {counted(len(parts), 'cell')}, area {describe_area((low, high))}")
    return out


def plane_lines(m: Any, contacts: Sequence[str] | None = None) -> list[str]:
    """A map of cells (:class:`verify.maps.plane.PlaneMap`) in words: the curves, the area of each behaviour
    (exact bounds) and one row per cell; impact sets by index, or by the ``contacts``' names.

    >>> import sympy as sp
    >>> from fractions import Fraction
    >>> from verify.maps.plane import plane_parts
    >>> from verify.models.corner import corner_system
    >>> build = lambda K: corner_system("1/2", sp.Symbol("e1"), sp.Symbol("e2"), backend=K)
    >>> box = (Fraction(0), Fraction(1), Fraction(0), Fraction(1))
    >>> m = plane_parts(build, ["1", "-1/10", "0"], box, ("e1", "e2"), 4)
    >>> print("\\n".join(plane_lines(m)[:3]))
    <BLANKLINE>
    The box cut into 29 exact cells (6 open regions, 14 arcs, 9 points) by 2 curves:
      e1 - 2*e2/5 + 2/13 = 0; e1 - 10*e2/9 + 5/13 = 0
    """
    dims = Counter(p.cell.dim for p in m.parts)
    curves = (
        "; ".join(f"{m.P.show(f, m.names)} = 0" for f in m.curves)
        if len(m.curves) <= SHOWN_CURVES
        else f"(more than {SHOWN_CURVES}: each in the JSON, --json)"
    )
    counts = f"{dims[2]} open regions, {dims[1]} arcs, {dims[0]} points"
    out = ["", f"The box cut into {len(m.parts)} exact cells ({counts}) by {len(m.curves)} curves:", f"  {curves}", "",
           *behaviour_lines(m, contacts)]  # fmt: skip
    out += [
        "",
        "Cells (x, then y; root k: the k-th real root in y in the box, counted from below; an irrational x "
        "to 12 digits, exact in the JSON):",
    ]
    for p in m.parts:
        shown = _sequence(p.impact_sets, contacts)
        what = {"exit": f"{p.stop} after {p.iterations}: {shown}", "non_terminating": f"{p.reason}: {shown}",
                "max_iterations": f"unexplored: {p.reason}"}.get(p.stop, f"not run: {p.reason}")  # fmt: skip
        out.append(f"  {p.cell.describe(m.P, m.names, digits=12)}: {what}")
    return out


def corner_map_text(found: Any) -> str:
    """The paper's corner mapped over its CORs (:func:`verify.checks.paper.corner_map.corner_maps`): the line
    eps2 = 1/1000, where its runs have repeated multiple impacts, and the area of the square where they do."""
    from verify.maps.plane import describe_area

    pieces = " and ".join(str(p) for p in found.repeated_pieces()) or "no value"
    velocity = ", ".join(format_exact(v) for v in found.plane.velocity)
    plane = found.plane.plane
    curves = sorted({plane.P.show(side.poly, plane.names) for p in found.repeated_plane
                     for side in (p.cell.y_lo, p.cell.y_hi) if getattr(side, "poly", None) is not None})  # fmt: skip
    return (
        eps_map_text(found.line, exact_in="verify.checks.paper.corner_map")
        + f"\nRepeated multiple impacts (the first two impulses both on both walls) on this line: exactly for eps1 in "
        f"{pieces}.\n\nBoth CORs over [0, 1]^2 as exact cells, up to "
        f"{counted(found.plane.max_impulses, 'impulse')}, from "
        f"velocity ({velocity}) (the paper's direction; the speed changes no "
        f"impact set or stop): {len(plane.parts)} cells; the first two impulses (two decide it) are multiple impacts "
        f"on {len(found.repeated_plane)} of "
        f"them, of area {describe_area(found.repeated_area())} (exact bounds), for eps1 from "
        f"{min((p.cell.x_lo for p in found.repeated_plane), default='-')} to "
        f"{max((p.cell.x_hi for p in found.repeated_plane), default='-')}, bounded below and above by "
        + ("; ".join(f"{c} = 0" for c in curves) or "the box")
        + ".\n\n"
        + "\n".join(behaviour_lines(plane, found.plane.system.names))
        + "\n"
    )


def eps_map_text(m: Any, *, exact_in: str = "eps_map_json(m)") -> str:
    """A map of :func:`verify.maps.general.eps_map` in words and tables, one table per line;
    ``exact_in`` says where the exact endpoints are (the command line passes ``"--json"``).

    >>> from verify.maps.general import eps_map
    >>> from verify.core.system import System
    >>> m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1], names=["spring"]), ["1", "0"], ["e"])
    >>> print(eps_map_text(m))
    A system of 2 coordinates and 1 contacts (spring), velocity (1, 0); CORs spring = e
    e in [0, 1]; explored up to 40 impulses; exact endpoints (in eps_map_json(m)), decimals rounded to 12 digits
    <BLANKLINE>
    e in [0, 1]:
    ...
    """
    from verify.maps.line import undecided_length

    cors = ", ".join(f"{name} = {cor}" for name, cor in zip(m.system.names, m.restitution))
    ranges = ", ".join(f"{n} in [{format_exact(lo)}, {format_exact(hi)}]" for n, (lo, hi) in m.parameters.items())
    lines = [
        f"A system of {m.system.n} coordinates and {m.system.r} contacts ({', '.join(m.system.names)}), velocity "
        f"({', '.join(format_exact(v) for v in m.velocity)}); CORs {cors}",
        f"{ranges}; explored up to {counted(m.max_impulses, 'impulse')}; exact endpoints (in {exact_in}), decimals "
        "rounded to "
        "12 digits",
        *_stopped_line(m.stopped),
    ]
    if m.plane is not None:
        return "\n".join(lines + plane_lines(m.plane, m.system.names)) + "\n"
    if m.layout != "interval":
        grid = "; ".join(f"{n}: {', '.join(format_exact(x) for x in xs)}" for n, xs in m.grid.items())
        lines.append(
            f"Two or more parameters: an exact grid of {len(m.lines)} lines, each parameter running over its "
            f"interval while the others take the grid values ({grid}); points off the lines are not mapped."
        )
    for line in m.lines:
        fixed = ", ".join(f"{n} = {format_exact(v)}" for n, v in line.fixed.items())
        lines += ["", f"{line.free} in {line.domain}" + (f", {fixed}" if fixed else "") + ":"]
        lines += parts_table(line.parts, line.free, m.system.names)
        lines += ["  " + x for x in boundary_lines(line.parts, line.free) if x]
        lo, hi = undecided_length(line.parts)
        if hi > 0:
            middle, error = format_decimal((lo + hi) / 2, 12), format_decimal((hi - lo) / 2, 2)
            lines.append(f"  undecided: a set of {line.free} of length {middle} (+- {error})")
    return "\n".join(lines) + "\n"
