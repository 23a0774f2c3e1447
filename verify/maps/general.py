"""The map of any system: its CORs as expressions in parameters, every value of the parameters at once.

:func:`eps_map` takes a system (built by hand, from a case file, or with
:meth:`~verify.dynamics.system.System.from_functions`), an entrance velocity, and one COR per contact
as an expression in named parameters (``"e1"``, ``"e2"``, or one shared ``"eps"``). The rule is
run on the symbolic backend and cut exactly where a sign changes (:mod:`verify.maps.line`).

- **One parameter**: the exact map of its interval. Every value belongs to one part, with exact
  algebraic ends; a part exits with a fixed impact sequence and an exit velocity that is a rational
  function of the parameter, or is proved never to exit (with a certificate), or is unexplored.
- **Two or more parameters**: by default an **exact grid of lines**: for each parameter, the lines
  on which it runs over its interval while every other parameter takes one of ``lines`` equally
  spaced rational values (both ends included). Each line is an exact one-parameter map, so every
  point of every line is decided exactly; points off the lines are not covered. With ``cells=True``
  and two parameters, the box is cut into exact cells instead (:mod:`verify.maps.plane`), and every
  point of it is mapped.

The system's numbers and the velocity are rationals, or algebraic numbers (``sqrt(3)/3``): a map along
lines then runs over the real number field they generate (:mod:`verify.numbers.backends.fieldfunc`), with the
same outputs; its ends are still real algebraic numbers, roots of polynomials with rational coefficients.
A map of cells of such a system runs over the same field (:mod:`verify.maps.backends.tower`).

>>> from verify.models.corner import corner_system
>>> m = eps_map(corner_system("1/2", "1", "1"), ["1", "-1/10", "0"], ["e1", "e2"], lines=3)
>>> len(m.lines), [str(v) for v in m.grid["e2"]]
(6, ['0', '1/2', '1'])
>>> part, velocity = m.at({"e1": "1/10", "e2": "1/2"})
>>> part.stop, part.iterations, [str(x) for x in velocity]
('exit', 1, ['-94/725', '11/1450', '0'])
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import sympy as sp

from verify.dynamics.system import System, is_algebraic
from verify.errors import BadNumber, InvalidInput, InvalidSystem
from verify.maps import DEFAULT_LINES, DEFAULT_WIDEN, MAX_LINES
from verify.maps.backends.plane import PlaneBackend
from verify.maps.line import Part, line_parts, parts_json, piece_json
from verify.maps.plane import PlaneMap, plane_json, plane_parts
from verify.maps.watch import Watch
from verify.numbers.algebraic import RealAlgebraic
from verify.numbers.backends import NumberFieldBackend, exact_for
from verify.numbers.backends.ratfunc import EPS
from verify.numbers.backends.symbolic import Piece, RootCache, Split, SymbolicBackend
from verify.numbers.format import counted, format_exact
from verify.numbers.parse import CONSTANTS, FUNCTIONS, Number, parse_number, to_number

_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")


@dataclass
class Line:
    """One exact one-parameter map: ``free`` runs over ``domain``, the others keep the ``fixed`` values."""

    free: str
    fixed: dict[str, Fraction]
    domain: Piece
    parts: list[Part]

    def locate(self, value: Fraction) -> Part:
        """The part that holds ``free = value``."""
        x = RealAlgebraic.rational(value)
        for part in self.parts:
            if part.piece.contains(x):
                return part
        raise InvalidInput(f"{self.free} = {format_exact(value)} is outside {self.domain}")

    def exit_velocity(self, part: Part) -> list[Any]:
        """A part's exit (or last) velocity as SymPy expressions in the free parameter's own name (as
        ``part.exit_velocity`` holds it)."""
        return [sp.sympify(x).subs(sp.Symbol(part.parameter), sp.Symbol(self.free)) for x in part.exit_velocity]


@dataclass
class EpsMap:
    """A map: the system, its CORs in the parameters, the parameters' intervals and the exact lines."""

    system: System
    velocity: list[Number]  # rationals, or algebraic numbers (then the map runs over their number field)
    restitution: list[Any]  # SymPy expressions in the parameters
    parameters: dict[str, tuple[Fraction, Fraction]]
    max_impulses: int
    grid: dict[str, list[Fraction]] = field(default_factory=dict)  # empty for one parameter
    lines: list[Line] = field(default_factory=list)
    stopped: str = ""  #: why the map stopped before it was complete (a budget, Ctrl-C), else ""
    plane: PlaneMap | None = None  #: two parameters mapped as cells (``cells=True``), else None

    @property
    def cells(self) -> PlaneMap:
        """The cells of a map of two parameters made with ``cells=True`` (ValueError on another map)."""
        if self.plane is None:
            raise ValueError(f"a map laid out as {self.layout}, not as cells")
        return self.plane

    @property
    def layout(self) -> str:
        if self.plane is not None:
            return "cells"
        return "interval" if len(self.parameters) == 1 else "grid of lines"

    def at(self, point: Mapping[str, Any]) -> tuple[Any, list[Number] | None]:
        """The part holding ``point`` (a value per parameter: on a line of the map, or anywhere in the box of a
        map of cells, whose part is then a :class:`~verify.maps.plane.CellPart`) and, when that part exits,
        the exact exit velocity there."""
        values = {name: _rational(point.get(name), name, "a point of the map") for name in self.parameters}
        if self.plane is not None:
            return self.plane.at(*(values[n] for n in self.plane.names))
        for line in self.lines:
            if all(values[n] == v for n, v in line.fixed.items()):
                part = line.locate(values[line.free])
                if part.stop != "exit":
                    return part, None
                x = sp.Rational(values[line.free].numerator, values[line.free].denominator)
                at = [sp.sympify(v).subs(sp.Symbol(part.parameter), x) for v in part.exit_velocity]
                return part, [to_number(sp.radsimp(sp.expand(v))) for v in at]
        shown = ", ".join(f"{n} = {format_exact(v)}" for n, v in values.items())
        raise InvalidInput(f"({shown}) is on no line of the map: take one coordinate from the grid {self.grid}")


