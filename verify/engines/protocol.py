"""The frame of an engine adapter: a program that reads a case file and writes exit velocities.

An adapter is run as ``python -m verify.engines.adapters.ENGINE`` (the ``verify oracle check --impl``
protocol, ``docs/oracle.md``): it reads a case file ``{"cases": [...]}`` on stdin and writes

    {"engine": {...description...},
     "results": [{"id": ..., "exit_velocity": ["...", ...]}, ...],
     "skipped": [{"id": ..., "reason": "..."}, ...]}

on stdout: velocity-only results (floats printed with all their digits, as strings), one per
case that the engine can build, and the others listed as skipped with the reason. Options:

- ``--describe``: print only the engine's description (name, version, how it combines
  restitution, how the adapter sets one COR per constraint, the solver settings, and the
  setting that matters most with its second value) and exit;
- ``--set NAME=VALUE`` (repeatable): change a solver setting (a number; names from
  ``--describe``).

An engine that is not installed makes the adapter exit with code 3 and one line on stderr
(``verify engines`` lists it as skipped): :func:`import_engine` imports an engine's module
when it is first needed, with what C code writes on standard output silenced
(:func:`silenced`), so that the adapter's standard output holds nothing but its JSON. A
subclass of :class:`Adapter` is all an engine module defines, with ``main = Adapter.main``
bound to it.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import functools
import importlib
import json
import math
import os
import sys
import tomllib
from collections.abc import Callable, Iterator, Sequence
from importlib import resources
from typing import Any, ClassVar

from verify.engines.scene import Corner, Cradle, Scene, Unsupported, scene_of

NOT_INSTALLED = 3  #: the adapter's exit code when its engine cannot be imported


class NotInstalled(Exception):
    """The engine's Python package cannot be imported."""


class CannotRun(NotInstalled):
    """The engine imports but cannot run here (no CPU backend, a missing driver): the message says
    what stopped it, measured (the error and the version), and ``verify engines`` lists it as skipped."""


@contextlib.contextmanager
def silenced(fd: int = 1) -> Iterator[None]:
    """Send what is written on a file descriptor (standard output by default) to /dev/null.

    Engines' C and C++ code writes there directly, past ``sys.stdout`` (pybullet prints its
    build time at import, on stderr in 3.2.7 and on stdout in other builds)."""
    (sys.stdout if fd == 1 else sys.stderr).flush()
    saved = os.dup(fd)
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, fd)
        yield
    finally:
        os.dup2(saved, fd)
        os.close(null)
        os.close(saved)


def import_engine(module: str) -> Any:
    """An engine's Python module, imported with standard output silenced; :class:`NotInstalled` if it cannot be.

    An adapter module named like its engine (``verify.engines.adapters.pymunk``) finds the engine, not
    itself: the import is absolute."""
    try:
        with silenced():
            return importlib.import_module(module)
    except ImportError as exc:
        raise NotInstalled(str(exc)) from None


def stepping(max_time: float) -> dict[str, float]:
    """The settings every stepping adapter has, last among its settings: the bodies' initial ``overlap``, the
    order they are made in (``reverse_order``) and the most simulated time of a case (``max_time``).

    >>> stepping(0.2)
    {'overlap': 0.0, 'reverse_order': 0, 'max_time': 0.2}
    """
    return {"overlap": 0.0, "reverse_order": 0, "max_time": max_time}


def whole(value: float, least: int = 1) -> bool:
    """Whether a setting is a whole number of at least ``least`` (iterations, steps).

    >>> whole(3.0), whole(2.5), whole(0)
    (True, False, False)
    """
    return value >= least and value == int(value)


def solver_model(
    kind: str, iterations: str, threshold: float | str, precision: str, source: str, **more: Any
) -> dict[str, Any]:
    """An :attr:`Adapter.solver` (see there): its kind, the setting of its sweeps, its restitution threshold,
    its precision and where the engine documents it; ``more``: ``threshold_of``, ``cor_floor``."""
    return {"kind": kind, "iterations": iterations, "threshold": threshold, "precision": precision, "source": source,
            **more}  # fmt: skip


#: the ranges of the settings that several adapters share (each checked where the adapter has it)
SHARED_RANGES: dict[str, Callable[[float], bool]] = {
    "time_step": lambda v: v > 0,
    "timestep": lambda v: v > 0,
    "reverse_order": lambda v: v in (0, 1),
    "per_contact": lambda v: v in (0, 1),
    "max_time": lambda v: v > 0,
    "max_steps": whole,
    "radius": lambda v: v > 0,
}


