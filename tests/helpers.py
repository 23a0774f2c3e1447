"""Shared test helpers: exactness checks in the manner of CPython's test_fractions, and long results shared by the
test processes."""

from __future__ import annotations

import fcntl
import hashlib
import os
import pickle
from collections.abc import Callable
from fractions import Fraction
from typing import Any

import pytest


class Poison(Fraction):
    """A rational whose conversion to float fails: any float path in the code raises."""

    def __float__(self) -> float:
        raise AssertionError(f"float() was called on the exact value {Fraction(self)}")

    def __round__(self, *args: Any) -> Any:
        raise AssertionError("round() was called on an exact value")


def exact_value(K: Any, x: Any) -> Fraction:
    """The exact value of a backend element, checking that it is an exact rational type."""
    assert K.is_exact
    assert not isinstance(x, float), f"a float {x!r} where an exact value was expected"
    assert type(x).__name__ in ("mpq", "fmpq", "Fraction"), f"unexpected type {type(x).__name__}"
    return K.to_number(x)


def assert_exact(expected: Any, K: Any, got: Any) -> None:
    """Value and type: ``got`` is an exact rational of the backend equal to ``expected``."""
    assert exact_value(K, got) == Fraction(expected), f"{K.to_exact(got)} != {expected}"


def assert_exact_vector(expected: list[Any], K: Any, got: Any) -> None:
    assert len(expected) == len(got)
    for e, g in zip(expected, got, strict=True):
        assert_exact(e, K, g)


def cradle_case(case_id: str, masses: list[str], restitution: list[str], velocity: list[str]) -> dict[str, Any]:
    """A cradle's case record, built by the model (geometry) and the one case-record writer."""
    from verify.models.cradle import cradle_geometry
    from verify.numbers.parse import to_number
    from verify.records.results import case_record

    g, normals = cradle_geometry([to_number(m) for m in masses])
    return case_record(case_id, g, normals, [to_number(e) for e in restitution], [to_number(x) for x in velocity])


def shared(
    tmp_path_factory: pytest.TempPathFactory,
    name: str,
    compute: Callable[[], Any],
    *,
    dump: Callable[[Any], bytes] = pickle.dumps,
    load: Callable[[bytes], Any] = pickle.loads,
) -> Any:
    """``compute()``, once per command, for every test process of pytest-xdist (``-n``, pyproject.toml): the
    first to need it computes it while holding a lock, and writes it (``dump``) into this run's temporary
    folder; the others wait for the lock and read it (``load``). A process keeps what it computed or read, by
    ``name``. Nothing outlives the command."""
    if name in _HERE:
        return _HERE[name]
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        found = _HERE[name] = compute()
        return found
    folder = tmp_path_factory.getbasetemp().parent  # this run's folder, common to its test processes
    path = folder / f"shared-{name}"
    with open(folder / f"shared-{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            if not path.exists():
                found = compute()
                part = path.with_name(path.name + ".part")
                part.write_bytes(dump(found))
                part.replace(path)
            else:
                found = load(path.read_bytes())
        finally:  # processes forked meanwhile hold the lock's file too: release it for them all
            fcntl.flock(lock, fcntl.LOCK_UN)
    _HERE[name] = found
    return found


#: what :func:`shared` computed or read in this process, by name
_HERE: dict[str, Any] = {}


def measured_once(measure: Callable[..., Any], tmp_path_factory: pytest.TempPathFactory) -> Callable[..., Any]:
    """``measure`` (e.g. ``verify.bench.throughput.bench``) made once per command for each set of options (all but
    ``progress``), for every test process (:func:`shared`): the commands that print it (text, JSON) in several tests
    print the same figures, measured once."""

    def once(**options: Any) -> Any:
        chosen = sorted((k, v) for k, v in options.items() if k != "progress")
        key = hashlib.sha256(repr((measure.__module__, measure.__name__, chosen)).encode()).hexdigest()[:16]
        return shared(tmp_path_factory, f"measured-{key}", lambda: measure(**options))

    return once


def bench_measured_once(monkeypatch: pytest.MonkeyPatch, tmp_path_factory: pytest.TempPathFactory) -> None:
    """Within the test, ``verify bench`` prints the measurement made once per command for its options
    (:func:`measured_once`): the tests that print it (the docs' text and JSON transcripts, the smoke test) share it."""
    import verify.bench.throughput

    monkeypatch.setattr(
        verify.bench.throughput, "bench", measured_once(verify.bench.throughput.bench, tmp_path_factory)
    )
