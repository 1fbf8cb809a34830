"""The documentation site (Sphinx): Markdown pages through MyST, the API reference from the public
packages' docstrings (autodoc), and an executed example gallery from ``examples/*.py``
(sphinx-gallery). ``bash scripts/docs.sh`` builds it into docs/_build/html, warnings as errors."""

from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if not os.environ.get("ILLUSIO_DOCS_INSTALLED"):  # scripts/docs-from-wheel.sh documents the installed wheel
    sys.path.insert(0, str(ROOT / "src"))

project = "illusio"
author = "the illusio developers"
copyright = "2026, the illusio developers"
from illusio import __version__ as release  # noqa: E402

version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
# the design journal and the build output are not pages of the site
exclude_patterns = ["_build", "gallery/*.ipynb", "gallery/*.py.md5", "gallery/*.zip"]
myst_heading_anchors = 3
html_theme = "furo"
html_title = f"illusio {release}"
html_static_path = []

autodoc_default_options = {"members": True, "member-order": "bysource", "undoc-members": False}
autodoc_typehints = "description"
autodoc_mock_imports = []

# `-b linkcheck` checks every link of the built site; the pages' own links are relative (checked by
# the html build with -W too), and sphinx-gallery's footer credit is the one address outside, which a
# CI machine that reaches only package registries cannot fetch
linkcheck_ignore = [r"https://sphinx-gallery\.github\.io/.*"]
linkcheck_anchors = True

sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",  # every plot_*.py is run as the site is built
    "ignore_pattern": r"(^|/)_[^/]*\.py$",  # the examples' shared helper (_display.py) is not an example
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "image_scrapers": ("matplotlib",),
    "matplotlib_animations": False,
    "plot_gallery": "True",
}
