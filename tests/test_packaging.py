"""The versions the package declares are the versions CI tests.

``pyproject.toml`` promises numpy, scipy and trimesh from a floor on; CI's core-only run installs
exactly those floors (``.ci/run``), so a use of a newer name (``numpy.trapezoid`` exists
from numpy 2.0 only) fails there instead of on a user's machine. Its "oldest extras" run
installs every optional extra at its floor (``tools/oldest_requirements.py``). These tests
keep the files from drifting apart.
"""

from __future__ import annotations

import importlib.util
import re
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def floors() -> dict[str, str]:
    """``{package: minimum version}`` of the core dependencies in pyproject.toml."""
    deps = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["dependencies"]
    out = {}
    for dep in deps:
        m = re.fullmatch(r"([A-Za-z0-9_.-]+)>=([0-9.]+)", dep.replace(" ", ""))
        assert m, f"a core dependency without a plain floor: {dep!r}"
        out[m[1].lower()] = m[2]
    return out


def ci_pins() -> dict[str, str]:
    """``{package: version}`` that .ci/run's core-only environment pins (``pkg==X.*``)."""
    text = (REPO / ".ci" / "run").read_text()
    core = [line for line in text.splitlines() if "$CORE/bin/python" in line and "install" in line]
    assert len(core) == 1, core
    return {m[1].lower(): m[2] for m in re.finditer(r'"([A-Za-z0-9_.-]+)==([0-9.]+)\.\*"', core[0])}


def test_the_core_dependencies_are_numpy_scipy_numba_and_trimesh():
    assert set(floors()) == {"numpy", "scipy", "numba", "trimesh"}


def test_the_mesh_extra_stays_and_the_docs_extra_builds_the_sweep_pages():
    """trimesh moved into the core: ``pip install 'mudrft[mesh]'`` still works (an extra
    that adds nothing); the documentation's gallery runs the sweep example."""
    table = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert table["mesh"] == []
    docs = [r for r in table["docs"] if r.startswith("mudrft[")]
    assert "sweep" in docs[0].removeprefix("mudrft[").rstrip("]").split(",")


def test_ci_tests_the_declared_floors():
    assert ci_pins() == floors()


@pytest.mark.parametrize("package", ["numpy", "scipy", "numba", "trimesh"])
def test_the_installed_version_is_at_least_the_floor(package):
    """The environment running the suite satisfies the floor (a stale environment would
    test something that users cannot install against)."""
    from importlib.metadata import version

    def key(v: str) -> tuple[int, ...]:
        return tuple(int(x) for x in re.findall(r"\d+", v)[:3])

    assert key(version(package)) >= key(floors()[package])


def _oldest_tool():
    spec = importlib.util.spec_from_file_location(
        "oldest", REPO / "tools" / "oldest_requirements.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_oldest_extras_pins_every_extra_at_its_floor():
    """Every requirement of the extra ``all`` (self-references expanded) is pinned, at the
    floor it states: a three-part floor exactly, a two-part one to its release series."""
    tool = _oldest_tool()
    table = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    pins = [tool.pin(r) for r in tool.requirements("all", table)]
    names = {re.match(r"[A-Za-z0-9_.-]+", p)[0] for p in pins}
    for extra in ("plot", "mesh", "mujoco", "jax", "numba", "pandas", "hdf5", "sweep", "mjx", "rl"):
        for req in table[extra]:
            if not req.startswith("mudrft["):
                assert re.match(r"[A-Za-z0-9_.-]+", req)[0] in names, (extra, req)
    assert tool.pin("zarr>=3.1.1") == "zarr==3.1.1"
    assert tool.pin("dask[distributed]>=2024.8") == "dask[distributed]==2024.8.*"
    with pytest.raises(SystemExit, match="plain floor"):
        tool.pin("jax")


def test_ci_installs_the_oldest_extras_and_runs_the_suite():
    text = (REPO / ".ci" / "run").read_text()
    assert "python tools/oldest_requirements.py >" in text
    assert '"$OLDEST/bin/python" -m pytest' in text
