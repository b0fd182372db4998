"""The project's layout holds: each package imports only the packages below it, and no module imports itself
back through others (an import circle).

The layers, bottom to top, are :data:`LAYERS`; packages on one layer are independent of each other. Every
import counts, at module level or inside a function (a lazy import is still a dependency), except imports under
``if TYPE_CHECKING:`` (never executed). The graph is read from the sources with :mod:`ast`, nothing is imported.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("fmu_base", "hydro_fmu", "mbd_fmu", "plain_mbd_fmu", "orchestrator", "wec_cosim")

# Bottom to top. A module belongs to the longest unit name that prefixes its dotted name.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("fmu_base",),
    ("hydro_fmu", "mbd_fmu", "plain_mbd_fmu"),
    ("orchestrator", "orchestrator.errors", "orchestrator.progress"),
    ("orchestrator.control",),
    ("orchestrator.scenario",),
    ("orchestrator.scene",),
    ("orchestrator.results", "orchestrator.reference", "orchestrator.fmi"),
    ("orchestrator.cosim",),
    ("wec_cosim.sweeps",),
    ("wec_cosim.benchreport",),
    ("wec_cosim",),
)
LAYER = {unit: i for i, units in enumerate(LAYERS) for unit in units}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def project_modules() -> dict[str, Path]:
    return {module_name(p): p for pkg in PACKAGES for p in sorted((ROOT / pkg).rglob("*.py"))}


def unit_of(module: str) -> str:
    candidates = [u for u in LAYER if module == u or module.startswith(u + ".")]
    if not candidates:
        raise AssertionError(f"module {module} belongs to no layer of tests/test_layering.py: place its package")
    return max(candidates, key=len)


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    return skip


def imports_of(module: str, path: Path, modules: dict[str, Path]) -> set[str]:
    """The project modules that ``module`` imports (a package's ``__init__`` counts as the package)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    skip = _type_checking_nodes(tree)
    found: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                origin = ".".join(base + ([node.module] if node.module else []))
            else:
                origin = node.module or ""
            # `from package import submodule` depends on the submodule; `from module import name` on the module
            names = [f"{origin}.{a.name}" if f"{origin}.{a.name}" in modules else origin for a in node.names]
        else:
            continue
        for name in names:
            if name.split(".")[0] not in PACKAGES:
                continue
            while name and name not in modules:  # `import a.b.c` of an attribute: its module
                name = name.rpartition(".")[0]
            if name and name != module:
                found.add(name)
    return found


def import_graph() -> dict[str, set[str]]:
    modules = project_modules()
    return {m: imports_of(m, p, modules) for m, p in modules.items()}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    problems = []
    for module, targets in sorted(graph.items()):
        unit = unit_of(module)
        for target in sorted(targets):
            other = unit_of(target)
            if other != unit and LAYER[other] >= LAYER[unit]:
                where = "a package above it" if LAYER[other] > LAYER[unit] else "a package on its own layer"
                problems.append(f"{module} imports {target} ({other}: {where})")
    return problems


def test_every_module_has_a_layer() -> None:
    for module in project_modules():
        unit_of(module)


def test_no_package_imports_upward_or_sideways() -> None:
    assert upward_imports(import_graph()) == []


def test_no_import_circles() -> None:
    assert circles(import_graph()) == []


def test_the_check_sees_an_upward_import_and_a_circle() -> None:
    """The checks fail on what they are meant to catch (a graph with one upward edge and one circle)."""
    graph = {"orchestrator.scene.scene": {"orchestrator.cosim.masters"},
             "orchestrator.cosim.masters": {"orchestrator.cosim.iterative_master"},
             "orchestrator.cosim.iterative_master": {"orchestrator.cosim.masters"}}
    assert upward_imports(graph) == ["orchestrator.scene.scene imports orchestrator.cosim.masters "
                                     "(orchestrator.cosim: a package above it)"]
    assert circles(graph) == [["orchestrator.cosim.iterative_master", "orchestrator.cosim.masters"]]


def test_the_import_reader_resolves_relative_and_lazy_imports(tmp_path) -> None:
    source = ("from __future__ import annotations\nfrom typing import TYPE_CHECKING\n"
              "from . import step_control\nfrom ..scene import Scene\n"
              "if TYPE_CHECKING:\n    from orchestrator.cosim.simulation import RunPlan\n"
              "def f():\n    from orchestrator.results.analysis import harmonic_fit\n")
    path = tmp_path / "x.py"
    path.write_text(source)
    modules = project_modules()
    found = imports_of("orchestrator.cosim.x", path, modules)
    assert found == {"orchestrator.cosim.step_control", "orchestrator.scene", "orchestrator.results.analysis"}


@pytest.mark.parametrize("name", ["sweeps", "benchreport"])
def test_no_generic_top_level_package(name: str) -> None:
    """Installed, the project adds only its own names to site-packages (``wec_cosim`` holds sweeps and the bench
    report)."""
    assert not (ROOT / name).exists()
    text = (ROOT / "pyproject.toml").read_text()
    assert f'"{name}*"' not in text
