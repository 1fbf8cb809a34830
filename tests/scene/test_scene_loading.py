import numpy as np
import pytest

from illusio.core import InputError
from illusio.scene import SCENES, load_scene
from tests.conftest import REPO


def test_example_yaml_scene_loads_with_cameras_lights_curves():
    s = load_scene(REPO / "examples" / "still-life.yaml")
    assert [n.name for n in s.nodes] == ["floor", "knot", "gear", "ball"]
    assert s.camera().camera.fov_y == 40
    assert len(s.lights) == 2
    curve = s.curves["fly-by"]
    np.testing.assert_allclose(curve.evaluate([0.0, 1.0]), [[3, 1.5, 3], [-3, 1.5, 1]])


def test_yaml_syntax_error_reports_line_and_column(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("nodes:\n  - name: a\n    shape: [sphere\n")
    with pytest.raises(InputError, match=r"bad\.yaml: not valid YAML at line \d+, column \d+"):
        load_scene(p)


@pytest.mark.parametrize(
    "text,message",
    [
        ("nodes:\n  - name: a\n    shape: sphere\n    colour: [1, 0, 0]\n", "unknown key"),
        ("nodes:\n  - name: a\n    shape: teapot\n", "unknown shape"),
        ("nodes:\n  - name: a\n    mesh: missing.obj\n", "no such file"),
        ("nodes: []\n", "no nodes"),
        ("nodes:\n  - name: a\n    shape: sphere\nlights:\n  - {type: spot, position: [0, 1, 0]}\n", "point or area"),
    ],
)
def test_yaml_mistakes_are_named(tmp_path, text, message):
    p = tmp_path / "s.yaml"
    p.write_text(text)
    with pytest.raises(InputError, match=message):
        load_scene(p)


def test_builtin_names_and_unknown_names():
    for name in SCENES:
        s = load_scene(name)
        assert s.name == name and "main" in s.cameras and s.lights
    with pytest.raises(InputError, match="not a built-in scene"):
        load_scene("kitchen")


def test_a_camera_that_sees_nothing_is_refused_up_front(tmp_path, capsys):
    """A view whose frustum holds none of the scene's bounding boxes is refused before anything is
    drawn (the image would be background only); a view inside the scene or at its edge is kept."""
    from illusio.scene.camera import Camera, Pose, View
    from tests.conftest import call_cli

    scene = load_scene("living-room")
    camera = Camera(45.0, 0.05, 100.0)
    with pytest.raises(InputError, match="sees nothing of scene 'living-room'"):
        scene.check_in_view(View(Pose((0, 100, 0), (0, 200, 0)), camera), (64, 48))
    with pytest.raises(InputError, match="sees nothing"):  # the scene beyond the far plane
        scene.check_in_view(View(Pose((0, 1, 500), (0, 1, 0)), camera), (64, 48))
    scene.check_in_view(View(Pose((0, 1, 0), (0, 50, 0)), camera), (64, 48))  # inside, looking up
    scene.check_in_view(View(Pose((0, 1, 9), (5.5, 1, 0)), camera), (64, 48))  # the room at the edge
    code, out = call_cli(
        ["render", "living-room", "--camera", "0,100,0:0,200,0", "-o", str(tmp_path / "x.png")], capsys
    )
    assert code == 2 and "sees nothing" in out.err and not (tmp_path / "x.png").exists()
    code, out = call_cli(["lines", "torus", "--camera", "0,0,-5,0,0,-10", "-o", str(tmp_path / "l.png")], capsys)
    assert code == 2 and "sees nothing of scene 'torus'" in out.err and not (tmp_path / "l.png").exists()
