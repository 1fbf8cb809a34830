"""The display factor D kept at the corners of every element, and the relit B gathered at the corners
the photograph's view shows: what the element methods (baseline, loscos) divide and draw, eq. (4.3)."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..radiosity import CornerGather, leaf_mesh
from .prepare import corner_image

#: the corners' kept sums take a source's new B once it moved by more than this share of the
#: largest reflected B (radiosity.CornerGather): each corner within it of the plain gather, a tenth
#: of a grey level at that B, below the solve's own error (its tolerance 10⁻⁴ on a step that
#: contracts ~0.93)
GATHER_TOLERANCE = 3e-4


def corner_gather() -> CornerGather:
    """The gather the session's corners are drawn with: its form factors and sums kept between edits."""
    return CornerGather(GATHER_TOLERANCE)


_CHILD_UV = np.array(
    [
        [(0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5)],
        [(0.5, 0), (1, 0), (1, 0.5), (0.5, 0.5)],
        [(0.5, 0.5), (1, 0.5), (1, 1), (0.5, 1)],
        [(0, 0.5), (0.5, 0.5), (0.5, 1), (0, 1)],
    ]
)
_CHILD_BARY = np.array(
    [
        [(0, 0), (0.5, 0), (0, 0.5), (0, 0.5)],
        [(0.5, 0), (1, 0), (0.5, 0.5), (0.5, 0.5)],
        [(0, 0.5), (0.5, 0.5), (0, 1), (0, 1)],
        [(0.5, 0), (0.5, 0.5), (0, 0.5), (0, 0.5)],
    ]
)


def store_display_factor(s) -> None:
    """D at the corners of every element (n_elements, 4, 3): the leaves' from the display factor
    mesh, so that leaves made later (a virtual object's new shadows) inherit theirs."""
    h = s.solution.hierarchy
    leaves = h.leaves()
    s.corner_d = np.zeros((len(h), 4, 3), np.float32)
    s.corner_d[leaves] = s.display_factor.radiance.reshape(-1, 4, 3)
    s.has_d = np.zeros(len(h), bool)
    s.has_d[leaves] = True


def inherit_display_factor(s) -> None:
    """Elements made since preparation take D interpolated from their parent's corners (bilinear on
    quads, barycentric on triangles); a virtual object's elements have none (shown by B/π). Their
    texture factor is 1 (no texture work reached them), so every per-element array covers them."""
    h = s.solution.hierarchy
    n = len(h)
    if n > len(s.texture_factor):
        s.texture_factor = np.concatenate([s.texture_factor, np.ones((n - len(s.texture_factor), 3))])
    if n > len(s.corner_d):
        s.corner_d = np.concatenate([s.corner_d, np.zeros((n - len(s.corner_d), 4, 3), np.float32)])
        s.has_d = np.r_[s.has_d, np.zeros(n - len(s.has_d), bool)]
    for lv in h.by_level()[1:]:
        todo = lv[~s.has_d[lv] & s.has_d[h.parent[lv]]]
        if not len(todo):
            continue
        parent = h.parent[todo]
        k = todo - h.child[parent]  # which child
        d = s.corner_d[parent]  # (m, 4, 3)
        tri = h.triangle[todo]
        uv = np.where(tri[:, None, None], _CHILD_BARY[k], _CHILD_UV[k])  # (m, 4, 2)
        u, v = uv[..., :1], uv[..., 1:]
        quad = (
            (1 - u) * (1 - v) * d[:, None, 0]
            + u * (1 - v) * d[:, None, 1]
            + u * v * d[:, None, 2]
            + (1 - u) * v * d[:, None, 3]
        )
        bary = (1 - u - v) * d[:, None, 0] + u * d[:, None, 1] + v * d[:, None, 2]
        s.corner_d[todo] = np.where(tri[:, None, None], bary, quad)
        s.has_d[todo] = True