def _rational(value: Any, where: str, what: str) -> Fraction:
    """``value`` as a Fraction; refused, naming the field ``where`` and saying what must be rational
    (``what``), when it is not a rational number."""
    if value is None:
        raise InvalidInput(f"{where}: no value given")
    x = to_number(value, where=where)
    if not isinstance(x, Fraction):
        raise InvalidInput(f"{where} = {value} is not rational: {what} must be rational for a map")
    return x


def parameter_names(restitution: Sequence[Any]) -> list[str]:
    """The names of parameters in COR strings or SymPy expressions, in order of first use.

    >>> parameter_names(["e1", "1/2", "(1 + e2)/2", "e1"])
    ['e1', 'e2']
    """
    names: list[str] = []
    known = {*FUNCTIONS, *CONSTANTS, "x"}
    for cor in restitution:
        found = (
            [str(s) for s in sorted(cor.free_symbols, key=str)]
            if isinstance(cor, sp.Basic)
            else _NAME.findall(cor)
            if isinstance(cor, str)
            else []
        )
        names += [n for n in found if n not in known and n not in names]
    return names


def _cors(restitution: Sequence[Any], names: Sequence[str]) -> list[Any]:
    """The CORs as SymPy expressions in the parameters (strings parsed exactly, without running code)."""
    symbols = {n: sp.Symbol(n) for n in names}
    out = []
    for i, cor in enumerate(restitution):
        if isinstance(cor, str):
            cor = parse_number(cor, where=f"restitution[{i}]", symbols=symbols)
        elif not isinstance(cor, sp.Basic):
            cor = to_number(cor, where=f"restitution[{i}]")
        out.append(sp.Rational(cor.numerator, cor.denominator) if isinstance(cor, Fraction) else cor)
    return out


def _intervals(names: Sequence[str], given: Mapping[str, Sequence[Any]] | None) -> dict[str, tuple[Fraction, Fraction]]:
    given = dict(given or {})
    unknown = sorted(set(given) - set(names))
    if unknown:
        raise InvalidInput(f"parameter {unknown[0]!r} appears in no COR (the CORs use {', '.join(names) or 'none'})")
    out = {}
    for name in names:
        ends = given.get(name, ("0", "1"))
        if isinstance(ends, str) or len(ends) != 2:
            raise InvalidInput(f"{name}: expected two ends LO,HI, got {ends!r}")
        lo, hi = (_rational(x, name, "the ends of a parameter's interval") for x in ends)
        if lo > hi:
            raise InvalidInput(f"{name}: the interval is reversed: {format_exact(lo)} > {format_exact(hi)}")
        out[name] = (lo, hi)
    return out


