"""
Your own scene: a glTF made with trimesh
========================================

A scene written as glTF by trimesh, as Blender and public sample sets write them: two coloured
shapes on a floor, read back with their materials (the file has no light, so the turntable's two
lamps are added, as the warning says) and drawn from a camera that frames the scene's bounds.
"""

import tempfile
import warnings
from pathlib import Path

import trimesh
from _display import display
from trimesh.visual.material import PBRMaterial

from illusio.passes import render_scene
from illusio.scene import load_scene

scene = trimesh.Scene()
for name, mesh, colour, at in (
    ("ball", trimesh.creation.icosphere(3, 0.4), [0.8, 0.2, 0.1, 1], [-0.5, 0.4, 0]),
    ("block", trimesh.creation.box((0.6, 0.8, 0.6)), [0.1, 0.4, 0.8, 1], [0.5, 0.4, 0]),
    ("floor", trimesh.creation.box((3, 0.02, 3)), [0.7, 0.7, 0.7, 1], [0, -0.01, 0]),
):
    # metallicFactor given: glTF's default is 1, a metal, which illusio's Phong mapping draws as its
    # highlight alone (docs: "Scenes from other tools")
    material = PBRMaterial(name, baseColorFactor=colour, metallicFactor=0.0, roughnessFactor=0.6)
    mesh.visual = trimesh.visual.TextureVisuals(material=material)
    scene.add_geometry(mesh, node_name=name, transform=trimesh.transformations.translation_matrix(at))
path = Path(tempfile.mkdtemp()) / "shapes.glb"
scene.export(path)

with warnings.catch_warnings(record=True) as said:
    warnings.simplefilter("always")
    loaded = load_scene(path)
print([node.name for node in loaded.nodes], "|", said[0].message if said else "")
figure = display(render_scene(loaded, size=(400, 300)), titles=("shapes.glb",))
