"""The layers point one way (docs/architecture.md): the core never imports the edges."""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import mudrft

SRC = Path(mudrft.__file__).resolve().parent
CORE = ("parameters", "constitutive", "feet", "terrains", "simulation")
EDGES = ("backends", "integrations", "calibration", "cli", "sweep", "envs")


def test_import_and_simulate_with_numpy_load_no_accelerator_and_no_edge():
    """``import mudrft`` loads neither numba nor an edge; ``simulate`` compiles the mud under
    a foot of mudrft.feet with numba (a core dependency, mudrft._jit) and loads no edge."""
    out = subprocess.run(
        [sys.executable, "-c", "import json, sys, mudrft; print(json.dumps(sorted(sys.modules)))"],
        capture_output=True, text=True, check=True, timeout=120,
    )  # fmt: skip
    assert "numba" not in set(json.loads(out.stdout.strip().splitlines()[-1]))
    code = (
        "import json, sys, mudrft\n"
        "foot = mudrft.feet.SemiCylinder()\n"
        "r = mudrft.simulate(foot, mudrft.paper_mud(0.25), mudrft.gait(speed=0.2))\n"
        "assert r.metrics()['peak_support'] > 0\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    )
    loaded = set(json.loads(out.stdout.strip().splitlines()[-1]))
    for name in (
        "jax",
        "mujoco",
        "gymnasium",
        "dask",
        "distributed",
        "xarray",
        "zarr",
        "mudrft.backends",
        "mudrft.integrations",
        "mudrft.calibration",
        "mudrft.sweep",
        "mudrft.envs",
    ):
        assert not any(m == name or m.startswith(name + ".") for m in loaded), name


def _imports(path: Path) -> set[str]:
    """Absolute names of the mudrft modules a file imports (at any depth of the file)."""
    tree = ast.parse(path.read_text())
    pkg = ".".join(("mudrft", *path.relative_to(SRC).with_suffix("").parts[:-1]))
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")[: len(pkg.split(".")) - node.level + 1]
                mod = ".".join([*base, node.module] if node.module else base)
            else:
                mod = node.module or ""
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
    return {m for m in out if m.startswith("mudrft")}


def test_no_core_module_imports_an_edge():
    bad = []
    for layer in CORE:
        files = [SRC / f"{layer}.py"] if (SRC / f"{layer}.py").exists() else []
        files += sorted((SRC / layer).rglob("*.py")) if (SRC / layer).is_dir() else []
        assert files, layer
        for f in files:
            for mod in _imports(f):
                if any(mod == f"mudrft.{e}" or mod.startswith(f"mudrft.{e}.") for e in EDGES):
                    bad.append(f"{f.relative_to(SRC)} imports {mod}")
    assert not bad, bad


def test_no_module_in_src_is_above_600_lines():
    long = {
        str(f.relative_to(SRC)): n
        for f in SRC.rglob("*.py")
        if (n := len(f.read_text().splitlines())) > 600
    }
    assert not long, long


def _module_name(path: Path, root: Path) -> str:
    parts = path.relative_to(root).with_suffix("").parts
    return ".".join(("mudrft", *(parts[:-1] if parts[-1] == "__init__" else parts)))


def import_graph(root: Path) -> dict[str, set[str]]:
    """The modules of the package at ``root`` outside ``integrations/``, each with the modules of
    that package it imports: anywhere in the file (inside functions and ``TYPE_CHECKING`` too),
    read from the source with ``ast``. ``from pkg import name`` points at the module ``pkg.name``
    where there is one, else at ``pkg`` (its ``__init__``)."""
    files = {
        _module_name(f, root): f
        for f in root.rglob("*.py")
        if f.relative_to(root).parts[0] != "integrations"
    }
    graph: dict[str, set[str]] = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join([*up, base] if base else up)
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    targets.add(sub if sub in files else base)
        graph[name] = {t for t in targets if t in files and t != name}
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` as the list of its modules (first repeated at the end), or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return [*path[path.index(nxt) :], nxt]
            if nxt not in state and (cycle := visit(nxt)):
                return cycle
        state[node] = 2
        path.pop()
        return None

    for start in sorted(graph):
        if start not in state and (cycle := visit(start)):
            return cycle
    return None


def test_find_cycle_reports_a_cycle_through_others_and_none_in_a_chain():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]


def test_no_two_modules_outside_integrations_import_each_other():
    graph = import_graph(SRC)
    assert "mudrft.feet.morphing.foot" in graph and "mudrft.feet.base" in graph
    cycle = find_cycle(graph)
    assert cycle is None, "modules that import each other: " + " -> ".join(cycle or [])
