"""The benchmark runner works and writes what RESULTS.md quotes (not a timing test)."""

import json
import subprocess
import sys

import pytest

from tests.conftest import REPO


def run_quick(out, *suites: str) -> dict:
    """``python -m benchmarks SUITES --quick --repeat 1``: each suite's JSON by name."""
    r = subprocess.run(
        [sys.executable, "-m", "benchmarks", *suites, "--quick", "--repeat", "1", "--out", str(out)],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=600,
    )
    assert r.returncode == 0, r.stderr
    return {suite: json.loads((out / f"{suite}.json").read_text()) for suite in suites}


def test_quick_core_benchmark_writes_json_with_ratios(tmp_path):
    results = run_quick(tmp_path, "core")
    data = results["core"]
    names = {t["name"] for t in data["timings"]}
    assert {"office/gbuffer", "office/gbuffer+shading+shadows", "mesh-1M/gbuffer"} <= names
    assert all(t["min_ms"] <= t["median_ms"] <= t["max_ms"] for t in data["timings"])
    assert "1,000,002 triangles" in next(t["notes"] for t in data["timings"] if t["name"] == "mesh-1M/gbuffer")
    assert data["ratios"] and data["machine"]["renderer"]


def test_quick_protocol_and_viewer_benchmarks_write_their_goals(tmp_path):
    results = run_quick(tmp_path, "protocol", "viewer")
    protocol = results["protocol"]
    for renderer in ("plain", "sis", "multiscene", "lines"):
        assert f"{renderer}: array / texture (goal <= 1.3)" in protocol["ratios"]
        assert f"{renderer}: one-shot / kept (goal <= 1.5)" in protocol["ratios"]
    viewer = results["viewer"]
    names = {t["name"] for t in viewer["timings"]}
    assert {"plain/default", "sis/tv", "sis/raw", "lines/drawing"} <= names
    assert all(v > 0 for v in viewer["ratios"].values())


def test_dof_speed_is_compared_with_the_accumulation_of_equal_quality():
    """The baseline of a method is the fewest lens positions reaching its PSNR, not a converged one."""
    from benchmarks.dof import matched

    ladder = {1: (29.0, 40.0), 2: (31.0, 80.0), 4: (34.0, 160.0), 8: (38.0, 320.0)}
    assert matched(ladder, 34.0) == pytest.approx((4.0, 160.0))
    n, t = matched(ladder, 32.5)  # half way from 2 to 4 positions, in log
    assert n == pytest.approx(2**1.5) and t == pytest.approx(80 * 2**0.5)
    assert matched(ladder, 28.0) == (1.0, 40.0)
    assert matched(ladder, 40.0) is None


def test_quick_scene_files_benchmark_times_our_load_beside_trimeshs(tmp_path):
    results = run_quick(tmp_path, "scene_files")
    data = results["scene_files"]
    names = {t["name"] for t in data["timings"]}
    assert {"scene-file/illusio load", "scene-file/trimesh load", "scene-file/trimesh load + vertex normals"} <= names
    assert data["ratios"]["illusio load peak memory (MB, tracemalloc)"] > 0


def test_quick_mgf_benchmark_scores_renderparks_scenes_against_mitsuba(tmp_path, mgf_scenes):
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    ratios = run_quick(tmp_path, "mgf_scenes")["mgf_scenes"]["ratios"]
    assert ratios["cube: elements"] > 0 and ratios["office2: links"] > 0
    # the cube is RenderPark's Cornell-like box: within the radiosity goal at 48×36, 64 paths
    assert ratios["cube: error against Mitsuba, 4×4 blocks"] < 0.05
    assert 0.9 < ratios["office2: mean radiance / Mitsuba's"] < 1.1


def test_quick_svg_and_sis_video_benchmarks_write_their_measures(tmp_path):
    """The SVG strokes before and after (and the SVG against the PNG), and the stereogram videos'
    change where the depth stays, held against regenerated."""
    results = run_quick(tmp_path, "svg_strokes", "sis_video")
    svg = results["svg_strokes"]["ratios"]
    assert svg["all: paths after"] < svg["all: paths before"]
    if "all: smallest SVG vs PNG F1" in svg:  # resvg-py installed (the test extra)
        assert svg["all: smallest SVG vs PNG F1"] > 0.95
    video = results["sis_video"]["ratios"]
    for name in ("torus-knot turning", "sphere crossing"):
        assert video[f"{name}: change held / regenerated"] < 1.0
