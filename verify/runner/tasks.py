"""Tasks: units of work with a stable id, run serially, in local processes or on a Dask cluster, and a
checkpoint file that lets a stopped run resume.

A :class:`Task` is a module-level function and a plain, picklable payload, named by an id that is the
same on every run. :func:`run_tasks` returns the results in the order of the tasks (never the order in
which they finish), so the output is the same whatever runs them. A task that raises, or whose worker
dies (a broken process pool, Dask's ``KilledWorker``), is tried once more; if it fails again it is
reported in :attr:`TaskRun.failures` and the other tasks still finish.

>>> run = run_tasks([Task("a", abs, -1, "row a"), Task("b", abs, -2, "row b")])
>>> run.results, run.failures
([1, 2], [])

A :class:`Checkpoint` is a JSON-lines file: a header (format version, the fingerprint of verify's source
and Hypothesis' version, the options that change results), then one line per finished task, appended and
flushed to disk as each finishes. Results are stored with :func:`encode`, which keeps Fractions, tuples
and lists apart, so that :func:`decode` gives back the same objects:

>>> from fractions import Fraction
>>> decode(json.loads(json.dumps(encode((Fraction(1, 3), [2, "x"], None)))))
(Fraction(1, 3), [2, 'x'], None)
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import os
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from verify.errors import InvalidInput

#: the version of the checkpoint format (its first line says which)
CHECKPOINT_FORMAT = 1
#: how many times a task is run at most (one retry)
ATTEMPTS = 2


@dataclass(frozen=True)
class Task:
    """One unit of work: ``fn(payload)``, named ``id`` (stable across runs) and described by ``label``
    (the case or row, for error messages). ``fn`` is a module-level function and ``payload`` plain data,
    so that both travel to other processes and machines."""

    id: str
    fn: Callable[[Any], Any]
    payload: Any
    label: str = ""


@dataclass(frozen=True)
class TaskFailure:
    """A task that failed on each of its attempts: its id, its label and the last error (one line)."""

    id: str
    label: str
    error: str
    #: whether the error is a bug (not bad input, nor a sign undecided at the precision asked)
    internal: bool = False


class TasksFailed(RuntimeError):
    """Raised once every other task is done, for the tasks that failed on each attempt (``failures``)."""

    def __init__(self, failures: Sequence[TaskFailure]):
        self.failures = list(failures)
        super().__init__("; ".join(f"{f.label}: {f.error}" for f in self.failures))


@dataclass
class TaskRun:
    """The results of a run, in the order of the tasks (None where the task failed), and its failures."""

    results: list[Any]
    failures: list[TaskFailure] = field(default_factory=list)


def _internal(exc: BaseException) -> bool:
    """Whether a task's error is a bug in verify (anything but bad input or an undecided sign)."""
    from verify.errors import InvalidInput, Undecided

    return not isinstance(exc, (InvalidInput, Undecided))


