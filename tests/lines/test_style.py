"""lines.style: the page a drawing is printed on — coverage and ink, width, antialiasing, one colour,
transparency and the fade — as properties of small drawn images."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.lines.style import LineStyle, coverage_and_ink, parse_colour, stylise


def page(h=32, w=32):
    return np.ones((h, w, 3), np.float32)


def test_coverage_and_ink_of_paper_and_inks():
    img = page(1, 4)
    img[0, 1] = 0.0  # black
    img[0, 2] = (1.0, 0.0, 0.0)  # red
    img[0, 3] = 0.5  # half-covered black
    cover, ink = coverage_and_ink(img)
    assert np.allclose(cover[0], [0, 1, 1, 0.5])
    assert np.allclose(ink[0, 1], 0) and np.allclose(ink[0, 2], [1, 0, 0]) and np.allclose(ink[0, 3], 0)


def test_width_widens_a_line_to_that_many_pixels():
    img = page()
    img[:, 10] = 0.0
    for width in (1, 3, 5):
        out = stylise(img, LineStyle(width=width))
        covered = (out[16, :, 0] < 0.5).sum()
        assert covered == width
    with pytest.raises(InputError):
        LineStyle(width=0.1)


def test_antialiasing_gives_edges_fractional_coverage_and_keeps_the_ink(rng):
    """A diagonal drawn at 2× and reduced: pixels of partial coverage along it, about as much ink as
    the same line drawn at 1× (within 40 %: the 2×2 pen thickens a staircase diagonal)."""
    big, small = page(64, 64), page(32, 32)
    for t in range(64):
        big[t, min(63, int(0.7 * t + 5))] = 0.0
    for t in range(32):
        small[t, min(31, int(0.7 * t + 2.5))] = 0.0
    aa = stylise(big, LineStyle(supersample=2))
    plain = stylise(small, LineStyle())
    cover_aa, cover_plain = 1 - aa[..., 0], 1 - plain[..., 0]
    assert ((cover_aa > 0.05) & (cover_aa < 0.95)).sum() > 10 and (
        (cover_plain > 0.05) & (cover_plain < 0.95)
    ).sum() == 0
    assert cover_aa.sum() == pytest.approx(cover_plain.sum(), rel=0.4)  # a diagonal widens a little more
    with pytest.raises(InputError):
        stylise(page(33, 32), LineStyle(supersample=2))


def test_colour_transparency_and_fade():
    img = page()
    img[:, 8] = 0.0
    img[:, 20] = (1.0, 0.0, 0.0)
    blue = stylise(img, LineStyle(colour=(0.0, 0.0, 1.0)))
    assert np.allclose(blue[:, 8], [0, 0, 1]) and np.allclose(blue[:, 20], [0, 0, 1]) and np.allclose(blue[:, 0], 1)
    rgba = stylise(img, LineStyle(transparent=True))
    assert rgba.shape == (32, 32, 4) and rgba[..., 3].max() == 1 and rgba[:, 0, 3].max() == 0
    over_white = rgba[..., :3] * rgba[..., 3:] + (1 - rgba[..., 3:])
    assert np.allclose(over_white, stylise(img, LineStyle()), atol=1e-6)
    assert np.allclose(rgba[:, 20, :3], [1, 0, 0])
    strength = np.ones((32, 32))
    strength[:, 8] = 0.25
    faded = stylise(img, LineStyle(fade=True), strength)
    assert np.allclose(faded[:, 8], 0.75) and np.allclose(faded[:, 20], [1, 0, 0])


def test_colour_parsing():
    assert parse_colour("0,0.5,1") == (0.0, 0.5, 1.0)
    assert np.allclose(parse_colour("#ffffff"), 1) and np.allclose(parse_colour("#000000"), 0)
    assert parse_colour("#808080")[0] == pytest.approx(0.2159, abs=1e-3)  # sRGB 128 is linear 0.216
    for bad in ("red", "1,2,3", "#12345", "0,0"):
        with pytest.raises(InputError):
            parse_colour(bad)


def test_debug_maps_carry_a_colour_legend(ctx):
    """The curvature debug view's bottom band is a bar from blue (concave) to red (convex) with its
    labels drawn under it; q1's is a grey ramp; the view above the band is untouched."""
    from illusio.core.renderer import Frame
    from illusio.lines.debug import debug_view
    from illusio.lines.drawing import LineRenderer, framing_view
    from illusio.scene.builtin import shapes

    mesh = shapes.torus()
    renderer = LineRenderer(ctx)
    renderer.prepare(mesh)
    view = framing_view(mesh)
    drawing = renderer.drawing(Frame(view, (200, 160)))
    curvature = renderer.curvature()
    for kind in ("curvature", "q1", "t1"):
        plain = debug_view(kind, drawing, mesh, curvature, legend=False)
        shown = debug_view(kind, drawing, mesh, curvature)
        band = 20
        assert shown.shape == plain.shape and np.array_equal(shown[:-band], plain[:-band])
        bar = shown[-band : -band // 2]
        if kind == "curvature":
            assert bar[0, 2, 2] > bar[0, 2, 0] + 0.3 and bar[0, -3, 0] > bar[0, -3, 2] + 0.3
        if kind == "q1":
            assert bar[0, 2].max() < 0.05 and bar[0, -3].min() > 0.95
        labels = shown[-band // 2 :]
        assert (labels.max(axis=-1) < 0.2).sum() > 20  # dark text under the bar
    renderer.release()
