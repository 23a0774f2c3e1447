"""``--quiet`` on a Dask cluster: only the result and errors reach stderr, not Dask's log lines.

A user saw ``distributed.client - WARNING - Couldn't gather 1 keys, rescheduling`` under ``--quiet``
(issue 34, item 19). Here a real ``--scheduler`` run of ``verify sweep`` logs that warning through
``distributed.client`` while the client is open; it runs in a fresh interpreter, where Dask sets up its
logging to stderr as it does for a user. (``--local-cluster`` silences Dask's stderr handler itself
while its cluster runs; a scheduler of the user's own does not.)
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]
WARNING = "Couldn't gather 1 keys, rescheduling"
ERROR = "a Dask error stays visible"

#: verify sweep, whose batch logs a warning and an error through distributed.client, then runs as usual
SCRIPT = f"""
import logging, sys
import verify.paper.sweep as sweep
real = sweep.random_sweep
def logging_sweep(*args, **kwargs):
    logging.getLogger("distributed.client").warning({WARNING!r})
    logging.getLogger("distributed.client").error({ERROR!r})
    return real(*args, **kwargs)
sweep.random_sweep = logging_sweep
from distributed import LocalCluster
from verify.cli import main
with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address="127.0.0.1:0",
                  silence_logs=False) as cluster:
    code = main([*sys.argv[1:], "--scheduler", cluster.scheduler_address])
levels = {{n: logging.getLogger(n).level for n in ("distributed", "distributed.client")}}
print("levels after", levels, file=sys.stderr)
sys.exit(code)
"""
SWEEP = ["sweep", "--cases", "3"]


def run(argv: list[str], scratch: Path) -> subprocess.CompletedProcess[str]:
    """The script with ``argv``; Dask's scratch space (its worker's folder) under ``scratch``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), TERM="dumb", TMPDIR=str(scratch))
    return subprocess.run(
        [sys.executable, "-c", SCRIPT, *argv],
        check=False,
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


def levels_after(stderr: str) -> str:
    return next(line for line in stderr.splitlines() if line.startswith("levels after"))


@pytest.fixture(scope="module")
def loud(tmp_path_factory: pytest.TempPathFactory) -> subprocess.CompletedProcess[str]:
    return run(SWEEP, tmp_path_factory.mktemp("loud"))


def test_without_quiet_dask_warnings_reach_stderr(loud: subprocess.CompletedProcess[str]) -> None:
    assert loud.returncode == 0, loud.stderr
    assert f"distributed.client - WARNING - {WARNING}" in loud.stderr
    assert ERROR in loud.stderr


def test_quiet_silences_dask_warnings_but_not_errors(loud: subprocess.CompletedProcess[str], tmp_path: Path) -> None:
    quiet = run([*SWEEP, "--quiet"], tmp_path)
    assert quiet.returncode == 0, quiet.stderr
    assert WARNING not in quiet.stderr
    assert ERROR in quiet.stderr  # --quiet: the result and errors
    assert quiet.stdout.splitlines()[1:] == loud.stdout.splitlines()[1:]  # the same result (line 1 has the time)
    # the levels are Dask's own again once the run is over, as after a run without --quiet
    assert levels_after(quiet.stderr) == levels_after(loud.stderr)
    assert f"'distributed.client': {logging.WARNING}" in levels_after(quiet.stderr)