def _describe(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def run_tasks(
    tasks: Sequence[Task],
    *,
    workers: int = 1,
    executor: Executor | None = None,
    finished: dict[str, Any] | None = None,
    on_result: Callable[[Task, Any], None] | None = None,
) -> TaskRun:
    """Run every task not already in ``finished`` (results by task id, e.g. from a checkpoint).

    ``executor`` is any ``concurrent.futures.Executor`` (a Dask cluster: ``Client(...).get_executor()``);
    without one, a local pool of ``workers`` processes runs the tasks, or none at all for one worker (they
    then run here, in order). ``on_result(task, result)`` is called here, in the order tasks finish, for
    each task that is run (not for those in ``finished``). A task that raises, or whose worker dies, is
    run once more. When a process of the local pool dies, the pool breaks and fails every task it held:
    those tasks are then run one by one, each in a process of its own, up to twice (the one that kills its
    process is found and reported; the others lose no attempt). Results come back in the order of ``tasks``.

    >>> seen = []
    >>> run_tasks([Task("x", abs, -3)], finished={}, on_result=lambda t, r: seen.append((t.id, r))).results
    [3]
    >>> seen
    [('x', 3)]
    >>> run_tasks([Task("x", abs, -3)], finished={"x": 7}).results  # already finished: not run again
    [7]
    """
    ids = [t.id for t in tasks]
    if len(set(ids)) != len(ids):
        raise ValueError("task ids must be unique")
    finished = dict(finished or {})
    results: dict[str, Any] = {t.id: finished[t.id] for t in tasks if t.id in finished}
    failures: dict[str, TaskFailure] = {}
    todo = [t for t in tasks if t.id not in finished]

    def succeeded(task: Task, result: Any) -> None:
        results[task.id] = result
        if on_result is not None:
            on_result(task, result)

    if executor is None and workers <= 1:
        for task in todo:
            _attempts(task, lambda t: t.fn(t.payload), succeeded, failures)
    else:
        _run_in_pool(todo, workers, executor, succeeded, failures)
    order = {t.id: i for i, t in enumerate(tasks)}
    return TaskRun(
        [results.get(t.id) for t in tasks],
        sorted(failures.values(), key=lambda f: order[f.id]),
    )


def _run_in_pool(
    todo: list[Task],
    workers: int,
    executor: Executor | None,
    succeeded: Callable[[Task, Any], None],
    failures: dict[str, TaskFailure],
) -> None:
    attempts = dict.fromkeys((t.id for t in todo), 0)
    interrupted = False
    suspects: list[Task] = []  # held by a local pool when one of its processes died: which one killed it is unknown
    pool = executor or ProcessPoolExecutor(max_workers=workers)

    def submit(task: Task) -> None:
        attempts[task.id] += 1
        try:
            pending[pool.submit(task.fn, task.payload)] = task
        except BrokenProcessPool:  # a given pool that broke (one of its processes died) takes no task
            suspects.append(task)

    try:
        pending: dict[Future[Any], Task] = {}
        for task in todo:
            submit(task)
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            retry: list[Task] = []
            broken = False
            for future in done:
                task = pending.pop(future)
                try:
                    result = future.result()
                except BrokenProcessPool:
                    suspects.append(task)
                    broken = True
                except Exception as exc:  # the task raised, or its Dask worker died (KilledWorker)
                    if attempts[task.id] >= ATTEMPTS:
                        failures[task.id] = TaskFailure(task.id, task.label, _describe(exc), _internal(exc))
                    else:
                        retry.append(task)
                else:
                    succeeded(task, result)
            if broken and executor is None:  # a broken pool fails every task it holds: a new one for the retries
                suspects += pending.values()
                pending.clear()
                pool.shutdown(wait=True, cancel_futures=True)
                pool = ProcessPoolExecutor(max_workers=workers)
            for task in retry:
                submit(task)
    except KeyboardInterrupt:  # Ctrl-C, SIGTERM or SIGHUP: the pool's processes stop now, not after their tasks
        if executor is None:
            stop_processes(pool)
        interrupted = True
        raise
    finally:
        if executor is None:  # an interrupted run does not wait (the interrupt may have left a future's lock held)
            pool.shutdown(wait=not interrupted, cancel_futures=True)
    for task in suspects:  # each alone in a process of its own, up to ATTEMPTS times
        _attempts(task, _alone, succeeded, failures)


def stop_processes(pool: Executor) -> None:
    """Terminate the processes of a local ``pool`` (which a SIGTERM sent to this process alone does not reach), and
    any other process of this one's that multiprocessing started (one forked while the interrupt came); the pool's
    shutdown then cancels what they held."""
    import multiprocessing

    pooled = list((getattr(pool, "_processes", None) or {}).values())
    for process in [*pooled, *multiprocessing.active_children()]:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            process.terminate()


def _alone(task: Task) -> Any:
    """``task`` run in a process of its own."""
    with ProcessPoolExecutor(max_workers=1) as alone:
        return alone.submit(task.fn, task.payload).result()


def _attempts(
    task: Task,
    call: Callable[[Task], Any],
    succeeded: Callable[[Task, Any], None],
    failures: dict[str, TaskFailure],
) -> None:
    """``call(task)`` up to :data:`ATTEMPTS` times, until it returns; the last error is a failure."""
    for attempt in range(ATTEMPTS):
        try:
            result = call(task)
        except Exception as exc:
            if attempt + 1 == ATTEMPTS:
                failures[task.id] = TaskFailure(task.id, task.label, _describe(exc), _internal(exc))
            continue
        succeeded(task, result)
        return


class TaskRunner:
    """Where tasks run, and what a stopped run keeps: ``executor`` (a Dask cluster's:
    ``Client(...).get_executor()``) or ``workers`` local processes (1: here, in order; None: one per core),
    and, with ``checkpoint`` (a file name), a :class:`Checkpoint` for a run with ``options``, shared by
    every :meth:`run` of the runner (task ids are then unique across them). ``progress(done, total, task,
    result)`` is called, within one :meth:`run`, as each task finishes (the tasks read from the checkpoint
    count as done from the start).

    >>> with TaskRunner() as runner:
    ...     runner.run([Task("a", abs, -1), Task("b", abs, -2)]).results
    [1, 2]
    """

    def __init__(
        self,
        *,
        workers: int | None = 1,
        executor: Executor | None = None,
        checkpoint: str | None = None,
        options: dict[str, Any] | None = None,
        progress: Callable[[int, int, Task, Any], None] | None = None,
    ):
        self.workers = workers or os.cpu_count() or 1
        self.executor = executor
        self.progress = progress
        self.store = Checkpoint(checkpoint, options or {}) if checkpoint else None
        self.finished: dict[str, Any] = {}
        self._lock = threading.Lock()  # runs from several threads (:meth:`one_pool`) record their results in turn
        self._pool: ProcessPoolExecutor | None = None  # the pool of :meth:`one_pool`

    def __enter__(self) -> TaskRunner:
        if self.store is not None:
            self.finished = self.store.open()
        return self

    def __exit__(self, *exc: object) -> None:
        if self.store is not None:
            self.store.close()

    def run(self, tasks: Sequence[Task], *, progress: Callable[[int, int, Task, Any], None] | None = None) -> TaskRun:
        """Run ``tasks`` (those in the checkpoint are not run again): :func:`run_tasks`, each finished task
        appended to the checkpoint as it finishes; ``progress`` replaces the runner's own for this run."""
        count = sum(1 for t in tasks if t.id in self.finished)
        progress = progress or self.progress

        def done(task: Task, result: Any) -> None:
            nonlocal count
            with self._lock:
                count += 1
                self.finished[task.id] = result
                if self.store is not None:
                    self.store.add(task.id, result)
                if progress is not None:
                    progress(count, len(tasks), task, result)

        return run_tasks(tasks, workers=self.workers, executor=self._executor(), finished=self.finished,
                         on_result=done)  # fmt: skip

    def _executor(self) -> Executor | None:
        """The executor of a run: the cluster's, or the pool of :meth:`one_pool` (a new one if a process of the
        last one died: a broken pool takes no task), or None (a pool of the run's own)."""
        if self._pool is None:
            return self.executor
        with self._lock:
            if getattr(self._pool, "_broken", False):
                self._pool.shutdown(wait=False, cancel_futures=True)
                self._pool = ProcessPoolExecutor(max_workers=self.workers)
            return self._pool

    @property
    def elsewhere(self) -> bool:
        """Whether the tasks run in other processes than this one, started already: on a cluster, or on the
        pool of :meth:`one_pool`."""
        return self.executor is not None or self._pool is not None

    @contextlib.contextmanager
    def one_pool(self) -> Iterator[TaskRunner]:
        """Within the block, every run of this runner, from any thread, uses one pool of its local processes,
        started here (with ``fork``, Linux's default, no process is then forked while another thread of this one
        runs; a pool replaces one whose process died), and tasks submitted from two threads share the processes
        in the order submitted. Nothing changes for a runner with an executor (a cluster) or one local process.

        >>> with TaskRunner(workers=2) as runner, runner.one_pool():
        ...     runner.map("abs", abs, [-1, -2])
        [1, 2]
        """
        if self.executor is not None or self.workers <= 1:
            yield self
            return
        self._pool = ProcessPoolExecutor(max_workers=self.workers)
        interrupted = False
        try:
            list(self._pool.map(abs, range(self.workers)))  # the processes start now
            yield self
        except KeyboardInterrupt:  # Ctrl-C, SIGTERM or SIGHUP: the processes stop now, not after their tasks
            if self._pool is not None:
                stop_processes(self._pool)
            interrupted = True
            raise
        finally:
            pool, self._pool = self._pool, None
            pool.shutdown(wait=not interrupted, cancel_futures=True)

    def map(
        self,
        name: str,
        fn: Callable[[Any], Any],
        payloads: Sequence[Any],
        *,
        key: Callable[[Any], Any] | None = None,
        progress: Callable[[int, int, Task, Any], None] | None = None,
        labels: Sequence[str] | None = None,
    ) -> list[Any]:
        """``[fn(p) for p in payloads]`` as tasks, named ``name`` with the index and a digest of the payload
        (of ``key(payload)`` if given: plain data whose repr is the same on every run), so that a checkpoint
        reuses a result only for the same work; tasks that failed twice raise :class:`TasksFailed` once
        the others are done, named by their ``labels`` (default ``name #i``). ``progress`` as for :meth:`run`.

        >>> TaskRunner().map("abs", abs, [-1, 2])
        [1, 2]
        """
        tasks = [
            Task(f"{name} | {i} | {_digest(key(p) if key else p)}", fn, p, labels[i] if labels else f"{name} #{i}")
            for i, p in enumerate(payloads)
        ]
        run = self.run(tasks, progress=progress)
        if run.failures:
            raise TasksFailed(run.failures)
        return run.results


def _digest(payload: Any) -> str:
    """A short digest of a payload (its repr: plain data, the same on every run)."""
    return hashlib.sha256(repr(payload).encode()).hexdigest()[:16]


# -- encoding results exactly ------------------------------------------------------------------------


def encode(value: Any) -> Any:
    """``value`` as JSON data that :func:`decode` turns back into an equal object of the same types:
    Fractions as ``{"fraction": "p/q"}``, tuples as ``{"tuple": [...]}``, dictionaries as
    ``{"dict": {...}}`` (string keys), dataclasses as ``{"dataclass": "module:Name", "fields": {...}}``.
    Floats are refused: nothing inexact goes into a checkpoint.

    >>> encode({"a": (Fraction(-1, 2),)})
    {'dict': {'a': {'tuple': [{'fraction': '-1/2'}]}}}
    >>> encode(0.5)
    Traceback (most recent call last):
    TypeError: cannot store a float in a checkpoint exactly: 0.5
    """
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, Fraction):
        return {"fraction": f"{value.numerator}/{value.denominator}"}
    if isinstance(value, tuple):
        return {"tuple": [encode(v) for v in value]}
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, dict):
        if not all(isinstance(k, str) for k in value):
            raise TypeError("cannot store a dictionary with keys that are not strings in a checkpoint")
        return {"dict": {k: encode(v) for k, v in value.items()}}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        kind = type(value)
        fields = {f.name: encode(getattr(value, f.name)) for f in dataclasses.fields(value)}
        return {"dataclass": f"{kind.__module__}:{kind.__qualname__}", "fields": fields}
    raise TypeError(f"cannot store a {type(value).__name__} in a checkpoint exactly: {value!r}")


