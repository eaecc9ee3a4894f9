"""The package's structure, checked from its source: the folders are the layers and imports flow
one way (numerics → physics → detection → sensors → scene → design → report → cli, with the
generic optimize layer beside them), no import cycle (function-level imports included), no
plug-in loading by name, and small modules and functions."""

import ast
from pathlib import Path

import pytest

from helpers.paths import REPO

PACKAGE = REPO / "diffsense"

#: each area and the areas it may import (besides itself); anything not listed is forbidden
ALLOWED = {
    "errors": set(),
    "numerics": {"errors"},
    "physics": {"numerics", "errors"},
    "detection": {"numerics", "errors"},
    "optimize": {"numerics", "errors"},
    "sensors": {"physics", "detection", "numerics", "errors"},
    "scene": {"sensors", "numerics", "errors"},
    "design": {"scene", "sensors", "optimize", "detection", "physics", "numerics", "errors"},
    "report": {"design", "scene", "sensors", "optimize", "detection", "physics", "numerics", "errors"},
    "explore": {"report", "design", "scene", "sensors", "optimize", "detection", "physics", "numerics", "errors"},
    "__main__": {"cli"},
    "cli": {"explore", "report", "design", "scene", "sensors", "optimize", "detection", "physics", "numerics", "errors"},
}
MAX_MODULE_LINES = 700
MAX_FUNCTION_LINES = 150


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _area(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def _imports(module: str, path: Path):
    """Every diffsense module ``module`` imports, at any depth of its code (``from pkg import
    sub`` counts as an import of ``pkg.sub`` when that is a module)."""
    tree = ast.parse(path.read_text())
    is_pkg = path.name == "__init__.py"
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                pkg = module.split(".") if is_pkg else module.split(".")[:-1]
                pkg = pkg[: len(pkg) - (node.level - 1)]
                base = ".".join(pkg + ([base] if base else []))
            for a in node.names:
                full = f"{base}.{a.name}"
                out.add(full if full in MODULES else base)
    return {m for m in out if m == "diffsense" or m.startswith("diffsense.")}


GRAPH = {m: _imports(m, p) & set(MODULES) for m, p in MODULES.items()}


def test_imports_flow_one_way_between_layers():
    bad = []
    for module, targets in GRAPH.items():
        area = _area(module)
        if area == "":
            continue  # the package's public face may name any layer
        for target in targets:
            t_area = _area(target)
            if t_area != area and t_area not in ALLOWED[area]:
                bad.append(f"{module} -> {target}")
    assert not bad, "imports against the layer order:\n" + "\n".join(sorted(bad))


def test_every_module_belongs_to_a_known_layer():
    unknown = sorted({_area(m) for m in MODULES} - set(ALLOWED) - {""})
    assert not unknown


def test_no_import_cycles_counting_function_level_imports():
    index, low, stack, on_stack, cycles = {}, {}, [], set(), []

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in GRAPH[v]:
                cycles.append(sorted(comp))

    for v in GRAPH:
        if v not in index:
            visit(v)
    assert not cycles, f"import cycles: {cycles}"


def test_no_loading_by_name():
    offenders = [str(p.relative_to(REPO)) for p in MODULES.values()
                 if "importlib" in p.read_text() or "__import__" in p.read_text()]
    assert not offenders


@pytest.mark.parametrize("module", sorted(MODULES))
def test_modules_and_functions_are_small(module):
    path = MODULES[module]
    text = path.read_text()
    assert text.count("\n") <= MAX_MODULE_LINES, f"{module}: {text.count(chr(10))} lines"
    long = [f"{n.name} ({n.end_lineno - n.lineno + 1} lines)" for n in ast.walk(ast.parse(text))
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))
            and n.end_lineno - n.lineno + 1 > MAX_FUNCTION_LINES]
    assert not long, f"{module}: {long}"
