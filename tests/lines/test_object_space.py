"""Object-space lines and the agreement of the two apparent-ridge methods."""

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.lines import analytic
from illusio.lines.compare import line_mask, score
from illusio.lines.curvature import estimate_curvature
from illusio.lines.drawing import LineRenderer, framing_view
from illusio.lines.object_space import (
    boundaries,
    chain,
    contours,
    ridges,
    suggestive_contours,
    valleys,
    vertex_gradient,
    zero_crossings,
)
from illusio.lines.params import LineParams
from illusio.scene.builtin import shape
from illusio.scene.mesh import load_mesh


def test_sphere_contour_lies_on_the_tangent_cone():
    """From an eye at distance D, the contour of a unit sphere is the circle of points p with
    p·(eye − p) = 0, i.e. p·eye = 1: every segment end must satisfy it (to the mesh's accuracy)."""
    mesh, _, _ = analytic.icosphere(5)
    curv = estimate_curvature(mesh, cache=False)
    eye = np.array([0.3, 0.5, 4.0])
    segs = contours(mesh, curv, eye)
    assert len(segs) > 100
    p = segs.points.reshape(-1, 3)
    np.testing.assert_allclose(p @ eye, 1.0, atol=0.02)
    lines = chain(segs)
    assert len(lines) <= 3 and sum(len(line) for line in lines) >= len(segs)  # one closed loop (or few pieces)


def test_zero_crossings_interpolate_linearly(rng):
    mesh, _, _ = analytic.icosphere(3)
    height = mesh.vertices[:, 2].astype(np.float64) - 0.3
    segs = zero_crossings(mesh, height)
    np.testing.assert_allclose(segs.points[..., 2], 0.3, atol=1e-6)  # linear field: exact


def test_vertex_gradient_of_a_linear_field_is_exact(rng):
    mesh, _, _ = analytic.icosphere(3)
    g = rng.normal(size=3)
    grad = vertex_gradient(mesh, mesh.vertices @ g)
    # the mesh-surface gradient is the tangential part of g
    tangential = g - mesh.normals * (mesh.normals @ g)[:, None]
    assert np.median(np.linalg.norm(grad - tangential, axis=1)) < 0.05 * np.linalg.norm(g)


def test_ellipsoid_ridges_and_valleys_where_expected():
    """On an ellipsoid with axes a > b > c, k_max is maximal along the ellipse through the two ends
    of the longest axis in the (x, z) plane... the ridges lie on the principal planes y = 0 or z = 0,
    and an ellipsoid has no valleys (k_min > 0 everywhere)."""
    mesh, _, _ = analytic.ellipsoid((1.5, 1.0, 0.6), 5)
    curv = estimate_curvature(mesh, cache=False)
    scale = curv.scale()
    r = ridges(mesh, curv, 0.5, scale)
    assert len(r) > 20
    p = r.points.reshape(-1, 3)
    near_plane = np.minimum(np.abs(p[:, 1]), np.abs(p[:, 2])) < 0.08
    assert near_plane.mean() > 0.9
    assert len(valleys(mesh, curv, 0.5, scale)) == 0


def test_no_suggestive_contours_on_a_sphere():
    mesh, _, _ = analytic.icosphere(4)
    curv = estimate_curvature(mesh, cache=False)
    assert len(suggestive_contours(mesh, curv, (0.0, 0.0, 4.0), 0.05, curv.scale())) == 0


@pytest.mark.parametrize("name", ["bunny.off", "fandisk.off", "decimated-max.obj"])
def test_hybrid_and_object_space_apparent_ridges_agree(ctx, models, name):
    """The hybrid method's lines include the occluding contours (q1 → ∞ there), so they are compared
    with Judd's object-space apparent ridges plus object-space contours: F1 of line pixels within
    3 px ≥ 0.8 with default settings (measured 0.95 on these meshes at 512²)."""
    mesh = load_mesh(models / name)
    renderer = LineRenderer(ctx)
    renderer.prepare(mesh)
    view = framing_view(mesh)
    hybrid = renderer.render(Frame(view, (512, 512)), LineParams(lines=("apparent-ridges",)))
    judd = renderer.render(
        Frame(view, (512, 512)), LineParams(lines=("apparent-ridges", "silhouettes"), method="object-space")
    )
    s = score(line_mask(hybrid), line_mask(judd), 3.0)
    assert s.f1 >= 0.8, str(s)
    renderer.release()


