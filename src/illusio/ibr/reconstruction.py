"""The first pass's input: an approximate surface of the scene rebuilt from the reference depths,
drawn into the new view's depth buffer whenever the camera moves (the text recomputes its depth
buffer only then). Our design: each reference's depth map becomes a grid mesh — a vertex every
``step`` pixels at the point the pixel sees, two triangles per cell — leaving out triangles with
nothing at a corner and those seen at more than ``grazing`` degrees from their normal (a triangle
bridging an occlusion edge lies almost along the reference's rays; a relative depth-jump test
instead cut floors seen at a low angle, whose depth grows fast from pixel to pixel); the meshes of
all references are drawn together with the z-buffer. A reference pixel lies on
the surface, so where any reference saw the surface the rebuilt depth is close to the true one;
the second pass then corrects it from the references."""

from __future__ import annotations

import numpy as np

from ..scene.mesh import Mesh
from .references import ReferenceSet, ReferenceView

__all__ = ["unproject", "reference_mesh", "reconstruction_mesh"]


def unproject(view, size, xs: np.ndarray, ys: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """World points (…, 3) seen at pixel coordinates (xs, ys) (pixels from the top-left corner,
    centres at +0.5) at linear view depth ``depth`` (metres along the view axis)."""
    w, h = size
    p = view.projection_matrix(w / h).astype(np.float64)
    ndc_x = xs / w * 2 - 1
    ndc_y = 1 - ys / h * 2
    z = np.asarray(depth, np.float64)
    x_view = (ndc_x * z + p[0, 2] * z) / p[0, 0]
    y_view = (ndc_y * z + p[1, 2] * z) / p[1, 1]
    camera = np.stack([x_view, y_view, -z, np.ones_like(z)], axis=-1)
    world = camera @ np.linalg.inv(view.view_matrix().astype(np.float64)).T
    return world[..., :3]


def reference_mesh(ref: ReferenceView, step: int = 2, grazing: float = 85.0) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of one reference's grid mesh (see the module docstring)."""
    w, h = ref.size
    rows = np.unique(np.r_[np.arange(0, h, step), h - 1])
    cols = np.unique(np.r_[np.arange(0, w, step), w - 1])
    ys, xs = np.meshgrid(rows, cols, indexing="ij")
    d = ref.depth[ys, xs].astype(np.float64)
    # the grid stretched by under a pixel so that it reaches the image's edges (pixel centres would
    # leave the outermost half pixels uncovered: holes along the border of the reference's own view)
    points = unproject(ref.view, (w, h), xs * w / max(w - 1, 1), ys * h / max(h - 1, 1), d)
    vertices = points.reshape(-1, 3)
    gh, gw = d.shape
    idx = np.arange(gh * gw).reshape(gh, gw)
    a, b, c, e = idx[:-1, :-1], idx[:-1, 1:], idx[1:, :-1], idx[1:, 1:]
    faces = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([b, c, e], -1).reshape(-1, 3)])
    seen = (d.reshape(-1)[faces] > 0).all(axis=1)
    p0, p1, p2 = (vertices[faces[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    ray = (p0 + p1 + p2) / 3 - np.asarray(ref.view.pose.position, np.float64)
    cosine = np.abs((normal * ray).sum(1)) / np.maximum(np.linalg.norm(normal, axis=1) * np.linalg.norm(ray, axis=1), 1e-30)
    keep = seen & (cosine > np.cos(np.radians(grazing)))
    return vertices, faces[keep]


def reconstruction_mesh(refs: ReferenceSet, step: int = 2, grazing: float = 85.0) -> Mesh:
    """Every reference's grid mesh in one Mesh (world coordinates)."""
    all_v, all_f, offset = [], [], 0
    for ref in refs.views:
        v, f = reference_mesh(ref, step, grazing)
        all_v.append(v)
        all_f.append(f + offset)
        offset += len(v)
    faces = np.concatenate(all_f) if all_f else np.zeros((0, 3), np.int64)
    if len(faces) == 0:
        faces = np.zeros((1, 3), np.int64)  # nothing seen: one degenerate triangle draws nothing
    return Mesh(np.concatenate(all_v).astype(np.float32), faces.astype(np.int32), name="ibr-reconstruction")
