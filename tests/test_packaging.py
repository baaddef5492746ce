"""The versions the package declares are the versions CI tests (decision D149).

``pyproject.toml`` promises numpy and scipy from a floor on; CI's core-only run installs
exactly those floors (``.ci/run``), so a use of a newer name (``numpy.trapezoid`` exists
from numpy 2.0 only) fails there instead of on a user's machine. These tests keep the two
files from drifting apart.
"""

from __future__ import annotations

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


def test_the_core_dependencies_are_numpy_and_scipy():
    assert set(floors()) == {"numpy", "scipy"}


def test_ci_tests_the_declared_floors():
    assert ci_pins() == floors()


@pytest.mark.parametrize("package", ["numpy", "scipy"])
def test_the_installed_version_is_at_least_the_floor(package):
    """The environment running the suite satisfies the floor (a stale environment would
    test something that users cannot install against)."""
    from importlib.metadata import version

    def key(v: str) -> tuple[int, ...]:
        return tuple(int(x) for x in re.findall(r"\d+", v)[:3])

    assert key(version(package)) >= key(floors()[package])
