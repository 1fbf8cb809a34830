"""The per-pixel variant (the chapter's own conclusion: do the texture work per pixel, not per
element). At the surface point x seen through each pixel, with normal n_x:

    H_s(x) = F_x→s · V_x→s · B_s          direct irradiance from lamp s (exact point-to-polygon F,
                                          V from rays to the lamp, B_s its radiosity)

A lamp is one-sided: x in the half-space behind its plane receives nothing from it, and V counts
only the rays to lamp points above x's tangent plane (the contour integral is taken in absolute
value, so without the first test the ceiling was lit by the backs of lamps facing down).
    I(x)                                  the indirect irradiance of the radiosity solution (per leaf)

and the relit image is the photograph scaled by the change of the irradiance at x,

    T(x) · (Σ_s k_s H_s(x) + I′(x)) / (Σ_s H_s(x) + I(x)),

so a photographed shadow of lamp s (V_x→s = 0 where the photograph is dark) loses exactly that lamp's
share when the lamp changes, at the photograph's resolution.
"""

from __future__ import annotations

import numpy as np

from ..radiosity import point_polygon
from . import prepare as preparation

__all__ = ["surface_points", "lamp_irradiance", "prepare", "pixel_indirect", "image"]


def surface_points(polygons, view, size):
    """(points (H, W, 3), normals (H, W, 3), polygon (H, W), −1 off the geometry) seen through the
    pixel centres (Embree)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    vertices, faces = polygons.triangles()
    face_polygon = np.r_[np.arange(len(polygons)), np.flatnonzero(~polygons.triangle)]
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices[faces])
    w, h = size
    directions = view.ray_directions((w, h)).reshape(-1, 3)
    origin = np.asarray(view.pose.position, np.float64)
    hit = scene.run(
        np.repeat(origin[None], len(directions), axis=0).astype(np.float32), directions.astype(np.float32), output=1
    )
    prim = np.asarray(hit["primID"])
    polygon = np.where(prim >= 0, face_polygon[np.maximum(prim, 0)], -1)
    points = origin + directions * np.where(prim >= 0, np.asarray(hit["tfar"], np.float64), 0)[:, None]
    n = polygons.normals()
    normals = np.where(polygon[:, None] >= 0, n[np.maximum(polygon, 0)], 0.0)
    return points.reshape(h, w, 3), normals.reshape(h, w, 3), polygon.reshape(h, w)


def lamp_irradiance(
    polygons,
    lamp_rows: np.ndarray,
    exitance: np.ndarray,
    points,
    normals,
    seen,
    samples: int = 16,
    seed: int = 0,
    unoccluded: bool = False,
):
    """H_s(x) for every seen pixel and every lamp polygon in ``lamp_rows``: (n_seen, n_lamps, 3) W/m².
    ``exitance``: B_s of each lamp polygon (n_lamps, 3). With ``unoccluded``, also F_x→s·B_s, the
    same without the visibility (what a shadow took away is the difference)."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    vertices, faces = polygons.triangles()
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, vertices[faces])
    rng = np.random.default_rng(seed)
    x = points[seen].astype(np.float64)
    n = normals[seen].astype(np.float64)
    extent = float(np.ptp(polygons.corners.reshape(-1, 3), axis=0).max())
    start = x + n * 1e-5 * extent
    out = np.zeros((len(x), len(lamp_rows), 3))
    free = np.zeros_like(out)
    lamp_normal = polygons.normals()[lamp_rows]
    for k, row in enumerate(lamp_rows):
        corners = np.repeat(polygons.corners[row][None], len(x), axis=0)
        in_front = (x - polygons.corners[row].mean(axis=0)) @ lamp_normal[k] > 0
        f = point_polygon(x[:, None], n, corners, np.repeat(polygons.triangle[row], len(x))) * in_front
        uv = rng.random((len(x), samples, 2))
        c = polygons.corners[row]
        u, v = uv[..., :1], uv[..., 1:]
        target = (1 - u) * (1 - v) * c[0] + u * (1 - v) * c[1] + u * v * c[2] + (1 - u) * v * c[3]
        d = target - start[:, None]
        length = np.linalg.norm(d, axis=2)
        hit = scene.run(
            np.repeat(start, samples, axis=0).astype(np.float32),
            (d / length[..., None]).reshape(-1, 3).astype(np.float32),
            dists=(length.reshape(-1) * (1 - 1e-4)).astype(np.float32),
            query="OCCLUDED",
        )
        above = (d * n[:, None]).sum(axis=2) > 0
        visible = ((np.asarray(hit).reshape(len(x), samples) < 0) & above).mean(axis=1)
        out[:, k] = (f * visible)[:, None] * exitance[k]
        free[:, k] = f[:, None] * exitance[k]
    return (out, free) if unoccluded else out


def prepare(s) -> None:
    """The per-pixel method's preparation on a session: the surface point, normal and each lamp's
    direct irradiance at every pixel it relights, and the indirect irradiance there."""
    m = s.model
    points, normals, polygon = surface_points(m, s.real.view, s.real.size)
    lamp_rows = np.flatnonzero(np.isin(m.group, m.lamps))
    emitting = m.exitance.max(axis=1) > 0  # lamps (scaled below) and self-luminous (kept)
    s.pixel_seen = (polygon >= 0) & ~emitting[np.maximum(polygon, 0)] & (s.pixel_element >= 0)
    s.lamp_rows = lamp_rows
    s.pixel_lamp = lamp_irradiance(
        m, lamp_rows, m.exitance[lamp_rows], points, normals, s.pixel_seen, seed=s.params.hierarchy.seed
    )
    s.pixel_indirect = pixel_indirect(s)


def pixel_indirect(s) -> np.ndarray:
    """I at the pixels the per-pixel method relights (n, 3): each leaf's indirect irradiance
    averaged at the corner points of its surface and interpolated across the leaf by the display
    (a flat value per leaf drew the leaves' edges as seams across the ceiling)."""
    return preparation.corner_image(s, preparation.indirect(s)[s.solution.hierarchy.leaves()])[s.pixel_seen]


def image(s) -> np.ndarray:
    """The relit photograph (H, W, 3), photograph scale, under the session's lamp scales."""
    m = s.model
    scale = np.array([s.scales.get(m.names[m.group[r]], 1.0) for r in s.lamp_rows])
    before = s.pixel_lamp.sum(axis=1) + s.pixel_indirect
    after = (s.pixel_lamp * scale[None, :, None]).sum(axis=1) + pixel_indirect(s)
    image = s.real.photograph.astype(np.float64).copy()
    image[s.pixel_seen] *= np.where(before > 0, after / np.where(before > 0, before, 1), 0)
    lamps = (s.pixel_polygon >= 0) & np.isin(m.group[np.maximum(s.pixel_polygon, 0)], m.lamps)
    lamp_scale = {m.names[g]: s.scales.get(m.names[g], 1.0) for g in m.lamps}
    image[lamps] *= np.array([lamp_scale[m.names[m.group[r]]] for r in s.pixel_polygon[lamps]])[:, None]
    return image
