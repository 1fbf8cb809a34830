"""The thin lens of section 2.2.1: one test per equation, and the agreement between the circle of
confusion and the accumulation method's moving eye."""

import math

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.dof.accumulation import lens_view
from illusio.dof.lens import coc_diameter, coc_pixels, fov_for_focal_length, image_distance
from illusio.scene.camera import Camera, Pose, View


def test_equation_1_thin_lens(rng):
    """1/F = 1/d + 1/d_s (the OCR's 1/d_s + 1/d_s is a slip: see shared/papers/README.md)."""
    F = rng.uniform(5, 60)
    d = rng.uniform(F * 1.01, F * 1000, 50)
    d_s = image_distance(F, d)
    np.testing.assert_allclose(1 / d + 1 / d_s, 1 / F, rtol=1e-12)
    assert (np.diff(image_distance(F, np.sort(d))) < 0).all()  # farther points focus closer to the lens
    with pytest.raises(InputError):
        image_distance(F, F * 0.5)


def test_equation_2_circle_of_confusion(rng):
    """C = A·|d_s(d) − d_s(d_f)| / d_s(d): zero at the focus distance, growing away from it, and equal
    to the closed form A·F·|d − d_f| / (d·(d_f − F))."""
    F, A = 17.0, rng.uniform(2, 8)
    d_f = rng.uniform(500, 5000)
    d = rng.uniform(100, 1e5, 200)
    c = coc_diameter(d, d_f, A, F)
    np.testing.assert_allclose(c, A * F * np.abs(d - d_f) / (d * (d_f - F)), rtol=1e-9)
    assert coc_diameter(d_f, d_f, A, F) == pytest.approx(0.0, abs=1e-12)
    near = np.sort(d[d < d_f])
    assert (np.diff(coc_diameter(near, d_f, A, F)) < 0).all()


def test_circle_in_pixels_is_the_circle_on_the_image_plane_scaled_to_the_image(rng):
    """coc_pixels = C / (image plane height) · H, the image plane at d_s(d_f) spanning the field of
    view: the focal length cancels out."""
    fov, H = rng.uniform(20, 80), 600
    A_mm, d_f = rng.uniform(5, 80), rng.uniform(0.5, 10)
    d = rng.uniform(0.2, 50, 100)
    px = coc_pixels(d, d_f, A_mm / 1000, fov, H)
    for F_mm in (17.0, 50.0, 200.0):
        plane = image_distance(F_mm / 1000, d_f) * 2 * math.tan(math.radians(fov) / 2)
        np.testing.assert_allclose(px, coc_diameter(d, d_f, A_mm / 1000, F_mm / 1000) / plane * H, rtol=1e-5)
    assert (
        coc_pixels(np.array([0.0, np.inf]), d_f, 0.01, fov, H)[0]
        == coc_pixels(np.array([np.inf]), d_f, 0.01, fov, H)[0]
    )


def test_moving_the_eye_over_the_lens_blurs_a_point_by_its_circle_of_confusion(rng):
    """The accumulation method's views: a point at the focus distance projects to the same pixel from
    every lens position; a point at depth d, seen from the rim of the lens (|offset| = A/2), moves by
    half its circle of confusion in pixels."""
    size = (640, 480)
    view = View(Pose((0.3, 1.2, 4.0), (0.1, 1.0, 0.0)), Camera(45.0, 0.05, 100.0))
    d_f, A = 2.5, 0.06
    forward = np.subtract(view.pose.target, view.pose.position)
    forward /= np.linalg.norm(forward)
    right, up, _ = view.pose.axes()
    for depth in (d_f, 1.2, 6.0):
        point = np.asarray(view.pose.position) + forward * depth + right * 0.2 - up * 0.1
        centre, _ = view.project(point[None], size)
        want = float(coc_pixels(np.array([depth]), d_f, A, view.camera.fov_y, size[1])[0]) / 2
        for angle in rng.uniform(0, 2 * np.pi, 5):
            offset = (A / 2 * np.cos(angle), A / 2 * np.sin(angle))
            moved, _ = lens_view(view, offset, d_f).project(point[None], size)
            assert np.linalg.norm(moved - centre) == pytest.approx(want, abs=1e-3)


def test_focal_length_gives_the_field_of_view_of_a_24mm_frame():
    assert fov_for_focal_length(50.0) == pytest.approx(26.99, abs=0.01)
    assert fov_for_focal_length(12.0) == pytest.approx(90.0)
