"""The main job and the committed reports: ``verify all`` writes what is committed.

``verify all --out TMP`` runs once here (the property verdicts of the test profile are
computed once per session and shared with tests/properties/test_properties.py, the corner's maps over its CORs with
tests/maps/test_algebraic.py); every page it writes
must equal the committed one, byte for byte, or the committed ``reports/`` is stale.
"""

from __future__ import annotations

import contextlib
import io
import shutil
import subprocess
from pathlib import Path

import pytest

import verify.paper.corner_map
import verify.properties.verdicts
from tests.conftest import PROPERTY_PROFILE
from tests.helpers import shared
from verify.cli import main
from verify.report.pages import PAGES

ROOT = Path(__file__).resolve().parents[2]
REPORTS = ROOT / "reports"


def committed(name: str) -> bytes:
    """The committed bytes of reports/NAME: from git's HEAD in a checkout, else the file on disk.

    In a checkout, ``verify all`` (the README's first command) may already have rewritten
    reports/ before the tests run: comparing with the working tree would then prove nothing.
    """
    if shutil.which("git") is not None:
        cmd = ["git", "-C", str(ROOT), "show", f"HEAD:reports/{name}"]
        out = subprocess.run(cmd, capture_output=True, check=False)
        if out.returncode == 0:
            return out.stdout
    return (REPORTS / name).read_bytes()


@pytest.fixture(scope="module")
def written(tmp_path_factory, request):
    """``verify all --out TMP`` once per command, for both test processes (tests.helpers.shared: the folder, the
    exit code and what it printed); the verdicts and the corner's maps it computes are the tests' own
    (``property_verdicts``, ``paper_corner_maps``), asked for only by the process that runs it."""

    def compute():
        out = tmp_path_factory.mktemp("reports")
        verdicts, maps = request.getfixturevalue("property_verdicts"), request.getfixturevalue("paper_corner_maps")
        text = io.StringIO()
        with pytest.MonkeyPatch.context() as patch, contextlib.redirect_stdout(text):
            patch.setattr(verify.properties.verdicts, "verdicts", lambda profile, **kw: verdicts)
            patch.setattr(verify.paper.corner_map, "corner_maps", lambda: maps)
            code = main(["all", "--out", str(out), "--workers", "2"])
        return out, code, text.getvalue()

    return shared(tmp_path_factory, "verify-all", compute)


@pytest.mark.slow(seconds=70)
def test_verify_all_succeeds_and_summarises(written) -> None:
    _, code, text = written
    assert code == 0
    for line in ("Table 1: 17 rows recomputed", "Cradle: threshold 3 -> 4 impulses at eps = 3 - 2*sqrt(2)",
                 "Properties (", "Oracle self-check: passed", "reports written to"):  # fmt: skip
        assert line in text, line


@pytest.mark.slow(seconds=70)
def test_committed_reports_are_up_to_date(written) -> None:
    out = written[0]
    names = sorted(p.name for p in out.iterdir())
    assert not [name for name in names if name.endswith(".tmp")]
    assert names == sorted(p.name for p in REPORTS.iterdir() if p.name != ".gitkeep")
    for name in names:
        if name in ("properties.md", "properties.json") and PROPERTY_PROFILE != "ci":
            continue  # the committed page is the ci profile's
        assert (out / name).read_bytes() == committed(name), f"reports/{name} is stale (regenerate and commit it)"


def test_every_page_is_in_the_index() -> None:
    index = (REPORTS / "README.md").read_text()
    assert all(f"]({name})" in index for name, _ in PAGES)
    for name, _ in PAGES:
        for line in (REPORTS / name).read_text().splitlines():
            if line.startswith("!["):
                assert (REPORTS / line.split("](")[1].rstrip(")")).exists(), line


def test_property_rows_started_early_give_their_verdicts_or_their_error(monkeypatch) -> None:
    """The rows run in a thread of their own while the pages are written (Findings.start_verdicts), when the
    runner's processes are started (one_pool, or a cluster): the page reads what they found, and an error of
    theirs is raised where the verdicts are asked for. Rows that would run in this process are not started."""
    from verify.report.findings import Findings
    from verify.runner.tasks import TaskFailure, TaskRunner, TasksFailed

    calls = []
    monkeypatch.setattr(verify.properties.verdicts, "verdicts", lambda profile, **kw: calls.append(kw) or ["v"])
    here = Findings("dev", TaskRunner(workers=2))
    here.start_verdicts()
    assert here._rows is None and here.verdicts == ["v"]

    def failing(profile, **kw):
        raise TasksFailed([TaskFailure("row", "a row", "ValueError: no")])

    with TaskRunner(workers=2) as runner, runner.one_pool():
        found = Findings("dev", runner)
        found.start_verdicts()
        found.start_verdicts()  # started once
        assert found._rows is not None and found.verdicts == ["v"] and len(calls) == 2
        monkeypatch.setattr(verify.properties.verdicts, "verdicts", failing)
        found = Findings("dev", runner)
        found.start_verdicts()
        with pytest.raises(TasksFailed):
            found.verdicts  # noqa: B018
        given = Findings("dev", runner, verdicts=["given"])
        given.start_verdicts()  # nothing to start
        assert given._rows is None and given.verdicts == ["given"]
