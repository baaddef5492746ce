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