#: the class attributes of :class:`Adapter` that ``engines.toml`` gives each engine
DESCRIBED = ("package", "module", "install", "combine_rule", "cor_setting", "walls", "alternate", "settings", "solver")


@functools.cache
def descriptions() -> dict[str, dict[str, Any]]:
    """``verify/engines/engines.toml``: each engine's table, by name (docs/engines.md, "Adapters")."""
    text = resources.files("verify.engines").joinpath("engines.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def description(name: str) -> dict[str, Any]:
    """An engine's table of ``engines.toml`` (empty for a name it does not hold).

    >>> description("pybullet")["alternate"], description("pybullet")["settings"]["solver_iterations"]
    (['solver_iterations', 1], 50)
    """
    return descriptions().get(name, {})


class Adapter:
    """One engine. Subclasses set the class attributes and implement the two scenes; they may
    check their settings' ranges (:meth:`checks`) and read the version otherwise (:meth:`version`).

    ``package`` and ``module`` default to ``name``: an engine module sets them only where they differ."""

    name: ClassVar[str] = "?"  #: the engine's name in reports ("box2d")
    package: ClassVar[str] = "?"  #: the pip package that installs it ("box2d")
    #: how to install it, when ``pip install PACKAGE`` is not enough ("" for that)
    install: ClassVar[str] = ""
    module: ClassVar[str] = "?"  #: the Python module it is imported as ("Box2D")
    #: the bodies' radius, which a setting ``overlap`` stays below (None: the setting ``radius``)
    radius: ClassVar[float | None] = None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        """An engine's adapter takes what it is (package, combine rule, settings, solver...) from its table of
        ``verify/engines/engines.toml``; what the table leaves out it inherits, and ``package`` and ``module``
        default to its name."""
        super().__init_subclass__(**kwargs)
        for key, value in description(cls.name).items():
            if key in DESCRIBED:  # a copy: the class's own, apart from the cached file
                setattr(cls, key, tuple(value) if key == "alternate" else copy.deepcopy(value))
        for attribute in ("package", "module"):
            if attribute not in vars(cls):  # neither the table nor the class names it: the engine's own name
                setattr(cls, attribute, cls.name)

    #: how the engine combines the restitutions of the two bodies of a contact
    combine_rule: ClassVar[str] = "?"
    #: how this adapter gives each contact (constraint) its own COR
    cor_setting: ClassVar[str] = "?"
    #: the solver settings used by default (name -> number), all changeable with --set
    settings: ClassVar[dict[str, float]] = {}
    #: whether :meth:`cradle` builds a cradle's fixed wall (:attr:`verify.engines.scene.Cradle.wall`)
    walls: ClassVar[bool] = False
    #: the setting that matters most, and its second value (run by ``verify engines``)
    alternate: ClassVar[tuple[str, float]] = ("", 0)
    #: the engine's contact solver, as an exact model replays it (``verify engines`` explains answers by it):
    #: ``kind`` is "sequential" (projected Gauss-Seidel sweeps of impulses, the restitution target taken
    #: before the solve), "simultaneous" (a complementarity problem solved exactly or to convergence) or
    #: "soft" (compliant contact: no exact model); ``iterations`` names the setting that holds the sweeps'
    #: count ("" if none); ``threshold`` is the incoming speed at or below which no restitution is applied
    #: (0: none; a number, or the name of the setting that holds it), compared with the COR times that speed
    #: when ``threshold_of`` is "cor_times_speed"; ``cor_floor``: a COR at or below it acts as 0;
    #: ``precision`` is "float32" or "float64" (the tolerance of an explanation: 1e-5 or 1e-9 of the speed);
    #: ``source`` cites where the engine documents it; ``step_model`` names the exact model of its step loop
    #: (:data:`verify.engines.models.STEP_MODELS`), when there is one
    solver: ClassVar[dict[str, Any]] = {
        "kind": "?",
        "iterations": "",
        "threshold": 0.0,
        "threshold_of": "speed",
        "cor_floor": 0.0,
        "precision": "float64",
        "source": "?",
    }

    def __init__(self, overrides: dict[str, float] | None = None):
        unknown = sorted(set(overrides or {}) - set(self.settings))
        if unknown:
            raise ValueError(f"unknown setting {unknown[0]!r} (known: {', '.join(sorted(self.settings))})")
        self.config = {**self.settings, **(overrides or {})}
        checked = self.checks()
        bad = [name for name in self.config if not checked.get(name, True)]  # the first in --describe's order
        if bad:
            raise ValueError(f"setting {bad[0]} = {self.config[bad[0]]!r} is out of range")

    # -- to implement (the scenes) or to override ---------------------------------------
    def checks(self) -> dict[str, bool]:
        """Whether each setting of :attr:`config` is in its range (``--set`` takes any number): here the
        settings of :data:`SHARED_RANGES` and ``overlap`` (below the radius); an adapter adds its own."""
        c = self.config
        found = {name: bool(ok(c[name])) for name, ok in SHARED_RANGES.items() if name in c}
        if "overlap" in c:
            radius = self.radius if self.radius is not None else c["radius"]
            found["overlap"] = 0 <= c["overlap"] < radius
        return found

    def engine(self) -> Any:
        """The engine's module (raises :class:`NotInstalled` when it cannot be imported)."""
        return import_engine(self.module)

    def version(self) -> str:
        """The engine's version (raises :class:`NotInstalled` when it cannot be imported)."""
        return str(self.engine().__version__)

    def cradle(self, scene: Cradle) -> list[float]:  # pragma: no cover - abstract
        """The balls' exit velocities along x (raise :class:`Unsupported` for what cannot be set)."""
        raise NotImplementedError

    def corner(self, scene: Corner) -> list[float]:  # pragma: no cover - abstract
        """The disk's exit velocity ``(vx, vy, omega)``."""
        raise NotImplementedError

    # -- the frame ---------------------------------------------------------------------
    def describe(self) -> dict[str, Any]:
        """The description printed by ``--describe`` and in every output."""
        return {
            "name": self.name,
            "package": self.package,
            "version": self.version(),
            "combine_rule": self.combine_rule,
            "cor_setting": self.cor_setting,
            "settings": dict(self.config),
            "alternate": {"setting": self.alternate[0], "value": self.alternate[1]},
            "solver": {**Adapter.solver, **self.solver},
        }

    def run(self, scene: Scene) -> list[float]:
        """The engine's exit velocity for a scene (a cradle against a wall only where :attr:`walls`)."""
        if isinstance(scene, Cradle) and scene.wall and not self.walls:
            raise Unsupported(f"a cradle against a wall: the {self.name} adapter does not build the wall")
        return self.cradle(scene) if isinstance(scene, Cradle) else self.corner(scene)

    def results(self, cases: Sequence[dict[str, Any]]) -> dict[str, Any]:
        """The adapter's output for a case file's cases."""
        out: dict[str, Any] = {"engine": self.describe(), "results": [], "skipped": []}
        for case in cases:
            cid = case.get("id")
            try:
                v = self.run(scene_of(case))
            except Unsupported as exc:
                out["skipped"].append({"id": cid, "reason": str(exc)})
                continue
            out["results"].append({"id": cid, "exit_velocity": [repr(float(x)) for x in v]})
        return out

    @classmethod
    def main(cls, argv: Sequence[str] | None = None) -> int:
        """The adapter program (``python -m verify.engines.adapters.ENGINE``)."""
        from verify.engines import ENGINES

        module = ENGINES.get(cls.name, cls.__module__)  # run as a program, the class is in __main__
        p = argparse.ArgumentParser(prog=f"python -m {module}", description=cls.__doc__)
        p.add_argument("--describe", action="store_true", help="print the engine's description and exit")
        p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="a solver setting")
        args = p.parse_args(argv)
        try:
            adapter = cls(_overrides(args.set))
            if args.describe:
                sys.stdout.write(json.dumps(adapter.describe(), indent=1) + "\n")
                return 0
            cases = _read_cases(sys.stdin.read())
            sys.stdout.write(json.dumps(adapter.results(cases), indent=1) + "\n")
        except CannotRun as exc:
            print(f"{cls.name}: cannot run here ({exc})", file=sys.stderr)
            return NOT_INSTALLED
        except NotInstalled as exc:
            print(f"{cls.name}: not installed ({exc}); {cls.install or 'pip install ' + cls.package}", file=sys.stderr)
            return NOT_INSTALLED
        except ValueError as exc:
            print(f"{cls.name}: {exc}", file=sys.stderr)
            return 2
        return 0


def _overrides(pairs: Sequence[str]) -> dict[str, float]:
    out: dict[str, float] = {}
    for pair in pairs:
        name, sep, value = pair.partition("=")
        try:
            number = float(value)
        except ValueError:
            number = math.nan
        if not sep or not name or not math.isfinite(number):
            raise ValueError(f"--set {pair!r}: expected NAME=NUMBER")
        out[name] = number
    return out


def _read_cases(text: str) -> list[dict[str, Any]]:
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"stdin is not JSON: {exc}") from None
    cases = data.get("cases") if isinstance(data, dict) else None
    if not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases):
        raise ValueError('stdin: expected a case file {"cases": [...]}')
    return cases