def decode(data: Any) -> Any:
    """The object that :func:`encode` encoded (dataclasses only from verify's own modules).

    >>> decode({"dict": {"b": [1, {"fraction": "3/4"}]}})
    {'b': [1, Fraction(3, 4)]}
    """
    if isinstance(data, list):
        return [decode(v) for v in data]
    if not isinstance(data, dict):
        return data
    if "fraction" in data:
        return Fraction(data["fraction"])
    if "tuple" in data:
        return tuple(decode(v) for v in data["tuple"])
    if "dict" in data:
        return {k: decode(v) for k, v in data["dict"].items()}
    if "dataclass" in data:
        import importlib

        module, name = data["dataclass"].split(":")
        if module != "verify" and not module.startswith("verify."):
            raise InvalidInput(f"a checkpoint names a class outside verify: {data['dataclass']}")
        kind = getattr(importlib.import_module(module), name)
        return kind(**{k: decode(v) for k, v in data["fields"].items()})
    raise InvalidInput(f"unreadable value in a checkpoint: {json.dumps(data)[:80]}")


# -- the checkpoint file -------------------------------------------------------------------------------


def source_fingerprint() -> str:
    """sha256 of verify's own ``.py`` files (paths and contents) and of Hypothesis' version: results
    checkpointed by other code are not reused.

    >>> len(source_fingerprint())
    64
    """
    import hypothesis

    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    digest.update(f"hypothesis {hypothesis.__version__}".encode())
    return digest.hexdigest()


