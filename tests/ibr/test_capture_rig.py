"""Where captured references stand, and which cameras and files a reference folder may name: the
rig stays in the room (issue 30: the office's reference 0 stood outside, facing a wall's back from
0.21 m); --camera indices are checked, T stays between the pair, a view's file stays in the folder."""

from __future__ import annotations

import json

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.ibr.reference_views import (
    WALL_MARGIN,
    capture,
    load_references,
    orbit_views,
    rig_placement,
    save_references,
)
from illusio.scene import load_scene
from illusio.scene.builtin import shapes
from illusio.scene.raycast import first_hit, world_triangles
from illusio.scene.scene import Node, Scene
from tests.conftest import call_cli


def test_first_hit_finds_the_nearest_face_of_a_box():
    scene = Scene("box")
    scene.add(Node("box", shapes.box((2.0, 2.0, 2.0))))  # faces at ±1
    triangles = world_triangles(scene)
    assert first_hit(triangles, (0, 0, 0), (1, 0, 0)) == pytest.approx(1.0)  # from inside, either facing
    assert first_hit(triangles, (-3, 0.2, 0.1), (1, 0, 0)) == pytest.approx(2.0)
    assert first_hit(triangles, (-3, 0, 0), (-1, 0, 0)) == float("inf")
    assert first_hit(triangles, (0, 0, 0), (1, 1, 0)) == pytest.approx(np.sqrt(2.0))


@pytest.mark.parametrize("name", ["office", "living-room", "museum"])
def test_the_capture_rig_stays_inside_the_room(name):
    scene = load_scene(name)
    triangles = world_triangles(scene)
    views = orbit_views(scene, 3, 1.2)
    main = np.asarray(scene.camera().pose.position, np.float64)
    right = scene.camera().pose.axes()[0]
    for view in views:
        eye = np.asarray(view.pose.position, np.float64)
        # on the main camera's side of every surface: nothing between the two eyes, room either side
        step = eye - main
        if np.linalg.norm(step) > 1e-9:
            assert first_hit(triangles, main, step) > np.linalg.norm(step)
        assert min(first_hit(triangles, eye, right), first_hit(triangles, eye, -right)) >= WALL_MARGIN - 1e-6
    assert rig_placement(scene, 1.2)[1] == pytest.approx(1.2)  # room for the whole baseline somewhere


def test_every_office_reference_sees_the_room(ctx):
    """Each reference's depth is mostly far from the camera (not a wall's back at 0.2 m)."""
    scene = load_scene("office")
    refs = capture(scene, orbit_views(scene, 3), (64, 48), ctx)
    for v in refs.views:
        seen = v.depth[v.depth > 0]
        assert seen.size > 0.9 * v.depth.size and np.median(seen) > 1.5


def test_camera_indices_and_t_are_checked_and_files_stay_in_the_folder(ctx, tmp_path, capsys):
    scene = load_scene("cornell-box")
    refs = capture(scene, orbit_views(scene, 2, 0.1), (32, 24), ctx)
    folder = save_references(refs, tmp_path / "refs")
    for camera, message in (
        ("ref:-1", "reference -1 does not exist; there are 2"),
        ("ref:2", "reference 2 does not exist"),
        ("between:0,1,5", "T must be in [0, 1]"),
        ("between:0,7", "reference 7 does not exist"),
    ):
        code, cap = call_cli(["ibr", "render", str(folder), "-o", str(tmp_path / "x.png"), "--camera", camera], capsys)
        assert code == 2 and message in cap.err and cap.err.count("\n") == 1, (camera, cap.err)
    assert not (tmp_path / "x.png").exists()
    # --extrapolate lets T leave the pair: the camera on the line through the two, 0.5 past reference 1
    from illusio.cli.ibr import parse_camera

    a, b = (np.asarray(v.view.pose.position) for v in refs.views)
    beyond = parse_camera("between:0,1,1.5", refs, extrapolate=True)
    assert np.allclose(beyond.pose.position, a + 1.5 * (b - a))
    code, cap = call_cli(
        ["ibr", "render", str(folder), "-o", str(tmp_path / "x.png"), "--camera", "between:0,1,1.5", "--extrapolate"],
        capsys,
    )
    assert code == 0, cap.err
    code, cap = call_cli(
        ["ibr", "render", str(folder), "-o", str(tmp_path / "y.png"), "--camera", "between:0,1,nan", "--extrapolate"],
        capsys,
    )
    assert code == 2 and "T must be in [0, 1]" in cap.err
    index = folder / "references.json"
    doc = json.loads(index.read_text())
    (tmp_path / "x.npz").write_bytes((folder / "view-0.npz").read_bytes())
    doc["views"][0]["file"] = "../x.npz"
    index.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="outside the folder"):
        load_references(folder)
