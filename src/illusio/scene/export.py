"""Write a Scene as glTF 2.0 (``.glb`` or ``.gltf``), for Blender and other tools, readable back by
:func:`illusio.scene.scene_file.load_scene_file`.

trimesh writes the nodes, meshes (with uvs and normals), transforms and PBR materials; pygltflib adds
what trimesh does not write: ``KHR_lights_punctual`` point lights, cameras, and illusio's own data in
``extras`` (glTF's place for application data, kept by Blender as custom properties).

Stated rules (the inverse of the reader's):
- a material is metallic 0, base colour = its colour, base colour texture = its texture encoded
  sRGB, roughness r = (2/(n + 2))^¼ from its Phong shininess n; emission as the emissive factor
  (with ``KHR_materials_emissive_strength`` above 1); its exact Phong k_s and n in the material's
  ``extras.illusio``;
- a point light of I W/sr is a glTF point light of 683·I cd;
- an area light (glTF has none) is an emissive rectangle other tools show, with the exact lamp in its
  node's ``extras.illusio.area_light`` (read back as that lamp, not as a mesh);
- a camera is a perspective camera (lens shift, pixel aspect, the distance to its target and its up
  hint in ``extras``: the target is where IBR's rig of reference views looks);
- node tags and visibility, the scene's ambient and background, curves and actions are ``extras``.
"""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.images import atomic_output, linear_to_srgb
from .scene import AreaLight, PointLight, Scene
from .scene_file import LUMENS_PER_WATT

__all__ = ["export_gltf"]


def export_gltf(scene: Scene, path: str | os.PathLike) -> Path:
    """Write ``scene`` to ``path`` (``.glb``: one binary file; ``.gltf``: JSON with embedded
    buffers), atomically. Returns the path."""
    import pygltflib
    import trimesh

    out = Path(path)
    if out.suffix.lower() not in (".glb", ".gltf"):
        raise InputError(f"{out}: export writes glTF: give a .glb or .gltf path")
    tscene = trimesh.Scene()
    materials: dict = {}  # illusio material by the unique name given to it
    for node in scene.nodes:
        tscene.add_geometry(
            _trimesh(node, materials),
            node_name=node.name,
            geom_name=node.name,
            transform=np.asarray(node.transform, np.float64),
        )
    lamps = [light for light in scene.lights if isinstance(light, AreaLight)]
    for light in lamps:
        tscene.add_geometry(_lamp_panel(light), node_name=_panel_name(light), geom_name=_panel_name(light))
    glb = tscene.export(file_type="glb")
    gltf = pygltflib.GLTF2.load_from_bytes(glb)
    by_name = {n.name: n for n in gltf.nodes}
    for node in scene.nodes:
        by_name[node.name].extras = {"illusio": {"tags": list(node.tags), "visible": bool(node.visible)}}
    for material in gltf.materials:
        source = materials.get(material.name)
        if source is not None:
            material.extras = {"illusio": {"specular": source.specular, "shininess": source.shininess}}
            # trimesh writes factors through a byte: the exact values
            material.pbrMetallicRoughness.baseColorFactor = [*map(float, source.colour), 1.0]
            if max(source.emission) > 0:
                material.emissiveFactor = [float(c) for c in source.emission]
            if max(source.emission) > 1:
                material.extensions = {
                    "KHR_materials_emissive_strength": {"emissiveStrength": float(max(source.emission))}
                }
                material.emissiveFactor = [float(c) / max(source.emission) for c in source.emission]
                _use(gltf, "KHR_materials_emissive_strength")
    for light in lamps:
        by_name[_panel_name(light)].extras = {"illusio": {"area_light": _area_light_record(light)}}
    points = [light for light in scene.lights if isinstance(light, PointLight)]
    if points:
        _use(gltf, "KHR_lights_punctual")
        gltf.extensions = {
            **(gltf.extensions or {}),
            "KHR_lights_punctual": {
                "lights": [
                    {
                        "type": "point",
                        "name": light.name,
                        "color": list(light.colour),
                        "intensity": float(light.intensity * LUMENS_PER_WATT),
                    }
                    for light in points
                ]
            },
        }
        for k, light in enumerate(points):
            gltf.nodes.append(
                pygltflib.Node(
                    name=f"{light.name} (light)",
                    translation=list(light.position),
                    extensions={"KHR_lights_punctual": {"light": k}},
                    extras={"illusio": {"shadows": bool(light.shadows), "name": light.name}},
                )
            )
            gltf.scenes[0].nodes.append(len(gltf.nodes) - 1)
    for name, view in scene.cameras.items():
        camera = view.camera
        gltf.cameras.append(
            pygltflib.Camera(
                type="perspective",
                name=name,
                perspective=pygltflib.Perspective(
                    yfov=float(np.radians(camera.fov_y)), znear=float(camera.near), zfar=float(camera.far)
                ),
                extras={"illusio": _camera_record(view)},
            )
        )
        world_from_camera = np.linalg.inv(np.asarray(view.pose.matrix(), np.float64))
        gltf.nodes.append(
            pygltflib.Node(name=name, camera=len(gltf.cameras) - 1, matrix=list(world_from_camera.T.reshape(-1)))
        )
        gltf.scenes[0].nodes.append(len(gltf.nodes) - 1)
    gltf.scenes[0].extras = {"illusio": _scene_record(scene)}
    with atomic_output(out) as tmp:
        if out.suffix.lower() == ".glb":
            gltf.save_binary(str(tmp))
        else:
            gltf.convert_buffers(pygltflib.BufferFormat.DATAURI)
            gltf.save_json(str(tmp))
    return out


