"""Photographic reference views: the scene path-traced by Mitsuba 3 (its ``scalar_rgb`` variant, no
system package needed), with its depth, shading normals and albedo as AOVs. The colour is the path
tracer's radiance (indirect light and soft shadows included), kept in ``ReferenceView.colour`` for
the "photographic" output; albedo, normals and depth serve the selection and the re-lighting.

What is exported: every visible node as a triangle mesh (a PLY written to a temporary folder, with
its uvs when textured) with the BSDF of its material (:func:`material_bsdf`: its texture as a
bitmap, Lambert or the principled BSDF), an area emitter where the material emits; point lights as
Mitsuba point lights of the same radiant intensity; rectangular lamps as emitting rectangles of the
same radiance. Mitsuba is an optional dependency (``pip install mitsuba``)."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from ..passes.mitsuba import load_mitsuba as _mitsuba
from ..passes.mitsuba import load_scene, mitsuba_available, render
from ..passes.mitsuba import rgb as _rgb
from ..passes.mitsuba import sensor as _sensor
from ..scene.camera import View
from ..scene.scene import AreaLight, PointLight, Scene
from .reference_views import ReferenceSet, ReferenceView

__all__ = ["capture_mitsuba", "mitsuba_available"]


def material_bsdf(mi, material, textured: bool) -> dict:
    """The Mitsuba BSDF of an illusio material: reflectance = colour × texture (a linear bitmap,
    flipped: Mitsuba's v runs down the image, ours up) or, untextured, the colour; Lambert (``diffuse``)
    without a specular term, else the ``principled`` BSDF, metallic 0, specular k_s / 0.08 (its F0
    is 0.08 × specular), roughness (2/(n + 2))^¼ from the Phong exponent n (the exporter's rule);
    an alpha mask wraps it in a ``mask`` BSDF, opaque where the opacity reaches the cutoff."""
    colour = np.asarray(material.colour, np.float64)
    if textured:
        image = (colour * np.asarray(material.texture, np.float64))[::-1].astype(np.float32)
        reflectance = {"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(image)), "raw": True}
    else:
        reflectance = _rgb(material.mean_albedo())  # a texture without uvs: its mean
    if material.specular <= 0:
        bsdf = {"type": "diffuse", "reflectance": reflectance}
    else:
        bsdf = {
            "type": "principled",
            "base_color": reflectance,
            "metallic": 0.0,
            "specular": float(min(1.0, material.specular / 0.08)),
            "roughness": float((2 / (material.shininess + 2)) ** 0.25),
        }
    if textured and material.opacity is not None:  # the alpha mask: cut (opacity 0) below the cutoff
        cut = (np.asarray(material.opacity) >= material.alpha_cutoff)[::-1].astype(np.float32)
        opacity = {"type": "bitmap", "bitmap": mi.Bitmap(np.ascontiguousarray(cut[:, :, None])), "raw": True}
        bsdf = {"type": "mask", "opacity": opacity, "bsdf": bsdf}
    return bsdf


def _scene_dict(mi, scene: Scene, folder: Path, lights: bool = True) -> dict:
    import trimesh

    out: dict = {"type": "scene"}
    for k, node in enumerate(scene.nodes):
        if not node.visible:
            continue
        world = (np.c_[node.mesh.vertices, np.ones(len(node.mesh.vertices))] @ node.transform.astype(np.float64).T)[
            :, :3
        ]
        path = folder / f"node-{k}.ply"
        material = node.material
        textured = material.texture is not None and node.mesh.uvs is not None
        mesh = trimesh.Trimesh(world, node.mesh.faces, process=False)
        if textured:  # the uvs travel in the PLY (s, t)
            mesh.visual = trimesh.visual.TextureVisuals(uv=np.asarray(node.mesh.uvs, np.float64))
        mesh.export(path)
        shape = {"type": "ply", "filename": str(path), "bsdf": material_bsdf(mi, material, textured)}
        if np.max(material.emission) > 0:
            shape["emitter"] = {"type": "area", "radiance": _rgb(material.emission)}
        out[f"node_{k}"] = shape
    for k, light in enumerate(scene.lights if lights else ()):
        if isinstance(light, PointLight):
            out[f"light_{k}"] = {
                "type": "point",
                "position": [float(v) for v in light.position],
                "intensity": _rgb(np.asarray(light.colour) * light.intensity),
            }
        elif isinstance(light, AreaLight):
            u, v = np.asarray(light.edge_u, np.float64), np.asarray(light.edge_v, np.float64)
            n = np.cross(u, v)
            n /= np.linalg.norm(n)
            m = np.eye(4)
            m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = u / 2, v / 2, n, light.centre
            out[f"light_{k}"] = {
                "type": "rectangle",
                "to_world": mi.ScalarTransform4f(m.tolist()),
                "emitter": {"type": "area", "radiance": _rgb(np.asarray(light.colour) * light.radiance)},
            }
    return out


def capture_mitsuba(
    scene: Scene, views: list[View], size: tuple[int, int], samples: int = 64, seed: int = 0
) -> ReferenceSet:
    """Path-traced reference views of ``scene`` from ``views`` at ``size`` with ``samples`` paths a
    pixel (box filter, so each pixel is its own footprint; ``seed`` for the sampler)."""
    mi = _mitsuba()
    w, h = size
    refs = []
    with tempfile.TemporaryDirectory(prefix="illusio-mitsuba-") as tmp:
        base = _scene_dict(mi, scene, Path(tmp))
        # the albedo AOV has no emission: the emitting surfaces seen directly (one bounce of a path
        # tracer), without the lamps' own rectangles, which share the panels' place and would
        # report the lamps' radiance, not the panels' emission the rasteriser shows
        glowing = _scene_dict(mi, scene, Path(tmp), lights=False)
        for view in views:
            sensor = _sensor(mi, view, size, samples, seed)
            doc = dict(base, sensor=sensor)
            doc["integrator"] = {
                "type": "aov",
                "aovs": "dd:depth,nn:sh_normal,al:albedo",
                "img": {"type": "path", "max_depth": 6},
            }
            image = np.array(render(mi, load_scene(mi, doc), seed=int(seed)), np.float32)
            colour, distance, normal, albedo = image[..., :3], image[..., 3], image[..., 4:7], image[..., 7:10]
            emission = np.array(
                render(
                    mi,
                    load_scene(mi, dict(glowing, sensor=sensor, integrator={"type": "path", "max_depth": 1})),
                    seed=int(seed),
                ),
                np.float32,
            )[..., :3]
            # Mitsuba's depth AOV is the distance along the ray from the near plane (its perspective
            # sensor starts rays there); ours is the depth along the view axis from the eye
            forward = np.asarray(view.pose.axes()[2], np.float64)
            axis_depth = distance * (view.ray_directions((w, h)) @ forward) + view.camera.near
            hit = distance > 0
            refs.append(
                ReferenceView(
                    view,
                    np.dstack([albedo, np.zeros((h, w), np.float32)]),
                    np.dstack([normal, np.full((h, w), 32.0, np.float32)]),
                    emission,
                    np.where(hit, axis_depth, 0.0).astype(np.float32),
                    colour=np.clip(colour, 0, None),
                )
            )
    return ReferenceSet(refs, list(scene.lights), tuple(scene.ambient), tuple(scene.background))
