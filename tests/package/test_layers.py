"""The package's shape: layers that import in one direction, small functions, no private names
across modules, no import cycle, no sub-package holding more than a fifth of the package.

The layers, lowest first (a module may import its own layer and the layers below it), are :data:`LAYERS`;
``docs/architecture.md`` says what each holds (``tests/package/test_architecture.py`` keeps it in step).
``verify/__init__.py`` (the public API) and ``verify/__main__.py`` stand above them all.
Everything here reads the source with :mod:`ast`; nothing of the package is run.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "verify"
LAYERS = (
    "errors", "bounds", "numbers", "dynamics", "proofs", "laws", "models", "records", "views", "runner", "maps",
    "properties", "paper", "oracle", "engines", "bench", "report", "cli",
)  # fmt: skip
TOP = ("__init__", "__main__")
MAX_FUNCTION_LINES = 80


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}
TREES = {name: ast.parse(path.read_text(encoding="utf-8")) for name, path in MODULES.items()}


def layer(module: str) -> int:
    """The rank of a module's layer (``verify`` and ``verify.__main__`` rank above every layer)."""
    parts = module.split(".")
    if len(parts) == 1 or parts[1] in TOP:
        return len(LAYERS)
    return LAYERS.index(parts[1])


def resolve(module: str, node: ast.ImportFrom) -> str:
    """The absolute name an ``from ... import`` refers to."""
    if not node.level:
        return node.module or ""
    base = module.split(".")
    if MODULES[module].name != "__init__.py":
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def imports(module: str, *, top_level_only: bool = False) -> Iterator[tuple[str, int, list[str]]]:
    """(imported verify module, line, names taken from it) for every import of ``module``."""
    tree = TREES[module]
    nodes = tree.body if top_level_only else ast.walk(tree)
    for node in nodes:
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "verify":
                    yield alias.name, node.lineno, []
        elif isinstance(node, ast.ImportFrom):
            target = resolve(module, node)
            if target.split(".")[0] != "verify":
                continue
            names = [a.name for a in node.names]
            submodules = [n for n in names if f"{target}.{n}" in MODULES]
            for n in submodules:
                yield f"{target}.{n}", node.lineno, []
            if len(submodules) < len(names):
                yield target, node.lineno, [n for n in names if n not in submodules]


def test_the_package_has_layers_as_subpackages() -> None:
    subpackages = {p.parent.name for p in PACKAGE.glob("*/__init__.py")}
    modules = {p.stem for p in PACKAGE.glob("*.py")}
    assert set(LAYERS) <= subpackages | modules
    top = [p.name for p in PACKAGE.glob("*.py")]
    assert len(top) <= 8, top


#: the largest share of the package's lines that one top-level sub-package may hold
MAX_SHARE = 0.2


def test_no_sub_package_holds_more_than_a_fifth_of_the_lines() -> None:
    lines = {name: len(path.read_text(encoding="utf-8").splitlines()) for name, path in MODULES.items()}
    total = sum(lines.values())
    shares = {}
    for name, n in lines.items():
        parts = name.split(".")
        if len(parts) > 2 or (MODULES[name].name == "__init__.py" and len(parts) == 2):
            shares[parts[1]] = shares.get(parts[1], 0) + n
    assert shares, "the guard: there are sub-packages"
    big = {k: f"{v / total:.1%}" for k, v in shares.items() if v > MAX_SHARE * total}
    assert not big, f"sub-packages over {MAX_SHARE:.0%} of {total} lines: {big}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_go_down_the_layers(module: str) -> None:
    wrong = [
        f"line {line}: {module} ({LAYERS[layer(module)] if layer(module) < len(LAYERS) else 'top'}) imports "
        f"{target} ({LAYERS[layer(target)]})"
        for target, line, _ in imports(module)
        if target != "verify" and layer(target) > layer(module)
    ]
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_private_name_crosses_a_module(module: str) -> None:
    """No ``from x import _y``, and no ``x._y`` on a module ``x`` imported by name."""
    wrong = [
        f"line {line}: imports {n} from {target}"
        for target, line, names in imports(module)
        for n in names
        if n.startswith("_") and not n.startswith("__")
    ]
    aliases = {
        (a.asname or a.name)
        for node in ast.walk(TREES[module])
        if isinstance(node, ast.ImportFrom) and (resolve(module, node).split(".")[0] == "verify")
        for a in node.names
        if f"{resolve(module, node)}.{a.name}" in MODULES
    }
    for node in ast.walk(TREES[module]):
        if (
            isinstance(node, ast.Attribute)
            and node.attr.startswith("_")
            and not node.attr.startswith("__")
            and isinstance(node.value, ast.Name)
            and node.value.id in aliases
        ):
            wrong.append(f"line {node.lineno}: reads {node.value.id}.{node.attr}")
    assert not wrong, "\n".join(wrong)


def test_no_import_cycle() -> None:
    """The graph of imports between verify's modules (inside functions too) has no cycle."""
    graph = {m: {t for t, _, _ in imports(m) if t in MODULES and t != m} for m in MODULES}
    state: dict[str, int] = {}

    def visit(m: str, path: list[str]) -> None:
        state[m] = 1
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                raise AssertionError("import cycle: " + " -> ".join([*path[path.index(t) :], t]))
            if t not in state:
                visit(t, [*path, t])
        state[m] = 2

    for m in sorted(MODULES):
        if m not in state:
            visit(m, [m])


def test_functions_are_short() -> None:
    long = [
        f"{module}.{node.name}: {node.end_lineno - node.lineno + 1} lines"
        for module, tree in TREES.items()
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and node.end_lineno is not None
        and node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES
    ]
    assert not long, "\n".join(long)


def test_the_checks_see_a_violation() -> None:
    """The walk itself works: an oracle module imports a law, found and allowed; the reverse would be
    refused."""
    found = {t for m in MODULES if m.startswith("verify.oracle") for t, _, _ in imports(m)}
    assert any(t.startswith("verify.laws") for t in found)
    assert layer("verify.cli") > layer("verify.oracle.reference") > layer("verify.laws.rule") > layer("verify.errors")


def probed_backends(tree: ast.AST) -> list[int]:
    """Lines that call getattr or hasattr on a backend: ``K``, ``Q`` or anything named ``...backend``."""
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("getattr", "hasattr"):
            target = node.args[0] if node.args else None
            name = (
                target.id if isinstance(target, ast.Name) else target.attr if isinstance(target, ast.Attribute) else ""
            )
            if name in ("K", "Q") or name.endswith("backend"):
                lines.append(node.lineno)
    return lines


def test_no_backend_is_probed_for_an_attribute() -> None:
    """The backend contract (``verify.numbers.backends.base.Backend``, a Protocol) declares every capability
    and method the code uses: a caller reads ``K.rationals``, never ``getattr(K, "rationals", False)``."""
    assert probed_backends(ast.parse("getattr(K, 'rationals', False)\nhasattr(system.backend, 'bounds')")) == [1, 2]
    wrong = [f"{module}: line {line}" for module, tree in TREES.items() for line in probed_backends(tree)]
    assert not wrong, "\n".join(wrong)
