"""A "real scene": coarse geometry (polygons, with the lamps marked), one photograph and its camera.

No photograph of a real room ships with the package, so the built-in case makes one: the office's
polygons path-traced by Mitsuba 3 from its ``main`` camera (the same camera and exposure as
``illusio radiosity office --reference``). The model then forgets the true reflectances and lamp
powers: relighting estimates them from the photograph (relight.estimate)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..radiosity import Polygons, scene_polygons
from ..scene.builtin import builtin_scene
from ..scene.camera import View

__all__ = ["RealScene", "builtin_real_scene", "polygon_ids"]


@dataclass(eq=False)
class RealScene:
    """polygons: the model (its ``lamps`` groups are the real lamps; reflectances and exitances are
    not used); view: the photograph's camera; photograph: radiance, float32 (H, W, 3), row 0 on top."""

    polygons: Polygons
    view: View
    photograph: np.ndarray

    def __post_init__(self):
        photo = np.asarray(self.photograph, np.float32)
        if photo.ndim != 3 or photo.shape[2] < 3 or min(photo.shape[:2]) < 8:
            raise InputError(f"the photograph must be an H×W×3 image of at least 8×8 pixels, got shape {photo.shape}")
        if not np.isfinite(photo).all():
            raise InputError("the photograph has non-finite pixels")
        self.photograph = photo[..., :3]
        if not self.polygons.lamps:
            raise InputError("the real scene has no lamp: relighting estimates the lamps' exitance")

    @property
    def size(self) -> tuple[int, int]:
        return self.photograph.shape[1], self.photograph.shape[0]


def builtin_real_scene(name: str = "office", size: tuple[int, int] = (320, 240), samples: int = 64, seed: int = 0) -> RealScene:
    """The built-in case: ``name``'s polygons photographed by Mitsuba from its main camera."""
    from ..radiosity.mitsuba import render_mitsuba

    scene = builtin_scene(name)
    polygons = scene_polygons(scene)
    view = scene.camera("main")
    return RealScene(polygons, view, render_mitsuba(polygons, view, size, samples, seed))


def polygon_ids(polygons: Polygons, view: View, size: tuple[int, int]) -> np.ndarray:
    """The polygon seen through each pixel centre, (H, W) int, −1 where none (rays cast with Embree)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    vertices, faces = polygons.triangles()
    face_polygon = np.r_[np.arange(len(polygons)), np.flatnonzero(~polygons.triangle)]
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices[faces])
    w, h = size
    directions = view.ray_directions((w, h)).reshape(-1, 3).astype(np.float32)
    origins = np.repeat(np.asarray(view.pose.position, np.float32)[None], len(directions), axis=0)
    prim = np.asarray(scene.run(origins, directions))
    ids = np.where(prim >= 0, face_polygon[np.maximum(prim, 0)], -1)
    return ids.reshape(h, w)
