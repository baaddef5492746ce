"""Skip the docstring examples that need an optional extra which is not installed.

pytest runs the examples in ``src`` (``--doctest-modules``). mudrft's core needs only
numpy and scipy, so a docstring whose examples need an extra (matplotlib, pandas, h5py,
trimesh, mujoco, jax, numba, dask, xarray) is skipped, with the missing package as the
reason, where that extra is absent. A docstring needs an extra when

* one of its examples imports it (``>>> import mujoco``), or
* it belongs to a module listed in :data:`MODULE_EXTRAS`, whose examples use the extra
  through mudrft itself (``>>> p = mjax.to_jax(...)`` needs jax).

The examples run unchanged wherever the extras are installed. This file is not part of
the package (setuptools installs packages only).
"""

from __future__ import annotations

import ast
import importlib.util
from collections.abc import Iterable

import pytest
from _pytest.doctest import DoctestItem

#: Optional packages (the extras of pyproject.toml and what they pull in).
EXTRAS = frozenset(
    {
        "matplotlib",
        "pandas",
        "h5py",
        "trimesh",
        "mujoco",
        "jax",
        "numba",
        "dask",
        "xarray",
        "zarr",
        "gymnasium",
    }
)

#: Modules (and their submodules) whose examples need an extra without importing it.
MODULE_EXTRAS: dict[str, tuple[str, ...]] = {
    "mudrft.backends.jax": ("jax",),
    "mudrft.backends._jax_base": ("jax",),
    "mudrft.integrations.mujoco": ("mujoco",),
    "mudrft.integrations.walk": ("mujoco",),
    "mudrft.integrations.mjx": ("mujoco", "jax", "mujoco.mjx"),
    "mudrft.envs": ("mujoco", "gymnasium"),
}


def _imported_extras(sources: Iterable[str]) -> set[str]:
    """Extras that the example sources import (top-level package names)."""
    found: set[str] = set()
    for src in sources:
        try:
            tree = ast.parse(src)
        except SyntaxError:  # not Python on its own (e.g. a continuation); nothing to see
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            else:
                continue
            found.update(n.split(".")[0] for n in names if n.split(".")[0] in EXTRAS)
    return found


def _module_extras(module: str) -> set[str]:
    return {
        extra
        for prefix, extras in MODULE_EXTRAS.items()
        if module == prefix or module.startswith(prefix + ".")
        for extra in extras
    }


def _installed(name: str) -> bool:
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):
        return False


#: Modules that cannot even be imported without their extra (a Gymnasium ``Env`` subclass).
collect_ignore_glob = [] if _installed("gymnasium") else ["mudrft/envs/*"]


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark a docstring's examples as skipped when an extra they need is missing."""
    for item in items:
        if not isinstance(item, DoctestItem) or item.dtest is None:
            continue
        module = str(item.dtest.globs.get("__name__", ""))
        need = _module_extras(module) | _imported_extras(ex.source for ex in item.dtest.examples)
        missing = sorted(extra for extra in need if not _installed(extra))
        if missing:
            reason = f"the example needs {', '.join(missing)} (optional extra, not installed)"
            item.add_marker(pytest.mark.skip(reason=reason))
