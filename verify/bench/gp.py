"""The paper's loop in PARI/GP, run and timed from Python (``verify bench``'s ratio against GP).

The paper checked the rule with PARI/GP. ``verify/data/gp/rule.gp`` is the repository's own GP
script of the paper's loop (any n, r; U and G precomputed per system) and ``table1.gp`` the
cradle of Table 1 in the paper's mode (at most 10^4 impulses and the AEEV stop of
:data:`verify.models.paper.PAPER_READING`). This module writes a batch to a temporary file in
GP syntax (rationals as ``a/b``), runs ``gp -q -f`` on it, and reads back, per case, the stop,
the impact sets (0-based, as :attr:`verify.laws.outcome.Result.impact_sets`) and the exit
velocity.

The time is measured inside GP with ``getabstime()`` (CPU milliseconds): the loop alone,
without gp's start-up, reading the batch or printing. The loop is repeated ``n`` times in a
row, ``n`` doubled until the ``n`` runs take at least :data:`MIN_MS` ms (the clock counts whole
milliseconds, so its resolution is under 1%); the figure is the best of ``repeats`` such
measurements, divided by ``n``. With ``real=True`` the inputs are made t_REAL (``* 1.``, at GP's
default ``realprecision``, 38 digits = 128 bits on 64-bit machines) before the clock starts;
otherwise GP computes on exact rationals.

>>> gp_value([[Fraction(1, 2), 0], (Fraction(-8, 5),)])
'[[1/2, 0], [-8/5]]'
>>> parse_line("exit|1,2;1|-8/5;-4/5;0")
('exit', [(0, 1), (0,)], (Fraction(-8, 5), Fraction(-4, 5), Fraction(0, 1)))
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

from verify.errors import VerifyError

GP_DIR = Path(__file__).resolve().parent.parent / "data" / "gp"  #: rule.gp and table1.gp
MIN_MS = 200  #: a timed measurement lasts at least this long (the clock counts whole ms)
PARISIZEMAX = "4G"  #: gp's stack may grow up to this (exact runs make large numbers)
CORNER_MAX_IMPULSES = 100  #: the cap of the corner batches of ``verify bench``
#: a general system: (mass matrix, normals (rows dF_i), CORs, velocity), rational
SystemData = tuple[Sequence[Sequence[Fraction]], Sequence[Sequence[Fraction]], Sequence[Fraction], Sequence[Fraction]]


class GPError(VerifyError, RuntimeError):
    """gp is not installed, or failed (its error message is in the exception's text)."""


@dataclass(frozen=True)
class GPRuns:
    """What GP computed on a batch, and how long its loop took."""

    seconds: float  #: best time of one pass of the loop over the whole batch
    loops: int  #: passes per timed measurement
    stops: list[str]  #: per case: "exit", "max_iterations" or "aeev"
    impact_sets: list[list[tuple[int, ...]]]  #: per case, 0-based
    exit_velocities: list[tuple[Fraction, ...]]  #: per case (reals: the value of the 38 printed digits)
    real: bool  #: whether GP computed in t_REAL (else exact rationals)
    precision: int  #: GP's realprecision (decimal digits), used only when ``real``
    bits: int  #: GP's realbitprecision

    @property
    def arithmetic(self) -> str:
        if self.real:
            return f"PARI t_REAL, realprecision {self.precision} ({self.bits} bits)"
        return "PARI exact rationals (t_INT, t_FRAC)"


@dataclass(frozen=True)
class Matrix:
    """Rows that :func:`gp_value` writes as a GP matrix (t_MAT), not as a vector of vectors."""

    rows: Sequence[Sequence[Any]]


def available() -> bool:
    """Whether ``gp`` (PARI/GP) is on the PATH."""
    return shutil.which("gp") is not None


def gp_value(x: Any) -> str:
    """A number (int or Fraction), a :class:`Matrix` or nested sequences of them, in GP syntax.

    >>> gp_value((Fraction(3), Fraction(-1, 3))), gp_value(Matrix([[1, 0], [0, Fraction(1, 2)]]))
    ('[3, -1/3]', '[1, 0; 0, 1/2]')
    >>> gp_value(Matrix([[-1, 1]]))  # one row: [-1, 1] alone would be a vector
    'Mat([-1, 1])'
    """
    if isinstance(x, Matrix):
        text = "[" + "; ".join(", ".join(gp_value(y) for y in row) for row in x.rows) + "]"
        return f"Mat({text})" if len(x.rows) == 1 else text
    if isinstance(x, (list, tuple)):
        return "[" + ", ".join(gp_value(y) for y in x) + "]"
    if isinstance(x, bool) or not isinstance(x, (int, Fraction)):
        raise TypeError(f"only ints and Fractions go to GP exactly, got {x!r}")
    return str(x)


def parse_number(text: str) -> Fraction:
    """A number printed by GP, exactly: ``a/b``, an integer, or a t_REAL such as ``1.5 E-2``.

    >>> parse_number("-8/5"), parse_number("1.5000 E-2"), parse_number("0.E-38")
    (Fraction(-8, 5), Fraction(3, 200), Fraction(0, 1))
    """
    from verify.numbers.parse import parse_number as exact

    value = exact(text.replace(" ", ""), where="gp output")  # the project's one exact number parser
    if not isinstance(value, Fraction):
        raise GPError(f"gp printed {text!r}, not a rational or decimal number")
    return value


def parse_line(line: str) -> tuple[str, list[tuple[int, ...]], tuple[Fraction, ...]]:
    """One run of rule.gp's report, ``stop|sets|velocity``: the impact sets made 0-based."""
    stop, sets, velocity = line.split("|")
    impact_sets = [tuple(int(i) - 1 for i in J.split(",")) for J in sets.split(";")] if sets else []
    return stop, impact_sets, tuple(parse_number(x) for x in velocity.split(";"))


def _gp_string(path: Path) -> str:
    return '"' + str(path).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _run(call: str, data: Any, *, repeats: int, real: bool, files: Sequence[str] = ("rule.gp",)) -> GPRuns:
    """Run ``call`` (a GP expression of the global ``data``) under rule.gp's clock; parse its report."""
    gp = shutil.which("gp")
    if gp is None:
        raise GPError("PARI/GP (gp) is not installed: no ratio against the paper's own tool")
    if repeats < 1:
        raise ValueError(f"repeats must be at least 1, got {repeats}")
    with tempfile.TemporaryDirectory(prefix="verify-gp-") as tmp:
        data_file, main_file = Path(tmp) / "data.gp", Path(tmp) / "main.gp"
        data_file.write_text(gp_value(data) + "\n", encoding="utf-8")
        lines = [f"read({_gp_string(GP_DIR / name)});" for name in files]
        lines.append(f"data = read({_gp_string(data_file)});")
        if real:
            lines.append("data = data * 1.;")
        lines += [f"rule_report(rule_time(() -> {call}, {repeats}, {MIN_MS}));", "quit"]
        main_file.write_text("\n".join(lines) + "\n", encoding="utf-8")
        done = subprocess.run(
            [gp, "-q", "-f", "--default", f"parisizemax={PARISIZEMAX}", str(main_file)],
            stdin=subprocess.DEVNULL,
            capture_output=True,
            text=True,
            check=False,
        )
    errors = [line for line in done.stderr.splitlines() if "***" in line and "Warning" not in line]
    out = done.stdout.splitlines()
    header = next((i for i, line in enumerate(out) if line.startswith("gp-rule ")), None)
    if done.returncode != 0 or errors or header is None:
        detail = "\n".join(errors or done.stderr.splitlines()[-10:] or out[-10:])
        raise GPError(f"gp failed (exit code {done.returncode}):\n{detail}")
    seconds, loops, precision, bits = out[header].removeprefix("gp-rule ").rsplit(" ", 3)
    runs = [parse_line(line) for line in out[header + 1 :]]
    return GPRuns(
        seconds=float(parse_number(seconds)),
        loops=int(loops),
        stops=[r[0] for r in runs],
        impact_sets=[r[1] for r in runs],
        exit_velocities=[r[2] for r in runs],
        real=real,
        precision=int(precision),
        bits=int(bits),
    )


def run_corners(
    cases: Sequence[tuple[Fraction, ...]],
    *,
    max_impulses: int = CORNER_MAX_IMPULSES,
    repeats: int = 3,
    real: bool = False,
) -> GPRuns:
    """The disk in the corner: ``cases`` of ``(k, xd, yd, e1, e2)`` (as :func:`verify.bench.throughput.batch`),
    mass matrix I3, normals (-k, 1, 0) and (-k, -1, 0), velocity (xd, yd, 0); U and G per case.

    >>> case = (Fraction(1, 2), Fraction(2), Fraction(0), Fraction(0), Fraction(1))
    >>> run_corners([case]).impact_sets  # doctest: +SKIP
    [[(0, 1), (0,)]]
    """
    return _run(f"rule_corners(data, {int(max_impulses)})", [list(c) for c in cases], repeats=repeats, real=real)


def run_systems(
    systems: Sequence[SystemData], *, max_impulses: int = 10_000, repeats: int = 3, real: bool = False
) -> GPRuns:
    """General systems ``(mass matrix, normals, CORs, velocity)`` as rational lists; U and G per system.

    >>> one = [[Fraction(1), 0, 0], [0, Fraction(1), 0], [0, 0, Fraction(1)]]
    >>> cradle = (one, [[-1, 1, 0], [0, -1, 1]], [Fraction(1, 2)] * 2, [Fraction(100), 0, 0])
    >>> run_systems([cradle]).exit_velocities  # doctest: +SKIP
    [(Fraction(325, 16), Fraction(375, 16), Fraction(225, 4))]
    """
    data = [[Matrix(g), Matrix(A), list(e), list(v)] for g, A, e, v in systems]
    return _run(f"rule_systems(data, {int(max_impulses)})", data, repeats=repeats, real=real)


def table1_eps() -> list[Fraction]:
    """The 17 CORs of Table 1 (``verify/data/paper/table1.json``), exactly.

    >>> table1_eps()[:3], len(table1_eps())
    ([Fraction(1, 1), Fraction(99, 100), Fraction(9, 10)], 17)
    """
    from verify.paper.readings import load_table1

    return [Fraction(row[0]) for row in load_table1()["rows"]]


def run_table1(eps: Sequence[Fraction] | None = None, *, real: bool = True, repeats: int = 3) -> GPRuns:
    """Table 1 in the paper's mode (table1.gp): one run per COR (default :func:`table1_eps`),
    v0 = 100, at most 10^4 impulses, the AEEV stop with sigma = 10^-9. ``seconds`` is the time
    of one whole table (``1 / seconds`` tables per second).

    >>> r = run_table1()  # doctest: +SKIP
    >>> r.stops[-1], len(r.impact_sets[-1])  # doctest: +SKIP
    ('aeev', 32)
    """
    from verify.models.paper import PAPER_MAX_ITERATIONS, PAPER_SIGMA_RELATIVE

    data = [list(table1_eps() if eps is None else eps), 100, PAPER_SIGMA_RELATIVE]
    call = f"table1(data[1], data[2], {PAPER_MAX_ITERATIONS}, data[3])"
    return _run(call, data, repeats=repeats, real=real, files=("rule.gp", "table1.gp"))
