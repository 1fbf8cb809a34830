"""Camera paths: smooth interpolation through every keyframe, clear errors, recording round trip."""

import json

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.scene.camera import Camera, Pose, View
from illusio.viewer.path import CameraPath, Keyframe, PathRecorder


def random_path(rng, n=5):
    times = np.cumsum(rng.uniform(0.3, 2.0, n)) - 0.3
    return CameraPath(
        [Keyframe(float(t), tuple(rng.uniform(-3, 3, 3)), tuple(rng.uniform(-3, 3, 3) + (0, 0, 10))) for t in times]
    )


def test_path_passes_through_every_keyframe_and_holds_outside(rng):
    path = random_path(rng)
    for k in path.keyframes:
        eye, target = path.at(k.t)
        np.testing.assert_allclose(eye, k.eye, atol=1e-12)
        np.testing.assert_allclose(target, k.target, atol=1e-12)
    np.testing.assert_allclose(path.at(path.keyframes[0].t - 5)[0], path.keyframes[0].eye)
    np.testing.assert_allclose(path.at(path.duration + 5)[0], path.keyframes[-1].eye)


def test_path_velocity_is_continuous_at_keyframes(rng):
    """Hermite segments with shared tangents: the velocity just before and just after an inner
    keyframe agree (a piecewise-linear path would jump)."""
    path = random_path(rng)
    h = 1e-6
    for k in path.keyframes[1:-1]:
        before = (path.at(k.t)[0] - path.at(k.t - h)[0]) / h
        after = (path.at(k.t + h)[0] - path.at(k.t)[0]) / h
        np.testing.assert_allclose(before, after, rtol=1e-3, atol=1e-3)


def test_bad_camera_paths_say_where(tmp_path):
    bad_json = tmp_path / "bad.json"
    bad_json.write_text('[{"t": 0, "eye": [0, 0, 1], "target": [0, 0, 0]},\n {"t": 1, "eye": [0, 0 1]}]')
    with pytest.raises(InputError, match=r"line 2, column \d+"):
        CameraPath.load(bad_json)
    for data, message in (
        ([{"t": 0, "eye": [0, 0, 1]}], "keyframe 1 must be an object"),
        ([{"t": 0, "eye": [0, 0, 1], "target": [0, 0]}], "keyframe 1: eye and target need 3"),
        (
            [{"t": 1, "eye": [0, 0, 1], "target": [0, 0, 0]}, {"t": 0.5, "eye": [0, 0, 2], "target": [0, 0, 0]}],
            "keyframe 2: time 0.5 s is not after",
        ),
        ([{"t": 0, "eye": [1, 1, 1], "target": [1, 1, 1]}], "the same point"),
        ({"t": 0}, "a JSON list"),
        ([], "at least one keyframe"),
    ):
        with pytest.raises(InputError, match=message):
            CameraPath.parse(json.dumps(data))
    with pytest.raises(InputError, match="no such camera path"):
        CameraPath.load(tmp_path / "missing.json")


def test_recorded_walk_saves_and_loads_as_the_same_path(rng, tmp_path):
    recorder = PathRecorder(interval=0.25)
    camera = Camera(50.0, 0.1, 50.0)
    views = []
    for i in range(40):  # 30 fps for 1.3 s
        eye = np.array([np.sin(i / 10), 1.5, 3 - i * 0.05])
        views.append(View(Pose(tuple(eye), tuple(eye + (0, 0, -1))), camera))
        recorder.add(i / 30, views[-1])
    file = recorder.save(tmp_path / "walk.json")
    path = CameraPath.load(file)
    assert [k.t for k in path.keyframes][:3] == pytest.approx([0.0, 0.2667, 0.5333], abs=1e-3)
    assert path.duration == pytest.approx(39 / 30)
    # the recorded path passes through the walk's views at its keyframes and stays near it between
    for i, view in enumerate(views):
        eye, _ = path.at(i / 30)
        assert np.linalg.norm(eye - view.pose.position) < 0.03  # a 1 m wiggle sampled 4 times a second