def _grid(lo: Fraction, hi: Fraction, count: int) -> list[Fraction]:
    return sorted({lo + (hi - lo) * k / (count - 1) for k in range(count)})


def eps_map(
    system: System,
    velocity: Sequence[Any],
    restitution: Sequence[Any] | None = None,
    parameters: Mapping[str, Sequence[Any]] | None = None,
    *,
    lines: int | None = None,
    max_impulses: int = 40,
    watch: Watch | None = None,
    widen: int = DEFAULT_WIDEN,
    cells: bool | None = None,
    leaving: bool = False,
    cell_cones: bool = False,
) -> EpsMap:
    """The rule on ``system`` from ``velocity`` for every value of the parameters of ``restitution``.

    ``restitution`` gives one COR per contact: a string (parsed exactly, ``"e1"``, ``"(1 + e)/2"``),
    a SymPy expression or a number; by default every contact has the COR ``eps``. ``parameters``
    maps a name to its interval ``(lo, hi)`` (rationals, default ``(0, 1)``); the CORs must lie in
    [0, 1] over it. With three or more parameters the map is a grid of ``lines`` values per parameter
    (default 5; see the module). ``max_impulses`` bounds each run: what is still impacting then, and not proved
    never to exit, is unexplored. ``watch`` (:class:`~verify.maps.line.Watch`) gives budgets and progress
    shared by every line; a map stopped by one (or by Ctrl-C) says why in ``stopped``. ``widen`` is the number
    of rational points of each unexplored interval at which a single run's cone is widened
    (:func:`~verify.maps.line.widened`); ``leaving`` proves exits above boundaries on lines
    (:func:`~verify.maps.line.line_parts`). With two parameters the map is the box cut into exact cells
    (:mod:`verify.maps.plane`): every rational point of the box is mapped; ``cells=False``, or a number of
    ``lines``, asks for the grid of lines instead (``cells`` None, the default: cells for two parameters unless
    ``lines`` is given, lines otherwise). ``cell_cones`` also
    tries boundary cones on its cells of three or more contacts (:mod:`verify.maps.cell_cones`).

    >>> m = eps_map(System([[1, 0], [0, 1]], [[-1, 1]], [1]), ["1", "0"], ["e"], {"e": ("1/2", "1")})
    >>> line = m.lines[0]
    >>> [(str(p.piece), p.stop, str(line.exit_velocity(p)[0])) for p in line.parts]
    [('[1/2, 1]', 'exit', '1/2 - e/2')]
    """
    if cells is None:  # two parameters: cells, unless a grid's lines are asked for
        cells = lines is None and len(parameter_names(list(restitution) if restitution is not None else [])) == 2
    lines = DEFAULT_LINES if lines is None else lines
    if isinstance(lines, bool) or not isinstance(lines, int) or not 2 <= lines <= MAX_LINES:
        raise InvalidInput(f"lines must be an integer from 2 to {MAX_LINES}, got {lines!r}")
    if isinstance(max_impulses, bool) or not isinstance(max_impulses, int) or max_impulses < 0:
        raise InvalidInput(f"max_impulses must be a non-negative integer, got {max_impulses!r}")
    cors_given = list(restitution) if restitution is not None else ["eps"] * system.r
    if len(cors_given) != system.r:
        raise InvalidSystem(f"restitution: expected {system.r} CORs (one per contact), got {len(cors_given)}")
    names = parameter_names(cors_given)
    if not names:
        raise InvalidInput("restitution: no COR depends on a parameter, so there is nothing to map")
    cors = _cors(cors_given, names)
    intervals = _intervals(names, parameters)
    if isinstance(velocity, str) or len(velocity) != system.n:
        raise InvalidInput(f"velocity: expected {system.n} numbers")
    v = [to_number(x, where=f"velocity[{i}]") for i, x in enumerate(velocity)]
    numbers = [*_source_numbers(system), *((f"velocity[{i}]", x) for i, x in enumerate(v))]
    for where, x in numbers:
        if not is_algebraic(x):
            raise InvalidSystem(f"a map needs algebraic numbers: {where} = {format_exact(x)} is not algebraic")
    number_field = exact_for([x for _, x in numbers])
    field_of = number_field if isinstance(number_field, NumberFieldBackend) else None
    if cell_cones and not cells:
        raise InvalidInput("cell cones are tried on a map of cells: two parameters, without a grid of lines")
    if cells:
        if len(names) != 2:
            raise InvalidInput(f"a map of cells takes two parameters; the CORs use {len(names)} ({', '.join(names)})")
        out = EpsMap(system, v, cors, intervals, max_impulses)
        out.plane = _plane(out, names, watch, field_of, cell_cones=cell_cones)
        out.stopped = out.plane.stopped
        return out
    grid = {n: _grid(lo, hi, lines) for n, (lo, hi) in intervals.items()} if len(names) > 1 else {}
    cache = RootCache(field_of)
    out = EpsMap(system, v, cors, intervals, max_impulses, grid)
    for free in names:
        others = [n for n in names if n != free]
        for values in itertools.product(*(grid[n] for n in others)):
            fixed = dict(zip(others, values))
            out.lines.append(_line(out, free, fixed, cache, watch=watch, widen=widen, leaving=leaving))
    out.stopped = watch.stopped if watch is not None else ""
    return out


