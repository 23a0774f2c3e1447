"""The rows of a run of the verdicts share their runs (verify.checks.properties.verdicts.shared_runs).

Hypothesis is derandomised, so the rows of one family and rule draw the same cases and most properties
make the same exact run of each first: within a run of the verdicts a run is made once per process. The
verdicts must be those of rows searched alone, and a direct search must share nothing.
"""

from __future__ import annotations

import pytest

import verify.checks.properties.verdicts as verdicts_module
from verify.checks.properties.catalogue import property_named
from verify.checks.properties.verdicts import run_verdicts, search, shared_runs

CHOSEN = {"properties": ["kinetic energy", "the exit velocity is outgoing", "homogeneity"], "families": ["cradle"],
          "rules": ["symmetric"], "laws": ["rule"]}  # fmt: skip


def counted(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Count the runs made (in this process) from now on."""
    made = [0]
    real = verdicts_module.run_record

    def run_record(*args, **kwargs):
        made[0] += 1
        return real(*args, **kwargs)

    monkeypatch.setattr(verdicts_module, "run_record", run_record)
    return made


def test_shared_runs_change_no_verdict_and_make_fewer_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    made = counted(monkeypatch)
    alone = [
        search(property_named(p), f, r, 25, law=law)
        for p in CHOSEN["properties"]
        for f, r, law in [("cradle", "symmetric", "rule")]
    ]
    runs_alone, made[0] = made[0], 0
    together = run_verdicts("dev", workers=1, **CHOSEN).results
    assert [v.record() for v in together] == [v.record() for v in alone]
    assert [(v.tally, v.counts) for v in together] == [(v.tally, v.counts) for v in alone]
    assert 0 < made[0] < runs_alone  # the second and third rows found the first one's runs


def test_a_direct_search_shares_nothing() -> None:
    """Outside a run of the verdicts (here, in the test process) there are no shared runs: a test that
    patches the rule and searches a row sees its own runs."""
    assert shared_runs() is None
    run_verdicts(
        "dev", workers=1, properties=["the exit velocity"], families=["corner"], rules=["ideal"], laws=["rule"]
    )
    assert shared_runs() is None
