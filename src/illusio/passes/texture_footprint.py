"""How stretched a pixel's footprint is in a node's texture: the ratio of the longest to the shortest
axis of the footprint (the singular values of the 2×2 map from pixel offsets to texel offsets).

A footprint is round (ratio 1) on a plane parallel to the image plane and stretched by 1/cos θ on a
plane tilted by θ; anisotropic filtering only helps where it is stretched. The passes sample a node's
texture with anisotropic filtering only when its ratio exceeds :data:`ANISOTROPY_THRESHOLD`: llvmpipe
pays the full price of its anisotropic filter even on a round footprint (~13 ms a 1080p frame for the
living room's back wall), and there it filters a round footprint less accurately than trilinear
filtering does (mean error against a 4×4 supersampled image, benchmarks/RESULTS.md).
"""

from __future__ import annotations

import math

import numpy as np

from ..scene.camera import View

__all__ = ["ANISOTROPY_THRESHOLD", "footprint_anisotropy"]

# ratios up to this get trilinear filtering: at 1.06 (a plane tilted 20°) trilinear was still as
# accurate as llvmpipe's 8× anisotropic filter, at 1.15 (30°) 10–17 % less accurate
ANISOTROPY_THRESHOLD = 1.1


def footprint_anisotropy(
    vertices: np.ndarray, faces: np.ndarray, texels: np.ndarray, view: View, size: tuple[int, int]
) -> float:
    """Largest footprint ratio over the corners of the triangles ``faces`` (F, 3) of world-space
    ``vertices`` (N, 3) with texture coordinates ``texels`` (N, 2) in texels (uv × texture size),
    seen in ``view`` at ``size`` = (width, height) pixels.

    Each triangle is a plane with an affine texture map, so at a corner the map from a pixel step
    to a texel step is exact: a ray through the corner moved by one pixel meets the triangle's plane
    at ``depth · h · (e − r (n·e)/(n·r))`` from the corner (r the ray scaled to unit depth, n the
    plane's normal, e the camera's right or up axis, h the size of a pixel at unit depth). The ratio
    over a triangle is taken at its corners (largest there: checked on dense samples in the tests).
    Triangles wholly behind the near plane draw nothing and are skipped; one that crosses it has an
    unbounded footprint: ``inf``. So are edge-on triangles. Conservative: triangles outside the
    frustum count too."""
    if len(faces) == 0:
        return 1.0
    m = view.view_matrix().astype(np.float64)
    cam = np.asarray(vertices, np.float64) @ m[:3, :3].T + m[:3, 3]
    p = cam[np.asarray(faces)]  # (F, 3 corners, 3)
    depth = -p[..., 2]
    near = view.camera.near
    seen = (depth > near).any(axis=1)
    if (seen & (depth <= near).any(axis=1)).any():
        return math.inf
    p, depth = p[seen], depth[seen]
    t = np.asarray(texels, np.float64)[np.asarray(faces)[seen]]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    normal = np.cross(e1, e2)
    length = np.linalg.norm(normal, axis=1)
    keep = length > 1e-12 * np.maximum(1.0, (e1 * e1).sum(1))
    if not keep.any():
        return 1.0
    p, depth, t, e1, e2 = p[keep], depth[keep], t[keep], e1[keep], e2[keep]
    normal = normal[keep] / length[keep, None]
    # texel offset per world offset within each plane: G [e1 e2 n] = [t1-t0 t2-t0 0]
    basis = np.stack([e1, e2, normal], axis=-1)
    offsets = np.stack([t[:, 1] - t[:, 0], t[:, 2] - t[:, 0], np.zeros((len(t), 2))], axis=-1)
    gradient = offsets @ np.linalg.inv(basis)  # (F, 2, 3)
    ray = p / depth[..., None]  # unit depth: (x, y, -1) in camera space
    n_dot_r = np.einsum("fk,fck->fc", normal, ray)
    if (np.abs(n_dot_r) < 1e-9).any():
        return math.inf
    pixel = 2.0 * math.tan(math.radians(view.camera.fov_y) / 2) / size[1]
    steps = []
    for axis in (0, 1):  # camera right, camera up
        e = np.zeros(3)
        e[axis] = 1.0
        step = e - ray * (normal[:, None, axis] / n_dot_r)[..., None]
        steps.append(pixel * depth[..., None] * step)  # (F, 3, 3): world offset per pixel
    jac = np.einsum("fij,fcjk->fcik", gradient, np.stack(steps, axis=-1))  # (F, 3, 2, 2) texels per pixel
    a, b, c, d = jac[..., 0, 0], jac[..., 0, 1], jac[..., 1, 0], jac[..., 1, 1]
    # singular values of [[a b] [c d]]: s1 s2 = |det|, s1² + s2² = Frobenius²
    frob = a * a + b * b + c * c + d * d
    det = np.abs(a * d - b * c)
    root = np.sqrt(np.maximum(frob * frob - 4 * det * det, 0.0))
    big, small = np.sqrt((frob + root) / 2), np.sqrt(np.maximum((frob - root) / 2, 0.0))
    if (big == 0).all():
        return 1.0  # a constant texture coordinate: one texel, nothing to filter
    if (small[big > 0] <= 1e-12 * big[big > 0]).any():
        return math.inf
    return float(np.max(np.where(big > 0, big / np.where(small > 0, small, 1.0), 1.0)))
