"""The loscos method's texture work on a prepared session: textures free of the photographed shadows
(4.3.2, visibility-independent textures with eqs. 4.6-4.9) and the optional fresh solution (4.3.3)."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..radiosity import (
    Radiosity,
    leaf_mesh,
)
from . import estimate, prepare, textures
from .corners import corner_gather, store_display_factor


def visibility_independent_textures(s) -> None:
    """Loscos 4.3.2 (relight.textures): per-leaf texture factors, the final reflectances, the new
    solution and its display factor D = B + ρĒ at the leaves' corners."""
    sol = s.solution
    h = sol.hierarchy
    leaves = h.leaves()
    rho = h.reflectance[leaves].copy()
    b_orig = h.radiosity[leaves]
    _, blocked, free, lit, shadowed = textures.lamp_transfer(h, sol.links, leaves)
    indirect = prepare.indirect(s)[leaves]
    # a leaf whose blocked light is a small share of what it would receive is in no shadow worth
    # the name (a monitor's light grazing the ceiling): its photograph is kept, and it may serve
    # as a reference
    significant = blocked.sum(axis=1) > textures.BLOCKED_SHARE * (free + indirect).sum(axis=1)
    lit = lit | (~significant & (free.sum(axis=1) > 0))
    shadowed &= significant
    shadowed &= h.exitance[leaves].max(axis=1) == 0  # a self-luminous leaf keeps its texture
    inter = np.where(b_orig > 0, (b_orig + rho * blocked) / np.where(b_orig > 0, b_orig, 1), 1.0)  # eq. 4.6
    count, mean_pixels = prepare.leaf_pixels(s)
    seen = count[leaves] > 0
    # ρ_inter: T_inter read as eq. 4.1 reads a texture (its brightness; the scale cancels in 4.9)
    rho_inter = mean_pixels[leaves] * inter / np.maximum(s.mean_scene, 1e-12) * s.mean_reflectance
    # the colour compared by Figure 4.11: the leaf's reflectance once unoccluded
    colour = np.clip(rho * inter if s.params.estimate == "brightness" else rho, 0, estimate.MAX_REFLECTANCE)
    near = textures.neighbours(h, leaves)
    frontier = lit & seen & np.array([bool(len(n)) and shadowed[n].any() for n in near])
    group = s.model.group[h.polygon[leaves]]
    ref = textures.references(h, leaves, shadowed, frontier, group, colour, s.params.colour_threshold)
    factor = inter.copy()
    fix = (ref >= 0) & seen & s.params.reference_correction
    r = ref[fix]
    # eq. 4.8 with the indirect irradiance I in both sums: the texture holds indirect light too, and
    # with the lamps' form factors alone a leaf nearer a lamp than its reference came out too bright
    unoccluded = free + indirect
    ratio = unoccluded[fix].sum(axis=1) / np.maximum(unoccluded[r].sum(axis=1), 1e-300)
    rho_corr = rho_inter[r] * ratio[:, None]  # eq. 4.8
    correction = rho_corr / np.maximum(rho_inter[fix], 1e-6)
    weight = (
        textures.correction_weight(blocked[fix], free[fix]) if s.params.reference_weight == "blocked-share" else 1.0
    )
    factor[fix] = inter[fix] * correction ** np.reshape(weight, (-1, 1))  # eq. 4.9
    s.references = (leaves, ref)
    s.shadowed = shadowed
    # ρ_final: the brightness of T_final (4.1), or the inverse estimate's ρ times what 4.9 changed
    texture_change = factor if s.params.estimate == "brightness" else factor / inter
    h.reflectance[leaves] = np.clip(rho * texture_change, 0, estimate.MAX_REFLECTANCE)
    prepare.pull_reflectance(s)
    sol.solve()
    final = leaf_mesh(h, sol.links, sol.exitance(), gather=s._gather)
    _, blocked, _, _, _ = textures.lamp_transfer(h, sol.links, leaves)
    final.radiance = final.radiance + np.repeat(h.reflectance[leaves] * blocked / np.pi, 4, axis=0).astype(np.float32)
    s.display_factor = final
    s.texture_factor[leaves] = factor


def fresh_solution(s) -> None:
    """Loscos 4.3.3, the chapter's usual end: a new solution over the final textures. Pass one:
    mesh and links made with ``final_hierarchy`` and the lamps' links at the leaves, each leaf's ρ
    the mean over its pixels of the final ρ, D = B + ρĒ at the corners. Pass two: the links made
    again on that mesh where the criterion puts them, and solved: the B that is displayed. The
    textures (T_final) stay those of the 4.3 mesh."""
    t = time.perf_counter()
    old = s.solution.hierarchy
    rho_map = old.reflectance[np.maximum(s.pixel_element, 0)]
    model = dataclasses.replace(s.model, reflectance=old.reflectance[old.roots[: len(s.model)]].copy())
    sol = Radiosity(
        model,
        dataclasses.replace(
            s.params.final_hierarchy, lights_to_leaves=True, sliver_piece=0.0, contact_cuts=False, reach_rays=0
        ),
    ).build()
    s.solution, s._gather = sol, corner_gather()
    h = sol.hierarchy
    element = prepare.pixel_leaf(s)
    count, mean_rho = prepare.leaf_pixels(s, rho_map, element)
    leaves = h.leaves()
    lit = leaves[count[leaves] > 0]
    h.reflectance[lit] = np.clip(mean_rho[lit], 0, estimate.MAX_REFLECTANCE)
    prepare.pull_reflectance(s)
    sol.solve()
    final = leaf_mesh(h, sol.links, sol.exitance(), gather=s._gather)
    _, blocked, _, _, _ = textures.lamp_transfer(h, sol.links, leaves)
    final.radiance = final.radiance + np.repeat(h.reflectance[leaves] * blocked / np.pi, 4, axis=0).astype(np.float32)
    s.display_factor, s.pixel_element = final, element
    store_display_factor(s)
    sol.relink()
    s.pixel_element = prepare.pixel_leaf(s)
    s.times["fresh solution"] = time.perf_counter() - t
