"""What every subcommand of ``verify`` shares: the parser class, the option types that check each
value when it is parsed, the checks of output paths, the status line, and one-line errors.

Each option type is an argparse ``type=``: a bad value ends the parse with one line naming the option
and the value (``--dps must be an integer >= 5, got '0'``), before anything is computed or written.
tests/cli/test_cli_options.py walks the parser and feeds every option of these types bad values.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import os
import sys
from collections.abc import Callable, Iterator, Sequence
from fractions import Fraction
from typing import Any

from verify.errors import VerifyError
from verify.numbers.format import counted

PROG = "verify"


class UsageError(VerifyError):
    """Command-line usage that argparse rejects (reported in one line, exit code 2)."""


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (a :class:`UsageError`), with no usage block; an error about
    a renamed option (:class:`Renamed`) names it as it was typed.

    >>> p = Parser(prog="x")
    >>> _ = renamed(p, "--max-impulses", "--max-iterations", type=int, default=None)
    >>> p.parse_args(["--max-iterations", "y"])
    Traceback (most recent call last):
    verify.cli.common.UsageError: x: --max-iterations: invalid int value: 'y'
    """

    typed: tuple[str, ...] = ()  #: the words this parser was given (``parse_known_args``)

    def parse_known_args(  # type: ignore[override]  # the same, remembering the words
        self, args: Sequence[str] | None = None, namespace: argparse.Namespace | None = None
    ) -> tuple[argparse.Namespace, list[str]]:
        self.typed = tuple(sys.argv[1:] if args is None else args)
        return super().parse_known_args(args, namespace)

    def error(self, message: str) -> None:  # type: ignore[override]  # raises instead of exiting
        import re

        # "argument --dps: must be ..." -> "--dps must be ..."; "argument --x: invalid ..." -> "--x: invalid ..."
        found = re.match(r"argument (\S+): (.*)", message, re.DOTALL)
        if found:
            names, rest = found.groups()
            name = next((n for n in names.split("/") if any(w.split("=")[0] == n for w in self.typed)), names)
            name = name.split("/")[0]  # a renamed option: as typed, else its new name
            message = f"{name} {rest}" if rest.startswith("must ") else f"{name}: {rest}"
        raise UsageError(f"{self.prog}: {message}")


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions and epilogs as written; a renamed option shows only its new name."""

    def _format_action_invocation(self, action: argparse.Action) -> str:
        if isinstance(action, Renamed):
            shown = [s for s in action.option_strings if s not in action.old]
            return ", ".join(shown) + (
                f" {self._format_args(action, action.dest.upper())}" if action.nargs != 0 else ""
            )
        return super()._format_action_invocation(action)


def formatter(prog: str) -> argparse.HelpFormatter:
    """The help layout of every (sub)command: descriptions and epilogs as written."""
    return _Formatter(prog, max_help_position=32)


#: the version after which the 0.2 names of renamed options (:func:`renamed`) stop working
OLD_NAMES_UNTIL = "0.3"


class Renamed(argparse.Action):
    """An option with a value whose 0.2 names (``old``) still work for one version: hidden from ``--help``,
    with a one-line note on stderr when used (``docs/cli.md``, "One vocabulary")."""

    def __init__(self, option_strings: list[str], dest: str, old: tuple[str, ...] = (), **kwargs: Any) -> None:
        super().__init__(option_strings, dest, **kwargs)
        self.old = old

    def __call__(
        self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: Any, option_string: Any = None
    ) -> None:
        if option_string in self.old:
            print(f"{PROG}: note: {option_string} is now {self.option_strings[0]} (the old name works in "
                  f"{OLD_NAMES_UNTIL} only)", file=sys.stderr)  # fmt: skip
        setattr(namespace, self.dest, values)


def renamed(p: argparse.ArgumentParser | Any, new: str, *old: str, **kwargs: Any) -> argparse.Action:
    """Declare the option ``new``, with its 0.2 names ``old`` kept as hidden aliases (:class:`Renamed`).

    >>> p = Parser(prog="x")
    >>> _ = renamed(p, "--max-impulses", "--max-iterations", type=int, default=None)
    >>> p.parse_args(["--max-impulses", "3"]).max_impulses
    3
    """
    return p.add_argument(new, *old, action=Renamed, old=old, **kwargs)


def max_impulses_option(p: argparse.ArgumentParser, *, default: int | None, help: str, **kwargs: Any) -> None:
    """``--max-impulses N``, the cap on impulses of every subcommand that runs the rule (0.2: ``--max-iterations``,
    ``--exact-cap`` in ``table1``)."""
    old = kwargs.pop("old", ("--max-iterations",))
    kwargs.setdefault("type", COUNT)
    renamed(p, "--max-impulses", *old, default=default, metavar="N", help=help, **kwargs)


def quiet_option(p: argparse.ArgumentParser, help: str = "no status line on stderr") -> None:
    """``--quiet``, on every subcommand: no progress or status lines on stderr."""
    p.add_argument("--quiet", action="store_true", help=help)


def split_option(text: str) -> list[str]:
    """A comma-separated option value as its entries (none empty).

    >>> split_option("1/2, 1")
    ['1/2', '1']
    """
    from verify.numbers.parse import split_list

    parts = split_list(text)
    if any(p == "" for p in parts):
        raise UsageError(f"empty entry in the list {text!r}")
    return parts


# -- option types: every numeric and output-path option is checked when it is parsed ----------------

#: the library's lower limit on decimal digits (verify.numbers.backends) and a ceiling on absurd requests
MIN_DPS, MAX_DPS = 5, 100_000
MAX_COUNT = 10**9  # caps on impulses, bits
MAX_SECONDS = 10**7  # about 16 weeks
MAX_BALLS = 1000
#: what ``--balls`` defaults to (:func:`verify.models.cradle.cradle_balls`)
BALLS_DEFAULT = "default: the number of --masses or --velocity when given, else 3"
MAX_CASES = 10**7
MAX_SEED = 2**63 - 1
MAX_WORKERS = 1024
MAX_IMPULSES_MAP = 100_000  # cradle-map --max-impulses
MAX_APPROACH = 20  # cradle-map --approach: eps = boundary + 10^-k, k up to this


class BoundedInt:
    """An integer option in ``[lo, hi]`` (decimal digits only: no ``1e3``, no ``0x10``).

    >>> BoundedInt(1, 8)("3")
    3
    >>> BoundedInt(1, 8)("0")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be an integer >= 1, got '0'
    """

    def __init__(self, lo: int, hi: int):
        self.lo, self.hi = lo, hi

    def __call__(self, text: str) -> int:
        import re

        stripped = text.strip()
        if not re.fullmatch(r"[+-]?[0-9]+", stripped):
            raise argparse.ArgumentTypeError(f"must be an integer, got {text!r}")
        if len(stripped.lstrip("+-").lstrip("0")) > 30:  # past every bound here (and not read as an int)
            value = self.lo - 1 if stripped.startswith("-") else self.hi + 1
        else:
            value = int(stripped)
        if value < self.lo:
            below = f">= {self.lo}" if self.lo <= 0 else f"an integer >= {self.lo}"
            raise argparse.ArgumentTypeError(f"must be {below}, got {text!r}")
        if value > self.hi:
            raise argparse.ArgumentTypeError(f"must be <= {self.hi}, got {text!r}")
        return value

    def __repr__(self) -> str:  # argparse names the type in some messages
        return f"integer in [{self.lo}, {self.hi}]"


class Seconds:
    """A positive, finite duration in seconds up to ``hi``, read exactly (``90``, ``0.5``,
    ``1/4``; not ``nan``, ``inf``, ``1e400``), returned as a float for the clock.

    >>> Seconds()("1/4")
    0.25
    >>> Seconds()("nan")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a number of seconds > 0, got 'nan'
    """

    def __init__(self, hi: int = MAX_SECONDS):
        self.hi = hi

    def __call__(self, text: str) -> float:
        value = rational_value(text)
        if value is None or value <= 0:
            raise argparse.ArgumentTypeError(f"must be a number of seconds > 0, got {text!r}")
        if value > self.hi:
            raise argparse.ArgumentTypeError(f"must be <= {self.hi} seconds, got {text!r}")
        return float(value)

    def __repr__(self) -> str:
        return "seconds"


class NonNegativeRational:
    """A rational number >= 0, read exactly (``1e-9`` is 1/10^9), returned as a Fraction.

    >>> NonNegativeRational()("1e-9")
    Fraction(1, 1000000000)
    """

    def __call__(self, text: str) -> Fraction:
        value = rational_value(text)
        if value is None or value < 0:
            raise argparse.ArgumentTypeError(f"must be a non-negative rational, got {text!r}")
        return value

    def __repr__(self) -> str:
        return "non-negative rational"


class IntList:
    """A list of integers in ``[lo, hi]`` and runs ``a-b`` (``1-20,25,30``), returned sorted without repeats.

    >>> IntList(1, 100)("3,1-2,2")
    (1, 2, 3)
    >>> IntList(1, 100)("0-3")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be integers from 1 to 100 and runs a-b (1-20,25), got '0-3'
    """

    def __init__(self, lo: int, hi: int):
        self.lo, self.hi = lo, hi

    def __call__(self, text: str) -> tuple[int, ...]:
        out: set[int] = set()
        try:
            for part in split_option(text):
                a, sep, b = part.partition("-")
                lo, hi = BoundedInt(self.lo, self.hi)(a.strip()), BoundedInt(self.lo, self.hi)(b.strip() if sep else a)
                if hi < lo or hi - lo > 10**5:
                    raise argparse.ArgumentTypeError(part)
                out.update(range(lo, hi + 1))
        except (argparse.ArgumentTypeError, UsageError):
            raise argparse.ArgumentTypeError(
                f"must be integers from {self.lo} to {self.hi} and runs a-b (1-20,25), got {text!r}"
            ) from None
        return tuple(sorted(out))

    def __repr__(self) -> str:
        return "list of integers"


class RationalList:
    """A list of non-negative rationals read exactly (``0,1/2,0.25``), returned sorted without repeats.

    >>> RationalList()("1/2, 0, 0.5")
    (Fraction(0, 1), Fraction(1, 2))
    """

    def __call__(self, text: str) -> tuple[Fraction, ...]:
        try:
            return tuple(sorted({NonNegativeRational()(x) for x in split_option(text)}))
        except (argparse.ArgumentTypeError, UsageError):
            raise argparse.ArgumentTypeError(
                f"must be non-negative rationals separated by commas, got {text!r}"
            ) from None

    def __repr__(self) -> str:
        return "list of rationals"


class ExactNumber:
    """A real number in the restricted syntax of :mod:`verify.numbers.parse` (``0.5``, ``pi/6``,
    ``3 - 2*sqrt(2)``), checked when parsed and returned as the text (the library reads it).

    >>> ExactNumber()("pi/6")
    'pi/6'
    """

    def __call__(self, text: str) -> str:
        from verify.errors import InvalidInput
        from verify.numbers.parse import parse_number

        try:
            parse_number(text)
        except InvalidInput as exc:
            raise argparse.ArgumentTypeError(one_line(exc)) from None
        return text

    def __repr__(self) -> str:
        return "number"


def rational_value(text: str) -> Fraction | None:
    """``text`` as a Fraction through the restricted parser, or None if it is not a rational."""
    from verify.errors import InvalidInput
    from verify.numbers.parse import parse_number, to_number

    try:
        value = to_number(parse_number(text))
    except InvalidInput:
        return None
    return value if isinstance(value, Fraction) else None


class OutputDir:
    """A folder to write into: it is a folder, or it can be created (its nearest existing
    ancestor is a folder in which a file can be created). Nothing is left behind by the
    check: a probe file is created and removed at once. Returns the text.

    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> OutputDir()(folder + "/new/reports") == folder + "/new/reports"
    True
    >>> open(folder + "/file", "w").close()
    >>> OutputDir()(folder + "/file/reports")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a folder that can be written, got '.../file/reports' (.../file is a file)
    >>> import shutil; shutil.rmtree(folder)
    """

    what = "a folder that can be written"

    def __call__(self, text: str) -> str:
        if not text:
            raise argparse.ArgumentTypeError(f"must be {self.what}, got ''")
        path = os.path.abspath(text)
        if os.path.exists(path) and not os.path.isdir(path):
            raise argparse.ArgumentTypeError(f"must be {self.what}, got {text!r} (a file is there)")
        check_writable(path, self.what, text)
        return text

    def __repr__(self) -> str:
        return "folder"


class OutputFile:
    """A file to write: not a folder, with one of ``suffixes`` (when given), in a folder that exists
    (no folder is created for a file) and can be written into; with ``stdout``, ``-`` means standard
    output. Returns the text.

    >>> OutputFile((".png",))("map.svg")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a file name ending in .png, got 'map.svg'
    >>> OutputFile()("/no/such/x.xml")
    Traceback (most recent call last):
    argparse.ArgumentTypeError: must be a file in a folder that exists, got '/no/such/x.xml' (no folder /no/such)
    >>> OutputFile(stdout=True)("-")
    '-'
    """

    def __init__(self, suffixes: tuple[str, ...] = (), *, stdout: bool = False):
        self.suffixes, self.stdout = suffixes, stdout

    def __call__(self, text: str) -> str:
        what = "a file that can be written"
        if self.stdout and text == "-":
            return text
        if self.suffixes and not text.lower().endswith(self.suffixes):
            endings = " or ".join(self.suffixes)
            raise argparse.ArgumentTypeError(f"must be a file name ending in {endings}, got {text!r}")
        if not text or text.endswith(("/", os.sep)) or os.path.isdir(text):
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r} (a folder)")
        folder = os.path.dirname(os.path.abspath(text))
        if os.path.exists(folder) and not os.path.isdir(folder):
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r} ({folder} is a file)")
        if not os.path.isdir(folder):
            raise argparse.ArgumentTypeError(
                f"must be a file in a folder that exists, got {text!r} (no folder {os.path.dirname(text) or folder})"
            )
        check_writable(folder, what, text)
        return text

    def __repr__(self) -> str:
        return "file"


@contextlib.contextmanager
def writing(path: str, option: str) -> Iterator[None]:
    """Report an OSError on ``path`` or inside it (a full disk, a folder removed since the option was
    checked) as one line naming the option; other errors pass through."""
    try:
        yield
    except OSError as exc:
        name = exc.filename if isinstance(exc.filename, str) else None
        if name is None or not os.path.abspath(name).startswith(os.path.abspath(path)):
            raise
        raise UsageError(f"{option} {path!r}: cannot write {name} ({exc.strerror or exc})") from None


def write_output(path: str, text: str, option: str) -> None:
    """Write ``text`` whole to ``path`` (:func:`verify.records.files.write_atomic`), an OSError
    reported in one line naming ``option``; ``-`` is standard output."""
    from verify.records.files import STDIO, write_atomic

    if path == STDIO:
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    with writing(path, option):
        write_atomic(path, text)


def check_writable(path: str, what: str, text: str) -> None:
    """Check that ``path`` is, or can be created as, a folder one can write into."""
    import tempfile

    ancestor = path
    while not os.path.exists(ancestor) and os.path.dirname(ancestor) != ancestor:
        ancestor = os.path.dirname(ancestor)
    if not os.path.isdir(ancestor):
        raise argparse.ArgumentTypeError(f"must be {what}, got {text!r} ({ancestor} is a file)")
    try:
        fd, probe = tempfile.mkstemp(prefix=".verify-probe-", dir=ancestor)
        os.close(fd)
        os.remove(probe)
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise argparse.ArgumentTypeError(
            f"must be {what}, got {text!r} (cannot write in {ancestor}: {reason})"
        ) from None


# -- progress and budgets ----------------------------------------------------------------------


class StatusLine:
    """A live status line on stderr, on a terminal only (never in a pipe or a log file): rewritten
    in place at most ten times a second, cut to the terminal's width, and erased by :meth:`close`.

    >>> line = StatusLine(enabled=False)  # stderr is not a terminal, or --quiet: shows nothing
    >>> line.show("case 1/3", now=True); line.close()
    """

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.shown = False
        self.last = 0.0
        self.width = 80
        if enabled:
            with contextlib.suppress(OSError, ValueError, AttributeError):
                self.width = os.get_terminal_size(sys.stderr.fileno()).columns or 80  # 0: size unknown

    @classmethod
    def for_args(cls, args: argparse.Namespace) -> StatusLine:
        """Enabled when stderr is a terminal and ``--quiet`` was not given."""
        tty = getattr(sys.stderr, "isatty", lambda: False)()
        return cls(enabled=tty and not getattr(args, "quiet", False) and os.environ.get("TERM") != "dumb")

    def show(self, text: str, *, now: bool = False) -> None:
        """Replace the line by ``text`` (unless it was rewritten less than 0.1 s ago and not ``now``)."""
        if not self.enabled:
            return
        import time

        t = time.monotonic()
        if not now and t - self.last < 0.1:
            return
        self.last = t
        sys.stderr.write("\r\x1b[K" + text[: max(self.width - 1, 10)])
        sys.stderr.flush()
        self.shown = True

    def close(self) -> None:
        """Erase the line."""
        if self.shown:
            sys.stderr.write("\r\x1b[K")
            sys.stderr.flush()
            self.shown = False


def run_budget(args: argparse.Namespace) -> Any:
    """The per-case :class:`verify.laws.rule.Budget` of ``--max-bits`` and ``--case-time-limit`` (None if neither)."""
    from verify.laws.rule import Budget

    if args.max_bits is None and args.case_time_limit is None:
        return None
    return Budget(bits=args.max_bits, seconds=args.case_time_limit)


def case_progress(status: StatusLine, label: str) -> Any:
    """A ``progress`` callback for :func:`verify.laws.rule.solve` that shows ``label``, the impulses so far
    and the time (None when the status line is off: no cost at all)."""
    if not status.enabled:
        return None
    import time

    start = time.monotonic()
    status.show(f"{label}: starting", now=True)
    return lambda count: status.show(f"{label}: {counted(count, 'impulse')}, {time.monotonic() - start:.0f} s")


# -- the parsers of the subcommands, and the options several of them share -----------------------


def command(sub: SubParsers, name: str, func: Callable[[argparse.Namespace], int]) -> argparse.ArgumentParser:
    """The parser of the subcommand ``name`` (``"oracle export"`` for one of ``verify oracle``), with its
    texts from ``commands.toml`` beside this module, run by ``func``.

    >>> sub = Parser(prog=PROG).add_subparsers(parser_class=Parser)
    >>> print(command(sub, "table1", print).epilog, end="")
    examples:
      verify table1
      verify table1 --json
    """
    texts = command_texts()[name]
    examples = texts["examples"]
    label = "examples" if len(examples) > 1 else "example"
    epilog = f"{label}:\n" + "".join(f"  {line}\n" for line in examples)
    word = name.rsplit(maxsplit=1)[-1]
    p: argparse.ArgumentParser = sub.add_parser(word, help=texts["help"], formatter_class=formatter,
                                                description=texts.get("description"), epilog=epilog)  # fmt: skip
    p.set_defaults(func=func)
    return p


@functools.cache
def command_texts() -> dict[str, Any]:
    """The texts of every subcommand's ``--help`` (``verify/cli/commands.toml``), by subcommand.

    >>> command_texts()["oracle export"]["examples"]
    ['verify oracle export golden']
    """
    import tomllib
    from importlib.resources import files

    return tomllib.loads(files("verify.cli").joinpath("commands.toml").read_text(encoding="utf-8"))


def budget_options(p: argparse.ArgumentParser, scope: str) -> None:
    max_impulses_option(
        p,
        default=None,
        help="cap on impulses, replacing each case's max_iterations (default: the case's own, else 10000)",
    )
    p.add_argument(
        "--max-bits",
        type=BoundedInt(1, MAX_COUNT),
        default=None,
        metavar="BITS",
        help=f"stop a run (stop budget) once its exact numbers pass BITS bits, {scope}: numerator plus "
        "denominator of the largest velocity component; the same on every machine; exact backend only",
    )
    renamed(
        p,
        "--case-time-limit",
        "--case-timeout",
        type=Seconds(),
        default=None,
        metavar="SECONDS",
        help=f"stop a run (stop budget) after SECONDS of wall time, {scope}: depends on the machine, so "
        "prefer --max-bits where results must be reproducible",
    )


def backend_options(p: argparse.ArgumentParser) -> None:
    from verify.numbers.backends import BACKENDS

    p.add_argument(
        "--backend",
        default="exact",
        choices=BACKENDS,
        help="arithmetic: exact (default), mp, interval (certified), float (not rigorous)",
    )
    p.add_argument(
        "--dps",
        type=BoundedInt(MIN_DPS, MAX_DPS),
        default=None,
        help=f"decimal digits for mp and interval, {MIN_DPS} to {MAX_DPS} (default 50)",
    )


def backend_choice(args: argparse.Namespace) -> dict[str, Any]:
    """What :func:`backend_options` parsed, as the ``backend`` and ``dps`` keyword arguments of the library.

    >>> backend_choice(argparse.Namespace(backend="mp", dps=40))
    {'backend': 'mp', 'dps': 40}
    """
    return {"backend": args.backend, "dps": args.dps}


#: library parameters that error messages name, and the command line's flags for them
_PARAMETER_FLAGS = {'backend="interval"': "--backend interval", 'backend="mp"': "--backend mp"}


def one_line(exc: Any) -> str:
    """The message of ``exc`` on one line, in the command line's terms.

    >>> one_line(ValueError('backend="mp"  needs\\n digits'))
    '--backend mp needs digits'
    """
    text = " ".join(str(exc).split())
    for parameter, flag in _PARAMETER_FLAGS.items():  # the library's terms, in the command line's
        text = text.replace(parameter, flag)
    return text


# -- where work runs: local processes or a Dask cluster ---------------------------------------------

CLUSTER_EXTRA = (
    "pip install '.[cluster]' in a clone of the repository (pip install 'verify-impacts[cluster]' from a package index)"
)


def cluster_options(p: argparse.ArgumentParser, workers_help: str = "processes (default: every core)") -> None:
    """``--workers``, ``--scheduler`` and ``--local-cluster`` (one of them at most), and ``--checkpoint``."""
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=WORKERS, default=None, help=workers_help)
    where.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run on the Dask cluster of this scheduler (tcp://host:8786)")  # fmt: skip
    where.add_argument("--local-cluster", metavar="N", type=WORKERS, default=None,
                       help="run on a local Dask cluster of N single-threaded worker processes")  # fmt: skip
    p.add_argument("--checkpoint", metavar="FILE", type=OutputFile(), default=None,
                   help="record each finished task in FILE (JSON lines); the same command resumes from it")  # fmt: skip


@contextlib.contextmanager
def cluster_executor(args: argparse.Namespace) -> Iterator[Any]:
    """The executor of ``--scheduler`` or ``--local-cluster`` (a Dask client's), closed on exit; None
    for local processes. A missing dask or an unreachable scheduler is one line (exit code 2).

    >>> with cluster_executor(argparse.Namespace(scheduler=None, local_cluster=None)) as executor:
    ...     print(executor)
    None
    """
    if args.scheduler is None and args.local_cluster is None:
        yield None
        return
    option = "--scheduler" if args.scheduler is not None else "--local-cluster"
    try:
        import logging

        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise UsageError(f"{option} needs dask: {CLUSTER_EXTRA}") from None
    with contextlib.ExitStack() as stack:
        if getattr(args, "quiet", False):  # only the result and errors: Dask's warnings too, until the client is closed
            stack.enter_context(quiet_loggers("distributed"))
        if args.scheduler is not None:
            try:
                client = stack.enter_context(Client(args.scheduler, timeout="10s"))
            except (OSError, ValueError, TypeError) as exc:  # TimeoutError is an OSError
                raise UsageError(f"--scheduler {args.scheduler!r}: cannot connect ({one_line(exc)})") from None
        else:
            with _workers_ignore_ctrl_c():
                cluster = stack.enter_context(
                    LocalCluster(
                        n_workers=args.local_cluster,
                        threads_per_worker=1,
                        processes=True,
                        # its HTTP server (Dask starts one even without a dashboard) on a free port of this
                        # machine only: 8787, Dask's default, may be another cluster's
                        dashboard_address="127.0.0.1:0",
                        silence_logs=logging.ERROR,
                    )
                )
            client = stack.enter_context(Client(cluster))
        yield client.get_executor()


@contextlib.contextmanager
def quiet_loggers(name: str, level: int = 40) -> Iterator[None]:
    """The logger ``name`` and those below it that set their own level show only records of ``level`` and
    above (40: errors) for the duration; their levels are restored after. Dask's ``distributed`` sets
    levels on ``distributed`` and below it (``distributed.client``: warning), hence every one of them.

    >>> import logging
    >>> log = logging.getLogger("example.client")
    >>> log.setLevel(logging.WARNING)
    >>> with quiet_loggers("example"):
    ...     log.isEnabledFor(logging.WARNING), log.isEnabledFor(logging.ERROR)
    (False, True)
    >>> log.isEnabledFor(logging.WARNING), log.level == logging.WARNING
    (True, True)
    """
    import logging

    names = [name, *(n for n in logging.root.manager.loggerDict if n.startswith(name + "."))]
    loggers = [logging.getLogger(n) for n in names]
    saved = [(log, log.level) for log in loggers if log.name == name or log.level != logging.NOTSET]
    for log, was in saved:
        log.setLevel(max(was, level))
    try:
        yield
    finally:
        for log, was in saved:
            log.setLevel(was)


@contextlib.contextmanager
def task_runner(args: argparse.Namespace, options: dict[str, Any]) -> Iterator[Any]:
    """The :class:`verify.runner.tasks.TaskRunner` of :func:`cluster_options`: ``--workers`` local processes
    or the cluster's executor, and the ``--checkpoint`` file for a run with ``options`` (those that change
    results: a checkpoint of other options is refused, exit code 2).

    >>> ns = argparse.Namespace(workers=1, scheduler=None, local_cluster=None, checkpoint=None)
    >>> with task_runner(ns, {}) as runner:
    ...     runner.map("abs", abs, [-2])
    [2]
    """
    from verify.runner.tasks import TaskRunner

    checkpoint = getattr(args, "checkpoint", None)
    with cluster_executor(args) as executor, contextlib.ExitStack() as stack:
        runner = TaskRunner(workers=args.workers, executor=executor, checkpoint=checkpoint, options=options)
        with writing(checkpoint, "--checkpoint") if checkpoint else contextlib.nullcontext():
            stack.enter_context(runner)  # reads the checkpoint, or starts it
        yield runner


@contextlib.contextmanager
def _workers_ignore_ctrl_c() -> Iterator[None]:
    """SIGINT ignored while the local cluster starts its worker processes, which inherit that: Ctrl-C then
    stops this process alone (one line), which closes the cluster, instead of a traceback from every worker."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


