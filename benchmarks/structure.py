"""The package's structure in numbers: who imports whom, and the longest code.

Every import is counted, those inside functions included (read from the source with
``ast``, nothing is imported or run). Prints

1. the package-level import graph: for each sub-package, the sub-packages it imports
   and how many import statements do so;
2. import cycles between modules (strongly connected components of the module graph);
3. the longest functions and the longest modules.

Run from the repository root::

    python benchmarks/structure.py            # the tables
    python benchmarks/structure.py --top 20   # more rows

The layer rule itself (nothing imports a package above it) is a test:
``tests/test_import_layers.py`` uses :func:`imports` from here.
"""

from __future__ import annotations

import argparse
import ast
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = "statue2model"


def module_name(path: Path, root: Path = ROOT) -> str:
    """Dotted module name of a file under ``root`` (``__init__`` is its package)."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def imports(root: Path = ROOT, package: str = PACKAGE) -> list[tuple[str, str, int, bool]]:
    """Every import of the package's modules as (importer, imported, line, inside_function).

    ``imported`` is the most specific module name the statement names (for
    ``from a.b import c`` it is ``a.b.c`` when ``a/b/c.py`` or ``a/b/c/`` exists, else
    ``a.b``). Only imports of the package itself are returned.
    """
    files = sorted((root / package).rglob("*.py"))
    known = {module_name(f, root) for f in files}
    out = []
    for f in files:
        mod = module_name(f, root)
        tree = ast.parse(f.read_text(encoding="utf-8"), filename=str(f))
        parents: dict[ast.AST, ast.AST] = {}
        for parent in ast.walk(tree):
            for child in ast.iter_child_nodes(parent):
                parents[child] = parent

        def inside_function(node: ast.AST) -> bool:
            while node in parents:
                node = parents[node]
                if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                    return True
            return False

        for node in ast.walk(tree):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _resolve(mod, f.name == "__init__.py", node)
                for a in node.names:
                    full = f"{base}.{a.name}"
                    targets.append(full if full in known else base)
            for t in targets:
                if t == package or t.startswith(package + "."):
                    out.append((mod, t, node.lineno, inside_function(node)))
    return out


def subpackage(module: str) -> str:
    """``statue2model.geometry.body`` -> ``geometry``; top-level modules keep their name."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "(root)"


def package_graph(edges) -> dict[str, dict[str, int]]:
    graph: dict[str, dict[str, int]] = defaultdict(lambda: defaultdict(int))
    for a, b, _, _ in edges:
        pa, pb = subpackage(a), subpackage(b)
        if pa != pb:
            graph[pa][pb] += 1
    return graph


def cycles(edges) -> list[list[str]]:
    """Module-level strongly connected components with more than one module (Tarjan)."""
    graph: dict[str, set[str]] = defaultdict(set)
    for a, b, _, _ in edges:
        if a != b:
            graph[a].add(b)
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        work = [(v, iter(sorted(graph.get(v, ()))))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        while work:
            node, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                    break
                if w in on:
                    low[node] = min(low[node], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == node:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def longest(root: Path = ROOT, package: str = PACKAGE):
    """(functions, modules): lists of (lines, name), longest first."""
    funcs, mods = [], []
    for f in sorted((root / package).rglob("*.py")):
        text = f.read_text(encoding="utf-8")
        mod = module_name(f, root)
        mods.append((len(text.splitlines()), mod))
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                funcs.append((node.end_lineno - node.lineno + 1, f"{mod}.{node.name}"))
    return sorted(funcs, reverse=True), sorted(mods, reverse=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--top", type=int, default=10)
    ap.add_argument("--root", type=Path, default=ROOT)
    args = ap.parse_args(argv)
    edges = imports(args.root)
    inside = sum(1 for e in edges if e[3])
    print(f"imports of the package: {len(edges)} ({inside} inside functions)\n")
    graph = package_graph(edges)
    print("package-level graph (importer -> imported: statements)")
    for p in sorted(graph):
        row = ", ".join(f"{q} {n}" for q, n in sorted(graph[p].items()))
        print(f"  {p:12s} -> {row}")
    mutual = sorted({tuple(sorted((p, q))) for p in graph for q in graph[p] if p in graph.get(q, {})})
    print(f"\npairs of packages importing each other: {len(mutual)}")
    for p, q in mutual:
        print(f"  {p} <-> {q}")
    cyc = cycles(edges)
    print(f"\nmodule import cycles: {len(cyc)}" + (f" (largest {max(map(len, cyc))} modules)" if cyc else ""))
    for c in cyc:
        print(f"  {len(c)}: " + " ".join(m.removeprefix(PACKAGE + '.') for m in c))
    funcs, mods = longest(args.root)
    print("\nlongest functions (lines)")
    for n, name in funcs[: args.top]:
        print(f"  {n:5d}  {name.removeprefix(PACKAGE + '.')}")
    print(f"functions over 60 lines: {sum(1 for n, _ in funcs if n > 60)}")
    print("\nlongest modules (lines)")
    for n, name in mods[: args.top]:
        print(f"  {n:5d}  {name.removeprefix(PACKAGE + '.')}")


if __name__ == "__main__":
    main()
