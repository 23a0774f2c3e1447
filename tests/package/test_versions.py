"""What a CI can pin (issue 60, item 3): one version, the same in the metadata, ``verify --version`` and
CHANGELOG.md; the schema and dataset versions in every JSON document the oracle writes, checked when read;
an sdist that carries its license and no tests."""

from __future__ import annotations

import importlib.metadata
import json
import re
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest

import verify
from verify.records.versions import GOLDEN_DATASET, SCHEMA_VERSION, generated_dataset

ROOT = Path(__file__).resolve().parents[2]


def run(*argv: str, cwd: Path = ROOT, stdin: str | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "verify", *argv], cwd=cwd, input=stdin, capture_output=True,
                          text=True, check=False, timeout=600)  # fmt: skip


def test_one_version_in_the_metadata_the_command_line_and_the_changelog() -> None:
    metadata = importlib.metadata.version("verify-impacts")
    assert metadata == verify.__version__
    assert run("--version").stdout == f"verify {metadata}\n"
    releases = re.findall(r"^## (\d+\.\d+\.\d+)", (ROOT / "CHANGELOG.md").read_text(encoding="utf-8"), re.M)
    assert releases[0] == metadata, "the newest CHANGELOG.md entry is not the package's version"
    assert len(set(releases)) == len(releases)


def test_every_document_the_oracle_writes_carries_its_versions(tmp_path: Path) -> None:
    golden = ROOT / "golden"
    for name in ("cases.json", "results.json", "results-simultaneous.json"):
        data = json.loads((golden / name).read_text(encoding="utf-8"))
        assert (data["schema_version"], data["dataset"]) == (SCHEMA_VERSION, GOLDEN_DATASET), name
    generated = json.loads(run("oracle", "generate", "--level", "1", "--seed", "3").stdout)
    assert (generated["schema_version"], generated["dataset"]) == (SCHEMA_VERSION, generated_dataset(1, 3))
    cases, results = str(golden / "cases.json"), str(golden / "results.json")
    for argv in (("check", cases, results, "--json", "--quiet"), ("explain", cases, results, "--json", "--quiet"),
                 ("table", cases, f"golden={results}", "--json")):  # fmt: skip
        done = run("oracle", *argv)
        document = json.loads(done.stdout)
        assert (document["schema_version"], document["dataset"]) == (SCHEMA_VERSION, GOLDEN_DATASET), argv


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        ({"schema_version": SCHEMA_VERSION + 1}, f"schema_version {SCHEMA_VERSION + 1} is newer than this verify"),
        ({"schema_version": SCHEMA_VERSION + 1, "provenance": "x"}, "is newer than this verify"),  # not "unknown field"
        ({"schema_version": "2"}, "schema_version"),
        ({"dataset": "golden-1"}, "made for dataset golden-1, but the case file is " + GOLDEN_DATASET),
    ],
)
def test_versions_are_checked_when_read(tmp_path: Path, edit: dict, message: str) -> None:
    data = json.loads((ROOT / "golden" / "results.json").read_text(encoding="utf-8"))
    path = tmp_path / "results.json"
    path.write_text(json.dumps({**data, **edit}), encoding="utf-8")
    done = run("oracle", "check", str(ROOT / "golden" / "cases.json"), str(path), "--quiet")
    assert done.returncode == 2 and message in done.stderr and done.stderr.count("\n") == 1, done.stderr
    cases = json.loads((ROOT / "golden" / "cases.json").read_text(encoding="utf-8"))
    path.write_text(json.dumps({**cases, **edit}), encoding="utf-8")
    if "schema_version" in edit:  # a case file is refused the same way
        done = run("oracle", "check", str(path), str(ROOT / "golden" / "results.json"), "--quiet")
        assert done.returncode == 2 and "schema_version" in done.stderr, done.stderr


@pytest.mark.slow(seconds=5)
def test_the_sdist_carries_the_package_its_license_and_no_tests(tmp_path: Path) -> None:
    """Built from a copy of the tree (the build's own files stay out of the repository)."""
    tree = tmp_path / "tree"
    skip = shutil.ignore_patterns(
        ".git", ".ci-venv", ".venv", "*.egg-info", "__pycache__", "build", "reports", ".*_cache"
    )
    shutil.copytree(ROOT, tree, ignore=skip)
    code = f"from setuptools import build_meta; print(build_meta.build_sdist({str(tmp_path)!r}))"
    done = subprocess.run([sys.executable, "-c", code], cwd=tree, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    name = done.stdout.strip().splitlines()[-1]
    with tarfile.open(tmp_path / name) as sdist:
        members = {m.split("/", 1)[1] for m in sdist.getnames() if "/" in m}
        info = sdist.extractfile(f"{name.removesuffix('.tar.gz')}/PKG-INFO")
        assert info is not None
        pkg_info = info.read().decode()
    assert {"LICENSE", "CHANGELOG.md", "README.md", "pyproject.toml", "verify/py.typed"} <= members
    assert not [m for m in members if m.startswith(("tests/", "golden/", "docs/", "reports/"))]
    assert f"Version: {verify.__version__}" in pkg_info and "License-Expression: MIT" in pkg_info
    assert "Classifier: Typing :: Typed" in pkg_info and "License-File: LICENSE" in pkg_info
