"""The Blender scene of tests/data/blender, made in Blender 5.0.1 (PyPI's ``bpy``) and exported with
Blender's own glTF and OBJ exporters, as a user would: the default cube (red sides, a blue top: two
materials), a floor with an image texture, an emissive ball, the default point light and camera.

Blender is not a dependency (its wheel is 400 MB); to make the files again, in a Python 3.11 of
its own::

    python -m venv /tmp/bpy && /tmp/bpy/bin/pip install bpy==5.0.1
    /tmp/bpy/bin/python tests/data/blender/make_scene.py tests/data/blender
"""

import sys

import bpy
import numpy as np

out = sys.argv[1]
bpy.ops.wm.read_factory_settings(use_empty=False)  # the default cube, point light and camera
cube = bpy.data.objects["Cube"]
cube.name = "red-cube"
red = bpy.data.materials.new("red-paint")
red.use_nodes = True
bsdf = red.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.8, 0.05, 0.05, 1.0)
bsdf.inputs["Roughness"].default_value = 0.5
cube.data.materials[0] = red  # the default cube's slot 0 holds Blender's "Material"
blue = bpy.data.materials.new("blue-paint")
blue.use_nodes = True
blue.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.05, 0.1, 0.8, 1.0)
cube.data.materials.append(blue)
for polygon in cube.data.polygons:  # the top face blue
    polygon.material_index = 1 if polygon.normal.z > 0.9 else 0

bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, -1))
floor = bpy.context.active_object
floor.name = "floor"
image = bpy.data.images.new("checker", 32, 32)
cells = ((np.indices((32, 32)) // 4).sum(0) % 2).astype(np.float32)
pixels = np.ones((32, 32, 4), np.float32)
pixels[..., :3] = (0.2 + 0.6 * cells)[..., None]
image.pixels = pixels.ravel()
image.filepath_raw = out + "/checker.png"
image.file_format = "PNG"
image.save()
checker = bpy.data.materials.new("checker-paint")
checker.use_nodes = True
nodes = checker.node_tree.nodes
tex = nodes.new("ShaderNodeTexImage")
tex.image = image
checker.node_tree.links.new(tex.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.9
floor.data.materials.append(checker)

bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(2, 0, 0), segments=16, ring_count=8)
ball = bpy.context.active_object
ball.name = "glow-ball"
glow = bpy.data.materials.new("glow")
glow.use_nodes = True
p = glow.node_tree.nodes["Principled BSDF"]
p.inputs["Base Color"].default_value = (0.0, 0.0, 0.0, 1.0)
p.inputs["Emission Color"].default_value = (1.0, 0.8, 0.4, 1.0)
p.inputs["Emission Strength"].default_value = 3.0
ball.data.materials.append(glow)

bpy.data.objects["Light"].name = "lamp"
bpy.data.objects["Camera"].name = "view"
bpy.ops.export_scene.gltf(filepath=out + "/blender.glb", export_format="GLB", export_lights=True, export_cameras=True)
bpy.ops.wm.obj_export(filepath=out + "/blender.obj", export_materials=True, path_mode="RELATIVE")
print("written")
