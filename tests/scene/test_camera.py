import math

import numpy as np
import pytest

from illusio.core import InputError
from illusio.scene import Camera, Pose, Screen, StereoRig, View


def test_project_and_ray_directions_agree(rng):
    view = View(Pose((0.3, 1.2, 4.0), (0.1, 0.4, 0.0)), Camera(47.0, 0.1, 50.0, shift=(0.05, -0.02)))
    size = (64, 48)
    dirs = view.ray_directions(size)
    ys, xs = rng.integers(0, 48, 20), rng.integers(0, 64, 20)
    points = np.asarray(view.pose.position) + dirs[ys, xs] * rng.uniform(1, 10, (20, 1))
    px, depth = view.project(points, size)
    np.testing.assert_allclose(px, np.c_[xs + 0.5, ys + 0.5], atol=1e-4)  # float32 matrices
    assert (depth > 0).all()


def test_orbit_looks_at_target_from_distance():
    pose = Pose.orbit((1, 2, 3), 5.0, azimuth=90.0, elevation=0.0)
    np.testing.assert_allclose(pose.position, (6, 2, 3), atol=1e-9)
    _, _, forward = pose.axes()
    np.testing.assert_allclose(forward, (-1, 0, 0), atol=1e-6)


def test_screen_width_from_diagonal_and_aspect():
    s = Screen(53.0, 16 / 9, 1920)
    assert math.isclose(s.width_cm, (16 / 9) * 53 / math.sqrt(1 + (16 / 9) ** 2))
    assert math.isclose(math.hypot(s.width_cm, s.height_cm), 53.0)
    assert s.height_px == 1080


def test_stereo_rig_zero_parallax_at_screen_and_no_toe_in(rng):
    base = View(Pose((0, 1.6, 3.0), (0, 1.2, 0)), Camera(50.0, 0.05, 100.0))
    rig = StereoRig(base, eye_separation=0.065, screen_distance=2.5)
    left, right = rig.left, rig.right
    np.testing.assert_allclose(left.pose.axes()[2], right.pose.axes()[2], atol=1e-7)  # parallel axes
    np.testing.assert_allclose(
        np.subtract(right.pose.position, left.pose.position), base.pose.axes()[0] * 0.065, atol=1e-7
    )
    size = (800, 600)
    r, u, f = base.pose.axes()
    eye = np.asarray(base.pose.position)
    for distance, sign in ((2.5, 0), (6.0, +1), (1.2, -1)):
        pts = eye + f * distance + np.outer(rng.uniform(-0.5, 0.5, 10), r) + np.outer(rng.uniform(-0.3, 0.3, 10), u)
        pl, _ = left.project(pts, size)
        pr, _ = right.project(pts, size)
        parallax = pr[:, 0] - pl[:, 0]
        np.testing.assert_allclose(pl[:, 1], pr[:, 1], atol=1e-6)  # no vertical parallax
        if sign == 0:
            np.testing.assert_allclose(parallax, 0, atol=1e-4)
        else:
            assert (np.sign(parallax) == sign).all()  # uncrossed behind the screen, crossed in front


def test_stereo_rig_from_screen_matches_viewing_angle():
    s = Screen()
    rig = StereoRig.from_screen(s, Pose((0, 0, 1.0), (0, 0, 0)))
    assert math.isclose(rig.view.camera.fov_y, math.degrees(2 * math.atan(s.height_cm / 2 / 100)))
    assert math.isclose(rig.eye_separation, 0.065) and math.isclose(rig.screen_distance, 1.0)


def test_bad_camera_values_are_input_errors():
    with pytest.raises(InputError):
        Camera(fov_y=0)
    with pytest.raises(InputError):
        Camera(near=1.0, far=0.5)
    with pytest.raises(InputError):
        Pose((0, 0, 0), (0, 0, 0))
    with pytest.raises(InputError):
        Pose((np.nan, 0, 0))


def test_look_at_is_the_orthonormal_frame_np_cross_states(rng):
    """transforms.look_at (its cross products written out: np.cross cost 25 µs a call, several
    matrices a frame) against the frame as np.cross states it, on random eyes and targets and
    looking straight along up: the same float32 matrix."""
    from illusio.scene.transforms import look_at

    def plain(eye, target, up=(0.0, 1.0, 0.0)):
        eye = np.asarray(eye, float)
        f = np.asarray(target, float) - eye
        f /= np.linalg.norm(f)
        s = np.cross(f, up)
        if np.linalg.norm(s) < 1e-9:
            s = np.cross(f, [1.0, 0.0, 0.0] if abs(f[0]) < 0.9 else [0.0, 0.0, 1.0])
        s /= np.linalg.norm(s)
        m = np.eye(4)
        m[0, :3], m[1, :3], m[2, :3] = s, np.cross(s, f), -f
        m[:3, 3] = -m[:3, :3] @ eye
        return m.astype(np.float32)

    pairs = [(rng.normal(size=3), rng.normal(size=3)) for _ in range(200)] + [((0, 0, 0), (0, 5, 0))]
    for eye, target in pairs:
        np.testing.assert_allclose(look_at(eye, target), plain(eye, target), rtol=1e-6, atol=1e-6)