class Checkpoint:
    """A checkpoint file for a run with ``options`` (those that change results, JSON data).

    :meth:`open` reads the tasks finished earlier (a torn last line, from a run stopped while writing,
    is dropped) or starts the file with its header; a header of another format, other source or other
    options is refused (:class:`verify.errors.InvalidInput`). :meth:`add` appends one finished task,
    flushed and synced to disk.

    >>> import tempfile
    >>> path = tempfile.mkdtemp() + "/run.jsonl"
    >>> with Checkpoint(path, {"profile": "dev"}) as cp:
    ...     cp.open(), cp.add("row-1", Fraction(1, 3))
    ({}, None)
    >>> with Checkpoint(path, {"profile": "dev"}) as cp:
    ...     cp.open()
    {'row-1': Fraction(1, 3)}
    >>> with Checkpoint(path, {"profile": "ci"}) as cp:
    ...     cp.open()  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    verify.errors.InvalidInput: the checkpoint ... was written with other options (profile: 'dev', not 'ci')...
    """

    def __init__(self, path: str, options: dict[str, Any]):
        self.path = path
        self.header: dict[str, Any] = {
            "checkpoint": "verify",
            "format": CHECKPOINT_FORMAT,
            "fingerprint": source_fingerprint(),
            "options": options,
        }
        self.file: Any = None

    def __enter__(self) -> Checkpoint:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Close the file."""
        if self.file is not None:
            self.file.close()
            self.file = None

    def open(self) -> dict[str, Any]:
        """The results of the tasks finished earlier, by id; the file is then ready for :meth:`add`."""
        finished: dict[str, Any] = {}
        keep = 0  # bytes of whole, valid lines
        if os.path.exists(self.path):
            with open(self.path, "rb") as f:
                data = f.read()
            lines = data.split(b"\n")[:-1]  # whole lines; what follows the last newline is torn
            for i, raw in enumerate(lines):
                try:
                    entry = json.loads(raw)
                except ValueError:
                    if i == len(lines) - 1:
                        break  # a damaged last line: dropped as torn
                    raise InvalidInput(f"the checkpoint {self.path} is damaged at line {i + 1}") from None
                if i == 0:
                    self._check_header(entry)
                else:
                    if not isinstance(entry, dict) or "id" not in entry or "result" not in entry:
                        raise InvalidInput(f"the checkpoint {self.path} is damaged at line {i + 1}")
                    finished[entry["id"]] = decode(entry["result"])
                keep += len(raw) + 1
        self.file = open(self.path, "r+b" if os.path.exists(self.path) else "wb")  # noqa: SIM115 - closed by close()
        self.file.truncate(keep)  # drop a torn last line
        self.file.seek(keep)
        if keep == 0:
            self._write(self.header)
        return finished

    def _check_header(self, entry: Any) -> None:
        if not isinstance(entry, dict) or entry.get("checkpoint") != "verify":
            raise InvalidInput(f"{self.path} is not a checkpoint of verify")
        if entry.get("format") != CHECKPOINT_FORMAT:
            raise InvalidInput(f"the checkpoint {self.path} has format {entry.get('format')}, not {CHECKPOINT_FORMAT}")
        if entry.get("fingerprint") != self.header["fingerprint"]:
            raise InvalidInput(
                f"the checkpoint {self.path} was written by another version of verify or Hypothesis: "
                "remove it or use another file"
            )
        theirs = entry.get("options")
        ours: dict[str, Any] = self.header["options"]
        if theirs != ours:
            theirs = theirs if isinstance(theirs, dict) else {}
            diff = sorted(k for k in set(theirs) | set(ours) if theirs.get(k) != ours.get(k))
            shown = ", ".join(f"{k}: {theirs.get(k)!r}, not {ours.get(k)!r}" for k in diff)
            raise InvalidInput(
                f"the checkpoint {self.path} was written with other options ({shown}): "
                "run with those options or use another file"
            )

    def add(self, task_id: str, result: Any) -> None:
        """Append one finished task, flushed and synced."""
        self._write({"id": task_id, "result": encode(result)})

    def _write(self, entry: dict[str, Any]) -> None:
        self.file.write((json.dumps(entry, sort_keys=True, separators=(",", ":")) + "\n").encode())
        self.file.flush()
        os.fsync(self.file.fileno())


__all__ = [
    "Checkpoint",
    "Task",
    "TaskFailure",
    "TaskRun",
    "TaskRunner",
    "TasksFailed",
    "decode",
    "encode",
    "run_tasks",
    "source_fingerprint",
]
