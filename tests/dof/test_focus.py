"""The interactive focus policies of section 4.2, on maps made up for the purpose and on the museum."""

from dataclasses import replace

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.dof import DofParams, DofRenderer, object_distance
from illusio.dof.focus import gaze_focus, largest_focus, nearest_exhibit_focus, speed_focus
from illusio.scene import load_scene
from illusio.scene.camera import Pose, View


def maps():
    ids = np.full((60, 80), 1, np.int64)  # a wall (node 0) at 9 m
    depth = np.full((60, 80), 9.0)
    ids[20:40, 30:50], depth[20:40, 30:50] = 3, 4.0  # a small object at the centre, 4 m
    ids[:, :25], depth[:, :25] = 2, 6.0  # a big one on the left, 6 m
    ids[29:31, 39:41], depth[29:31, 39:41] = 1, 9.0  # a thin gap at the very centre
    return ids, depth


def test_gaze_looks_through_a_window_not_a_texel():
    ids, depth = maps()
    assert gaze_focus(ids, depth) == pytest.approx(4.0)  # the gap does not send it to the wall
    assert gaze_focus(np.zeros_like(ids), depth) is None


def test_largest_object_and_its_candidates():
    ids, depth = maps()
    assert largest_focus(ids, depth) == pytest.approx(9.0)  # the wall covers most
    assert largest_focus(ids, depth, {2, 3}) == pytest.approx(6.0)
    assert largest_focus(ids, depth, {7}) is None


def test_speed_looks_farther_when_walking_faster():
    assert speed_focus(0.0) == pytest.approx(2.0)
    assert speed_focus(2.0) > speed_focus(1.0) > speed_focus(0.0)


def test_policies_in_the_museum(ctx):
    museum = load_scene("museum")
    node = museum.node("exhibit-superquadric")  # a solid one: the torus's hole would show the wall
    lo, hi = node.mesh.bounds
    centre = node.transform[:3, :3] @ ((np.asarray(lo) + hi) / 2) + node.transform[:3, 3]
    view = View(Pose(tuple(centre + (0.0, 0.4, 3.0)), tuple(centre)), museum.camera().camera)
    assert nearest_exhibit_focus(museum, view) == pytest.approx(object_distance(museum, "exhibit-superquadric", view))
    behind = View(Pose(view.pose.position, tuple(2 * np.asarray(view.pose.position) - view.pose.target)), view.camera)
    assert nearest_exhibit_focus(museum, behind) is None  # the exhibits are behind the visitor: none in sight
    renderer = DofRenderer(ctx)
    renderer.prepare(museum)
    gaze = DofParams(policy="gaze", accommodation=0.0)
    renderer.render(Frame(view, (96, 72)), gaze)
    assert renderer.result().focus_distance == pytest.approx(
        object_distance(museum, "exhibit-superquadric", view), rel=0.15
    )
    # the speed policy reads the viewer's walk from frame to frame
    speed = replace(gaze, policy="speed")
    renderer.render(Frame(view, (48, 36), time=0.0), speed)
    moved = View(
        Pose(tuple(np.asarray(view.pose.position) - (0, 0, 2.0)), tuple(np.asarray(view.pose.target) - (0, 0, 2.0))),
        view.camera,
    )
    renderer.render(Frame(moved, (48, 36), time=1.0), speed)
    assert renderer.result().focus_distance == pytest.approx(speed_focus(2.0))
    # accommodation: the focus follows a change over time, in dioptres
    slow = replace(gaze, accommodation=1.0)
    renderer.release()
    renderer.prepare(museum)
    far = View(Pose((0.0, 1.6, 6.0), (0.0, 1.6, -5.0)), view.camera)
    renderer.render(Frame(far, (48, 36), time=0.0), slow)
    start = renderer.result().focus_distance
    renderer.render(Frame(view, (48, 36), time=0.5), slow)
    halfway = renderer.result().focus_distance
    target = gaze_target = object_distance(museum, "exhibit-superquadric", view)
    assert min(start, gaze_target) < halfway < max(start, target)
    renderer.release()
