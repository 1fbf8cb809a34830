"""illusio compile (issue 45, cold start): numba's kernels are compiled into their disk cache, so a
first command after setup loads them instead of compiling them: the curvature's, the radiosity's
on a box and on the office (clusters' links, textures' means) and its edits' (a moved object)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

CHECK = (
    "from illusio.core.kernels import cached_on_disk\n"
    "from illusio.lines import curvature\n"
    "from illusio.radiosity import clusters, dynamic, formfactor, links, texture_reflectance\n"
    "kernels = (curvature._fit_all, curvature._smooth_tensors, formfactor._point_polygon, links._scatter_gather,\n"
    "    clusters._cluster_rays, texture_reflectance._mean_kernel, dynamic._links_in_shafts)\n"
    "print(cached_on_disk(*kernels))"
)


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_compile_writes_the_kernels_a_first_command_would_compile(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba"), "ILLUSIO_CACHE": str(tmp_path / "cache")}
    env.pop("DISPLAY", None)

    def cached() -> str:
        return subprocess.run([sys.executable, "-c", CHECK], env=env, capture_output=True, text=True).stdout.strip()

    assert cached() == "False"  # an empty cache: a first command would compile
    run = subprocess.run(
        [sys.executable, "-m", "illusio.cli.main", "--quiet", "compile"], env=env, capture_output=True, text=True
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert "radiosity:" in run.stdout and "stereograms:" in run.stdout
    assert cached() == "True"