def test_boundaries_are_the_edges_one_face_uses(ctx):
    """rtsc's mesh boundaries: an open plane's four sides (their length is its perimeter, chained into
    one closed loop), none on a closed sphere, none on a box stored as six separate faces (welded by
    position first); drawn, they outline the plane seen from above."""
    from illusio.scene.builtin import shapes
    from illusio.scene.camera import Camera, Pose, View

    plane = shapes.plane((2.0, 1.0))
    segs = boundaries(plane)
    lengths = np.linalg.norm(segs.points[:, 1] - segs.points[:, 0], axis=1)
    assert lengths.sum() == pytest.approx(6.0)
    loops = chain(segs)
    assert len(loops) == 1 and np.allclose(loops[0][0], loops[0][-1])
    border = np.maximum(np.abs(segs.points[..., 0]) / 1.0, np.abs(segs.points[..., 2]) / 0.5)
    assert np.allclose(border, 1.0)  # every end on the rim
    assert len(boundaries(analytic.icosphere(3)[0])) == 0
    assert len(boundaries(shapes.box((1, 1, 1)))) == 0
    for name in ("sphere", "torus", "blob", "torus-knot"):  # seams of sin 0 against sin 2π, −0.0 against 0.0
        assert len(boundaries(shape(name))) == 0, name
    renderer = LineRenderer(ctx)
    renderer.prepare(plane)
    view = View(Pose((0.0, 3.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, -1.0)), Camera(45.0, 0.1, 10.0))
    image = renderer.render(Frame(view, (200, 200)), LineParams(lines=("boundaries",)))
    ink = image.max(axis=-1) < 0.5
    rows, cols = np.nonzero(ink)
    assert ink.mean() > 0.005 and ink[90:110, 90:110].sum() == 0  # an outline, empty inside
    assert (cols.max() - cols.min()) > 1.5 * (rows.max() - rows.min())  # 2 m wide, 1 m deep


def test_k_zero_and_h_zero_curves_of_tori_where_geometry_puts_them():
    """A torus (axis y, tube radius r around a circle of radius R): K = 0 on its top and bottom
    circles (|y| = r, R from the axis); H = 0, for a fat torus (R < 2r), where cos v = −R/(2r) (the
    circles R + r cos v from the axis, |y| = r sin v). Estimated curvature, so within a few %."""
    from illusio.lines.object_space import mean_zero_lines, parabolic_lines
    from illusio.scene.builtin import shapes

    thin = shapes.torus(1.0, 0.35, 160, 64)
    segs = parabolic_lines(thin, estimate_curvature(thin, cache=False))
    p = segs.points.reshape(-1, 3)
    assert len(segs) > 100
    np.testing.assert_allclose(np.abs(p[:, 1]), 0.35, atol=0.01)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 2]), 1.0, atol=0.02)
    fat = shapes.torus(1.0, 0.7, 160, 96)
    v = np.arccos(-1.0 / 1.4)
    segs = mean_zero_lines(fat, estimate_curvature(fat, cache=False))
    p = segs.points.reshape(-1, 3)
    assert len(segs) > 100
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 2]), 1.0 + 0.7 * np.cos(v), atol=0.03)
    np.testing.assert_allclose(np.abs(p[:, 1]), 0.7 * np.sin(v), atol=0.03)
    assert len(mean_zero_lines(thin, estimate_curvature(thin, cache=False))) == 0  # R > 2r: none


def test_isophotes_of_a_sphere_are_circles_of_constant_n_dot_l(rng):
    """On a unit sphere n = p, so the isophote n·l = c is the circle p·l = c (estimated normals, so
    within 0.01)."""
    from illusio.lines.object_space import isophotes

    mesh, _, _ = analytic.icosphere(4)
    curv = estimate_curvature(mesh, cache=False)
    light = rng.normal(size=3)
    light /= np.linalg.norm(light)
    level = float(rng.uniform(0.1, 0.9))
    segs = isophotes(mesh, curv.normals, light, level)
    p = segs.points.reshape(-1, 3)
    assert len(segs) > 50
    np.testing.assert_allclose(p @ light, level, atol=0.01)


def _phase(segments, wavenumber):
    """k·x mod 2π of the segment ends away from the sheet's border (the estimate is one-sided there)."""
    p = segments.points.reshape(-1, 3)
    inner = (np.abs(p[:, 0]) < 0.8) & (np.abs(p[:, 1]) < 0.8)
    return np.mod(wavenumber * p[inner, 0], 2 * np.pi)


