"""Result records: the JSON shape of ``shared/docs/contracts.md``.

A result record carries the exit velocity (exact strings on exact backends, decimals
otherwise), its decimals with 30 significant digits, the iteration count, the impact sets
(0-based), beta per impulse (``null`` for single impacts), the stop reason and the
kinetic energies in and out. Two fields are added beyond the contract's example:
``backend`` (which backend produced it) and ``rigorous`` (whether every branch was
decided exactly or with proof); interval results also carry ``exit_velocity_enclosure``
and any run carries ``notes`` when there is something to say (precision raised).

>>> from verify.cradle import run_cradle
>>> rec = result_record(run_cradle("1/2"), "cradle")
>>> rec["exit_velocity"], rec["impact_sets"], rec["stop"]
(['325/16', '375/16', '225/4'], [[0], [1], [0]], 'exit')
"""

from __future__ import annotations

import json
from typing import Any

from verify.rule import Result

DECIMAL_DIGITS = 30


def value_string(K: Any, x: Any, digits: int = DECIMAL_DIGITS) -> str:
    """The exact string of ``x`` on exact backends, its decimal string otherwise."""
    return K.to_exact(x) if K.is_exact else K.to_decimal(x, digits)


def result_record(result: Result, case_id: str, *, digits: int = DECIMAL_DIGITS) -> dict[str, Any]:
    """The result record of the contracts for one run."""
    K = result.backend
    record: dict[str, Any] = {
        "id": case_id,
        "exit_velocity": [value_string(K, x, digits) for x in result.exit_velocity],
        "exit_velocity_decimal": [K.to_decimal(x, digits) for x in result.exit_velocity],
        "iterations": result.iterations,
        "impact_sets": [list(J) for J in result.impact_sets],
        "betas": [None if b is None else value_string(K, b, digits) for b in result.betas],
        "stop": result.stop,
        "kinetic_energy_in": value_string(K, result.kinetic_energy_in, digits),
        "kinetic_energy_out": value_string(K, result.kinetic_energy_out, digits),
        "backend": K.describe(),
        "rigorous": K.is_rigorous,
    }
    if K.enclosure(K.one) is not None:
        record["exit_velocity_enclosure"] = [list(K.enclosure(x, digits)) for x in result.exit_velocity]
    if result.notes:
        record["notes"] = list(result.notes)
    if result.certificate is not None:
        record["certificate"] = result.certificate
    return record


def dumps(obj: Any) -> str:
    """JSON text as written by :mod:`verify`: sorted keys, two-space indentation, final newline."""
    return json.dumps(obj, indent=2, sort_keys=True, ensure_ascii=False) + "\n"
