"""The figures of the maps: the cradle's staircase over eps, a map over one COR, the cells of a plane of two."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

from verify.numbers.format import counted, format_decimal
from verify.views.figures import load_pyplot, save_figure, to_float

if TYPE_CHECKING:
    from verify.maps.cradle import CradleMap
    from verify.maps.general import EpsMap
    from verify.numbers.algebraic import RealAlgebraic


def _unexplored_kind(part: Any) -> str:
    """``"exits_later"`` when every eps of an unexplored part is proved to exit after the bound, else
    ``"undecided"``."""
    return "exits_later" if part.exits_beyond_bound else "undecided"


#: how each kind of part is drawn (the staircase's legend shows the same styles)
_UNEXPLORED_STYLE: dict[str, dict[str, Any]] = {
    "exits_later": {"facecolor": "0.6", "alpha": 0.3, "hatch": "//"},
    "undecided": {"facecolor": "0.85", "alpha": 0.6, "hatch": "xx"},
}


def _staircase_band(part: Any) -> dict[str, Any]:
    """The band of a staircase part that does not exit: red where it never exits, grey where unexplored."""
    if part.stop == "non_terminating":
        return {"color": "C3", "alpha": 0.18}
    return _UNEXPLORED_STYLE[_unexplored_kind(part)]


def staircase_legend(cmap: CradleMap) -> list[tuple[str, str]]:
    """The legend of :func:`cradle_staircase`: ``(kind, label)`` for each kind of thing drawn, and only those.

    Kinds: ``exit`` (the pieces), ``non_terminating`` (proved never to exit), ``exits_later``
    (unexplored, every eps proved to exit after the bound), ``undecided`` (unexplored, not
    decided: the label gives the map's reason), ``boundary`` and ``threshold_3_4``.

    >>> from verify.maps.cradle import cradle_map
    >>> staircase_legend(cradle_map(upper="1/20", max_impulses=2))
    [('non_terminating', 'never exits (proved)')]
    >>> dict(staircase_legend(cradle_map(balls=4, max_impulses=3)))["undecided"]
    'undecided: still impacting after 3 impulses\\n(no invariant cone found for the whole interval)'
    """
    from verify.maps.cradle import termination_boundaries, threshold_between

    out = []
    if cmap.pieces:
        out.append(("exit", "exits after n impulses (exact pieces)"))
    if cmap.non_terminating:
        out.append(("non_terminating", "never exits (proved)"))
    kinds = [_unexplored_kind(p) for p in cmap.unexplored]
    if "exits_later" in kinds:
        out.append(("exits_later", f"exits after more than {counted(cmap.max_impulses, 'impulse')}"))
    if "undecided" in kinds:
        reasons = []
        for part in cmap.unexplored:
            why = part.reason.split("; ", 1)[-1]  # the map's reason: "still impacting after N impulses; WHY"
            if _unexplored_kind(part) == "undecided" and why != "not decided" and why not in reasons:
                reasons.append(why)
        label = f"undecided: still impacting after {counted(cmap.max_impulses, 'impulse')}"
        out.append(("undecided", label + "".join(f"\n({why})" for why in reasons)))
    boundaries = termination_boundaries(cmap)
    if boundaries:
        out.append(("boundary", f"termination boundary {boundaries[0]}"))
    t34 = threshold_between(cmap, 4, 3)
    if t34 is not None:
        out.append(("threshold_3_4", f"3 -> 4 impulses at {t34}"))
    return out


def cradle_staircase(cmap: CradleMap, path: str | Path, marks: Sequence[tuple[Fraction, int]] = ()) -> Path:
    """Iteration count against eps for a cradle map: the staircase, the thresholds and the
    termination boundary. Left: the whole range. Right (when there is a termination
    boundary): the same steps against the distance to the boundary, on a log scale.
    The legend (:func:`staircase_legend`) names only what is drawn; unexplored parts are
    marked as proved to exit later or as undecided, with the map's reason. ``marks``: points (eps, impulses) drawn
    over it, such as the counts Table 1 prints."""
    return save_figure(staircase_figure(cmap, marks), path)


def staircase_figure(cmap: CradleMap, marks: Sequence[tuple[Fraction, int]] = ()) -> Any:
    """The matplotlib figure of :func:`cradle_staircase`, not saved (close it with ``plt.close``)."""
    plt = load_pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from verify.maps.cradle import termination_boundaries, threshold_between

    boundaries = termination_boundaries(cmap)
    t34 = threshold_between(cmap, 4, 3)
    fig, axes = plt.subplots(
        1, 2 if boundaries else 1, figsize=(10 if boundaries else 5.5, 4), constrained_layout=True, squeeze=False
    )
    ax = axes[0][0]
    for part in cmap.parts:
        a, b = to_float(part.piece.lower), to_float(part.piece.upper)
        _part_on_axes(ax, part, a, b, lw=1.6, band=_staircase_band)
    for x in boundaries:
        ax.axvline(to_float(x), color="C3", ls="--", lw=1)
    if t34 is not None:
        ax.axvline(to_float(t34), color="C2", ls=":", lw=1)
    ax.set_xlim(to_float(cmap.domain.lower), to_float(cmap.domain.upper))
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel("coefficient of restitution eps")
    ax.set_ylabel("impulses until exit")
    masses = "" if all(m == 1 for m in cmap.masses) else f" (masses {', '.join(str(m) for m in cmap.masses)})"
    ax.set_title(f"Newton's cradle, {cmap.balls} balls{masses}, eps in [{cmap.domain.lower}, {cmap.domain.upper}]")
    ax.grid(alpha=0.3)
    style: dict[str, Callable[[str], Any]] = {
        "exit": lambda label: Line2D([], [], color="C0", lw=1.6, label=label),
        "non_terminating": lambda label: Patch(color="C3", alpha=0.18, label=label),
        "exits_later": lambda label: Patch(**_UNEXPLORED_STYLE["exits_later"], label=label),
        "undecided": lambda label: Patch(**_UNEXPLORED_STYLE["undecided"], label=label),
        "boundary": lambda label: Line2D([], [], color="C3", ls="--", label=label),
        "threshold_3_4": lambda label: Line2D([], [], color="C2", ls=":", label=label),
    }
    handles = [style[kind](label) for kind, label in staircase_legend(cmap)]
    if marks:
        ax.plot([to_float(e) for e, _ in marks], [n for _, n in marks], "kx", ms=5)
        handles.append(Line2D([], [], color="black", marker="x", ls="", label="Table 1's eps, printed count"))
    ax.legend(handles=handles, loc="upper right", fontsize=8)
    if boundaries:
        _distance_panel(axes[0][1], cmap, boundaries[0])
    return fig


def _distance_panel(ax: Any, cmap: CradleMap, boundary: RealAlgebraic | Fraction) -> None:
    """The steps against eps - boundary on a log scale: they grow like (eps - boundary)^(-1/2)."""
    b = to_float(boundary)
    smallest = None
    for part in cmap.parts:
        lo, hi = to_float(part.piece.lower) - b, to_float(part.piece.upper) - b
        if hi <= 0:
            continue
        if part.stop == "exit" and not part.piece.is_point and lo > 0:
            ax.hlines(part.iterations, lo, hi, color="C0", lw=1.6)
            smallest = lo if smallest is None else min(smallest, lo)
        elif part.stop == "max_iterations":
            ax.axvspan(max(lo, 1e-12), hi, lw=0, **_UNEXPLORED_STYLE[_unexplored_kind(part)])
    left = (smallest or 1e-3) / 5
    ax.set_xscale("log")
    ax.set_xlim(left, to_float(cmap.domain.upper) - b)
    ax.set_ylim(0, cmap.max_impulses + 2)
    ax.set_xlabel(f"eps - ({boundary})   (log scale)")
    ax.set_ylabel("impulses until exit")
    ax.set_title("near the termination boundary")
    ax.grid(alpha=0.3, which="both")


def eps_map_figure(m: EpsMap, path: str | Path) -> Path:
    """A map of :func:`verify.maps.general.eps_map` drawn (:func:`eps_map_plot`) and written to
    ``path`` (PNG) whole or not at all."""
    return save_figure(eps_map_plot(m), path)


def eps_map_legend(m: EpsMap) -> list[tuple[str, str]]:
    """The legend of :func:`eps_map_plot`: ``(kind, label)`` for each kind of part drawn, and only those.

    Kinds: ``exit`` (one parameter: the impulses to exit; two or more: the colour bar says them),
    ``non_terminating`` (proved never to exit) and ``unexplored`` (still impacting at the bound).

    >>> from verify.maps.general import eps_map
    >>> from verify.models.cradle import cradle_system
    >>> eps_map_legend(eps_map(cradle_system("1", 3), ["1", "0", "0"], max_impulses=4))
    [('non_terminating', 'never exits (proved)'),
     ('unexplored', 'unexplored: still impacting after 4 impulses'),
     ('exit', 'exit after k impulses')]
    """
    drawn = {p.stop for line in _drawn_lines(m) for p in line.parts}
    labels = {
        "non_terminating": "never exits (proved)",
        "max_iterations": f"unexplored: still impacting after {counted(m.max_impulses, 'impulse')}",
        "exit": "exit after k impulses",
    }
    kinds = {"non_terminating": "non_terminating", "max_iterations": "unexplored", "exit": "exit"}
    return [
        (kinds[stop], label)
        for stop, label in labels.items()
        if stop in drawn and (stop != "exit" or len(m.parameters) == 1)
    ]


def _drawn_lines(m: Any) -> list[Any]:
    """The lines a map's figure draws: all of them, but with three parameters or more only those where
    the third and later take their lowest value."""
    names = list(m.parameters)
    lowest = {n: lo for n, (lo, _) in m.parameters.items() if n not in names[:2]}
    return [line for line in m.lines if all(v == lowest[n] for n, v in line.fixed.items() if n in lowest)]


#: how :func:`eps_map_plot` draws the parts that do not exit: bands for one parameter, coloured lines for two
_MAP_STYLE: dict[str, dict[str, Any]] = {
    "non_terminating": {"color": "C3", "alpha": 0.25},
    "unexplored": {"facecolor": "0.7", "alpha": 0.5, "hatch": "xx"},
}


_GRID_COLOUR = {"non_terminating": "C3", "max_iterations": "0.6", "unexplored": "0.6"}


def eps_map_plot(m: EpsMap) -> Any:
    """The matplotlib figure of a map, not saved (close it with ``plt.close``). One parameter: the
    impulses to exit against it, as the cradle's staircase, with the parts that never exit and the
    unexplored ones as shaded bands; two: each line of the grid in the plane of the first two parameters,
    coloured by its impulses, red where the rule never exits, grey where unexplored (a third parameter and
    more: the lines where they take their lowest value). The legend (:func:`eps_map_legend`) names what is
    drawn; the title gives each contact's COR by the contact's name."""
    plt = load_pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    names = list(m.parameters)
    fig, ax = plt.subplots(figsize=(5.5, 4.5), constrained_layout=True)
    top = max([p.iterations for line in m.lines for p in line.parts if p.stop == "exit"], default=1)
    cmap = plt.get_cmap("viridis")
    one = len(names) == 1
    for line in _drawn_lines(m):
        for part in line.parts:
            a, b = to_float(part.piece.lower), to_float(part.piece.upper)
            if one:
                _part_on_axes(ax, part, a, b, lw=2, band=_map_band)
                continue
            color = cmap(part.iterations / top) if part.stop == "exit" else _GRID_COLOUR[part.stop]
            if line.free == names[0]:
                ax.hlines(to_float(line.fixed[names[1]]), a, b, color=color, lw=3)
            elif line.free == names[1]:
                ax.vlines(to_float(line.fixed[names[0]]), a, b, color=color, lw=3)
    ax.set_xlabel(names[0])
    ax.set_ylabel("impulses until exit" if one else names[1])
    if one:
        ax.set_xlim(to_float(m.lines[0].domain.lower), to_float(m.lines[0].domain.upper))
        ax.set_ylim(0, top + 1)
    else:
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0, top))
        fig.colorbar(sm, ax=ax, label="impulses to exit")
    handles = [
        Line2D([], [], color="C0", lw=2, label=label)
        if kind == "exit"
        else Patch(**_MAP_STYLE[kind], label=label)
        if one
        else Line2D([], [], color=_GRID_COLOUR[kind], lw=3, label=label)
        for kind, label in eps_map_legend(m)
    ]
    if handles:
        ax.legend(handles=handles, loc="upper right", fontsize=8)
    cors = ", ".join(f"{name} = {cor}" for name, cor in zip(m.system.names, m.restitution))
    where = f"the exact map on {len(m.lines)} lines" if not one else "the exact map"
    ax.set_title(f"{where}\nCORs: {cors}", fontsize=9)
    return fig


def _map_band(part: Any) -> dict[str, Any]:
    """The band of a one-parameter map's part that does not exit: never exits, or unexplored."""
    return _MAP_STYLE["non_terminating" if part.stop == "non_terminating" else "unexplored"]


def _part_on_axes(ax: Any, part: Any, a: float, b: float, *, lw: float, band: Any) -> None:
    """One part of a map against its parameter (the cradle's staircase, a one-parameter map): a step at
    its impulses when it exits (a dot for a point), else a band over [a, b] in the style ``band(part)``."""
    if part.stop == "exit":
        if part.piece.is_point:
            ax.plot([a], [part.iterations], "o", color="C0", ms=3)
        else:
            ax.hlines(part.iterations, a, b, color="C0", lw=lw)
    else:
        ax.axvspan(a, b, lw=0, **band(part))


#: rational x per open cell where its sides are computed for the drawing
DRAW_STEPS = 48


def _named_sequence(sets: list[tuple[int, ...]], names: list[str]) -> str:
    return "".join("(" + ",".join(names[j] for j in J) + ")" for J in sets)


def _behaviour(part: Any) -> tuple[Any, ...]:
    """What a cell is drawn as: an exit by its impulses and impact sets; a cell that never exits, or that is
    still impacting at the bound, by that alone (its sequence so far is in the text and the JSON)."""
    return (part.stop, part.iterations, tuple(part.impact_sets)) if part.stop == "exit" else (part.stop,)


def plane_legend(m: EpsMap) -> list[tuple[tuple[Any, ...], str]]:
    """``(behaviour, label)`` for each behaviour drawn (:func:`_behaviour`), the largest area first, with its
    area (exact bounds, rounded; "on a curve" for cells of no area).

    >>> from verify.maps.general import case_map
    >>> m = case_map("docs/examples/corner-map.json", cells=True, max_impulses=4)
    >>> [label for _, label in plane_legend(m)]
    ['exit after 2: (S1,S2)(S2), area 0.758-0.767', 'exit after 1: (S1,S2), area 0.155-0.169',
     'exit after 2: (S1,S2)(S1), area 0.0733-0.0782']
    """
    plane, names = m.cells, list(m.system.names)
    kinds: dict[tuple[Any, ...], list[Any]] = {}
    for p in plane.parts:
        if p.stop != "not_run":
            kinds.setdefault(_behaviour(p), []).append(p)
    total = plane.area("exit")[1] + 1  # an upper bound of any area, for the order only
    out = []
    for key, parts in sorted(kinds.items(), key=lambda kv: total - sum(p.cell.area[0] for p in kv[1])):
        low, high = plane.bounds_of(parts)
        if key[0] == "exit":
            what = f"exit after {key[1]}: {_named_sequence(list(key[2]), names)}"
        elif key[0] == "non_terminating":
            what = "never exits (proved)"
        else:
            what = f"unexplored: still impacting after {counted(m.max_impulses, 'impulse')}"
        area = "on a curve" if high == 0 else (f"area {format_decimal(low, 3, rounding='floor')}-"
                                               f"{format_decimal(high, 3, rounding='ceiling')}")  # fmt: skip
        out.append((key, f"{what}, {area}"))
    return out


def _xs(cell: Any) -> list[Fraction]:
    """Rational x inside an open cell, from near its left end to near its right end."""
    from verify.maps.cells import inside

    lo, hi, _, _ = inside(cell.x_lo, cell.x_hi)
    return [lo + (hi - lo) * k / DRAW_STEPS for k in range(DRAW_STEPS + 1)]


def plane_plot(m: EpsMap, title: str = "") -> Any:
    """The matplotlib figure of a map of two parameters as cells (``verify map --figure FILE``), not saved: each
    open cell filled with the colour of its behaviour (the legend names each, with its area bounds), cells that
    never exit dotted, unexplored cells hatched; the curves between cells drawn from their exact description
    (each side's y computed exactly at rational x, rounded for the drawing only), the cells that are points as
    dots. When every behaviour but the largest lies in the lowest third of the box, a second panel shows that
    strip stretched. ``title`` heads the figure (default: the CORs)."""
    plt = load_pyplot()
    from matplotlib.patches import Patch

    from verify.maps.cells import Roots, bound_at

    plane, (xname, yname) = m.cells, m.cells.names
    cache = Roots()
    legend = plane_legend(m)
    colours = {key: plt.get_cmap("tab10")(k % 10) for k, (key, _) in enumerate(legend)}
    largest = legend[0][0] if legend else None
    shapes: list[tuple[str, Any, list[float], list[float], list[float]]] = []
    for part in plane.parts:
        cell = part.cell
        if part.stop == "not_run" or cell.dim == 0 or (cell.dim == 1 and cell.on_line):
            continue
        xs = _xs(cell)
        low = [to_float(bound_at(plane.P, cell.y_lo, x, plane.box, cache)) for x in xs]
        high = low if cell.dim == 1 else [to_float(bound_at(plane.P, cell.y_hi, x, plane.box, cache)) for x in xs]
        shapes.append((part.stop, _behaviour(part), [to_float(x) for x in xs], low, high))
    points = [(to_float(p.cell.sample[0]), to_float(p.cell.sample[1])) for p in plane.parts
              if p.cell.dim == 0 and p.cell.sample is not None]  # fmt: skip
    a, b, c, d = (to_float(v) for v in plane.box)
    detail = max((max(hi) for stop, key, _, _, hi in shapes if key != largest and stop != "not_run"), default=d)
    zoom = detail < c + (d - c) / 3
    fig, axes = plt.subplots(1, 2 if zoom else 1, figsize=(10.5 if zoom else 6.2, 5.2), squeeze=False,
                             constrained_layout=True)  # fmt: skip
    for k, ax in enumerate(axes[0]):
        for stop, key, px, low, high in shapes:
            if low is high:  # a curve between cells
                ax.plot(px, low, color="black", lw=0.8)
            else:  # a cell: its edge in its own colour covers the seams between cells of one behaviour
                ax.fill_between(px, low, high, lw=0.6 if stop == "exit" else 0, **_plane_style(stop, colours[key]))
        if points:
            ax.plot(*zip(*points), "o", color="black", ms=2)
        top = d if k == 0 else c + min(d - c, 1.15 * (detail - c))
        ax.set_xlim(a, b)
        ax.set_ylim(c, top)
        ax.set_xlabel(xname)
        ax.set_ylabel(yname)
        ax.set_title("the whole box" if k == 0 else f"detail: {yname} from {c:g} to {top:.2g}", fontsize=9)
    cors = ", ".join(f"{n} = {c}" for n, c in zip(m.system.names, m.restitution))
    fig.suptitle(title or f"{len(plane.parts)} exact cells; CORs {cors}", fontsize=10)
    handles = [Patch(label=label, **_plane_style(key[0], colours[key])) for key, label in legend]
    fig.legend(handles=handles, fontsize=8, loc="outside lower center", ncol=2 if zoom else 1)
    return fig


def _plane_style(stop: str, colour: Any) -> dict[str, Any]:
    """How a cell of this stop is filled: exits in their colour, never-exits dotted in theirs, unexplored cells hatched
    in the colour of their impact sequence so far."""
    if stop == "exit":
        return {"color": colour}
    if stop == "non_terminating":
        return {"hatch": "..", "facecolor": colour, "edgecolor": "black", "alpha": 0.6}
    return {"hatch": "xx", "facecolor": "0.85", "edgecolor": colour}


def plane_figure(m: EpsMap, path: str | Path, title: str = "") -> Path:
    """:func:`plane_plot` written to ``path`` (PNG) whole or not at all."""
    return save_figure(plane_plot(m, title), path)
