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


#: a measured time or speed-up in prose: it goes stale with the next change or machine (issue 61, item 6)
MEASURED = re.compile(
    r"\b\d+(?:\.\d+)?\s?(?:times|x) (?:faster|slower|longer|shorter)\b"
    r"|\b(?:takes?|took|taking|lasts?|costs?|in|about|under)(?: about)? \d+(?:\.\d+)?\s?"
    r"(?:s|ms|seconds?|minutes?|min)\b"
    r"|\bon \d+ cores\b"
)


def prose(source: str) -> list[tuple[int, str]]:
    """(line, text) of every docstring line and comment of a module, doctest examples and outputs left out."""
    import ast
    import doctest
    import io
    import tokenize

    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            doc = ast.get_docstring(node, clean=False)
            if doc and node.body:
                parts = doctest.DocTestParser().parse(doc)
                text = "".join(p for p in parts if isinstance(p, str))
                out += [(node.body[0].lineno, line) for line in text.splitlines()]
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            out.append((tok.start[0], tok.string))
    return out


def test_no_measured_time_in_the_package_prose() -> None:
    """Docstrings and comments say what code does, not how long it took once: figures come from commands
    (``verify bench``, the tests' ``--durations``), which measure them again."""
    assert MEASURED.search("a cold cache costs 50 s") and MEASURED.search("ten runs took 3.5 s")
    assert MEASURED.search("it is 21 times longer per impulse") and not MEASURED.search("a time step of 0.01 s")
    assert prose('"""Took 3 s.\n\n>>> f()\ndone in 5 s\n"""\nx = 1  # a comment\n') == [
        (1, "Took 3 s."),
        (1, ""),
        (6, "# a comment"),
    ]
    found = [
        f"{path.relative_to(ROOT)}:{line}: {text.strip()}"
        for path in sorted((ROOT / "verify").rglob("*.py"))
        for line, text in prose(path.read_text(encoding="utf-8"))
        if MEASURED.search(text)
    ]
    assert not found, "measured figures in the package's prose:\n" + "\n".join(found)
