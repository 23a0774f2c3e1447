"""The text of a run: a result's trace, its law, and the headers of the cradle, the corner and a case file's runs
(``verify cradle``, ``verify corner``, ``verify solve``).

>>> from verify.models.cradle import run_cradle
>>> print(cradle_text(run_cradle("1"), eps=["1"], mode="exact").splitlines()[0])
Newton's cradle: 3 balls (masses 1, 1, 1), eps = 1 for every contact
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from verify.dynamics.system import default_names
from verify.laws.outcome import Result, energy_words, stop_words
from verify.numbers.backends.base import Backend
from verify.numbers.format import counted, format_exact
from verify.records.results import value_string

if TYPE_CHECKING:
    from verify.models.corner import CornerRun

TRACE_LIMIT = 40


def cradle_text(result: Result, *, eps: list[str], mode: str, full_trace: bool = False) -> str:
    """The human-readable report of one cradle run."""
    K = result.backend
    s = result.system
    masses = [K.to_decimal(s.g[i][i], 12) for i in range(s.n)]
    eps_text = (
        f"eps = {eps[0]} for every contact"
        if len(eps) == 1
        else "eps = " + join_values([f"{e} for {name}" for e, name in zip(eps, s.names)])
    )
    lines = [
        f"Newton's cradle: {s.n} balls (masses {join_values(masses)}), {eps_text}",
        f"left velocity: {join_values([value_string(K, x) for x in result.velocity_in])}",
        f"backend: {K.describe()}; mode: {mode}",
        *law_lines(result),
    ]
    lines += [f"note: {n}" for n in result.notes]
    if result.steps:
        lines += ["", *trace_lines(result, full_trace), ""]
    label = result.velocity_name
    if K.is_exact:
        lines.append(f"{label} (exact): {join_values([short_exact(K, x) for x in result.exit_velocity])}")
    lines.append(f"{label} ({decimal_label(K)}): {join_values([K.to_decimal(x, 30) for x in result.exit_velocity])}")
    limit = result.limit
    if limit is not None:
        if K.is_exact:
            lines.append(f"limit velocity (exact): {join_values([short_exact(K, x) for x in limit.velocity])}")
        lines.append(
            f"limit velocity ({decimal_label(K)}): {join_values([K.to_decimal(x, 30) for x in limit.velocity])}"
        )
        lines.append(
            f"limit proved: {limit.statement(lambda x: short_exact(K, x) if K.is_exact else K.to_decimal(x, 12))}"
        )
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
    lines.append(f"iterations: {impulses_words(result)}{which}; stop: {stop}")
    lines.append(energy_line(result) + " (12 significant digits)")
    return "\n".join(lines) + "\n"


def impulses_words(result: Result) -> str:
    """A run's impulses: their number, or, for a run proved never to exit, that they never end."""
    if result.stop == "non_terminating":
        return f"never end (infinitely many; proved after {result.iterations})"
    return str(result.iterations)


def energy_line(result: Result) -> str:
    """The kinetic energy in and out; for a run that never exits, in and when it was proved (there is no out)."""
    K = result.backend
    if result.stop == "non_terminating":
        return f"kinetic energy: {energy_words(result, 12)}"
    before, after = K.to_decimal(result.kinetic_energy_in, 12), K.to_decimal(result.kinetic_energy_out, 12)
    return f"kinetic energy: {before} -> {after}"


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
        vel = join_values([K.to_decimal(x, 12) for x in st.velocity])
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
    lam = join_values([K.to_decimal(x, 12) for x in result.impulses or ()])
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

    >>> from verify.laws.rule import solve
    >>> from verify.dynamics.system import System
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
    unit = "sweep" if result.law == "sequential" else "impulse"
    lines = [
        f"{case_id}: {stop_words(result.stop, result.iterations, unit)} ({K.describe()})",
        f"  impact sets: {sets or '-'}",
        *law_lines(result, "  "),
    ]
    if trace and result.steps:  # verify solve --trace
        lines += trace_lines(result, True, "  ", names=shown)
    if K.is_exact:
        lines.append(f"  {result.velocity_name}: {join_values([short_exact(K, x) for x in result.exit_velocity])}")
    lines.append(f"  {decimal_label(K)}: {join_values([K.to_decimal(x, 20) for x in result.exit_velocity])}")
    lines.append(f"  {energy_line(result)} ({len(s.names)} constraints, {s.n} coordinates)")
    lines += [f"  note: {n}" for n in result.notes]
    return "\n".join(lines) + "\n"


def corner_text(
    run: CornerRun, *, alpha: str | None, slope: str | None, phi: str, v0: str, eps1: str, eps2: str
) -> str:
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
        lines.append(f"{label} (exact): {', '.join(short_exact(K, x, 120) for x in r.exit_velocity[:2])}")
    lines.append(f"{label} ({decimal_label(K)}): {', '.join(K.to_decimal(x, 30) for x in r.exit_velocity[:2])}")
    if K.encloses:
        for name, x in zip(("xd", "yd"), r.exit_velocity[:2]):
            lo, hi = K.enclosure(x, 20)
            lines.append(f"  {name} in [{lo}, {hi}]")
    lines.append(f"iterations: {impulses_words(r)}; stop: {r.stop}")
    lines.append(energy_line(r))
    return "\n".join(lines) + "\n"


def join_values(values: list[str]) -> str:
    return ", ".join(values)


def decimal_label(K: Backend) -> str:
    """What the decimals are: interval backends print only the digits their enclosures certify
    (:meth:`verify.numbers.backends.IntervalBackend.to_decimal`), so fewer than asked for."""
    return "decimal, certified digits only" if K.encloses else "decimal"


def short_exact(K: Backend, x: Any, limit: int = 60) -> str:
    text = K.to_exact(x)
    if len(text) <= limit:
        return text
    return f"<a fraction of {len(text)} characters: see --json>"
