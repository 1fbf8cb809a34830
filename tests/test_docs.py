"""The documentation site builds (issue 43): Sphinx with warnings as errors (a broken cross-reference,
a docstring that does not parse, an example that raises all fail it), every example of the gallery
run and its picture on its page; and every repository path the pages name exists."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from tests.conftest import REPO

DOCS = REPO / "docs"


@pytest.mark.timeout(600)
def test_the_site_builds_without_a_warning_and_each_example_shows_its_picture(tmp_path):
    pytest.importorskip("sphinx_gallery", reason="the docs extra (pip install 'illusio[docs]')")
    pytest.importorskip("myst_parser", reason="the docs extra")
    out = tmp_path / "html"
    r = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS), str(out)],
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert r.returncode == 0, r.stderr[-3000:]
    examples = sorted(p.stem for p in (REPO / "examples").glob("plot_*.py"))
    assert len(examples) >= 5
    for name in examples:
        page = (out / "gallery" / f"{name}.html").read_text(encoding="utf-8")
        assert re.search(rf'src="[^"]*sphx_glr_{name}_\d+\.png"', page), name  # the picture it made
    api = (out / "api.html").read_text(encoding="utf-8")
    for name in ("line_drawing", "stereogram", "depth_of_field", "radiosity_image", "RelightSession", "show"):
        assert re.search(rf'id="illusio(\.\w+)*\.{name}"', api), name  # documented from its docstring


def test_every_repository_path_the_pages_name_exists():
    pages = [DOCS / "index.md", DOCS / "getting-started.md", DOCS / "scene-files.md", DOCS / "api.md"]
    named = set()
    for page in pages:
        named |= set(
            re.findall(r"`((?:scripts|examples|docs|benchmarks|tests|src)/[\w./-]+)`", page.read_text(encoding="utf-8"))
        )
    assert named, "no path named"
    missing = sorted(p for p in named if not (REPO / p).exists())
    assert not missing, missing
