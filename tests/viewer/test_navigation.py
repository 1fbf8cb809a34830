"""Walking and orbiting: keys and mouse moves change the view as a person expects."""

import numpy as np
import pytest

from illusio.scene.camera import Camera, Pose, View
from illusio.viewer.navigation import OrbitCamera, WalkCamera


def test_walk_camera_starts_at_the_view_and_walks_along_its_heading(rng):
    eye, target = rng.uniform(-2, 2, 3), rng.uniform(-2, 2, 3) + (0, 0, -5)
    walk = WalkCamera.from_view(View(Pose(tuple(eye), tuple(target)), Camera()), speed=2.0)
    direction = (target - eye) / np.linalg.norm(target - eye)
    np.testing.assert_allclose(walk.forward, direction, atol=1e-9)
    start = walk.position.copy()
    walk.move({"w"}, 0.5)
    heading = np.array([direction[0], 0, direction[2]]) / np.hypot(direction[0], direction[2])
    np.testing.assert_allclose(walk.position - start, heading * 1.0, atol=1e-9)  # 2 m/s for 0.5 s, level
    walk.move({"d"}, 0.5)
    side = walk.position - start - heading
    assert abs(side @ heading) < 1e-9 and np.cross(heading, side)[1] < 0  # to the right of the heading
    walk.move({"e"}, 0.25)
    assert walk.position[1] - start[1] == pytest.approx(0.5)


def test_mouse_look_turns_and_clamps_the_pitch():
    walk = WalkCamera(np.zeros(3), 0.0, 0.0, Camera(), sensitivity=0.5)
    walk.look(-180, 0)  # drag left by 180 px: turn left 90°
    np.testing.assert_allclose(walk.forward, (-1, 0, 0), atol=1e-9)
    walk.look(0, -1000)
    assert walk.pitch == 89.0


def test_orbit_keeps_its_target_and_distance_and_zooms():
    view = View(Pose.orbit((1, 2, 3), 4.0, 30, 20), Camera(30, 0.4, 12.0))
    orbit = OrbitCamera.from_view(view)
    assert (
        orbit.distance == pytest.approx(4.0)
        and orbit.azimuth == pytest.approx(30)
        and orbit.elevation == pytest.approx(20)
    )
    orbit.look(50, -30)
    orbit.move({"a", "w"}, 0.3)
    v = orbit.view()
    assert np.linalg.norm(np.subtract(v.pose.position, (1, 2, 3))) == pytest.approx(4.0)
    orbit.zoom(3)
    v = orbit.view()
    assert np.linalg.norm(np.subtract(v.pose.position, (1, 2, 3))) == pytest.approx(4.0 * 0.9**3)
    assert v.camera.near == pytest.approx(0.4 * 0.9**3)  # the planes follow the zoom
