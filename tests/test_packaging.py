"""What a source distribution holds (issue 43): the LICENSE, and every file and folder README.md
points to (its setup and test scripts, constraints, examples, docs, benchmarks and their results),
so an unpacked sdist does what README says."""

from __future__ import annotations

import re
import subprocess
import sys
import tarfile

import pytest

from tests.conftest import REPO


@pytest.fixture(scope="module")
def sdist_names(tmp_path_factory):
    pytest.importorskip("build", reason="the test extra (pip install build)")
    import shutil

    # from the files a clone holds: an installed tree's egg-info (its SOURCES.txt) would add to the sdist
    tree, out = tmp_path_factory.mktemp("tree"), tmp_path_factory.mktemp("sdist")
    files = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard"], capture_output=True, text=True, cwd=REPO, check=True
    ).stdout.split()
    for name in files:
        if (REPO / name).is_file():
            (tree / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(REPO / name, tree / name)
    r = subprocess.run(
        [sys.executable, "-m", "build", "--sdist", "--outdir", str(out), str(tree)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    (archive,) = out.glob("illusio-*.tar.gz")
    with tarfile.open(archive) as tar:
        return {name.split("/", 1)[1] for name in tar.getnames() if "/" in name}


def test_the_sdist_holds_the_license_and_what_readme_points_to(sdist_names):
    assert {"LICENSE", "README.md", "constraints.txt", "pyproject.toml"} <= sdist_names
    readme = (REPO / "README.md").read_text()
    named = set(re.findall(r"`((?:scripts|examples|docs|benchmarks|tests)/[\w./-]+)`", readme))
    named |= {t.rstrip("/") for t in re.findall(r"\]\(([^)\s:#]+)\)", readme)}  # its links: pages, the strip
    named |= {"scripts/demo.sh", "scripts/test.sh", "benchmarks/RESULTS.md", "docs/scene-files.md"}
    present = {p for p in named if (REPO / p).exists() and "/_build/" not in p}  # built, not shipped
    assert len(present) >= 5
    missing = sorted(p for p in present if p.rstrip("/") not in sdist_names)
    assert not missing, missing
    assert not any("__pycache__" in n or n.startswith("benchmarks/out/") for n in sdist_names)
    assert any(n.endswith(".glsl") for n in sdist_names)  # the shaders beside their passes
