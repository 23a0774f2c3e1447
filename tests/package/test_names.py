"""A module or file that the docs, the tests or the docstrings name exists (issue 61, item 6): a stale name
fails here, not in a reader's hands. Names with a placeholder (``verify.engines.adapters.NAME``) are patterns."""

from __future__ import annotations

import dataclasses
import importlib
import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FILES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "tests").rglob("*.py")),
         *sorted((ROOT / "verify").rglob("*.py")), *sorted((ROOT / "examples").glob("*.py"))]  # fmt: skip
PATH = re.compile(r"(?<![\w/.-])(verify/[A-Za-z0-9_/]+\.(?:py|toml|json))")
MODULE = re.compile(r"(?<![\w/.-])(verify(?:\.[A-Za-z_][A-Za-z0-9_]*)+)")
PLACEHOLDER = re.compile(r"^(?:[A-Z]+|x)$")  # NAME, ENGINE, x: a pattern, not a name


def resolves(name: str) -> bool:
    """Whether ``name`` is a module of the package, or an attribute (a dataclass field too) of one."""
    if name == "verify.__main__":
        return (ROOT / "verify" / "__main__.py").exists()  # importing it runs the command line
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        module = ".".join(parts[:k])
        try:
            found = not module.endswith("__main__") and importlib.util.find_spec(module) is not None
        except ModuleNotFoundError:  # a parent is a module, not a package: ``module`` is an attribute
            found = False
        if not found:
            continue
        obj = importlib.import_module(module)
        for part in parts[k:]:
            fields = {f.name for f in dataclasses.fields(obj)} if dataclasses.is_dataclass(obj) else set()
            if part in fields:
                return True
            if not hasattr(obj, part):
                return False
            obj = getattr(obj, part)
        return True
    return False


def test_every_module_and_file_named_exists() -> None:
    stale = []
    for path in FILES:
        text = path.read_text(encoding="utf-8")
        for match in PATH.finditer(text):
            name = match.group(1)
            if (
                not any(PLACEHOLDER.match(p.removesuffix(".py")) for p in name.split("/"))
                and not (ROOT / name).exists()
            ):
                stale.append(f"{path.relative_to(ROOT)}: {name}")
        for match in MODULE.finditer(text):
            name = match.group(1)
            if not any(PLACEHOLDER.match(p) for p in name.split(".")) and not resolves(name):
                stale.append(f"{path.relative_to(ROOT)}: {name}")
    assert not stale, "names of modules or files that do not exist:\n" + "\n".join(sorted(set(stale)))
