"""docs/architecture.md stays true: every sub-package of verify/ is named there, in the order of the layers
that tests/package/test_layers.py enforces, nothing that does not exist is named, and each subcommand of the command
line has its row, naming packages and modules that exist."""

from __future__ import annotations

import re

from tests.package.test_layers import LAYERS, PACKAGE

ROOT = PACKAGE.parent
DOC = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")


def section(title: str) -> str:
    start = DOC.index(f"## {title}")
    end = DOC.find("\n## ", start + 1)
    return DOC[start : end if end != -1 else len(DOC)]


def table_rows(text: str) -> list[list[str]]:
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in text.splitlines() if line.startswith("| ")]
    return rows[1:]  # the header row


def test_the_layers_are_named_in_their_order() -> None:
    named = [re.fullmatch(r"`verify/(\w+)(?:/|\.py)`", row[0]) for row in table_rows(section("The layers"))]
    assert all(named), [row[0] for row in table_rows(section("The layers"))]
    assert tuple(m.group(1) for m in named if m) == LAYERS


def test_every_sub_package_is_named_in_its_layer_row() -> None:
    rows = {row[0]: row[1] for row in table_rows(section("The layers"))}
    missing = []
    for init in sorted(PACKAGE.rglob("__init__.py")):
        parts = init.parent.relative_to(PACKAGE).parts
        if not parts:
            continue
        row = rows.get(f"`verify/{parts[0]}/`")
        if row is None or (len(parts) > 1 and f"`{'/'.join(parts[1:])}/`" not in row):
            missing.append("/".join(parts))
    assert not missing, f"sub-packages docs/architecture.md does not name: {missing}"


def test_every_path_named_exists() -> None:
    named = set(re.findall(r"`(verify/[\w/]+(?:\.py)?)`", DOC))
    assert named, "the guard: the page names paths"
    assert not [p for p in named if not (ROOT / p).exists()]


def test_every_subcommand_has_its_row() -> None:
    from verify.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    commands = set(sub.choices)  # type: ignore[arg-type]
    rows = table_rows(section("Where each subcommand lives"))
    assert {re.sub(r"^`verify (\S+)`$", r"\1", row[0]) for row in rows} == commands
    for row in rows:
        assert re.search(r"`verify/\w+", row[1]) and re.fullmatch(r"`verify/cli/\w+\.py`", row[2]), row


def test_the_tests_mirror_the_package() -> None:
    """A feature's tests are in the folder named after its sub-package (``tests/maps/`` for ``verify/maps/``);
    ``tests/package/`` holds those of the package as a whole, and the root only the shared helpers."""
    tests = ROOT / "tests"
    folders = {p.parent.name for p in tests.glob("*/__init__.py")}
    assert folders and folders <= set(LAYERS) | {"package"}, folders - set(LAYERS)
    assert not sorted(p.name for p in tests.glob("test_*.py")), "a test file outside its feature's folder"
