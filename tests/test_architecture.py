"""The package's shape: no circle in its import graph, no module over 450 lines.

The graph is read from the source, not from what Python happened to import: every ``import`` and
``from ... import`` of a package module counts, at module level or inside a function (a deferred
import that closes a circle is still a circle: the two modules still need each other). ``from P
import name`` counts as an edge to the module ``P.name`` where there is one, else to ``P`` itself
(the package's ``__init__``). A circle is a strongly connected component of more than one module.
"""
from __future__ import annotations

import ast
from pathlib import Path

import en17037cli

PACKAGE = Path(en17037cli.__file__).parent
#: The hard limit on a module's length (docs/project-file.md: "none over about 400 lines").
MAX_LINES = 450
#: Modules that are tables of constants (coefficients, lookup tables) may be longer; by path from
#: the package's folder, with why. None is needed today.
TABLES_OF_CONSTANTS: dict[str, str] = {}


def modules(root: Path = PACKAGE) -> dict[str, Path]:
    """Dotted module name -> file, for every module of the package (a package by its ``__init__``)."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def import_graph(mods: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (anywhere in its source)."""
    def owner(name: str) -> str | None:  # the module a dotted name lives in
        while name and name not in mods:
            name = name.rpartition(".")[0]
        return name or None

    edges: dict[str, set[str]] = {m: set() for m in mods}
    for m, path in mods.items():
        package = m if path.name == "__init__.py" else m.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets: list[str | None] = []
            if isinstance(node, ast.Import):
                targets = [owner(a.name) for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[: len(package.split(".")) - node.level + 1]
                    where = ".".join(base + ([node.module] if node.module else []))
                else:
                    where = node.module or ""
                targets = [f"{where}.{a.name}" if f"{where}.{a.name}" in mods else owner(where) for a in node.names]
            edges[m].update(t for t in targets if t is not None and t != m)
    return edges


def circles(edges: dict[str, set[str]]) -> list[frozenset[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out = []
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            v, children = work[-1]
            w = next(children, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(edges[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = set()
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.add(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(frozenset(comp))
    return out


def test_the_circle_finder_finds_circles_and_only_them():
    """Hand-made graphs: a -> b -> c -> a is one circle, d -> a hangs off it, e <-> f another."""
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"f"}, "f": {"e"}, "g": set()}
    assert sorted(map(sorted, circles(edges))) == [["a", "b", "c"], ["e", "f"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_the_graph_counts_deferred_and_package_imports(tmp_path):
    """A function-level import and a name taken from a package's ``__init__`` are edges."""
    pkg = tmp_path / "en17037cli"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("def f():\n    from en17037cli.sub.leaf import x\n")
    (pkg / "sub" / "__init__.py").write_text("from en17037cli.sub import leaf\n")
    (pkg / "sub" / "leaf.py").write_text("from en17037cli import f\nx = 1\n")
    edges = import_graph(modules(pkg))
    assert edges == {"en17037cli": {"en17037cli.sub.leaf"}, "en17037cli.sub": {"en17037cli.sub.leaf"},
                     "en17037cli.sub.leaf": {"en17037cli"}}
    assert circles(edges) == [frozenset({"en17037cli", "en17037cli.sub.leaf"})]


def test_no_circle_in_the_import_graph():
    found = [sorted(c) for c in circles(import_graph(modules()))]
    assert not found, f"modules that import each other (directly or around a circle): {found}"


def test_no_module_over_450_lines():
    lengths = {p.relative_to(PACKAGE).as_posix(): len(p.read_text(encoding="utf-8").splitlines()) for p in modules().values()}
    long = {name: n for name, n in lengths.items() if n > MAX_LINES and name not in TABLES_OF_CONSTANTS}
    assert not long, f"modules over {MAX_LINES} lines: {long}"
