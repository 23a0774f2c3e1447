"""The committed reports are what the program writes now (a stale page fails this test)."""

from __future__ import annotations

from pathlib import Path

from tests.conftest import PROPERTY_PROFILE
from verify.report import PAGES, write_reports

REPORTS = Path(__file__).resolve().parent.parent / "reports"


def test_committed_reports_are_up_to_date(tmp_path: Path, property_verdicts) -> None:
    write_reports(tmp_path, profile=PROPERTY_PROFILE, workers=2, verdicts=property_verdicts)
    written = sorted(p.name for p in tmp_path.iterdir())
    assert not [name for name in written if name.endswith(".tmp")]
    assert written == sorted(p.name for p in REPORTS.iterdir() if p.name != ".gitkeep")
    for name in written:
        if name == "properties.md" and PROPERTY_PROFILE != "ci":
            continue  # the committed page is the ci profile's
        assert (tmp_path / name).read_bytes() == (REPORTS / name).read_bytes(), f"reports/{name} is stale"


def test_every_page_is_in_the_index() -> None:
    index = (REPORTS / "README.md").read_text()
    assert all(f"]({name})" in index for name, _ in PAGES)
    for name, _ in PAGES:
        text = (REPORTS / name).read_text()
        for line in text.splitlines():
            if line.startswith("!["):
                assert (REPORTS / line.split("](")[1].rstrip(")")).exists(), line
