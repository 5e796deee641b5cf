"""No import cycles inside mcbat, counting every import statement: at module level and
inside functions (a deferred import hides a cycle from the interpreter, not from the
design), relative imports resolved, and ``from mcbat.x import y`` counted as an import of
the submodule ``mcbat.x.y`` when ``y`` is one."""

import ast
from pathlib import Path

import pytest

from tests.conftest import ROOT

PACKAGE = ROOT / "mcbat"


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def _targets(node, module: str, is_package: bool, modules) -> list[str]:
    """The mcbat modules an ``import`` or ``from ... import`` statement in ``module``
    imports (the named module itself; ``from P import y`` names ``P.y`` when it is a
    module, else ``P``)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names if alias.name in modules]
    if node.level:  # relative: from the module's package, one level up per extra dot
        package = module if is_package else module.rpartition(".")[0]
        for _ in range(node.level - 1):
            package = package.rpartition(".")[0]
        base = f"{package}.{node.module}" if node.module else package
    else:
        base = node.module or ""
    if base.split(".")[0] != "mcbat":
        return []
    found = []
    for alias in node.names:
        sub = f"{base}.{alias.name}"
        found.append(sub if sub in modules else base)
    return [name for name in found if name in modules]


def import_graph(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the mcbat modules it imports anywhere in its text."""
    graph = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        is_package = path.name == "__init__.py"
        edges = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                edges.update(_targets(node, module, is_package, modules))
        edges.discard(module)
        graph[module] = edges
    return graph


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle (``[a, b, ..., a]``) through each strongly connected component of more
    than one module (Tarjan's algorithm, iterative)."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []
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
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.add(member)
                    if member == node:
                        break
                if len(component) > 1:
                    components.append(component)
    return [_cycle_in(graph, component) for component in components]


def _cycle_in(graph, component) -> list[str]:
    """A shortest cycle through the alphabetically first module of ``component``."""
    start = min(component)
    previous = {start: None}
    queue = [start]
    for node in queue:  # breadth first, inside the component
        for child in sorted(graph[node] & component):
            if child == start:
                path = [node]
                while previous[path[-1]] is not None:
                    path.append(previous[path[-1]])
                return [*reversed(path), start]
            if child not in previous:
                previous[child] = node
                queue.append(child)
    raise AssertionError(f"no cycle in component {sorted(component)}")


def test_mcbat_has_no_import_cycle():
    modules = _modules()
    assert "mcbat.study.spec" in modules and "mcbat.core.batch" in modules
    cycles = find_cycles(import_graph(modules))
    assert cycles == [], "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


# ---------------------------------------------------------------- the checker itself


def _graph_of(tmp_path, files: dict[str, str]):
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    modules = {}
    for path in sorted(tmp_path.rglob("*.py")):
        parts = path.relative_to(tmp_path).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return import_graph(modules)


@pytest.mark.parametrize("files, expected", [
    # a function-level import closes the loop
    ({"mcbat/__init__.py": "", "mcbat/a.py": "import mcbat.b\n",
      "mcbat/b.py": "def f():\n    from mcbat.a import thing\n"},
     [["mcbat.a", "mcbat.b", "mcbat.a"]]),
    # relative imports, and "from package import submodule"
    ({"mcbat/__init__.py": "", "mcbat/p/__init__.py": "from .x import X\n",
      "mcbat/p/x.py": "from . import y\n", "mcbat/p/y.py": "from mcbat.p import x\n"},
     [["mcbat.p.x", "mcbat.p.y", "mcbat.p.x"]]),
    # a submodule imported from its package's __init__ is no cycle by itself
    ({"mcbat/__init__.py": "", "mcbat/p/__init__.py": "from mcbat.p.x import X\n",
      "mcbat/p/x.py": "from mcbat.p import y\n", "mcbat/p/y.py": "Y = 1\n"}, []),
    # importing a name of the package (not a submodule) is an import of its __init__
    ({"mcbat/__init__.py": "", "mcbat/p/__init__.py": "from mcbat.p.x import X\n",
      "mcbat/p/x.py": "from ..p import Y\nX = 1\n"}, [["mcbat.p", "mcbat.p.x", "mcbat.p"]]),
])
def test_the_checker_finds_cycles_of_every_kind(tmp_path, files, expected):
    assert find_cycles(_graph_of(tmp_path, files)) == expected