# -- the types of the numeric options (each checks its range when parsed: one line, exit code 2) -----

COUNT = BoundedInt(0, MAX_COUNT)  #: caps on impulses
BALLS = BoundedInt(2, MAX_BALLS)
CASES = BoundedInt(1, MAX_CASES)
SEED = BoundedInt(0, MAX_SEED)
WORKERS = BoundedInt(1, MAX_WORKERS)
NUMBER = ExactNumber()

#: what ``add_parser`` of the subcommands' parsers returns (``sub.add_parser(...)``)
SubParsers = Any


#: the options of the sequential law's settings (``--law sequential``)
SWEEP_OPTIONS = ("iterations", "order", "threshold")


def law_options(p: argparse.ArgumentParser, *, append: bool = False, help: str | None = None) -> None:
    """``--law`` (the paper's rule by default; with ``append``, repeatable) and the sequential law's settings
    ``--iterations``, ``--order``, ``--threshold`` (:class:`verify.laws.sequential.Sequential`)."""
    from verify.laws.rule import LAWS
    from verify.laws.sequential import DEFAULT_ITERATIONS

    what = help or (
        "rule: the paper's iterative rule (default); simultaneous: Newton's restitution with complementarity, all "
        "constraints at once; sequential: the sweeps of single-contact impulses that physics engines run"
    )
    if append:
        p.add_argument("--law", action="append", choices=LAWS, help=what)
    else:
        p.add_argument("--law", default="rule", choices=LAWS, help=what)
    p.add_argument("--iterations", type=BoundedInt(1, MAX_COUNT), default=None, metavar="K",
                   help=f"with --law sequential: sweeps over the contacts (default {DEFAULT_ITERATIONS}, as Bullet's "
                        "and Chipmunk's solvers; Box2D 2.3 runs 8)")  # fmt: skip
    p.add_argument("--order", default=None, metavar="I,J,...",
                   help="with --law sequential: the constraints' order in a sweep, by 0-based index, e.g. 1,0, "
                        "or reversed (for a file whose cases have different numbers of constraints; default: as "
                        "given)")  # fmt: skip
    p.add_argument("--threshold", default=None, metavar="SPEED",
                   help="with --law sequential: no restitution for a contact incoming at this speed or slower "
                        "(one number, or one per constraint: 1 or 1,0; default 0)")  # fmt: skip


