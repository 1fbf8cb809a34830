"""The documentation site builds (issue 43): Sphinx with warnings as errors (a broken cross-reference,
a docstring that does not parse, an example that raises all fail it), every example of the gallery
run and its picture on its page; and every repository path the pages name exists."""

from __future__ import annotations

import importlib
import os
import re
import subprocess
import sys

import pytest

from tests.conftest import REPO

DOCS = REPO / "docs"
#: the packages the API reference documents, every name of their __all__
PUBLIC = ("core", "passes", "scene", "sis", "lines", "dof", "ibr", "radiosity", "relight", "batch", "viewer", "gallery")


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
    assert 'id="illusio.show"' in api
    undocumented = [
        f"illusio.{package}.{name}"
        for package in PUBLIC
        for name in importlib.import_module(f"illusio.{package}").__all__
        if f'id="illusio.{package}.{name}"' not in api
    ]
    assert not undocumented, undocumented  # every exported name has its entry in the API reference


def pages() -> list:
    """README.md and the documentation pages (not the built site nor sphinx-gallery's output)."""
    docs = sorted(p for p in DOCS.rglob("*.md") if not {"_build", "gallery"} & set(p.relative_to(DOCS).parts))
    return [REPO / "README.md", *docs]


def test_every_repository_path_the_pages_name_exists():
    named = {}
    for page in pages():
        for path in re.findall(
            r"`((?:scripts|examples|docs|benchmarks|tests|src)/[\w./-]+)`", page.read_text(encoding="utf-8")
        ):
            named.setdefault(path.rstrip("/"), page.name)
    assert len(named) > 50
    missing = sorted(f"{page}: {path}" for path, page in named.items() if not (REPO / path).exists())
    assert not missing, missing


def test_every_relative_link_of_the_pages_reaches_a_file():
    """A Markdown link to a page or file of the repository (README's links read on GitHub; the
    site's are also checked by Sphinx) names one that exists; a page's link without a suffix is
    the site's own (gallery/index, a gallery example) and must be one of those."""
    examples = {f"gallery/{p.stem}" for p in (REPO / "examples").glob("plot_*.py")} | {"gallery/index"}
    broken = []
    for page in pages():
        for target in re.findall(r"\]\(([^)\s]+)\)", page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue  # a web address or an anchor on the page
            path = (page.parent / target.split("#")[0]).resolve()
            site = path.relative_to(DOCS).as_posix() if path.is_relative_to(DOCS) else None
            if not (path.exists() or site in examples):
                broken.append(f"{page.relative_to(REPO)}: {target}")
    assert not broken, broken


#: dotted names the pages give (``sis.physics.linear_depth_error``): the packages they start from
PACKAGES = (
    "core",
    "scene",
    "passes",
    "sis",
    "dof",
    "lines",
    "ibr",
    "radiosity",
    "relight",
    "batch",
    "viewer",
    "gallery",
)


def _resolve(dotted: str):
    import importlib

    parts = dotted.removeprefix("illusio.").split(".")
    for k in range(len(parts), 0, -1):
        try:
            value = importlib.import_module("illusio." + ".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for name in parts[k:]:
            value = getattr(value, name)
        return value
    raise ModuleNotFoundError(dotted)


def test_every_dotted_name_the_pages_give_is_real():
    """``radiosity.display.corner_gather``, ``illusio.sis.stereogram``, ``Camera.shift``-free: each
    name the pages write in code spans from a package down is a module, class, function or
    attribute that exists (the decision records and technique pages name the code they describe)."""
    pattern = re.compile(rf"`((?:illusio\.)?(?:{'|'.join(PACKAGES)})(?:\.\w+)+)(?:\(\))?`")
    named = {}
    for page in pages():
        for dotted in pattern.findall(page.read_text(encoding="utf-8")):
            if not dotted.endswith((".py", ".glsl", ".md", ".json", ".yaml")):
                named.setdefault(dotted, page.name)
    assert len(named) > 30
    missing = []
    for dotted, page in sorted(named.items()):
        try:
            _resolve(dotted)
        except (ImportError, AttributeError) as e:
            missing.append(f"{page}: {dotted} ({e})")
    assert not missing, missing


def _python_blocks():
    for page in pages():
        for k, block in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), re.S)):
            yield pytest.param(page, block, id=f"{page.stem}-{k}")


@pytest.mark.parametrize(("page", "block"), list(_python_blocks()))
def test_the_pages_python_runs_as_written(page, block, tmp_path, monkeypatch):
    """Each ```python block of README and the pages runs as written, in a fresh namespace."""
    if "builtin_real_scene" in block:
        pytest.importorskip("mitsuba", reason="the photograph is path-traced (photo extra)")
    monkeypatch.chdir(tmp_path)  # a block may write a file
    exec(compile(block, str(page), "exec"), {"__name__": "__doc_block__"})