def _plane(
    m: EpsMap, names: list[str], watch: Watch | None, number_field: Any, *, cell_cones: bool = False
) -> PlaneMap:
    """The map of cells of two parameters; the CORs are checked in [0, 1] on every cell (their signs cut
    the box as the rule's do)."""
    src = m.system.source
    first, second = names

    def build(K: PlaneBackend) -> System:
        try:
            system = System(src["mass_matrix"], src["normals"], m.restitution, src["time_terms"], backend=K,
                            names=m.system.names, coordinates=m.system.coordinates)  # fmt: skip
        except BadNumber as exc:
            raise InvalidSystem(f"a map needs a system of rational numbers: {exc}") from None
        for i, (c, shown) in enumerate(zip(system.restitution, m.restitution)):
            if K.sign(c) < 0 or K.sign(K.one - c) < 0:
                x, y = K.sample
                raise InvalidSystem(f"restitution[{i}] = {shown} is outside [0, 1] at {first} = {x}, {second} = {y}")
        return system

    (a, b), (c, d) = m.parameters[first], m.parameters[second]
    return plane_parts(build, m.velocity, (a, b, c, d), (first, second), m.max_impulses, watch=watch,
                       number_field=number_field, cell_cones=cell_cones)  # fmt: skip


def _source_numbers(system: System) -> list[tuple[str, Any]]:
    src = system.source
    out = [(f"mass_matrix[{i}][{j}]", x) for i, row in enumerate(src["mass_matrix"]) for j, x in enumerate(row)]
    out += [(f"normals[{i}][{k}]", x) for i, row in enumerate(src["normals"]) for k, x in enumerate(row)]
    return out + [(f"time_terms[{i}]", x) for i, x in enumerate(src["time_terms"])]


def _check_cors(m: EpsMap, cors: list[Any], domain: Piece, where: str, cache: RootCache) -> None:
    """Each COR lies in [0, 1] for every value of the line (exactly: its sign conditions hold on the whole
    interval, or they change inside it)."""
    K = SymbolicBackend(domain, cache)
    for i, (c, shown) in enumerate(zip(cors, m.restitution)):
        x = K.convert(c)
        try:
            inside = K.nonnegative(x) and K.nonnegative(K.one - x)
        except Split:
            inside = False
        if not inside:
            raise InvalidSystem(f"restitution[{i}] = {shown} is outside [0, 1] for some point of {where}")


def _line(
    m: EpsMap, free: str, fixed: dict[str, Fraction], cache: RootCache, *, watch: Watch | None = None,
    widen: int = DEFAULT_WIDEN,
    leaving: bool = False,
) -> Line:  # fmt: skip
    subs = {sp.Symbol(n): sp.Rational(v.numerator, v.denominator) for n, v in fixed.items()}
    cors = [sp.sympify(c).subs({**subs, sp.Symbol(free): EPS}, simultaneous=True) for c in m.restitution]
    src = m.system.source

    def build(K: SymbolicBackend) -> System:
        try:
            return System(src["mass_matrix"], src["normals"], cors, src["time_terms"], backend=K,
                          names=m.system.names, coordinates=m.system.coordinates)  # fmt: skip
        except BadNumber as exc:
            raise InvalidSystem(f"a map needs a system of rational numbers: {exc}") from None

    lo, hi = m.parameters[free]
    domain = Piece.closed(lo, hi)
    shown = ", ".join(f"{n} = {format_exact(v)}" for n, v in fixed.items())
    _check_cors(m, cors, domain, f"{free} in {domain}" + (f", {shown}" if shown else ""), cache)
    parts = line_parts(build, m.velocity, domain, m.max_impulses, cache, parameter=free, watch=watch, widen=widen,
                       leaving=leaving)  # fmt: skip
    for part in parts:
        if part.stop == "max_iterations" and not part.stopped_by and not part.reason:
            part.reason = f"still impacting after {counted(part.iterations, 'impulse')}; not proved never to exit"
    return Line(free, fixed, domain, parts)