def _trimesh(node, materials: dict):
    import trimesh
    from PIL import Image
    from trimesh.visual.material import PBRMaterial

    mesh, material = node.mesh, node.material
    name = f"{node.name}-material"
    materials[name] = material
    texture, mask = None, {}
    if material.texture is not None and mesh.uvs is not None:
        rgb = np.round(linear_to_srgb(material.texture) * 255).astype(np.uint8)
        if material.opacity is not None:  # glTF's alpha mask: the texture's alpha (linear) and the cutoff
            alpha = np.round(np.clip(material.opacity, 0, 1) * 255).astype(np.uint8)
            rgb = np.dstack([rgb, alpha])
            mask = {"alphaMode": "MASK", "alphaCutoff": float(material.alpha_cutoff)}
        texture = Image.fromarray(rgb)
    emission = np.asarray(material.emission, np.float64)
    pbr = PBRMaterial(
        name=name,
        baseColorFactor=[*map(float, material.colour), 1.0],
        baseColorTexture=texture,
        metallicFactor=0.0,
        roughnessFactor=float((2 / (material.shininess + 2)) ** 0.25),
        emissiveFactor=list(np.clip(emission, 0, 1)) if emission.any() else None,
        **mask,
    )
    visual = trimesh.visual.TextureVisuals(uv=mesh.uvs, material=pbr)
    return trimesh.Trimesh(
        np.asarray(mesh.vertices, np.float64),
        np.asarray(mesh.faces, np.int64),
        vertex_normals=np.asarray(mesh.normals, np.float64),
        visual=visual,
        process=False,
    )


def _panel_name(light: AreaLight) -> str:
    """The emissive panel's node name (a lamp and the node of its fitting often share a name)."""
    return f"{light.name} (area light)"


def _lamp_panel(light: AreaLight):
    import trimesh
    from trimesh.visual.material import PBRMaterial

    c, u, v = (np.asarray(x, np.float64) for x in (light.centre, light.edge_u, light.edge_v))
    corners = np.array([c - u / 2 - v / 2, c + u / 2 - v / 2, c + u / 2 + v / 2, c - u / 2 + v / 2])
    glow = np.asarray(light.colour, np.float64) * min(1.0, light.radiance)
    material = PBRMaterial(name=f"{light.name}-emitter", baseColorFactor=[0, 0, 0, 1], emissiveFactor=list(glow))
    return trimesh.Trimesh(
        corners, [[0, 1, 2], [0, 2, 3]], visual=trimesh.visual.TextureVisuals(material=material), process=False
    )


def _area_light_record(light: AreaLight) -> dict:
    record = dataclasses.asdict(light)
    return {k: list(v) if isinstance(v, tuple) else v for k, v in record.items()}


def _scene_record(scene: Scene) -> dict:
    return {
        "name": scene.name,
        "ambient": list(scene.ambient),
        "background": list(scene.background),
        "curves": [
            {"name": c.name, "kind": c.kind, "points": np.asarray(c.points).tolist()} for c in scene.curves.values()
        ],
        "actions": [dataclasses.asdict(a) for a in scene.actions.values()],
    }


def _use(gltf, extension: str) -> None:
    gltf.extensionsUsed = sorted(set(gltf.extensionsUsed or ()) | {extension})


def _camera_record(view) -> dict:
    """What a glTF camera lacks: its lens shift and pixel aspect, and the pose's target (as a
    distance along the view, so a camera moved in Blender keeps a target ahead of it) and up hint."""
    pose = view.pose
    eye, target = np.asarray(pose.position, np.float64), np.asarray(pose.target, np.float64)
    return {
        "shift": list(view.camera.shift),
        "pixel_aspect": view.camera.pixel_aspect,
        "target_distance": float(np.linalg.norm(target - eye)),
        "up": [float(u) for u in pose.up],
    }
