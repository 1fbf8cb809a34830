"""Debug views of a line drawing: the maps of the hybrid method's first pass, and the curvature as
seen from the view. Used by ``illusio lines --debug`` and the viewer's lines mode."""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..scene.mesh import Mesh
from .curvature import Curvature
from .drawing import Drawing

__all__ = ["DEBUG_VIEWS", "debug_view"]

DEBUG_VIEWS = ("q1", "t1", "curvature")


def debug_view(kind: str, drawing: Drawing, mesh: Mesh, curvature: Curvature) -> np.ndarray:
    """A debug image of ``drawing`` (float32 (H, W, 3) linear): "q1" map (grey), "t1" direction field
    (hue), or "curvature": the mean curvature seen from the view (blue concave, red convex)."""
    if kind not in DEBUG_VIEWS:
        raise InputError(f"debug view must be one of {', '.join(DEBUG_VIEWS)}, got {kind!r}")
    maps = drawing.q_t1
    covered = maps[..., 3] > 0
    if kind == "q1":
        return np.where(covered, maps[..., 0], 1.0)
    if kind == "t1":
        angle = np.arctan2(maps[..., 2], maps[..., 1])  # t1 and −t1 are one direction: double the angle
        rgb = 0.5 + 0.5 * np.stack([np.cos(2 * angle), np.cos(2 * angle - 2.094), np.cos(2 * angle + 2.094)], -1)
        return np.where(covered[..., None], rgb, 1.0).astype(np.float32)
    curv = curvature
    mean = (curv.k_min + curv.k_max) / 2 / max(curv.scale(), 1e-12)
    colour = np.clip(np.stack([0.5 + mean, 0.5 - np.abs(mean) * 0.5, 0.5 - mean], -1), 0, 1)
    # shade each visible pixel by the nearest projected vertex's colour
    px, depth = drawing.view.project(mesh.vertices, drawing.size)
    w, h = drawing.size
    image = np.ones((h, w, 3), np.float32)
    xi, yi = px[:, 0].astype(int), px[:, 1].astype(int)
    ok = (xi >= 0) & (xi < w) & (yi >= 0) & (yi < h) & (depth > 0)
    order = np.argsort(-depth[ok])  # far first, near last wins
    image[yi[ok][order], xi[ok][order]] = colour[ok][order]
    known = np.zeros((h, w), bool)
    known[yi[ok], xi[ok]] = True
    return np.where(covered[..., None], _fill(image, known), 1.0).astype(np.float32)


def _fill(image: np.ndarray, known: np.ndarray) -> np.ndarray:
    """Every pixel takes the colour of the nearest known one."""
    from scipy import ndimage

    _, (iy, ix) = ndimage.distance_transform_edt(~known, return_indices=True)
    return image[iy, ix]
