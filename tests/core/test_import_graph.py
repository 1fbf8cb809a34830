"""The package's import graph: no cycle (imports inside functions counted), no private name imported
from another module, and a technique's Params importable without numba or GL (so reading defaults,
``illusio --help`` and the registry stay light). The graph is read from the source with ast."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "illusio"


def _modules() -> dict[str, Path]:
    out = {}
    for path in SRC.rglob("*.py"):
        parts = path.relative_to(SRC.parent).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def _imports(name: str, path: Path, modules: dict[str, Path]):
    """(line, imported module, imported names) for every import in the file, function bodies included."""
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
            if target in modules:
                for alias in node.names:
                    sub = f"{target}.{alias.name}"
                    yield node.lineno, (sub if sub in modules else target), alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in modules:
                    yield node.lineno, alias.name, None


def _graph():
    modules = _modules()
    return modules, {m: {t for _, t, _ in _imports(m, p, modules)} for m, p in modules.items()}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10000))
    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_the_import_graph_has_no_cycle():
    _, graph = _graph()
    assert _cycles(graph) == []


def test_the_cycle_finder_finds_one():
    """The check above can fail: a back edge makes a cycle it reports."""
    _, graph = _graph()
    graph["illusio.batch.job"].add("illusio.cli.main")  # what batch once did (command_table)
    assert any({"illusio.batch.job", "illusio.cli.main"} <= set(c) for c in _cycles(graph))


def test_no_private_name_is_imported_from_another_module():
    modules = _modules()
    found = [
        f"{path.relative_to(SRC.parent)}:{line}: {name} from {target}"
        for module, path in modules.items()
        for line, target, name in _imports(module, path, modules)
        if name and name.startswith("_") and not name.startswith("__")
    ]
    assert found == []


@pytest.mark.parametrize("technique", ["sis", "lines", "dof", "ibr", "radiosity", "relight"])
def test_params_import_without_numba_or_gl(technique):
    code = (
        f"import sys, illusio.{technique}.params, illusio.core.technique as t; t.technique('{technique}'); "
        "print(sorted(m for m in ('numba', 'moderngl') if m in sys.modules))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


TECHNIQUES = ("sis", "dof", "lines", "ibr", "radiosity", "relight")


def _cross_technique_imports(modules, imports) -> list[str]:
    """Imports from one technique's package of another technique's submodules (only the other
    package itself, its public API, may be imported)."""
    found = []
    for module, edges in imports.items():
        parts = module.split(".")
        if len(parts) < 2 or parts[1] not in TECHNIQUES:
            continue
        for line, target in edges:
            other = target.split(".")
            if len(other) > 2 and other[1] in TECHNIQUES and other[1] != parts[1]:
                found.append(f"{modules[module].relative_to(SRC.parent)}:{line}: {target}")
    return found


def test_no_technique_imports_another_techniques_submodules():
    """docs/architecture.md: a technique uses another only through the names its package exports."""
    modules = _modules()
    imports = {m: [(line, t) for line, t, _ in _imports(m, p, modules)] for m, p in modules.items()}
    assert _cross_technique_imports(modules, imports) == []


def test_the_cross_technique_check_finds_one():
    """The check above can fail: relight reaching into radiosity's engine module is reported."""
    modules = _modules()
    imports = {"illusio.relight.session": [(1, "illusio.radiosity.engine")]}
    assert _cross_technique_imports(modules, imports) == ["illusio/relight/session.py:1: illusio.radiosity.engine"]


@pytest.mark.parametrize("package", ["passes", "sis", "dof", "lines", "ibr", "radiosity", "relight"])
def test_every_exported_name_resolves(package):
    """Each name a package lists in ``__all__`` (most are lazy exports) imports: a renamed module left
    behind in a package's export table fails here, not in a user's first call."""
    import importlib

    module = importlib.import_module(f"illusio.{package}")
    for name in module.__all__:
        assert getattr(module, name) is not None, f"illusio.{package}.{name}"


def test_an_export_named_as_its_submodule_stays_the_export_and_dir_lists_the_exports():
    """README's one-shot ``from illusio.sis import stereogram`` is the function even after its
    submodule ``illusio.sis.stereogram`` was imported (Python sets the package's attribute to the
    module then); every lazily exported name of every package is no module; ``dir()`` (tab
    completion, ``help()``) lists the exports. In a fresh interpreter: the import order matters."""
    import subprocess
    import sys

    program = (
        "import importlib, types\n"
        "import illusio.sis.stereogram, illusio.sis.multiscene\n"
        "from illusio.sis import stereogram, multiscene\n"
        "assert callable(stereogram) and callable(multiscene), (stereogram, multiscene)\n"
        "assert not isinstance(stereogram, types.ModuleType)\n"
        "for package in ('passes', 'sis', 'dof', 'lines', 'ibr', 'radiosity', 'relight', 'core'):\n"
        "    module = importlib.import_module('illusio.' + package)\n"
        "    exports = module.__dict__.get('_lazy_exports', {})\n"
        "    assert set(exports) <= set(dir(module)), package\n"
        "    for name in exports:\n"
        "        assert not isinstance(getattr(module, name), types.ModuleType), (package, name)\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr[-2000:]
