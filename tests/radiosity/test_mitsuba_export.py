"""Mitsuba's scene of the polygons: each polygon seen at its own reflectance, in a handful of shapes
however many reflectances there are (``without_textures`` gives each textured polygon its own)."""

from __future__ import annotations

import numpy as np
import pytest

from illusio.radiosity.polygons import Polygons
from illusio.scene.camera import Camera, Pose, View


def _floor_under_a_lamp(left, right) -> Polygons:
    """Two floor quads (x < 0 of reflectance ``left``, x > 0 of ``right``) facing up at y = 0, and a
    small lamp facing down at y = 1 over the seam: mirrored points get the same irradiance."""
    floor = [[[x0, 0, 1], [x1, 0, 1], [x1, 0, -1], [x0, 0, -1]] for x0, x1 in ((-1.0, 0.0), (0.0, 1.0))]
    lamp = [[-0.1, 1, -0.1], [0.1, 1, -0.1], [0.1, 1, 0.1], [-0.1, 1, 0.1]]
    return Polygons(
        np.array([*floor, lamp], np.float64),
        np.zeros(3, bool),
        np.array([left, right, [0, 0, 0]], np.float64),
        np.array([[0, 0, 0], [0, 0, 0], [20, 20, 20]], np.float64),
        np.array([0, 0, 1]),
        ["floor", "lamp"],
        [1],
    )


def test_each_polygon_its_own_reflectance_in_one_shape(rng, tmp_path):
    """The two halves of one floor, each its own random reflectance, are one Mitsuba shape holding only
    its own 8 vertices; lit by direct light alone, mirrored pixels are in the ratio of the halves'
    reflectances (within 5 %: Mitsuba's noise at 64 paths over about a hundred pixels)."""
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    from illusio.radiosity.mitsuba import _scene_dict, render_mitsuba

    left, right = rng.uniform(0.1, 0.9, 3), rng.uniform(0.1, 0.9, 3)
    polygons = _floor_under_a_lamp(left, right)
    shapes = [v for k, v in _scene_dict(polygons, tmp_path).items() if k != "type"]
    assert sorted(s.vertex_count() for s in shapes) == [4, 8]

    view = View(Pose((0, 3, 0), (0, 0, 0), (0, 0, -1)), Camera(fov_y=60))
    image = render_mitsuba(polygons, view, (32, 32), 64, seed=int(rng.integers(1 << 30)), max_depth=2)
    mirrored = image[:, ::-1]
    # both pixels on the floor (the lamp's dark back hides the middle), a pixel a side of the seam
    lit = (image.mean(axis=2) > 0) & (mirrored.mean(axis=2) > 0)
    lit[:, 15:17] = False
    right_half = lit & (np.arange(32) >= 16)[None, :]
    ratio = image[right_half].sum(axis=0) / mirrored[right_half].sum(axis=0)
    print(f"{right_half.sum()} pixels, ratio {ratio} for reflectances {right / left}")
    assert right_half.sum() > 100
    np.testing.assert_allclose(ratio, right / left, rtol=0.05)
