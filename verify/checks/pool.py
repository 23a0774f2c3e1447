"""One worker pool: run a function on many items in processes, results in the order of the items.

>>> map_in_processes(abs, [-1, 2, -3], workers=1)
[1, 2, 3]
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

T = TypeVar("T")
R = TypeVar("R")


def map_in_processes(
    fn: Callable[[T], R],
    items: Sequence[T],
    *,
    workers: int | None = None,
    executor: Executor | None = None,
    on_done: Callable[[int, R], Any] | None = None,
) -> list[R]:
    """``[fn(item) for item in items]``, computed in parallel.

    ``executor`` is any ``concurrent.futures.Executor`` (a Dask cluster:
    ``Client(...).get_executor()``); without one, a local pool of ``workers`` processes
    (None: one per core) runs them, or none at all for one worker (``fn`` then runs here, in
    order). ``on_done(done, result)`` is called as each result arrives (``done`` counts them),
    in the order they finish. ``fn`` and the items must be picklable for processes.
    """
    workers = workers or os.cpu_count() or 1
    if executor is None and workers <= 1:
        out: list[R] = []
        for item in items:
            out.append(fn(item))
            if on_done is not None:
                on_done(len(out), out[-1])
        return out
    pool = executor or ProcessPoolExecutor(max_workers=workers)
    try:
        futures: dict[Future[R], int] = {pool.submit(fn, item): i for i, item in enumerate(items)}
        results: dict[int, R] = {}
        for future in as_completed(futures):
            results[futures[future]] = future.result()
            if on_done is not None:
                on_done(len(results), results[futures[future]])
    finally:
        if executor is None:
            pool.shutdown()
    return [results[i] for i in range(len(items))]
