"""Drawing scores, and the lines/curvature commands."""

import numpy as np
import pytest

from tests.conftest import call_cli as call
from illusio.lines.compare import image_edges, score


def test_scores_of_a_shifted_line():
    a = np.zeros((50, 60), bool)
    a[20, 5:55] = True
    b = np.roll(a, 3, axis=0)
    within = score(a, b, tolerance=3)
    assert within.precision == within.recall == 1.0 and within.chamfer == pytest.approx(3.0)
    beyond = score(a, b, tolerance=2)
    assert beyond.f1 == 0.0
    assert score(a, a).f1 == 1.0 and score(a, a).chamfer == 0.0


def test_canny_finds_a_square_outline():
    img = np.ones((80, 80), np.float32)
    img[20:60, 20:60] = 0.2
    edges = image_edges(img, "canny")
    outline = np.zeros_like(edges)
    outline[20:60, [20, 59]] = outline[[20, 59], 20:60] = True
    assert score(edges, outline, 2).f1 > 0.9




def test_lines_cli_png_svg_and_curvature(tmp_path, capsys):
    png, svg, npz = tmp_path / "knot.png", tmp_path / "knot.svg", tmp_path / "knot.npz"
    code, out = call(["lines", "torus-knot", "-o", str(png), "--size", "256x256", "--compare", "canny"], capsys)
    out = out.out
    assert code == 0 and png.exists() and (tmp_path / "knot-compare.png").exists() and "F1" in out
    assert call(["lines", "torus-knot", "-o", str(svg), "--size", "256x256", "--lines", "apparent-ridges,silhouettes,ridges"], capsys)[0] == 0
    text = svg.read_text()
    assert text.count("<polyline") > 5 and 'id="silhouettes"' in text
    assert call(["curvature", "sphere", "-o", str(npz)], capsys)[0] == 0
    with np.load(npz) as data:
        assert np.isfinite(data["k_max"]).all() and (data["k_min"] > 0).mean() > 0.95


@pytest.mark.parametrize("args", [["lines", "missing.obj", "-o", "x.png"], ["lines", "sphere", "-o", "x.jpg"],
                                  ["lines", "sphere", "-o", "x.png", "--lines", "edges"],
                                  ["lines", "sphere", "-o", "x.png", "--view", "10"],
                                  ["curvature", "sphere", "-o", "x.txt"]])
def test_bad_input_is_one_line_and_exit_2(tmp_path, monkeypatch, capsys, args):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.obj").write_text("v 1 2\nf 1 2 3\n")
    code, out = call(args, capsys)
    assert code == 2
    err = out.err.strip()
    assert err.startswith("illusio: error:") and "\n" not in err
    assert not list(tmp_path.glob("x.*"))