def eps_map_json(m: EpsMap) -> dict[str, Any]:
    """The map in its JSON shape (``docs/json-outputs.md``): exit velocities in the free parameter of
    each line."""
    return {
        "contacts": list(m.system.names),
        "restitution": [str(c) for c in m.restitution],
        "velocity": [format_exact(x) for x in m.velocity],
        "parameters": {n: [format_exact(lo), format_exact(hi)] for n, (lo, hi) in m.parameters.items()},
        "layout": m.layout,
        "grid": {n: [format_exact(x) for x in values] for n, values in m.grid.items()},
        "max_impulses": m.max_impulses,
        **({"stopped": m.stopped} if m.stopped else {}),
        **({"cells": plane_json(m.plane)} if m.plane is not None else {}),
        "lines": [
            {
                "free": line.free,
                "fixed": {n: format_exact(v) for n, v in line.fixed.items()},
                "interval": piece_json(line.domain),
                **parts_json(line.parts, name=line.free),
            }
            for line in m.lines
        ],
    }


def case_map(
    path: str,
    case_id: str | None = None,
    parameters: Mapping[str, Sequence[Any]] | None = None,
    *,
    lines: int | None = None,
    max_impulses: int = 40,
    watch: Watch | None = None,
    widen: int = DEFAULT_WIDEN,
    cells: bool | None = None,
    leaving: bool = False,
    cell_cones: bool = False,
) -> EpsMap:
    """:func:`eps_map` of a case in a case file (``docs/records.md``) whose ``restitution`` strings name
    parameters (``["e1", "e2"]``); ``case_id`` picks the case (needed when the file has several);
    ``watch``, ``widen``, ``cells``, ``leaving`` and ``cell_cones`` as for :func:`eps_map`.

    >>> import json, os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "case.json")
    >>> case = {"id": "a", "mass_matrix": [["1", "0"], ["0", "1"]], "normals": [["-1", "1"]],
    ...         "restitution": ["e"], "velocity": ["1", "0"]}
    >>> with open(path, "w") as fh:
    ...     json.dump({"cases": [case]}, fh)
    >>> [(str(p.piece), p.stop) for p in case_map(path).lines[0].parts]
    [('[0, 1]', 'exit')]
    """
    from verify.records.files import load_json
    from verify.records.results import case_from_record
    from verify.records.schema import validate

    data = load_json(path, path=path)
    if not isinstance(data, dict) or not isinstance(data.get("cases"), list) or not data["cases"]:
        raise InvalidInput(f'{path}: expected an object {{"cases": [...]}} with at least one case')
    validate(data, "case")
    ids = [c.get("id") for c in data["cases"] if isinstance(c, dict)]
    if case_id is None and len(data["cases"]) > 1:
        raise InvalidInput(f"{path}: {len(ids)} cases; name one with --case ({', '.join(map(str, ids))})")
    index = 0 if case_id is None else ids.index(case_id) if case_id in ids else -1
    if index < 0:
        raise InvalidInput(f"{path}: no case {case_id!r} (the cases are {', '.join(map(str, ids))})")
    record = data["cases"][index]
    where = f"{path}: cases[{index}]"
    cors = record.get("restitution")
    if not isinstance(cors, list):
        raise InvalidInput(f"{where}.restitution: expected a list of strings")
    case = case_from_record({**record, "restitution": ["1"] * len(cors)}, where)  # the geometry, validated
    try:
        return eps_map(case.system, record["velocity"], cors, parameters, lines=lines, max_impulses=max_impulses,
                       watch=watch, widen=widen, cells=cells, leaving=leaving,
                       cell_cones=cell_cones)  # fmt: skip
    except InvalidInput as exc:
        raise type(exc)(f"{where}: {exc}") from None
