"""Preparation (Loscos 4.2.1), the part every method shares: the estimates from the photograph and
the first hierarchy. Each function takes the RelightSession it prepares and sets its fields.

The polygon under each pixel of the photograph gives B̂_i (mean pixel of polygon i) and B̂_A (mean
over every non-lamp pixel); eq. (4.1) with the user's ρ̂, ρ̂ re-estimated as the area-weighted mean,
eq. (4.1) again; polygons the photograph does not see get ρ̂. Eq. (4.2) gives every lamp the same
exitance. The hierarchy is built and solved; each leaf the photograph sees then takes its own ρ from
eq. (4.1) with its pixels (the chapter's update at subdivision), inner elements the area-weighted
mean of their children's, and the solution is solved again. With the inverse estimate
(``RelightParams.estimate``, the default) each lamp the photograph shows unclipped and from the
front takes π × its mean pixel instead of eq. (4.2)'s share, and each seen leaf's ρ is then set to
π·B̂/H, H the irradiance the solution gathers there, alternated with the solve until it settles
(``INVERSE_TOLERANCE``): the ρ that explains the leaf's photographed light rather than its
brightness."""

from __future__ import annotations

import time

import numpy as np

from ..core.errors import InputError
from ..radiosity import Polygons, corner_average, leaf_mesh, polygon_areas
from . import estimate
from .params import INVERSE_MAX_ITERATIONS, INVERSE_TOLERANCE
from .photograph import polygon_ids
from .shadow_refine import refine_by_texture


def estimate_model(s) -> tuple[Polygons, np.ndarray]:
    p, photo = s.real.polygons, s.real.photograph.astype(np.float64)
    ids = polygon_ids(p, s.real.view, s.real.size)
    s.pixel_polygon = ids
    lamp = np.isin(p.group, p.lamps)
    # a surface the model gives an exitance but that is not a lamp (a monitor's screen) shines by
    # itself: not relit, its exitance taken from the photograph, its reflectance 0
    glowing = (p.exitance.max(axis=1) > 0) & ~lamp
    seen = ids >= 0
    surface = seen & ~lamp[np.maximum(ids, 0)]
    if not surface.any():
        raise InputError("the camera sees none of the scene's (non-lamp) geometry")
    mean_scene = photo[surface].mean(axis=0)  # B̂_A (radiance)
    count = np.bincount(ids[surface], minlength=len(p))
    total = np.stack(
        [np.bincount(ids[surface], weights=photo[surface][:, c], minlength=len(p)) for c in range(3)], axis=1
    )
    visible = (count > 0) & ~lamp & ~glowing
    areas = polygon_areas(p.corners, p.triangle)
    rho = np.zeros((len(p), 3))
    rho_visible, rho_hat = estimate.reestimated_reflectance(
        total[visible] / count[visible, None], mean_scene, s.params.mean_reflectance, areas[visible]
    )
    rho[visible] = rho_visible
    rho[~visible & ~lamp & ~glowing] = rho_hat
    exitance = np.zeros((len(p), 3))
    seen_glow = glowing & (count > 0)
    exitance[seen_glow] = np.pi * total[seen_glow] / count[seen_glow, None]
    exitance[glowing & ~seen_glow] = np.pi * mean_scene
    glow_power = (exitance[glowing] * areas[glowing, None]).sum(axis=0)
    exitance[lamp] = estimate.lamp_exitance(
        rho_hat, mean_scene, float(areas[~lamp].sum()), float(areas[lamp].sum()), other_power=glow_power
    )
    if s.params.estimate == "inverse":
        lamps_from_pixels(s, exitance)
    s.mean_scene = mean_scene
    return Polygons(p.corners, p.triangle, rho, exitance, p.group, list(p.names), list(p.lamps)), rho_hat


def lamps_from_pixels(s, exitance: np.ndarray) -> None:
    """The inverse estimate's lamps: each lamp group whose pixels (eroded by one, off its rim) the
    photograph holds unclipped takes E = π × their mean; the others keep eq. (4.2)'s."""
    from scipy import ndimage

    p, ids, photo = s.real.polygons, s.pixel_polygon, s.real.photograph
    # a photograph that never passes 1 is a low-dynamic-range one: its lamps clip there
    saturation = None if float(photo.max()) > 1.0 else 1.0
    eye = np.asarray(s.real.view.pose.position, np.float64)
    normals, centres = p.normals(), p.corners.mean(axis=1)
    s.lamps_read = []
    for g in p.lamps:
        rows = p.group == g
        if ((eye - centres[rows]) * normals[rows]).sum(axis=1).min() <= 0:
            continue  # seen from behind (or edge-on): its pixels are not its light
        own = ndimage.binary_erosion((ids >= 0) & (p.group[np.maximum(ids, 0)] == g))
        read = estimate.lamp_exitance_from_pixels(photo[own], saturation)
        if read is not None and read.max() > 0:
            exitance[rows] = read
            s.lamps_read.append(p.names[g])


