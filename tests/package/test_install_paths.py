"""The oracle's commands on a plain install (issue 60, items 1 and 2).

A plain install (no extras) has neither gmpy2 nor python-flint, and SymPy then computes with its
pure-Python rationals. ``VERIFY_RATIONALS=python`` and ``SYMPY_GROUND_TYPES=python`` force that
arithmetic on any install; the fresh process these tests start also makes the optional modules
unimportable (numpy, matplotlib, gmpy2, python-flint, dask) and hypothesis with them (a base
dependency, but the oracle's grading must not need the property suite). They run the oracle's
commands so and require the bytes of the installed arithmetic (the committed golden files, and the
hard cases as this process makes them), so that a fallback path cannot break unseen.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from verify.oracle.hardcases import generate_file_text

ROOT = Path(__file__).resolve().parents[2]
PURE = {"VERIFY_RATIONALS": "python", "SYMPY_GROUND_TYPES": "python"}
#: what a plain install lacks (or the oracle must not use): an import of any of them fails in the process
ABSENT = ("numpy", "matplotlib", "gmpy2", "flint", "dask", "hypothesis")
#: ``verify`` with the modules of ABSENT unimportable, as if they were not installed
PLAIN = f"""
import sys
for name in {ABSENT!r}:
    sys.modules[name] = None
from verify.cli import main
code = main(sys.argv[1:])
loaded = sorted(n for n in sys.modules if n.split(".")[0] in {ABSENT!r} and sys.modules[n] is not None)
assert not loaded, loaded
raise SystemExit(code)
"""


def verify(*argv: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, **PURE}
    return subprocess.run([sys.executable, "-c", PLAIN, *argv], cwd=cwd, env=env, capture_output=True,
                          text=True, check=False, timeout=600)  # fmt: skip


def test_a_module_made_absent_cannot_be_imported(tmp_path: Path) -> None:
    done = verify("cradle-map", "--figure", str(tmp_path / "x.png"), cwd=tmp_path)
    assert done.returncode == 2 and "pip install '.[figures]' in a clone" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "x.png").exists()
    done = verify("all", "--out", str(tmp_path / "reports"), cwd=tmp_path)
    assert done.returncode == 2 and done.stdout == "" and done.stderr.count("\n") == 1, done.stdout + done.stderr
    assert "[figures]" in done.stderr and not (tmp_path / "reports").exists()


def test_the_pure_python_arithmetic_is_what_the_process_uses(tmp_path: Path) -> None:
    code = "from verify.numbers.backends import rationals; print(rationals().describe())"
    out = subprocess.run(
        [sys.executable, "-c", code], env={**os.environ, **PURE}, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0 and "python" in out.stdout, out


@pytest.mark.slow(seconds=10)
def test_export_generate_check_and_table_give_the_same_bytes_on_pure_python(tmp_path: Path) -> None:
    done = verify("oracle", "export", str(tmp_path / "golden"), cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    for name in ("cases.json", "results.json", "results-simultaneous.json", "README.md"):
        assert (tmp_path / "golden" / name).read_bytes() == (ROOT / "golden" / name).read_bytes(), name
    done = verify(
        "oracle", "generate", "--level", "1", "--seed", "0", "--save", str(tmp_path / "hard.json"), cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "hard.json").read_text(encoding="utf-8") == generate_file_text(1, 0)
    golden = ROOT / "golden"
    done = verify("oracle", "check", str(golden / "cases.json"), str(golden / "results.json"), "--quiet", cwd=tmp_path)
    assert done.returncode == 0 and "OK: every case agrees" in done.stdout, done.stdout + done.stderr
    done = verify("oracle", "table", str(golden / "cases.json"), f"golden={golden / 'results.json'}", cwd=tmp_path)
    assert done.returncode == 0 and "golden" in done.stdout, done.stderr
