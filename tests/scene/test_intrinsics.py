"""Intrinsics and lens distortion (scene.intrinsics): undistortion by OpenCV's model, and its
inverse used to make test photographs."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.scene.intrinsics import Intrinsics, distort_image, undistort_image

LENS = Intrinsics(160, 120, 118.0, 126.0, 81.0, 58.0, "OPENCV", (-0.15, 0.02, 0.001, -0.002))


def test_distort_then_undistort_gives_the_image_back():
    yy, xx = np.mgrid[0:120, 0:160]
    image = np.stack([np.sin(xx / 6.0), np.cos(yy / 8.0), np.sin((xx + yy) / 9.0)], axis=-1).astype(np.float32)
    back = undistort_image(distort_image(image, LENS), LENS)
    inner = (slice(12, -12), slice(16, -16))
    assert np.abs(back[inner] - image[inner]).mean() < 0.01
    assert np.abs(distort_image(image, LENS)[inner] - image[inner]).mean() > 0.05  # it did move (0.078)


def test_a_pixel_lands_where_the_model_puts_it():
    """A single bright pixel of the pinhole image, distorted: it lands at OpenCV's model of its ray
    (x'' = x(1 + k1 r² + k2 r⁴) + 2 p1 x y + p2 (r² + 2x²), …)."""
    image = np.zeros((120, 160, 1), np.float32)
    u, v = 30, 20
    image[v, u] = 1.0
    x, y = (u - LENS.cx) / LENS.fx, (v - LENS.cy) / LENS.fy
    k1, k2, p1, p2 = LENS.distortion
    r2 = x * x + y * y
    xd = x * (1 + k1 * r2 + k2 * r2 * r2) + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * (1 + k1 * r2 + k2 * r2 * r2) + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    recorded = distort_image(image, LENS)[..., 0]
    vv, uu = np.unravel_index(np.argmax(recorded), recorded.shape)
    assert abs(uu - (xd * LENS.fx + LENS.cx)) <= 1 and abs(vv - (yd * LENS.fy + LENS.cy)) <= 1


def test_bad_intrinsics_are_refused():
    with pytest.raises(InputError, match="positive"):
        Intrinsics(0, 120, 100.0, 100.0, 50.0, 50.0)
    with pytest.raises(InputError, match="OPENCV with"):
        Intrinsics(160, 120, 100.0, 100.0, 50.0, 50.0, "OPENCV", (0.1,))
