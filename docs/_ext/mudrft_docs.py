"""Local Sphinx extension of the mudrft documentation.

* **Offline MathJax.** The equations are typeset by MathJax 3, whose files come from the
  pip package ``django-static-mathjax`` (a plain copy of MathJax 3.2.2; it imports nothing
  of Django). They are copied into ``_static/mathjax`` of the build, so the site renders
  its equations without a network (the headless-browser check has none). Without the
  package the site falls back to Sphinx's CDN default, with a note in the log.
* **The gallery.** :func:`gallery_argv` gives every example ``--quick --out FOLDER``: the
  small setting of the build, and a folder of its own for the PNG files it writes.
  :func:`png_scraper` puts the PNG files an example wrote beside its code (the examples
  close their matplotlib figures after saving them, so the default scraper sees none).
* **The paper's numbers.** Equations labelled ``chen2026-eq-N`` carry ``\\tag{N}``; their
  Sphinx number is dropped so that only the paper's shows.
* **Modules not in this build.** ``.. optional-module:: NAME`` on an API page documents the
  module ``NAME`` and its members when it imports, and says that it is not part of this
  build otherwise (``mudrft.sweep`` and ``mudrft.envs`` land from other branches).
"""

from __future__ import annotations

import importlib
import importlib.util
import re
import shutil
import tempfile
from pathlib import Path
from typing import Any

# -- offline MathJax ---------------------------------------------------------------------

_MATHJAX_PARTS = (
    "tex-mml-chtml.js",
    "input",
    "output/chtml",
    "output/chtml.js",
    "a11y",
    "adaptors",
    "ui",
    "sre",
    "startup.js",
    "loader.js",
    "core.js",
)


def _mathjax_es5() -> Path | None:
    spec = importlib.util.find_spec("mathjax")
    if spec is None or not spec.submodule_search_locations:
        return None
    for location in spec.submodule_search_locations:
        es5 = Path(location) / "static" / "mathjax" / "es5"
        if (es5 / "tex-mml-chtml.js").is_file():
            return es5
    return None


def _use_local_mathjax(app: Any, config: Any) -> None:
    es5 = _mathjax_es5()
    app.env_mathjax_es5 = es5  # type: ignore[attr-defined]
    if es5 is None:
        from sphinx.util import logging

        logging.getLogger(__name__).info(
            "mudrft_docs: django-static-mathjax not installed; equations load MathJax from a CDN"
        )
        return
    config.mathjax_path = "mathjax/tex-mml-chtml.js"


def _copy_mathjax(app: Any, exc: Exception | None) -> None:
    es5 = getattr(app, "env_mathjax_es5", None)
    if exc is not None or es5 is None or app.builder.format != "html":
        return
    target = Path(app.outdir) / "_static" / "mathjax"
    for part in _MATHJAX_PARTS:
        src = es5 / part
        dst = target / part
        if src.is_dir():
            shutil.copytree(src, dst, dirs_exist_ok=True)
        elif src.is_file():
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)


# -- the gallery -------------------------------------------------------------------------

_OUT: dict[str, Path] = {}
_SEEN: dict[str, set[str]] = {}


def _example_out(src_file: str) -> Path:
    key = str(Path(src_file).resolve())
    if key not in _OUT:
        _OUT[key] = Path(tempfile.mkdtemp(prefix=f"mudrft-gallery-{Path(src_file).stem}-"))
        _SEEN[key] = set()
    return _OUT[key]


def gallery_argv(gallery_conf: dict, script_vars: dict) -> list[str]:
    """Command-line arguments of an example run by the gallery: ``--quick --out FOLDER``."""
    return ["--quick", "--out", str(_example_out(script_vars["src_file"]))]


def _remove_example_folders(app: Any, exc: Exception | None) -> None:
    for folder in _OUT.values():
        shutil.rmtree(folder, ignore_errors=True)
    _OUT.clear()
    _SEEN.clear()


def png_scraper(block: Any, block_vars: dict, gallery_conf: dict) -> str:
    """The PNG files an example wrote since the last code block, as gallery images."""
    from sphinx_gallery.scrapers import figure_rst

    key = str(Path(block_vars["src_file"]).resolve())
    out = _OUT.get(key)
    if out is None:
        return ""
    seen = _SEEN[key]
    new = sorted(
        (p for p in out.glob("*.png") if p.name not in seen),
        key=lambda p: (p.stat().st_mtime, p.name),
    )
    paths = []
    for png, image_path in zip(new, block_vars["image_path_iterator"], strict=False):
        shutil.copyfile(png, image_path)
        seen.add(png.name)
        paths.append(image_path)
    return figure_rst(paths, gallery_conf["src_dir"]) if paths else ""


# -- API pages of modules that this build may not have ------------------------------------

_OPTIONAL = re.compile(r"^\.\. optional-module:: (?P<name>[\w.]+)\n", re.M)


def _importable(name: str) -> bool:
    try:
        importlib.import_module(name)
    except ImportError:
        return False
    return True


def _optional_modules(app: Any, docname: str, source: list[str]) -> None:
    # ``.. optional-module:: NAME`` becomes ``.. automodule:: NAME`` with its members when
    # NAME imports, and a note otherwise (autosummary would try to import an automodule
    # line before any event could fence it, hence a directive name of our own).
    def replace(m: re.Match[str]) -> str:
        name = m.group("name")
        if _importable(name):
            return f".. automodule:: {name}\n   :members:\n"
        return (
            f".. note::\n\n   ``{name}`` is not part of this build of mudrft (it is not "
            "installed, or not yet merged); its reference appears here once it is.\n"
        )

    source[0] = _OPTIONAL.sub(replace, source[0])


# -- the paper's equation numbers ------------------------------------------------------------


def _paper_numbers(app: Any, doctree: Any, docname: str) -> None:
    # A docstring states the paper's equation (N) as ``.. math::`` labelled ``chen2026-eq-N``
    # with ``\tag{N}`` in its TeX: MathJax shows the paper's number, so Sphinx's own
    # page-local number (1, 2, ... on every page) would only contradict it.
    from docutils import nodes

    for node in doctree.findall(nodes.math_block):
        if str(node.get("label") or "").startswith("chen2026-eq-"):
            node["number"] = None


def setup(app: Any) -> dict[str, Any]:
    app.connect("config-inited", _use_local_mathjax)
    app.connect("build-finished", _copy_mathjax)
    app.connect("build-finished", _remove_example_folders)
    app.connect("source-read", _optional_modules)
    app.connect("doctree-resolved", _paper_numbers)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
