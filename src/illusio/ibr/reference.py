"""Image-based rendering stated plainly in NumPy: the specification the GPU passes are tested
against. ``select`` for SelectPass (the per-pixel choice of the reference view); the first pass's
reference is passes.reference.gbuffer ray-casting the reconstruction mesh, nearer than
``point_depth`` of the points the mesh leaves out."""

from __future__ import annotations

import numpy as np

from .proxy_mesh import unproject

__all__ = ["select", "point_depth"]


def select(
    reconstructed: np.ndarray,
    view,
    references,
    use_3d: bool = False,
    bilinear: bool = True,
    max_distance: float = 3.0,
    photographic: bool = False,
) -> dict[str, np.ndarray]:
    """Per pixel of the new view (row 0 at the top): back-project the pixel centre at its
    reconstructed depth into each reference, read the reference's depth there (bilinear over the
    four texels around the point when all four see something and ``bilinear``, else the nearest),
    unproject it to the point the reference saw, and measure its distance to ours (pixels on the new
    image plane, or metres with ``use_3d``); keep the reference with the smallest distance (the first
    on ties), none beyond ``max_distance``. Attributes: bilinear where the four texels around the
    point lie on one surface (depths within 1 %), else the nearest texel. Returns source (H, W) int (reference index
    + 1, 0 =
    hole; a reference whose stored normal faces away from the new eye saw the other side of a thin
    surface and is skipped), depth (the seen point's view depth in the new view), position (H, W, 3), albedo (H, W, 4),
    normal (H, W, 4), emission (H, W, 3) from the chosen reference's nearest texel. ``photographic``:
    "emission" is the reference's recorded colour, bilinear everywhere (an image of the light, as a
    camera's pixel blends what it covers; texel indices clamped to the image)."""
    z = np.asarray(reconstructed, np.float64)
    h, w = z.shape
    ys, xs = np.mgrid[0:h, 0:w]
    point = unproject(view, (w, h), xs + 0.5, ys + 0.5, z)
    best = np.full((h, w), np.inf)
    out = {
        "source": np.zeros((h, w), np.int64),
        "depth": np.zeros((h, w)),
        "position": np.zeros((h, w, 3)),
        "albedo": np.zeros((h, w, 4)),
        "normal": np.zeros((h, w, 4)),
        "emission": np.zeros((h, w, 3)),
    }
    new_vp = view.view_projection((w, h)).astype(np.float64)
    new_view = view.view_matrix().astype(np.float64)
    homogeneous = np.concatenate([point, np.ones((h, w, 1))], axis=-1)
    for index, ref in enumerate(references):
        rw, rh = ref.size
        clip = homogeneous @ ref.view.view_projection((rw, rh)).astype(np.float64).T
        ok = (z > 0) & (clip[..., 3] > 0)
        uv = np.where(ok[..., None], clip[..., :2] / np.where(ok, clip[..., 3], 1.0)[..., None] * 0.5 + 0.5, -1.0)
        ok &= (uv >= 0).all(-1) & (uv < 1).all(-1)
        t = uv * (rw, rh) - 0.5
        gl_depth = np.asarray(ref.depth, np.float64)[::-1]  # GL rows from the bottom
        nearest = np.clip(np.floor(t + 0.5).astype(int), 0, (rw - 1, rh - 1))
        d = gl_depth[nearest[..., 1], nearest[..., 0]]
        t0 = np.clip(np.floor(t).astype(int), 0, (rw - 1, rh - 1))
        t1 = np.minimum(t0 + 1, (rw - 1, rh - 1))
        f = np.clip(t - t0, 0, 1)

        def bilerp(a):
            a = np.asarray(a, np.float64)[::-1]
            fx, fy = f[..., 0:1] if a.ndim == 3 else f[..., 0], f[..., 1:2] if a.ndim == 3 else f[..., 1]
            return (a[t0[..., 1], t0[..., 0]] * (1 - fx) + a[t0[..., 1], t1[..., 0]] * fx) * (1 - fy) + (
                a[t1[..., 1], t0[..., 0]] * (1 - fx) + a[t1[..., 1], t1[..., 0]] * fx
            ) * fy

        corners = np.stack(
            [
                gl_depth[t0[..., 1], t0[..., 0]],
                gl_depth[t0[..., 1], t1[..., 0]],
                gl_depth[t1[..., 1], t0[..., 0]],
                gl_depth[t1[..., 1], t1[..., 0]],
            ],
            -1,
        )
        lo, hi = corners.min(-1), corners.max(-1)
        smooth = (lo > 0) & (hi <= lo * 1.01)
        if bilinear:
            d = np.where(lo > 0, bilerp(ref.depth), d)
        ok &= d > 0
        ref_x, ref_y = uv[..., 0] * rw, (1 - uv[..., 1]) * rh
        seen = unproject(ref.view, (rw, rh), ref_x, ref_y, np.where(ok, d, 1.0))

        def attribute(a):
            at_nearest = np.asarray(a, np.float64)[::-1][nearest[..., 1], nearest[..., 0]]
            return np.where(smooth[..., None], bilerp(a), at_nearest)

        normal = attribute(ref.normal)
        ok &= (normal[..., :3] * (np.asarray(view.pose.position, np.float64) - seen)).sum(-1) > 0  # not the other side
        if use_3d:
            distance = np.linalg.norm(seen - point, axis=-1)
        else:
            c = np.concatenate([seen, np.ones((h, w, 1))], axis=-1) @ new_vp.T
            ok &= c[..., 3] > 0
            cw = np.where(ok, c[..., 3], 1.0)
            px = (c[..., 0] / cw * 0.5 + 0.5) * w
            py = (0.5 - c[..., 1] / cw * 0.5) * h
            distance = np.hypot(px - (xs + 0.5), py - (ys + 0.5))
        take = ok & (distance <= max_distance) & (distance < best)
        best = np.where(take, distance, best)
        out["source"][take] = index + 1
        seen_view = np.concatenate([seen, np.ones((h, w, 1))], axis=-1) @ new_view.T
        out["depth"][take] = -seen_view[..., 2][take]
        out["position"][take] = seen[take]
        for name in ("albedo", "normal", "emission"):
            out[name][take] = attribute(getattr(ref, name))[take]
        if photographic:
            out["emission"][take] = bilerp(np.asarray(ref.colour)[..., :3])[take]
    return out


