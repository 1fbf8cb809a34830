"""NumPy statements of the shared passes, the specification the GPU passes are tested against.

- :func:`gbuffer`: ray casting (Möller–Trumbore) through every pixel centre against every
  triangle; nearest hit wins. Textures are not sampled (colour = material colour).
- :func:`shading`: the Lambert + normalised Phong sum of ``shaders/shading.glsl`` without shadows.
- :func:`stereo_composite`: the layouts and anaglyphs of ``shaders/stereo.glsl``.
"""

from __future__ import annotations

import numpy as np

from ..scene.camera import View
from ..scene.scene import Scene
from ..scene.transforms import transform_normals, transform_points
from .gbuffer import GBufferImages
from .lights import Emitters
from .shading import ShadingParams

__all__ = ["gbuffer", "shading", "stereo_composite"]


def gbuffer(scene: Scene, view: View, size: tuple[int, int]) -> GBufferImages:
    """Ray-cast G-buffer of the visible nodes; same conventions as :class:`GBufferImages`."""
    w, h = size
    origin = np.asarray(view.pose.position, np.float64)
    dirs = view.ray_directions((w, h)).reshape(-1, 3)
    n_pix = len(dirs)
    best_t = np.full(n_pix, np.inf)
    obj = np.zeros(n_pix, np.int32)
    normal = np.zeros((n_pix, 3))
    back = np.zeros(n_pix, bool)  # the hit face's winding is clockwise as seen (gl_FrontFacing false)
    colour = np.zeros((n_pix, 3))
    spec = np.zeros(n_pix)
    shin = np.zeros(n_pix)
    emis = np.zeros((n_pix, 3))
    for index, node in enumerate(scene.nodes):
        if not node.visible:
            continue
        v = transform_points(node.transform, node.mesh.vertices).astype(np.float64)
        nv = transform_normals(node.transform, node.mesh.normals).astype(np.float64)
        f = node.mesh.faces
        a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        e1, e2 = b - a, c - a
        for chunk in range(0, len(f), 256):
            sl = slice(chunk, chunk + 256)
            p = np.cross(dirs[:, None, :], e2[None, sl])  # (P, T, 3)
            det = np.einsum("ptk,tk->pt", p, e1[sl])
            ok = np.abs(det) > 1e-12
            inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
            s = origin - a[sl]  # (T, 3)
            u = np.einsum("ptk,tk->pt", p, s) * inv
            q = np.cross(s, e1[sl])  # (T, 3)
            vv = (dirs @ q.T) * inv
            t = (q * e2[sl]).sum(1)[None, :] * inv
            hit = ok & (u >= 0) & (vv >= 0) & (u + vv <= 1) & (t > view.camera.near * 0.999)
            t = np.where(hit, t, np.inf)
            k = np.argmin(t, axis=1)
            tk = t[np.arange(n_pix), k]
            closer = tk < best_t
            if not closer.any():
                continue
            best_t[closer] = tk[closer]
            tri = f[sl][k[closer]]
            uu, ww = u[closer, k[closer]], vv[closer, k[closer]]
            nn = nv[tri[:, 0]] * (1 - uu - ww)[:, None] + nv[tri[:, 1]] * uu[:, None] + nv[tri[:, 2]] * ww[:, None]
            normal[closer] = nn
            geometric = np.cross(e1[sl], e2[sl])[k[closer]]
            back[closer] = (geometric * dirs[closer]).sum(1) > 0
            obj[closer] = index + 1
            colour[closer] = node.material.colour
            spec[closer] = node.material.specular
            shin[closer] = node.material.shininess
            emis[closer] = node.material.emission
    hit = obj > 0
    normal = normal / np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-30)
    normal[back & hit] *= -1  # seen from behind: flipped, as the G-buffer shader does
    position = origin + dirs * np.where(hit, best_t, 0)[:, None]
    forward = view.pose.axes()[2]
    depth = np.where(hit, (dirs @ forward) * best_t, np.inf)

    def img(a, c=None):
        return a.reshape((h, w) if c is None else (h, w, c)).astype(np.float32)

    return GBufferImages(
        colour=img(colour, 3),
        specular=img(spec),
        depth=img(depth),
        normal=img(normal, 3),
        shininess=img(shin),
        position=img(position, 3),
        object_id=obj.reshape(h, w),
        emission=img(emis, 3),
    )


def shading(
    g: GBufferImages, emitters: Emitters, camera_position, params: ShadingParams = ShadingParams()
) -> np.ndarray:
    """Linear radiance (H, W, 3): Σ_k (ρ/π + k_s (s+2)/(2π) max(0, r_k·v)^s) E_k + ambient·ρ + emission,
    E_k = W_k max(0, n·l_k) (m_k = 0 ? 1 : max(0, −m_k·l_k)) / max(r_k², r_min²); background elsewhere."""
    p = g.position.astype(np.float64)
    n = g.normal.astype(np.float64)
    n = n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-30)
    albedo = g.colour.astype(np.float64)
    v = np.asarray(camera_position, np.float64) - p
    v /= np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-30)
    total = np.zeros_like(p)
    for pos, m, weight in zip(emitters.position, emitters.normal, emitters.weight):
        to_light = pos.astype(np.float64) - p
        r2 = np.maximum((to_light * to_light).sum(-1), params.min_distance**2)
        to_light /= np.maximum(np.linalg.norm(to_light, axis=-1, keepdims=True), 1e-30)
        cos_r = np.maximum((n * to_light).sum(-1), 0)
        cos_e = np.maximum(-(to_light @ m), 0) if np.dot(m, m) > 0 else 1.0
        irradiance = weight[None, None, :] * (cos_r * cos_e / r2)[..., None]
        refl = 2 * (n * to_light).sum(-1, keepdims=True) * n - to_light
        phong = g.specular * (g.shininess + 2) / (2 * np.pi) * np.maximum((refl * v).sum(-1), 0) ** g.shininess
        total += (albedo / np.pi + phong[..., None]) * irradiance * (cos_r > 0)[..., None]
    total += np.asarray(params.ambient) * albedo + g.emission
    total *= params.exposure
    out = np.where(g.mask[..., None], total, np.asarray(params.background))
    return out.astype(np.float32)


def stereo_composite(left: np.ndarray, right: np.ndarray, mode: str) -> np.ndarray:
    """Two (H, W, 3) linear images → the composite (rows from the top): side by side (left image on
    the left; cross-eyed: on the right), top-bottom (left on top), or an anaglyph: out = clamp(L·left +
    R·right) with the scheme's matrices (``passes.stereo.ANAGLYPH_MATRICES``)."""
    from .stereo import ANAGLYPH_MATRICES, composite_size

    left = np.asarray(left, np.float64)[..., :3]
    right = np.asarray(right, np.float64)[..., :3]
    composite_size(mode, (left.shape[1], left.shape[0]))  # refuses an unknown mode
    if mode == "side-by-side":
        return np.concatenate([left, right], axis=1).astype(np.float32)
    if mode == "cross-eyed":
        return np.concatenate([right, left], axis=1).astype(np.float32)
    if mode == "top-bottom":
        return np.concatenate([left, right], axis=0).astype(np.float32)
    lm, rm = ANAGLYPH_MATRICES[mode]
    return np.clip(left @ np.asarray(lm).T + right @ np.asarray(rm).T, 0.0, 1.0).astype(np.float32)