def law_choice(args: argparse.Namespace, command: str) -> Any:
    """The law of ``--law`` with the sequential law's settings (a ``Sequential``), checked; with a repeatable
    ``--law``, the list of laws (or None for all)."""
    from verify.errors import InvalidInput
    from verify.laws.sequential import DEFAULT_ITERATIONS, Sequential

    given = [f"--{name}" for name in SWEEP_OPTIONS if getattr(args, name) is not None]
    laws = [args.law] if isinstance(args.law, str) else list(args.law or ())
    if not given:
        return args.law
    if "sequential" not in laws:
        raise UsageError(f"{PROG} {command}: {given[0]} is a setting of the sequential law: add --law sequential")
    order: Any = None
    if args.order is not None and args.order.strip() == "reversed":
        order = "reversed"
    elif args.order is not None:
        try:
            order = tuple(int(x) for x in split_option(args.order))
        except ValueError:
            raise UsageError(
                f"{PROG} {command}: --order: expected 0-based indices such as 1,0, got {args.order!r}"
            ) from None
    threshold: Any = 0
    if args.threshold is not None:
        parts = split_option(args.threshold)
        for x in parts:
            try:
                NUMBER(x)
            except argparse.ArgumentTypeError as exc:
                raise UsageError(f"{PROG} {command}: --threshold: {exc}") from None
        threshold = parts[0] if len(parts) == 1 else tuple(parts)
    try:
        law = Sequential(args.iterations or DEFAULT_ITERATIONS, order, threshold)
        law.thresholds(1 if not isinstance(threshold, tuple) else len(threshold))  # a negative one: refused now
    except InvalidInput as exc:
        raise UsageError(f"{PROG} {command}: {one_line(exc)}") from None
    chosen = [law if x == "sequential" else x for x in laws]
    return chosen[0] if isinstance(args.law, str) else chosen
