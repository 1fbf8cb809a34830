"""The final gather: each pixel's light gathered at its own point from the solved radiosities.

The corner gather (:mod:`.display`) is exact at each leaf's corners and linear between them; where
light changes faster than the leaves (a ceiling 8 cm over a lamp's upward face, a floor under a
desk's edge) the image follows the leaves, not the light. Here each pixel sample x — the point of
the leaf the display drew there, on the camera ray — gathers, as one more bounce of the solve,

    B(x) = E(x) + ρ(x)·(H_lamps(x) + H_reflected(x))

- H_lamps(x) = Σ_l E_l·F_x→l·V_x,l over the lamps (the emitting roots): F the exact
  point-to-polygon form factor (:func:`.formfactor.point_polygon`), V by ``shadow_rays`` rays to
  uniform points of lamps drawn in proportion to E_l·F_x→l (stratified over the draw), each weighted
  so the sum is unbiased: (Σ_l E_l·F_l)·(E_k·F_k / |E_k·F_k|)·V over the draws k.
- H_reflected(x) = ∫ (B − E)(y) cos θ/π dω, the mean over ``gather_rays`` cosine-weighted rays
  (a jittered grid) of B − E at the leaf each ray meets (:meth:`.hierarchy.Hierarchy.leaf_at`; its
  reversed twin's where a ray meets a two-sided face from behind; nothing at a one-sided face's back
  or off the scene). The lamps' own E is H_lamps's, so it is left out here.

The solve's B is already the gain cap's and the cluster links' (h.radiosity holds it all); an error
in a leaf's B is averaged over the rays that meet it, as one bounce of a path tracer averages its
next hits. Each random choice comes from ``seed``: the image is deterministic.
"""

from __future__ import annotations

import numba
import numpy as np

from ..core.progress import phase
from ..core.rays import cast
from ..scene.camera import View
from .formfactor import point_polygon
from .hierarchy import leaf_of
from .visibility import cosine_directions, jittered_grid

__all__ = ["final_gather", "pixel_points", "reflected_along", "twin_roots"]

#: pixel samples gathered at once (their rays and lamp form factors: ~1 kB a sample and ray)
SLICE = 8192


def pixel_points(h, view: View, element: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(pixels, leaves, points): the flat indices of the pixels of ``element`` (H, W) int, row 0 at
    the top, that show a leaf (≥ 0), those leaves, and where each pixel centre's camera ray meets
    the leaf's plane (n, 3) metres (the leaf's centre where the ray runs along the plane)."""
    rows, cols = element.shape
    pixels = np.flatnonzero(element.reshape(-1) >= 0)
    leaves = element.reshape(-1)[pixels]
    directions = view.ray_directions((cols, rows)).reshape(-1, 3)[pixels]
    eye = np.asarray(view.pose.position, np.float64)
    normal = h.normal[leaves]
    along = (directions * normal).sum(axis=1)
    grazing = np.abs(along) < 1e-9
    t = ((h.centre[leaves] - eye) * normal).sum(axis=1) / np.where(grazing, 1.0, along)
    points = np.where(grazing[:, None], h.centre[leaves], eye + t[:, None] * directions)
    return pixels, leaves, points


@numba.njit(cache=True)
def _draw_lamps(weight, strata, out):
    """Per sample (row of ``weight`` (n, L) ≥ 0), the lamp each stratum's uniform (n, S) falls on
    in the row's cumulative weight, −1 where the row is all 0."""
    n, lamps = weight.shape
    cumulative = np.empty(lamps)
    for i in range(n):
        total = 0.0
        for j in range(lamps):
            total += weight[i, j]
            cumulative[j] = total
        for s in range(strata.shape[1]):
            if total <= 0:
                out[i, s] = -1
                continue
            # the first lamp whose cumulative weight passes the target (never one of weight 0)
            out[i, s] = min(np.searchsorted(cumulative, strata[i, s] * total, side="right"), lamps - 1)


def _lamp_light(solution, points, normals, shadow_rays: int, rng) -> np.ndarray:
    """H_lamps at ``points`` (n, 3) facing ``normals`` (n, 3): (n, 3) W/m² (the module docstring)."""
    h, vis = solution.hierarchy, solution.visibility
    n = len(points)
    exitance = solution.exitance()
    roots = h.roots[h.active[h.roots]]
    lamps = roots[exitance[roots].max(axis=1) > 0]
    if not len(lamps) or not n:
        return np.zeros((n, 3))
    form_factor = np.empty((n, len(lamps)))
    for k, lamp in enumerate(lamps):  # one lamp at a time: no (n × lamps) copy of the corners
        form_factor[:, k] = point_polygon(
            points[:, None], normals, np.broadcast_to(h.corners[lamp], (n, 4, 3)), np.full(n, h.triangle[lamp])
        )
    light = np.maximum(form_factor, 0.0)[:, :, None] * exitance[lamps][None]  # E_l·F_x→l (n, L, 3)
    weight = light.mean(axis=2)
    strata = (np.arange(shadow_rays)[None] + rng.random((n, shadow_rays))) / shadow_rays
    drawn = np.empty((n, shadow_rays), np.int64)
    _draw_lamps(weight, strata, drawn)
    ok = drawn >= 0
    lamp = np.maximum(drawn, 0)
    targets = h.sample_points(lamps[lamp.reshape(-1)], rng.random((n * shadow_rays, 1, 2)))[:, 0]
    origins = np.repeat(points + vis.offset * normals, shadow_rays, axis=0)
    segment = targets - origins
    length = np.linalg.norm(segment, axis=1)
    segment /= np.maximum(length, 1e-300)[:, None]
    # stopped short of the lamp (a ray to its own polygon is not blocked by it)
    blocked = np.asarray(cast(vis.scene, origins, segment, np.maximum(length - 4 * vis.offset, 0.0), "OCCLUDED"))
    clear = ok & (blocked < 0).reshape(n, shadow_rays) if not vis.empty else ok
    picked = np.take_along_axis(light, lamp[:, :, None], axis=1)  # (n, S, 3)
    share = picked / np.maximum(np.take_along_axis(weight, lamp, axis=1), 1e-300)[:, :, None]
    return (share * clear[:, :, None]).mean(axis=1) * weight.sum(axis=1)[:, None]


