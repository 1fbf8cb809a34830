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


@pytest.mark.parametrize("text,message", [
    ("nodes:\n  - name: a\n    shape: sphere\n    colour: [1, 0, 0]\n", "unknown key"),
    ("nodes:\n  - name: a\n    shape: teapot\n", "unknown shape"),
    ("nodes:\n  - name: a\n    mesh: missing.obj\n", "no such file"),
    ("nodes: []\n", "no nodes"),
    ("nodes:\n  - name: a\n    shape: sphere\nlights:\n  - {type: spot, position: [0, 1, 0]}\n", "point or area"),
])
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