def shown_elements(s) -> np.ndarray:
    """Elements the photograph's view can show (mask): the leaves seen through its pixels at
    preparation, what they were split into since, the elements they were merged into, and every
    virtual object's (not in the photograph). The edits gather only at those leaves' corners."""
    h = s.solution.hierarchy
    seen = np.zeros(len(h), bool)
    seen[s.pixel_element[(s.pixel_element >= 0) & (s.pixel_element < len(h))]] = True
    shown = seen.copy()
    frontier = np.flatnonzero(seen)
    while len(frontier):  # up: a seen leaf merged into its parent
        frontier = h.parent[frontier]
        frontier = frontier[frontier >= 0]
        frontier = frontier[~shown[frontier]]
        shown[frontier] = True
    down = seen.copy()
    for lv in h.by_level()[1:]:  # down: a seen leaf split since
        down[lv] |= down[h.parent[lv]]
    shown = (shown & h.leaf) | down
    if s.virtual_groups:
        shown |= np.isin(s.solution.polygons.group[h.polygon], list(s.virtual_groups))
    return shown


def geometry_key(s) -> tuple:
    """What the lamps' basis is kept under: the elements', links' and lamps' counts. Two geometries
    can share it (a crate dragged to where the counts come out the same): every edit of the
    geometry drops the basis (:func:`geometry_changed`), so a key met again is never a stale one."""
    sol = s.solution
    return (len(sol.hierarchy), len(sol.links), tuple(sol.lamp_names))


def geometry_changed(s) -> None:
    """After an edit of the geometry (a virtual lamp or object added or moved): the lamps' basis was
    of the geometry before; the next edit gathers directly and the one after makes it again."""
    s._basis_key = None


def corner_radiosity(s, shown: np.ndarray | None = None):
    """The leaf mesh with B at the corners under ``s.scales``. With the links kept, B is linear in
    the lamps' exitances, so the corners' B are gathered once per lamp (and once with every lamp
    off, for the other emitters) and an edit is their weighted sum; after a change of geometry (a
    virtual object or lamp) the first edit gathers directly and the next makes the basis again."""
    sol = s.solution
    h = sol.hierarchy
    key = geometry_key(s)
    if getattr(s, "_basis_key", None) != key and getattr(s, "_geometry_key", None) != key:
        # the geometry just changed (a virtual object moved): one gather now; the basis waits for
        # a second edit of the same geometry, so dragging an object does not pay for it each step
        s._geometry_key = key
        if not np.array_equal(sol.lamp_scales(s.scales), sol.lamp_scale):
            sol.set_lamps(s.scales)  # (the edit solved under the session's lamps already)
        return leaf_mesh(
            h, sol.links, sol.exitance(), gather=s._gather, shown=shown_elements(s) if shown is None else shown
        )
    if getattr(s, "_basis_key", None) != key:
        t = time.perf_counter()
        off = {n: 0.0 for n in s.lamp_names}
        sol.set_lamps(off)
        shown = shown_elements(s) if shown is None else shown
        base = leaf_mesh(h, sol.links, sol.exitance(), gather=s._gather, shown=shown)
        basis = []
        for name in s.lamp_names:
            sol.set_lamps({**off, name: 1.0})
            basis.append(
                leaf_mesh(h, sol.links, sol.exitance(), gather=s._gather, shown=shown).radiance - base.radiance
            )
        s._basis, s._basis_mesh, s._basis_key = basis, base, key
        s.times["lamp basis"] = time.perf_counter() - t
    sol.set_lamps(s.scales)  # the solution's state follows the edit (cheap: links kept)
    radiance = s._basis_mesh.radiance.copy()
    for name, response in zip(s.lamp_names, s._basis):
        radiance += float(s.scales.get(name, 1.0)) * response
    return dataclasses.replace(s._basis_mesh, radiance=radiance)


def pixel_texture_factor(s) -> np.ndarray:
    """The texture factor at each pixel (H, W, 3): modulated at the leaves' vertices, as the
    chapter does (4.3.2), not flat over each leaf (which drew the leaves as patches); 1 off the
    geometry and on self-luminous leaves (their texture is the photograph)."""
    h = s.solution.hierarchy
    leaves = h.leaves()
    factor = corner_image(s, s.texture_factor[leaves])
    element = s.pixel_element
    keep = (element < 0) | (h.exitance[np.maximum(element, 0)].max(axis=-1) > 0)
    factor[keep] = 1.0
    return factor