def _reflected_light(solution, points, normals, gather_rays: int, twin_root, rng) -> np.ndarray:
    """H_reflected at ``points`` facing ``normals``: (n, 3) W/m² (the module docstring)."""
    n = len(points)
    if solution.visibility.empty or not n:
        return np.zeros((n, 3))
    directions = cosine_directions(normals, jittered_grid(n, gather_rays, rng)).reshape(-1, 3)
    origins = np.repeat(points + solution.visibility.offset * normals, gather_rays, axis=0)
    return _gathered_rays(solution, origins, directions, twin_root, gather_rays)


def reflected_along(solution, origins: np.ndarray, directions: np.ndarray, twin_root: np.ndarray) -> np.ndarray:
    """(n, 3) W/m²: B − E of the leaf each ray (``origins``, unit ``directions`` (n, 3)) meets first
    — the front it meets, or a two-sided surface's twin (``twin_root``: :func:`twin_roots`) where it
    meets one from behind —, 0 where it meets a one-sided face's back or nothing."""
    return _gathered_rays(solution, origins, directions, twin_root, 1)


def _gathered_rays(solution, origins, directions, twin_root, rays: int) -> np.ndarray:
    """(n / rays, 3): the mean of :func:`reflected_along` over each run of ``rays`` rays."""
    h, vis = solution.hierarchy, solution.visibility
    hit = cast(vis.scene, origins, directions)
    out = np.zeros((len(origins) // rays, 3))
    _mean_of_hits(
        np.asarray(hit["primID"]),
        np.asarray(hit["tfar"]),
        np.ascontiguousarray(origins, np.float64),
        np.ascontiguousarray(directions, np.float64),
        vis.triangle_root,
        h.normal,
        twin_root,
        h.corners,
        h.triangle,
        h.child,
        h.radiosity - solution.exitance(),
        rays,
        out,
    )
    return out


@numba.njit(cache=True, parallel=True)
def _mean_of_hits(
    prim, tfar, origins, directions, triangle_root, normal, twin_root, corners, triangle, child, reflected, rays, out
):
    """reflected_along's leaf and value for each hit, averaged over each sample's ``rays``."""
    for i in numba.prange(out.shape[0]):
        for r in range(i * rays, (i + 1) * rays):
            if prim[r] < 0:
                continue
            root = triangle_root[prim[r]]
            d = directions[r]
            if d[0] * normal[root, 0] + d[1] * normal[root, 1] + d[2] * normal[root, 2] >= 0:
                root = twin_root[root]  # met from behind: the twin, if the face has one
                if root < 0:
                    continue
            t = tfar[r]  # the hit point as a tuple: no array allocated per ray
            hit = (origins[r, 0] + t * d[0], origins[r, 1] + t * d[1], origins[r, 2] + t * d[2])
            leaf = leaf_of(corners, triangle, child, root, hit)
            for c in range(3):
                out[i, c] += reflected[leaf, c]
        for c in range(3):
            out[i, c] /= rays


def twin_roots(h) -> np.ndarray:
    """(len(h),): the root of each root's reversed twin (Polygons.twins), −1 where it has none."""
    root_of = np.full(len(h.polygons), -1, np.int64)
    root_of[h.polygon[h.roots]] = h.roots
    twin = h.polygons.twins()[h.polygon[h.roots]]
    out = np.full(len(h), -1, np.int64)
    out[h.roots] = np.where(twin >= 0, root_of[np.maximum(twin, 0)], -1)
    return out


def final_gather(
    solution,
    view: View,
    element: np.ndarray,
    gather_rays: int = 64,
    shadow_rays: int = 16,
    seed: int = 0,
    reflectance: np.ndarray | None = None,
) -> np.ndarray:
    """B (H, W, 3) W/m² at each pixel of ``element`` (H, W) int — the leaf the display drew at each
    pixel centre, −1 where none: its map, row 0 at the top — gathered at the pixel's point (the
    module docstring); 0 where no leaf is. ``solution``: a solved :class:`.engine.Radiosity`;
    ``gather_rays`` and ``shadow_rays`` ≥ 1. ``reflectance`` (n_elements, 3), optional: the ρ each
    leaf's pixels reflect their light with (display.drawn_reflectance where textures modulate the
    image after); the leaves' own by default."""
    h = solution.hierarchy
    rng = np.random.default_rng(seed)
    pixels, leaves, points = pixel_points(h, view, np.asarray(element))
    twin_root = twin_roots(h)
    out = np.zeros((element.size, 3))
    exitance = solution.exitance()
    rho = h.reflectance if reflectance is None else reflectance
    name = f"radiosity: final gather, {len(pixels):,} pixel samples × {gather_rays} + {shadow_rays} rays"
    with phase(name, len(pixels)) as advance:
        for at in range(0, len(pixels), SLICE):
            part = slice(at, at + SLICE)
            leaf, x = leaves[part], points[part]
            normal = h.normal[leaf]
            light = _lamp_light(solution, x, normal, shadow_rays, rng) + _reflected_light(
                solution, x, normal, gather_rays, twin_root, rng
            )
            out[pixels[part]] = exitance[leaf] + rho[leaf] * light
            advance(len(leaf))
    return out.reshape(element.shape + (3,))
