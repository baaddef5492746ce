"""Sphinx configuration of the mudrft documentation site.

Build (from the repository root, after ``pip install -e ".[docs]"``)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

Sources: the user guide (``docs/*.md``, ``docs/guide/``), the model chapter
(``docs/model.md``), performance and architecture (Markdown, through MyST), the gallery
(``examples/*.py``, run during the build by sphinx-gallery with ``--quick``) and the API
reference (``docs/api/``, autosummary over the numpydoc docstrings).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE / "_ext"))

os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("MUJOCO_GL", "egl")

import mudrft  # noqa: E402

project = "mudrft"
author = "mudrft developers"
copyright = "2026, mudrft developers (MIT license)"
release = version = mudrft.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
    "sphinx_design",
    "sphinx_gallery.gen_gallery",
    "mudrft_docs",  # docs/_ext: offline MathJax, gallery scraper, optional API pages
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = [
    "_build",
    "screenshots",
    "Thumbs.db",
    ".DS_Store",
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "auto_examples/*.json",
]
templates_path = ["_templates"]

# -- MyST (Markdown: model.md, performance.md, architecture.md, the guide) -----------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# -- API reference -------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_typehints = "none"  # the numpydoc docstrings state types and units
autodoc_member_order = "bysource"
autodoc_preserve_defaults = True  # `xp=np`, not the repr of the numpy module
numpydoc_show_class_members = False  # the class template lists methods (own pages)
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True
numpydoc_xref_param_type = False
# Checks every public docstring must pass (a failure is a build warning, so -W fails):
# a summary line, a Parameters section that names no argument the function lacks.
numpydoc_validation_checks = {"GL08", "PR02"}
numpydoc_validation_exclude = {
    r"\.__init__$",
    r"\.__call__$",
    r"\.__repr__$",
}

# -- gallery (examples/*.py) -----------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    # run every example but the RL training one: it needs the 'rl-train' extra (torch), which
    # the docs build does not install; the gallery shows its code without running it
    "filename_pattern": r"(?<!train_mud_walker)(?<!train_mud_walker_brax)\.py$",
    "ignore_pattern": r"__init__\.py",
    "reset_argv": "mudrft_docs.gallery_argv",  # --quick --out <folder of this build>
    "image_scrapers": ("mudrft_docs.png_scraper",),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "show_memory": False,
    "min_reported_time": 1,
    "write_computation_times": False,  # its page styles a table from a CDN; times are per example
}

# -- HTML -------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"mudrft {version}"
html_static_path = ["_static"]
html_css_files = ["mudrft.css"]
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "header_links_before_dropdown": 8,
    "navbar_persistent": ["search-button"],
    "secondary_sidebar_items": ["page-toc", "sourcelink"],
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
# pages with no sub-pages need no section navigation (it would be an empty column)
html_sidebars = {
    page: []
    for page in ("index", "getting-started", "model", "performance", "architecture", "changelog")
}
html_show_sourcelink = True
html_last_updated_fmt = None

# Equations: MathJax 3 from the pip package django-static-mathjax, copied into the build
# (docs/_ext/mudrft_docs.py), so the pages render offline; the CDN only when it is missing.
mathjax3_config = {
    "tex": {"tags": "none", "macros": {"d": "\\mathrm{d}"}},
    "chtml": {"displayAlign": "center"},
}