def test_suggestive_highlights_contours_and_dwkr_on_a_corrugated_sheet():
    """z = a sin(kx) seen from far off, tilted 40° towards +x (steeper than the folds, tan 40° > ak:
    no point faces the eye): across the folds n·v is largest where the slope turns towards the eye
    (kx = π) and smallest where it turns away (kx = 0), both at inflections (κ_r = 0). So the
    suggestive highlights (n·v a maximum along w) lie on kx ≡ π, the suggestive contours (a
    minimum) on kx ≡ 0, and D_w κ_r — the derivative of the fold's curvature along w, τ_r = 0
    here — changes sign where that curvature is extreme, kx ≡ π/2 (mod π): the DwKr lines at 0."""
    from illusio.lines.object_space import dwkr_lines, suggestive_highlights

    mesh, _, _ = analytic.corrugated(0.1, 2 * np.pi)
    curv = estimate_curvature(mesh, cache=False)
    tilt = np.radians(40)
    eye = 50 * np.array([np.sin(tilt), 0.0, np.cos(tilt)])
    scale = curv.scale()
    highlights = _phase(suggestive_highlights(mesh, curv, eye, 0.05, scale), 2 * np.pi)
    contours_ = _phase(suggestive_contours(mesh, curv, eye, 0.05, scale), 2 * np.pi)
    dwkr = _phase(dwkr_lines(mesh, curv, eye, 0.0, scale), 2 * np.pi)
    assert len(highlights) > 100 and len(contours_) > 100 and len(dwkr) > 100
    np.testing.assert_allclose(highlights, np.pi, atol=0.05)
    np.testing.assert_allclose(np.minimum(contours_, 2 * np.pi - contours_), 0.0, atol=0.05)
    np.testing.assert_allclose(np.mod(dwkr, np.pi), np.pi / 2, atol=0.05)
    # a threshold keeps D_w κ_r at that level: its lines move off the extremes of the curvature
    shifted = _phase(dwkr_lines(mesh, curv, eye, 0.5, scale), 2 * np.pi)
    assert len(shifted) > 100 and np.abs(np.mod(shifted, np.pi) - np.pi / 2).min() > 0.05


def test_principal_highlights_where_the_surface_faces_the_eye():
    """Principal highlights (w ⊥ e_max on convex parts): on an open cylinder seen from the side, the
    generator facing the eye (x = 0, z = r); on the corrugated sheet seen 25° off its normal with
    ak = 0.75 > tan 25°, the crests' points whose normal points at the eye, cos kx = −tan 25°/(ak)."""
    from illusio.lines.object_space import principal_highlights

    mesh, _, _ = analytic.cylinder(0.5, 2.0)
    curv = estimate_curvature(mesh, cache=False)
    segs = principal_highlights(mesh, curv, np.array([0.0, 0.3, 4.0]), 0.05, curv.scale())
    p = segs.points.reshape(-1, 3)
    assert len(segs) > 50 and np.ptp(p[:, 1]) > 1.5
    np.testing.assert_allclose(p[:, 0], 0.0, atol=0.01)
    np.testing.assert_allclose(p[:, 2], 0.5, atol=0.01)
    sheet, _, _ = analytic.corrugated(0.12, 2 * np.pi)
    curv = estimate_curvature(sheet, cache=False)
    tilt = np.radians(25)
    segs = principal_highlights(sheet, curv, 50 * np.array([np.sin(tilt), 0.0, np.cos(tilt)]), 0.05, curv.scale())
    expected = np.arccos(-np.tan(tilt) / (0.12 * 2 * np.pi))
    phase = _phase(segs, 2 * np.pi)
    assert len(phase) > 100
    np.testing.assert_allclose(phase, expected, atol=0.06)
    # none on a concave part: the sheet seen from below (normals away) has no convex face towards it
    assert (
        len(principal_highlights(sheet, curv, -50 * np.array([np.sin(tilt), 0.0, np.cos(tilt)]), 0.05, curv.scale()))
        == 0
    )


def test_zero_crossing_kernel_matches_its_numpy_reference(rng):
    """The numba zero crossings (every object-space line type goes through them) give the NumPy
    reference's segments exactly — points, edge keys, order — with and without a face filter and
    strengths, on the mesh's own float32 / int32 arrays."""
    from illusio.lines.object_space import _crossings, _crossings_reference

    mesh = shape("torus-knot")
    v = np.asarray(mesh.vertices)
    values = v.astype(np.float64) @ rng.normal(size=3) + rng.normal() * 0.1
    keep = rng.random(len(mesh.faces)) < 0.7
    strength = rng.random(len(v))
    for keep_face, st in ((None, None), (keep, strength)):
        got = _crossings(v, mesh.faces, values, keep_face, st)
        want = _crossings_reference(v.astype(np.float64), np.asarray(mesh.faces, np.int64), values, keep_face, st)
        assert len(got) > 20
        np.testing.assert_array_equal(got.points, want.points)
        np.testing.assert_array_equal(got.edges, want.edges)
        np.testing.assert_allclose(got.strength, want.strength, rtol=0, atol=1e-12)
