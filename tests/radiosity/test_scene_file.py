"""Radiosity of a scene read from glTF (made by trimesh and pygltflib, the lamp an emissive panel
of KHR_materials_emissive_strength): the same image as the built-in scene it was made from, and
against Mitsuba of the same file within the noise of few paths."""

from __future__ import annotations

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.radiosity import RadiosityParams, RadiosityRenderer
from illusio.scene import builtin_scene
from illusio.scene.scene_file import load_scene_file

trimesh = pytest.importorskip("trimesh")
pygltflib = pytest.importorskip("pygltflib")


def cornell_glb(path):
    """The Cornell box written as another tool would: world-space meshes, PBR base colours
    (metallic 0), the lamp an emissive quad whose radiance is its emissive strength."""
    from trimesh.visual.material import PBRMaterial

    box = builtin_scene("cornell-box")
    scene = trimesh.Scene()
    for node in box.nodes:
        world = trimesh.Trimesh(node.mesh.vertices, node.mesh.faces, process=False).apply_transform(node.transform)
        colour = [*node.material.colour, 1.0]
        world.visual = trimesh.visual.TextureVisuals(
            material=PBRMaterial(name=node.name, baseColorFactor=colour, metallicFactor=0.0, roughnessFactor=1.0)
        )
        scene.add_geometry(world, node_name=node.name, geom_name=node.name)
    (lamp,) = box.lights
    c, u, v = (np.asarray(x) for x in (lamp.centre, lamp.edge_u, lamp.edge_v))
    corners = [c - u / 2 - v / 2, c + u / 2 - v / 2, c + u / 2 + v / 2, c - u / 2 + v / 2]
    faces = [[0, 1, 2], [0, 2, 3]] if np.dot(np.cross(u, v), lamp.normal) > 0 else [[0, 2, 1], [0, 3, 2]]
    panel = trimesh.Trimesh(corners, faces, process=False)
    panel.visual = trimesh.visual.TextureVisuals(
        material=PBRMaterial(name="lamp", baseColorFactor=[0, 0, 0, 1], emissiveFactor=list(lamp.colour))
    )
    scene.add_geometry(panel, node_name="lamp", geom_name="lamp")
    scene.export(str(path))
    gltf = pygltflib.GLTF2().load(str(path))
    material = next(m for m in gltf.materials if m.name == "lamp")
    material.emissiveFactor = list(lamp.colour)  # unrounded
    material.extensions = {"KHR_materials_emissive_strength": {"emissiveStrength": lamp.radiance}}
    gltf.extensionsUsed = ["KHR_materials_emissive_strength"]
    for m in gltf.materials:  # unrounded base colours
        node = next((n for n in box.nodes if n.name == m.name), None)
        if node is not None:
            m.pbrMetallicRoughness.baseColorFactor = [*node.material.colour, 1.0]
    gltf.save(str(path))
    return box


def test_radiosity_of_a_gltf_scene_matches_its_source_and_mitsuba(tmp_path, ctx):
    box = cornell_glb(tmp_path / "cornell.glb")
    loaded = load_scene_file(tmp_path / "cornell.glb")
    assert not loaded.lights and max(loaded.node("lamp").material.emission) == pytest.approx(18.387)
    view, size = box.camera("main"), (48, 48)
    renderer = RadiosityRenderer(ctx)
    try:
        renderer.prepare(box)
        built_in, _ = renderer.radiance(Frame(view, size), RadiosityParams(), 4)
        renderer.prepare(loaded)
        image, emitter = renderer.radiance(Frame(view, size), RadiosityParams(), 4)
        polygons = renderer.polygons
    finally:
        renderer.release()
    # the same room lit by the same lamp: the same radiosity (the panel's fitting is drawn, the
    # lamp of the built-in scene is not: those pixels aside)
    lit = ~emitter
    difference = np.abs(image - built_in)[lit].mean() / built_in[lit].mean()
    print(f"from the built-in scene's: {difference:.4f}")
    assert difference < 0.02
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    from illusio.radiosity.mitsuba import render_mitsuba, score

    reference = render_mitsuba(polygons, view, size, 128, seed=3)
    s = score(image, reference, lit, block=4)
    print(f"against Mitsuba over 4×4 blocks: {s.mean_relative_error:.3f}")
    assert s.mean_relative_error < 0.1, s