def point_depth(points: np.ndarray, footprint: np.ndarray, view, size: tuple[int, int]) -> np.ndarray:
    """The first pass's points (reconstruction.Reconstruction's) as GL draws them: each a square
    of side max(1, footprint · f_x / z) pixels (f_x the view's focal length in pixels, z its view
    depth) centred where it projects; every pixel whose centre lies inside takes its depth, the
    nearest winning. (H, W) metres along the view axis, 0 = no point (row 0 at the top)."""
    w, h = size
    out = np.full((h, w), np.inf)
    if len(points):
        pixel, z = view.project(np.asarray(points, np.float64), size)
        focal = view.projection_matrix(w / h)[0, 0] * w / 2
        half = np.maximum(1.0, np.asarray(footprint, np.float64) * focal / np.maximum(z, 1e-6)) / 2
        for k in np.flatnonzero(z > view.camera.near):
            # pixel centres c + 0.5 inside [x − half, x + half)
            x0, x1 = int(np.ceil(pixel[k, 0] - half[k] - 0.5)), int(np.ceil(pixel[k, 0] + half[k] - 0.5))
            y0, y1 = int(np.ceil(pixel[k, 1] - half[k] - 0.5)), int(np.ceil(pixel[k, 1] + half[k] - 0.5))
            block = out[max(y0, 0) : max(min(y1, h), 0), max(x0, 0) : max(min(x1, w), 0)]
            np.minimum(block, z[k], out=block)
    return np.where(np.isfinite(out), out, 0.0)
