"""Texture-based refinement that outlines the photographed shadows (Loscos 4.3.1, Figure 4.7).

The initial mesh (a coarse BF refinement, Figure 4.6a) does not follow the shadows the photograph
shows; the texture work of 4.3.2 is per leaf, so a leaf that straddles a shadow edge keeps half a
shadow. This pass splits leaves where the photograph's colours and the lamps' visibility disagree:

for each leaf i seen by the photograph and each touching leaf n of the same surface (textures.neighbours),
- colours similar (eq. 4.4 distance < ``colour_threshold``) but visibility from the lamps different
  → split i (case 1: a shadow edge the mesh does not follow yet);
- colours different but visibility similar → split i (case 2: the rays may have missed it);
- else, any lamp seen PARTIALly → split i (penumbra);
and the split is undone when no child's visibility differs from i's (the colour change was the
texture's own, Figure 4.8a). Kept children are examined again, down to the minimum element area or
to leaves that cover fewer than ``min_pixels`` pixels of the photograph (below that a child has no
colour of its own).

Visibility of a leaf from a lamp is the form-factor-weighted mean V over the links from that lamp's
elements (Σ F V / Σ F); its type VISIBLE / PARTIAL / INVISIBLE as the links'. Two leaves' visibility
is similar when every lamp has the same type and V differs by less than ``visibility_threshold``.
The lamps' links sit at the leaves (``lights_to_leaves``) and follow each split to the children.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..radiosity import INVISIBLE, PARTIAL, VISIBLE
from .textures import colour_distance, neighbours

__all__ = ["lamp_visibility", "split_decision", "refine_by_texture", "RefineStats"]


@dataclass
class RefineStats:
    """rounds: passes over the candidates; split: leaves split and kept; undone: splits undone."""

    rounds: int = 0
    split: int = 0
    undone: int = 0


def lamp_visibility(h, links, elements: np.ndarray, lamp_groups, group_of_element) -> tuple[np.ndarray, np.ndarray]:
    """(V (n, L), type (n, L) int8) of ``elements`` from each lamp group: V = Σ F·V / Σ F over the
    links from the lamp's elements received by the element; no link from a lamp (it faces away)
    counts as INVISIBLE with V = 0."""
    from_lamp = np.isin(group_of_element[links.source], lamp_groups)
    r, s = links.receiver[from_lamp], links.source[from_lamp]
    f, v = links.form_factor[from_lamp], links.visibility[from_lamp]
    row = np.full(len(h), -1)
    row[elements] = np.arange(len(elements))
    keep = row[r] >= 0
    r, s, f, v = row[r[keep]], s[keep], f[keep], v[keep]
    lamp = np.searchsorted(np.asarray(lamp_groups), group_of_element[s])
    shape = (len(elements), len(lamp_groups))
    weight, seen = np.zeros(shape), np.zeros(shape)
    lit_all, dark_all, count = np.ones(shape, bool), np.ones(shape, bool), np.zeros(shape, int)
    np.add.at(weight, (r, lamp), f)
    np.add.at(seen, (r, lamp), f * v)
    np.add.at(count, (r, lamp), 1)
    np.logical_and.at(lit_all, (r, lamp), v >= 1.0)
    np.logical_and.at(dark_all, (r, lamp), v <= 0.0)
    visibility = np.where(weight > 0, seen / np.where(weight > 0, weight, 1), 0.0)
    kind = np.where(count == 0, INVISIBLE, np.where(lit_all, VISIBLE, np.where(dark_all, INVISIBLE, PARTIAL)))
    return visibility, kind.astype(np.int8)


def similar_visibility(v_a, t_a, v_b, t_b, threshold: float) -> np.ndarray:
    """Same type from every lamp and V within ``threshold`` (rows of (n, L) arrays)."""
    return np.all((t_a == t_b) & (np.abs(v_a - v_b) < threshold), axis=-1)


def split_decision(
    colour: np.ndarray,
    has_colour: np.ndarray,
    visibility: np.ndarray,
    kind: np.ndarray,
    near: list[np.ndarray],
    colour_threshold: float,
    visibility_threshold: float,
    rows: np.ndarray | None = None,
) -> np.ndarray:
    """Figure 4.7's test for each of ``rows`` (default: all): split where a touching leaf with a
    colour of its own breaks case 1 or case 2, or where some lamp is seen PARTIALly. ``colour``:
    linear RGB scaled to white = 1 (n, 3); ``has_colour``: the row covers photograph pixels. Returns
    a mask over all rows (False outside ``rows``)."""
    asked = np.zeros(len(colour), bool)
    asked[np.arange(len(colour)) if rows is None else rows] = True
    split = np.any(kind == PARTIAL, axis=1) & asked
    for i in np.flatnonzero(has_colour & ~split & asked):
        n = near[i]
        n = n[has_colour[n]]
        if not len(n):
            continue
        same_colour = colour_distance(np.repeat(colour[i][None], len(n), axis=0), colour[n]) < colour_threshold
        same_vis = similar_visibility(visibility[i][None], kind[i][None], visibility[n], kind[n], visibility_threshold)
        split[i] = bool(np.any(same_colour != same_vis))
    return split & has_colour


def refine_by_texture(
    sol,
    pixel_leaf,
    photograph: np.ndarray,
    white: float,
    colour_threshold: float,
    visibility_threshold: float,
    min_pixels: int = 4,
    max_rounds: int = 12,
) -> RefineStats:
    """Refine ``sol`` (a built Radiosity with the lamps' links at the leaves) in place.
    ``pixel_leaf()``: the leaf seen through each photograph pixel (H, W), −1 where none, for the
    current hierarchy; ``photograph``: radiance (H, W, 3); ``white``: the radiance shown as white
    (the colour distance works on the photograph divided by it)."""
    h, L = sol.hierarchy, sol.links
    group = sol.polygons.group
    group_of_element = group[h.polygon]
    lamp_groups = np.sort(np.asarray(sol.polygons.lamps))
    photo = photograph.reshape(-1, 3).astype(np.float64) / max(white, 1e-300)
    stats = RefineStats()
    candidates = h.leaves()
    for _ in range(max_rounds):
        if not len(candidates):
            break
        stats.rounds += 1
        group_of_element = group[h.polygon]
        leaves = h.leaves()
        element = pixel_leaf().reshape(-1)
        on = element >= 0
        count = np.bincount(element[on], minlength=len(h))
        colour = np.stack([np.bincount(element[on], weights=photo[on, c], minlength=len(h)) for c in range(3)], axis=1)
        colour = colour / np.maximum(count, 1)[:, None]
        vis, kind = lamp_visibility(h, L, leaves, lamp_groups, group_of_element)
        rows = np.searchsorted(leaves, candidates)
        near = neighbours(h, leaves)
        split = split_decision(
            colour[leaves], count[leaves] > 0, vis, kind, near, colour_threshold, visibility_threshold, rows
        )
        split &= (count[leaves] >= min_pixels) & (h.area[leaves] / 4 >= sol.min_area)
        split &= h.exitance[leaves].max(axis=1) == 0
        parents = leaves[split]
        if not len(parents):
            break
        # the lamps' links move from each parent to its four children
        from_lamp = np.isin(group_of_element[L.source], lamp_groups) & np.isin(L.receiver, parents)
        old = L.remove(from_lamp)
        first = h.subdivide(parents)
        children = (first[:, None] + np.arange(4)).reshape(-1)
        slot = np.full(len(h), -1)
        slot[parents] = np.arange(len(parents))
        k = slot[old.receiver]
        recv = (first[k][:, None] + np.arange(4)).reshape(-1)
        sol.add_links(recv, np.repeat(old.source, 4))
        group_of_element = group[h.polygon]
        child_vis, child_kind = lamp_visibility(h, L, children, lamp_groups, group_of_element)
        parent_row = np.searchsorted(leaves, parents)
        same = (
            similar_visibility(
                np.repeat(vis[parent_row], 4, axis=0),
                np.repeat(kind[parent_row], 4, axis=0),
                child_vis,
                child_kind,
                visibility_threshold,
            )
            .reshape(-1, 4)
            .all(axis=1)
        )
        undo = parents[same]
        if len(undo):
            L.remove(np.isin(L.receiver, (h.child[undo][:, None] + np.arange(4)).reshape(-1)))
            back = np.isin(old.receiver, undo)
            L.extend(old.receiver[back], old.source[back], old.form_factor[back], old.visibility[back])
            h.collapse(undo)
        sol.links_changed()
        stats.split += int((~same).sum())
        stats.undone += int(same.sum())
        kept = parents[~same]
        candidates = np.sort((h.child[kept][:, None] + np.arange(4)).reshape(-1)) if len(kept) else kept
    return stats
