"""Files Blender itself wrote (tests/data/blender, made by its make_scene.py with Blender 5.0.1's glTF
and OBJ exporters): the names the user gave in Blender's outliner, Blender's colours, texture,
emission, light and camera, and the OBJ and the glTF of one scene read as the same materials and
drawn as the same image."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from illusio.scene.scene_file import LUMENS_PER_WATT, load_scene_file
from tests.cli.test_cli import illusio

pytest.importorskip("trimesh")

FOLDER = Path(__file__).parents[1] / "data" / "blender"
NAMES = {"red-cube/red-paint", "red-cube/blue-paint", "floor", "glow-ball"}


def _load(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing in either file goes undrawn (the OBJ's lamp: the glowing ball)
        return load_scene_file(FOLDER / name)


def test_blenders_glb_keeps_the_outliners_names_and_blenders_values():
    scene = _load("blender.glb")
    assert {n.name for n in scene.nodes} == NAMES  # the cube's two materials: a node each, "object/material"
    assert np.allclose(scene.node("red-cube/red-paint").material.colour, (0.8, 0.05, 0.05), atol=1e-6)
    assert np.allclose(scene.node("red-cube/blue-paint").material.colour, (0.05, 0.1, 0.8), atol=1e-6)
    # Principled's emission colour (1, 0.8, 0.4) × strength 3 (KHR_materials_emissive_strength)
    assert np.allclose(scene.node("glow-ball").material.emission, (3.0, 2.4, 1.2), atol=1e-6)
    floor = scene.node("floor").material
    assert floor.texture.shape == (32, 32, 3) and floor.colour == (1.0, 1.0, 1.0)
    # roughness 0.5 (the cube) → α = 0.25, n = 2/α² − 2 = 30; dielectric k_s = 0.04
    red = scene.node("red-cube/red-paint").material
    assert red.shininess == pytest.approx(30.0) and red.specular == pytest.approx(0.04)
    # the light is named after its object ("lamp"), not its data ("Light"); Blender's 1000 W point
    # light, written as 1000/(4π)·683 cd, is 1000/(4π) W/sr again
    (lamp,) = scene.lights
    assert lamp.name == "lamp" and lamp.intensity == pytest.approx(1000 / (4 * math.pi), rel=1e-4)
    assert lamp.intensity * LUMENS_PER_WATT == pytest.approx(54351.4, rel=1e-4)
    # Blender's default camera, Z up → glTF's Y up: (7.36, −6.93, 4.96) → (7.36, 4.96, 6.93); a 50 mm
    # lens on a 36 mm sensor at 16:9 is 22.9° vertically
    (name,) = scene.cameras
    view = scene.camera("view")
    assert name == "view" and np.allclose(view.pose.position, (7.3589, 4.9583, 6.9258), atol=1e-3)
    assert view.camera.fov_y == pytest.approx(math.degrees(2 * math.atan(18 / 50 * 9 / 16)), abs=0.01)


def test_blenders_obj_and_glb_of_one_scene_read_as_the_same_materials():
    glb, obj = _load("blender.glb"), _load("blender.obj")
    assert {n.name for n in obj.nodes} == NAMES  # the `o` objects' names, not the materials'
    for node in glb.nodes:
        a, b = node.material, obj.node(node.name).material
        # Blender's MTL holds Principled's terms (Ks the specular level, Ns from roughness): read as such
        for field in ("colour", "specular", "shininess", "emission"):
            assert np.allclose(getattr(a, field), getattr(b, field), rtol=1e-4, atol=1e-6), (node.name, field)
        assert (a.texture is None) == (b.texture is None)
        if a.texture is not None:
            assert np.abs(a.texture - b.texture).max() < 1e-6


def test_blenders_obj_and_glb_draw_the_same_image(ctx):
    from illusio.passes.scene_renderer import render_scene

    glb, obj = _load("blender.glb"), _load("blender.obj")
    obj.lights = glb.lights  # the OBJ has no light or camera: the same ones for both
    view = glb.camera("view")
    a, b = render_scene(glb, view, (160, 90), ctx), render_scene(obj, view, (160, 90), ctx)
    assert a.mean() > 0.1  # a lit scene, not a blank one
    assert np.abs(a - b).max() < 2 / 255


def test_blenders_files_through_the_command_line(tmp_path):
    out = tmp_path / "r.png"
    r = illusio("radiosity", FOLDER / "blender.glb", "--set-lamp", "lamp=0.5", "--size", "64x36", "-o", out)
    assert r.returncode == 0 and out.is_file(), r.stderr
    out = tmp_path / "s.png"
    r = illusio("sis-scene", FOLDER / "blender.obj", "--host", "floor", "--size", "64x36", "-o", out)
    assert r.returncode == 0 and out.is_file(), r.stderr
