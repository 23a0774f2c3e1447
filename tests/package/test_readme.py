"""The README opens with the two commands, and CI runs them."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"```sh\n(.*?)```", text, re.S)
    assert block is not None and text.index(block.group(0)) < 200, "the README must open with its commands"
    return [line for line in block.group(1).splitlines() if line.strip()]


def test_readme_opens_with_exactly_two_commands():
    commands = readme_commands()
    assert len(commands) == 2
    assert commands[0].endswith("verify all")
    assert "pytest" in commands[1]


def ci_commands() -> list[str]:
    """The lines of .ci/run after it has made and entered its virtual environment."""
    lines = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(". .ci-venv/bin/activate"))
    return [line for line in lines[start + 1 :] if line.strip() and not line.startswith("#")]


def test_ci_runs_the_readme_commands_and_nothing_else():
    """CI is the README: its two commands verbatim, in order, and no other command after the venv."""
    assert ci_commands() == readme_commands()


def test_ci_sets_no_environment_variable_of_ours():
    text = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert "export" not in text and "HYPOTHESIS" not in text


def test_an_empty_hypothesis_profile_means_the_default():
    """Some CI systems export empty variables: HYPOTHESIS_PROFILE="" must still start the suite."""
    env = {**os.environ, "HYPOTHESIS_PROFILE": ""}
    collect = ["-q", "-p", "no:cacheprovider", "-n", "0", "--collect-only", "tests/package/test_readme.py"]
    cmd = [sys.executable, "-m", "pytest", *collect]
    out = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.skipif(shutil.which("ruff") is None, reason="ruff is not installed")
def test_ruff_is_clean():
    out = subprocess.run(["ruff", "check", str(ROOT)], capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.skipif(shutil.which("mypy") is None, reason="mypy is not installed")
def test_mypy_is_clean():
    """The types check: mypy strict on the whole package (configuration in pyproject.toml)."""
    out = subprocess.run(["mypy"], cwd=ROOT, capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stdout + out.stderr


#: import names whose distribution on the package registry has another name
DISTRIBUTIONS = {"flint": "python-flint", "Box2D": "box2d", "warp": "warp-lang", "ppl": "pplpy"}


def test_every_third_party_import_is_declared():
    """Each package that verify/ imports is a dependency or an optional extra of pyproject.toml."""
    import ast
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    specs = project["dependencies"] + [d for extra in project["optional-dependencies"].values() for d in extra]
    declared = {re.split(r"[<>=\[ ]", spec, maxsplit=1)[0].lower() for spec in specs}
    imported = set()
    for path in (ROOT / "verify").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                imported |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                imported.add(node.module.split(".")[0])
    third_party = {m for m in imported if m not in sys.stdlib_module_names and m != "verify"}
    missing = sorted(m for m in third_party if DISTRIBUTIONS.get(m, m).lower() not in declared)
    assert not missing, f"imported but not declared in pyproject.toml: {missing}"
