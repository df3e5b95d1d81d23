"""The package's layers run one way: no module imports a package above its own.

Every import statement of the package is read with ``ast`` (those inside functions
included; nothing is imported), by :func:`imports` of ``benchmarks/structure.py``, which
also prints the package graph (``python benchmarks/structure.py``).
"""
from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

LAYERS = [
    ["errors", "quantities", "version"],
    ["io"],
    ["compute"],
    ["geometry"],
    ["fabrication"],
    ["hazard"],
    ["rocking"],
    ["isolator"],
    ["assessment"],
    ["crosscheck"],
    ["report"],
    ["pipeline"],
    ["cli", "__main__"],
]
"""Bottom to top; a module may import its own package and those of the rows below it.
Within the first row the modules import only ``errors``."""

LEVEL = {name: i for i, row in enumerate(LAYERS) for name in row}


def _structure():
    spec = importlib.util.spec_from_file_location("structure", ROOT / "benchmarks" / "structure.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


S = _structure()


@pytest.fixture(scope="module")
def edges():
    """Every import of the package (benchmarks/structure.imports), read when a test of this file
    first asks (not at collection, which every pytest-xdist worker does)."""
    return S.imports(ROOT)


ROOT_PACKAGE = "(root)"
"""What :func:`subpackage` calls the package itself (its __init__: the public facade)."""
_part = S.subpackage


def test_every_package_has_a_layer(edges):
    parts = {_part(a) for a, *_ in edges} | {_part(b) for _, b, *_ in edges}
    parts |= {p.stem if p.is_file() else p.name for p in (ROOT / "statue2model").iterdir()
              if (p.suffix == ".py" and p.stem != "__init__") or (p / "__init__.py").exists()}
    parts.discard(ROOT_PACKAGE)
    assert parts <= set(LEVEL), f"give these a row of LAYERS: {sorted(parts - set(LEVEL))}"


def test_scanner_sees_imports_inside_functions(edges):
    # the rule must hold for lazy imports too: the scanner reports them
    inside = [e for e in edges if e[3]]
    assert len(inside) > 100
    assert any(a == "statue2model.pipeline.stages" and b.startswith("statue2model.rocking") and fn
               for a, b, _, fn in edges)


def test_no_import_goes_up(edges):
    up = []
    for a, b, line, inside in edges:
        pa, pb = _part(a), _part(b)
        if pa == pb:
            continue
        if pb == ROOT_PACKAGE:
            up.append(f"{a}:{line} imports the package root (import from the module itself)")
        elif pa == ROOT_PACKAGE:
            continue                         # the package root is the public facade, above all
        elif LEVEL[pb] > LEVEL[pa] or (LEVEL[pb] == LEVEL[pa] == 0 and pb != "errors"):
            up.append(f"{a}:{line}{' (inside a function)' if inside else ''} imports {b}")
    assert not up, "imports that go up a layer:\n" + "\n".join(sorted(up))


def test_no_import_cycle(edges):
    """No two modules reach each other through imports (lazy ones included), inside a package
    or across packages: each module can be read after those it imports."""
    assert not S.cycles(edges), f"module import cycles: {S.cycles(edges)}"


def test_cycles_are_found():
    edges = [("p.a", "p.b", 1, False), ("p.b", "p.c", 1, True), ("p.c", "p.a", 1, True), ("p.c", "p.d", 1, False)]
    assert S.cycles(edges) == [["p.a", "p.b", "p.c"]]


@pytest.mark.parametrize("bad", ["statue2model.cli.argtypes", "statue2model.pipeline.config"])
def test_the_rule_can_fail(tmp_path, bad):
    """A module of geometry/ that imports the command line or the pipeline is caught."""
    pkg = tmp_path / "statue2model"
    (pkg / "geometry").mkdir(parents=True)
    (pkg / "cli").mkdir()
    (pkg / "pipeline").mkdir()
    for d in (pkg, pkg / "geometry", pkg / "cli", pkg / "pipeline"):
        (d / "__init__.py").write_text("")
    (pkg / "cli" / "argtypes.py").write_text("")
    (pkg / "pipeline" / "config.py").write_text("")
    (pkg / "geometry" / "scan.py").write_text(f"def f():\n    from ..{bad.split('.', 1)[1].replace('.', ' import ', 1)}\n")
    edges = S.imports(tmp_path)
    assert ("statue2model.geometry.scan", bad, 2, True) in edges