def leaf_pixels(s, values: np.ndarray | None = None, element: np.ndarray | None = None):
    """(pixels seen per element (n,), the mean of ``values`` (H, W, 3; default the photograph's
    radiance) over them (n, 3)) for the non-emitting elements under ``element`` (default
    ``pixel_element``)."""
    h = s.solution.hierarchy
    element = s.pixel_element if element is None else element
    values = s.real.photograph.astype(np.float64) if values is None else values
    seen = (element >= 0) & (h.exitance[np.maximum(element, 0)].max(axis=-1) == 0)
    count = np.bincount(element[seen], minlength=len(h))
    total = np.stack(
        [np.bincount(element[seen], weights=values[seen][:, c], minlength=len(h)) for c in range(3)], axis=1
    )
    return count, total / np.maximum(count, 1)[:, None]


def textures_to_leaves(s) -> None:
    """Each seen leaf's ρ from its own pixels — eq. (4.1), or with the inverse estimate ρ = πB̂/H
    alternated with the solve — pulled up the tree, then solved again."""
    sol = s.solution
    h = sol.hierarchy
    s.pixel_element = pixel_leaf(s)
    count, mean_pixels = leaf_pixels(s)
    leaves = h.leaves()
    lit = leaves[count[leaves] > 0]
    h.reflectance[lit] = estimate.reflectance_from_photograph(mean_pixels[lit], s.mean_scene, s.mean_reflectance)
    pull_reflectance(s)
    sol.solve()
    if s.params.estimate == "inverse":
        s.inverse_iterations = 0
        while s.inverse_iterations < INVERSE_MAX_ITERATIONS:
            before = h.reflectance[lit].mean(axis=1)
            h.reflectance[lit] = estimate.reflectance_from_irradiance(mean_pixels[lit], leaf_irradiance(s)[lit])
            pull_reflectance(s)
            sol.solve()
            s.inverse_iterations += 1
            change = np.abs(h.reflectance[lit].mean(axis=1) - before) / np.maximum(before, 1e-6)
            if not len(lit) or np.median(change) < INVERSE_TOLERANCE:
                break


def leaf_irradiance(s) -> np.ndarray:
    """H per element (n, 3): the irradiance gathered at it and at every ancestor (links may end
    above the leaves), W/m²."""
    h = s.solution.hierarchy
    total = h.irradiance.copy()
    for lv in h.by_level()[1:]:
        total[lv] += total[h.parent[lv]]
    return total


def pixel_leaf(s) -> np.ndarray:
    """The leaf seen through each pixel of the photograph (H, W) int, −1 where none."""
    s.display.load(leaf_mesh(s.solution.hierarchy, smooth=False))
    colour, element = s.display(s.real.view, s.real.size)
    out = s.ctx.readback_image(element, 1, clip=False)[..., 0].astype(np.int64)
    s.ctx.release(colour, element)
    return out


def texture_refinement(s) -> None:
    """Loscos 4.3.1 (relight.shadow_refine), then the solution solved on the new leaves."""
    t = time.perf_counter()
    photo = s.real.photograph
    surface = s.pixel_polygon >= 0
    surface &= s.model.exitance[np.maximum(s.pixel_polygon, 0)].max(axis=-1) == 0
    luminance = photo[surface] @ np.array([0.2126, 0.7152, 0.0722]) if surface.any() else np.ones(1)
    white = float(np.percentile(luminance, 99))
    p = s.params
    s.refine_stats = refine_by_texture(
        s.solution, lambda: pixel_leaf(s), photo, white, p.colour_threshold, p.visibility_threshold, p.min_pixels
    )
    s.solution.solve()
    s.times["texture refinement"] = time.perf_counter() - t


def pull_reflectance(s) -> None:
    h = s.solution.hierarchy
    for lv in h.by_level()[-2::-1]:
        inner = lv[h.child[lv] >= 0]
        if len(inner):
            c = h.child[inner][:, None] + np.arange(4)
            h.reflectance[inner] = (h.area[c][..., None] * h.reflectance[c]).sum(axis=1) / h.area[inner][:, None]


def indirect(s) -> np.ndarray:
    """I per leaf (n_leaves, 3): the irradiance the solution gathers, less the lamps' direct part."""
    sol = s.solution
    h = sol.hierarchy
    lamp = sol.exitance()[sol.links.source].max(axis=1) > 0
    direct = np.zeros((len(h), 3))
    weight = sol.links.form_factor * sol.links.visibility
    b = h.radiosity[sol.links.source]
    for c in range(3):
        direct[:, c] = np.bincount(sol.links.receiver[lamp], weights=(weight * b[:, c])[lamp], minlength=len(h))
    lamps = direct
    for lv in h.by_level()[1:]:
        lamps[lv] += lamps[h.parent[lv]]
    return np.clip(leaf_irradiance(s) - lamps, 0, None)


def corner_image(s, values: np.ndarray) -> np.ndarray:
    """Per-leaf ``values`` (n_leaves, 3) averaged at the corner points of each surface
    (radiosity.display.corner_average) and interpolated across the leaves by the display: (H, W,
    3) at the photograph's pixels, 0 off the geometry. No step at a leaf's edge."""
    h = s.solution.hierarchy
    mesh = leaf_mesh(h, smooth=False)
    mesh.radiance = corner_average(h, h.leaves(), values).reshape(-1, 3).astype(np.float32)
    s.display.load(mesh)
    colour, _ = s.display(s.real.view, s.real.size, elements=False)
    out = s.ctx.readback_image(colour, 3, clip=False)
    s.ctx.release(colour)
    return out.astype(np.float64)
