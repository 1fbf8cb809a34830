"""Where the focus goes: a fixed distance, or a named object of the scene (the distance along the
view axis to its bounding box's centre)."""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..scene.camera import View
from ..scene.scene import Scene
from ..scene.transforms import transform_points

__all__ = ["object_distance"]


def object_distance(scene: Scene, name: str, view: View) -> float:
    """Metres along ``view``'s axis to the centre of the node named (or tagged) ``name``; at least
    the camera's near plane."""
    nodes = [n for n in scene.nodes if n.name == name or name in n.tags]
    if not nodes:
        raise InputError(f"scene {scene.name!r} has no object named {name!r}; objects: "
                         + ", ".join(n.name for n in scene.nodes))
    lo, hi = nodes[0].mesh.bounds
    centre = transform_points(nodes[0].transform, ((np.asarray(lo, np.float64) + hi) / 2)[None])[0]
    eye_space = view.view_matrix().astype(np.float64) @ np.append(centre, 1.0)
    return max(float(-eye_space[2]), view.camera.near)
