"""The per-pixel method's direct light (relight.per_pixel): one-sided lamps."""

import numpy as np
import pytest

from illusio.radiosity import Polygons
from illusio.radiosity.reference import point_polygon_form_factor
from illusio.relight.per_pixel import lamp_irradiance, surface_points
from illusio.scene.camera import Camera, Pose, View


def _quad(centre, half_u, half_v, down=False):
    c, u, v = (np.asarray(x, float) for x in (centre, half_u, half_v))
    q = np.array([c - u + v, c + u + v, c + u - v, c - u - v])  # facing +y for u = x, v = z
    return q[::-1] if down else q


def _floor_under_lamp(lamp_faces_down: bool):
    corners = np.array(
        [
            _quad((0, 0, 0), (2, 0, 0), (0, 0, 2)),  # floor, up
            _quad((0.3, 1.5, 0), (0.2, 0, 0), (0, 0, 0.2), down=lamp_faces_down),
        ]
    )
    polygons = Polygons(
        corners,
        np.zeros(2, bool),
        np.array([[0.5] * 3, [0.0] * 3]),
        np.array([[0.0] * 3, [50.0] * 3]),
        np.arange(2),
        ["floor", "lamp"],
        [1],
    )
    view = View(Pose((0.0, 4.0, 0.01), (0.0, 0.0, 0.0)), Camera(fov_y=40.0))
    points, normals, polygon = surface_points(polygons, view, (32, 32))
    seen = polygon == 0
    return (
        polygons,
        lamp_irradiance(polygons, np.array([1]), polygons.exitance[[1]], points, normals, seen, samples=16)[:, 0],
        points[seen],
    )


def test_a_lamp_facing_away_lights_nothing():
    """The floor under a lamp that faces up receives nothing from it (the contour integral's
    absolute value gave it the light of a lamp facing down)."""
    _, away, _ = _floor_under_lamp(lamp_faces_down=False)
    assert np.all(away == 0)


def test_a_lamp_facing_the_floor_lights_it_by_the_contour_integral():
    polygons, direct, x = _floor_under_lamp(lamp_faces_down=True)
    rng = np.random.default_rng(2)
    for k in rng.choice(len(x), 20, replace=False):
        f = point_polygon_form_factor(x[k], (0.0, 1.0, 0.0), polygons.corners[1])
        assert direct[k, 0] == pytest.approx(f * 50.0, rel=1e-6)
    assert direct.min() > 0
