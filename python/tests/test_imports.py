"""The package's modules import one another in one direction (no cycle): each module's
imports of sibling modules, read from its source, form a graph without a loop."""
import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "velum"


def sibling_imports(path):
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                names.add(node.module.split(".")[0])
            else:
                names.update(alias.name for alias in node.names)
    return names


def test_no_import_cycle():
    graph = {p.stem: sibling_imports(p) for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    done, active = set(), []

    def visit(name):
        if name in active:
            loop = active[active.index(name):] + [name]
            raise AssertionError("import cycle: " + " -> ".join(loop))
        if name in done or name not in graph:
            return
        active.append(name)
        for other in sorted(graph[name]):
            visit(other)
        active.pop()
        done.add(name)

    for name in sorted(graph):
        visit(name)
