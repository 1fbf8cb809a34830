"""The solution on the GPU: leaf elements as triangles, B/π at their vertices (shaders/display.glsl),
and the links an element receives as lines (shaders/links.glsl). The reference is
:func:`illusio.radiosity.reference.display` (rays cast through the pixel centres at the same mesh).

Smooth display (the chapter's, radiosity interpolated from the vertices): the radiosity at each leaf
corner is gathered at that point, B(x) = E + ρ·Σ F_x→j·V_ij·B_j over the links the leaf and its
ancestors receive, with the exact point-to-polygon form factor at x and the link's visibility; the
values of the leaves of one surface (Polygons.surfaces: polygons of one material sharing edges in
one plane) meeting at a point are averaged, leaves that see nothing (under a
block, behind a door) all but left out so their black does not bleed out. (The usual mean of the
neighbouring elements' B flattens every gradient toward a polygon's border: on the Cornell box's
back wall it renders the direct light 2.8 % too dark where the element values themselves are within
0.8 %.) Flat display (the element mesh): every leaf keeps its own B and its outline is drawn.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numba
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .corner_cache import CornerGather
from .formfactor import point_polygon
from .hierarchy import Hierarchy, leaves_under
from .links import Links
from .visibility import INVISIBLE, PARTIAL, VISIBLE, splitmix

__all__ = ["LeafMesh", "leaf_mesh", "corner_average", "DisplayPass", "LINK_COLOURS"]

#: the colour each link type is drawn in (linear RGB)
LINK_COLOURS = {VISIBLE: (0.1, 0.9, 0.1), PARTIAL: (1.0, 0.8, 0.0), INVISIBLE: (0.9, 0.1, 0.1)}
_QUAD_UV = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
_TRI_UV = np.array([[0, 0, 1], [1, 0, 1], [0, 1, 1], [0, 1, 1]], np.float32)


@dataclass(eq=False)
class LeafMesh:
    """Triangles of the leaves: positions (m, 3), radiance B/π (m, 3) W/(m²·sr), corner (m, 3) (see
    the shader), element (m,) the leaf each vertex belongs to, faces (k, 3) int32, face_element
    (k,) the leaf each triangle belongs to and two_sided (m,) 1 where the leaf is one side of a
    two-sided surface (seen from behind, it is not drawn: its twin is), else 0."""

    positions: np.ndarray
    radiance: np.ndarray
    corner: np.ndarray
    element: np.ndarray
    faces: np.ndarray
    face_element: np.ndarray
    two_sided: np.ndarray | None = None


def corner_form_factors(h: Hierarchy, leaf: np.ndarray, source: np.ndarray) -> np.ndarray:
    """F from each corner of ``leaf`` to element ``source`` (pairs, (n, 4)). A corner on a seam lies
    in the neighbouring polygon's plane (F = 0 there), so it is taken 1 % of the way to the centre."""
    corners = h.corners[leaf] + 0.01 * (h.centre[leaf][:, None] - h.corners[leaf])
    return point_polygon(corners, h.normal[leaf], h.corners[source], h.triangle[source], average=False)


def corner_gather(
    h: Hierarchy,
    links: Links,
    leaves: np.ndarray,
    exitance: np.ndarray,
    scale: np.ndarray | None = None,
    lamp: np.ndarray | None = None,
) -> np.ndarray:
    """B at each corner of ``leaves`` (n, 4, 3), gathered at the corner point through the links of
    the leaf and its ancestors from the solved B (see the module docstring); ``exitance``: E per
    element (n_elements, 3), lamp scales applied. ``scale`` (n_elements,) and ``lamp`` (n_elements,
    3), optional: the solve's factor on each element's reflected light (solve.form_factor_scale)
    and the lamps' exitance as a B (E pulled up the hierarchy): then B = E + ρ·(H_lamps + s·(H −
    H_lamps)), H_lamps gathered from ``lamp``, as the solve has it. The plain statement, every pair
    computed afresh: ``corner_cache.CornerGather`` is the same gather keeping its form factors
    between calls."""
    element, leaf_under = leaves_under(h, leaves)
    lo = np.searchsorted(element, links.receiver)
    count = np.searchsorted(element, links.receiver, side="right") - lo
    pair_link = np.repeat(np.arange(len(links)), count)  # every (link, leaf under it)
    leaf = leaf_under[lo[pair_link] + np.arange(len(pair_link)) - np.repeat(np.cumsum(count) - count, count)]
    weight = corner_form_factors(h, leaf, links.source[pair_link]) * links.visibility[pair_link][:, None]
    row = np.full(len(h), -1)
    row[leaves] = np.arange(len(leaves))
    irradiance = np.zeros((len(leaves), 4, 3))
    np.add.at(irradiance, row[leaf], weight[:, :, None] * h.radiosity[links.source[pair_link]][:, None])
    if scale is not None:
        from_lamps = np.zeros((len(leaves), 4, 3))
        np.add.at(from_lamps, row[leaf], weight[:, :, None] * np.asarray(lamp)[links.source[pair_link]][:, None])
        irradiance = from_lamps + np.asarray(scale)[leaves][:, None, None] * (irradiance - from_lamps)
    return exitance[leaves][:, None] + h.reflectance[leaves][:, None] * irradiance


@numba.njit(cache=True)
def _received_sums(receiver, form_factor, visibility, n):
    """(Σ F·V, Σ F) over the links each element receives, in one pass (two bincounts and their
    product took 1.4 ms of a relighting drag's move)."""
    seen, total = np.zeros(n), np.zeros(n)
    for k in range(len(receiver)):
        seen[receiver[k]] += form_factor[k] * visibility[k]
        total[receiver[k]] += form_factor[k]
    return seen, total


def exposure_weights(h: Hierarchy, links: Links, leaves: np.ndarray) -> np.ndarray:
    """1 for a leaf that sees something (Σ F·V over its links and its ancestors' above 1 % of Σ F), a
    tiny weight for one that sees nothing (under a block, behind a door): its black must not bleed
    into the visible neighbours it shares corners with."""
    seen, total = _received_sums(links.receiver, links.form_factor, links.visibility, len(h))
    for lv in h.by_level()[1:]:
        seen[lv] += seen[h.parent[lv]]
        total[lv] += total[h.parent[lv]]
    return np.where(seen[leaves] > 0.01 * total[leaves], 1.0, 1e-6)


@numba.njit(cache=True)
def _row_hashes(key):
    out = np.empty(len(key), np.uint64)
    for i in range(len(key)):
        z = np.uint64(0x9E3779B97F4A7C15)
        for c in range(key.shape[1]):
            z = splitmix(z ^ np.uint64(key[i, c]))
        out[i] = z
    return out


@numba.njit(cache=True)
def _ids_by_table(key, hashes, vertex):
    """Number the rows by an open-addressing table on their 64-bit hashes: a new id, in the order
    rows first appear, for each distinct row; False if two different rows share a hash (then nothing
    can be trusted)."""
    size = 1
    while size < 2 * len(key):
        size *= 2
    slot_row = np.full(size, -1, np.int64)
    mask = np.uint64(size - 1)
    ids = 0
    for i in range(len(key)):
        slot = np.int64(hashes[i] & mask)
        while True:
            j = slot_row[slot]
            if j < 0:
                slot_row[slot] = i
                vertex[i] = ids
                ids += 1
                break
            if hashes[j] == hashes[i]:
                for c in range(key.shape[1]):
                    if key[i, c] != key[j, c]:
                        return False
                vertex[i] = vertex[j]
                break
            slot = (slot + 1) & (size - 1)
    return True


def corner_ids(key: np.ndarray) -> np.ndarray:
    """One id per distinct row of ``key`` (m, k) int64, 0… in some order: the rows put in a hash table
    by a 64-bit hash (one pass; an argsort of the hashes took 1.2 ms of a relighting drag's move),
    checked row by row; np.lexsort where two rows differ but hash alike. (np.unique(axis=0) sorts
    the rows as opaque records, 10× slower.)"""
    key = np.ascontiguousarray(key, np.int64)
    vertex = np.empty(len(key), np.int64)
    if _ids_by_table(key, _row_hashes(key), vertex):
        return vertex
    order = np.lexsort(key.T[::-1])
    starts = np.r_[True, np.any(key[order[1:]] != key[order[:-1]], axis=1)]
    vertex[order] = np.cumsum(starts) - 1
    return vertex


def vertex_radiosity(
    h: Hierarchy,
    leaves: np.ndarray,
    links: Links | None = None,
    exitance: np.ndarray | None = None,
    gather=None,
    shown: np.ndarray | None = None,
    scale: np.ndarray | None = None,
    lamp: np.ndarray | None = None,
) -> np.ndarray:
    """B at each corner of ``leaves`` (n, 4, 3): gathered at the corners (with ``links``,
    ``exitance`` and, optional, the solve's ``scale`` and ``lamp``: corner_gather's; by ``gather``,
    a CornerGather that keeps its form factors between calls, when given) or each leaf's own B, then
    averaged over the leaves of the same surface sharing that corner point (``Polygons.surfaces``: a
    wall cut into triangles is smoothed as one). ``shown`` (mask over the elements, optional): the
    leaves whose pixels will be displayed; only they and the leaves sharing a corner point with them
    are gathered (every corner of a shown leaf is then exact), the others keep their own B: a view
    that sees part of a room pays for that part."""
    vertex, corner_of_tri = _corner_points(h, leaves)
    if links is not None and gather is None:
        gather = CornerGather()
    b = np.repeat(h.radiosity[leaves][:, None], 4, axis=1)
    if links is not None:
        needed = np.ones(len(leaves), bool)
        if shown is not None:
            near = np.zeros(len(vertex), bool)
            near[np.repeat(shown[leaves], 4)] = True
            touched = np.zeros(int(vertex.max()) + 1, bool)
            touched[vertex[near]] = True
            needed = touched[vertex].reshape(-1, 4).any(axis=1)
        b[needed] = (
            gather(h, links, leaves[needed], exitance)
            if scale is None
            else gather(h, links, leaves[needed], exitance, scale, lamp)
        )
    weight = exposure_weights(h, links, leaves) if links is not None else None
    return _average_at(vertex, corner_of_tri, b, weight)


def _corner_points(h: Hierarchy, leaves: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(the id of each corner's point on its surface (4n,), whether the corner is a real one (a
    triangle's fourth is a repeat)): corners of leaves of one surface at one point share an id."""
    corners = h.corners[leaves]  # (n, 4, 3)
    extent = max(float(np.ptp(h.corners[h.roots].reshape(-1, 3), axis=0).max()), 1e-9)
    q = np.round(corners / (1e-7 * extent)).astype(np.int64)
    key = np.c_[np.repeat(h.polygons.surfaces()[h.polygon[leaves]], 4), q.reshape(-1, 3)]
    corner_of_tri = np.tile([True, True, True, False], len(leaves)) | ~np.repeat(h.triangle[leaves], 4)
    return corner_ids(key), corner_of_tri


def _average_at(vertex, corner_of_tri, values, weight=None) -> np.ndarray:
    """(n, 4, 3) corner values → each replaced by the (weighted by leaf) mean at its point."""
    b = np.ascontiguousarray(np.asarray(values, np.float64).reshape(-1, 3))
    w = np.repeat(np.ones(len(b) // 4) if weight is None else np.asarray(weight, np.float64), 4)
    return _mean_at(vertex, corner_of_tri, b, w, int(vertex.max()) + 1).reshape(-1, 4, 3)


@numba.njit(cache=True)
def _mean_at(vertex, counted, b, w, size):
    """Each row of ``b`` replaced by the w-weighted mean of the ``counted`` rows with its vertex id
    (one pass each way: four bincounts took 1 ms of a relighting drag's move)."""
    total, count = np.zeros((size, 3)), np.zeros(size)
    for i in range(len(vertex)):
        if counted[i]:
            for c in range(3):
                total[vertex[i], c] += w[i] * b[i, c]
            count[vertex[i]] += w[i]
    out = np.empty_like(b)
    for i in range(len(vertex)):
        for c in range(3):
            out[i, c] = total[vertex[i], c] / max(count[vertex[i]], 1e-300)
    return out


def corner_average(h: Hierarchy, leaves: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Per-leaf ``values`` (n, 3) → (n, 4, 3) at the leaves' corners: at each corner point the mean
    over the leaves of the same surface meeting there (as the display smooths B without links), so
    a value interpolated across the leaves from their corners has no step at their edges."""
    vertex, corner_of_tri = _corner_points(h, leaves)
    return _average_at(vertex, corner_of_tri, np.repeat(np.asarray(values, np.float64)[:, None], 4, axis=1))


def flat_reflectance(h: Hierarchy, leaves: np.ndarray) -> np.ndarray:
    """(n, 3): the mean reflectance of the texture of each textured leaf's surface (what the texture
    modulation divides by), NaN for the others."""
    polygons = h.polygons
    group = polygons.group[h.polygon[leaves]]
    flat = np.full((len(leaves), 3), np.nan)
    for g, image in polygons.textures.items():
        flat[group == g] = image.reshape(-1, 3).mean(axis=0)
    flat[~np.isfinite(h.uv[leaves]).all(axis=(1, 2))] = np.nan
    return flat


def drawn_reflectance(h: Hierarchy) -> np.ndarray:
    """(len(h), 3): ρ as the image is drawn before the texture modulation — a textured element's
    surface mean (the modulation turns it into the texel's), the others' own ρ."""
    flat = flat_reflectance(h, np.arange(len(h)))
    return np.where(np.isfinite(flat).all(axis=1)[:, None], flat, h.reflectance[: len(h)])


def texture_factor(h: Hierarchy, leaves: np.ndarray) -> np.ndarray:
    """(n, 4, 1) at each leaf corner: the surface's mean reflectance / ρ there for textured leaves
    (ρ of the leaves meeting at the corner, averaged as B is), 1 for the others."""
    flat = flat_reflectance(h, leaves)
    textured = np.isfinite(flat).all(axis=1)
    rho = corner_average(h, leaves, h.reflectance[leaves])
    ratio = np.where(
        textured[:, None, None] & (rho > 1e-6), np.nan_to_num(flat)[:, None, :] / np.maximum(rho, 1e-6), 1.0
    )
    return ratio


def leaf_mesh(
    h: Hierarchy,
    links: Links | None = None,
    exitance: np.ndarray | None = None,
    smooth: bool = True,
    gather=None,
    shown: np.ndarray | None = None,
    textured: bool = False,
    scale: np.ndarray | None = None,
    lamp: np.ndarray | None = None,
) -> LeafMesh:
    """The leaves as a triangle mesh for display (see the module docstring). Smooth: gathered at the
    corners with ``links`` and ``exitance`` (E per element; ``gather``, ``shown``: see
    vertex_radiosity; ``scale``, ``lamp``: the solve's, see corner_gather), or averaged from the
    leaves without. ``textured``: the image will be
    modulated by the textures (texture_modulation: × albedo(x) / the surface's mean), so a textured
    leaf's corners carry B × that mean / ρ there (ρ averaged at the corners as B is): the texture
    then shows once, not once in the elements' ρ and again in the modulation."""
    leaves = h.leaves()
    n = len(leaves)
    b = (
        vertex_radiosity(h, leaves, links, exitance if exitance is not None else h.exitance, gather, shown, scale, lamp)
        if smooth
        else np.repeat(h.radiosity[leaves][:, None], 4, axis=1)
    )
    if textured and h.polygons.textures:
        b = b * texture_factor(h, leaves)
    tri = h.triangle[leaves]
    base = np.arange(n) * 4
    faces = np.concatenate([np.c_[base, base + 1, base + 2], np.c_[base[~tri], base[~tri] + 2, base[~tri] + 3]])
    face_element = np.r_[leaves, leaves[~tri]]
    corner = np.where(tri[:, None, None], _TRI_UV, _QUAD_UV)
    return LeafMesh(
        h.corners[leaves].reshape(-1, 3).astype(np.float32),
        (b / np.pi).reshape(-1, 3).astype(np.float32),
        corner.reshape(-1, 3).astype(np.float32),
        np.repeat(leaves, 4).astype(np.float32),
        faces.astype(np.int32),
        face_element,
        np.repeat(h.polygons.sides()[h.polygon[leaves]] > 0, 4).astype(np.float32),
    )


class DisplayPass:
    """``load(mesh)`` when the solution changes; ``(view, size, exposure, edges)`` → (RGBA f4 colour,
    R32F element index, −1 off the geometry): pooled textures. ``links(...)`` draws lines over a colour."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.programs = {edges: ctx.program("radiosity/shaders/display.glsl", EDGES=edges) for edges in (False, True)}
        self.line_program = ctx.program("radiosity/shaders/links.glsl")
        self._buffers: list = []
        self._vaos: dict = {}

    def load(self, mesh: LeafMesh) -> None:
        self.ctx.make_current()  # buffers belong to the context current when they are made
        self.release()
        if not len(mesh.faces):  # nothing shown (no leaf in view): draws nothing; GL refuses empty buffers
            return
        gl = self.ctx.gl
        two_sided = mesh.two_sided if mesh.two_sided is not None else np.zeros(len(mesh.positions), np.float32)
        data = np.hstack([mesh.positions, mesh.radiance, mesh.corner, mesh.element[:, None], two_sided[:, None]])
        vbo = gl.buffer(np.ascontiguousarray(data.astype(np.float32)).tobytes())
        ibo = gl.buffer(np.ascontiguousarray(mesh.faces).tobytes())
        self._buffers = [vbo, ibo]
        for edges, program in self.programs.items():
            layout = (
                (vbo, "3f 3f 3f 1f 1f", "in_position", "in_radiance", "in_corner", "in_element", "in_two_sided")
                if edges
                else (vbo, "3f 3f 12x 1f 1f", "in_position", "in_radiance", "in_element", "in_two_sided")
            )
            self._vaos[edges] = gl.vertex_array(program, [layout], ibo)

    def __call__(
        self,
        view: View,
        size: tuple[int, int],
        exposure: float = 1.0,
        edges: bool = False,
        edge_colour=(0.0, 0.0, 0.0),
        elements: bool = True,
    ):
        """(colour, element) targets; ``elements=False``: no element target (None), a cheaper draw."""
        ctx = self.ctx
        w, h = size
        colour = ctx.acquire((w, h), 4, "f4")
        element = ctx.acquire((w, h), 1, "f4") if elements else None
        fbo = ctx.framebuffer([colour, element] if elements else [colour], depth=True)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        if elements:
            ctx.framebuffer([element]).clear(-1.0, -1.0, -1.0, -1.0)
            fbo.use()
        program = self.programs[bool(edges)]
        set_uniform(program, "view_matrix", view.view_matrix())
        set_uniform(program, "projection_matrix", view.projection_matrix(w / h))
        set_uniform(program, "exposure", float(exposure))
        if edges:
            set_uniform(program, "edge_colour", tuple(float(c) for c in edge_colour))
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.disable(moderngl.CULL_FACE)
        if self._vaos:
            self._vaos[bool(edges)].render(moderngl.TRIANGLES)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        return colour, element

    def links(self, colour: moderngl.Texture, view: View, h: Hierarchy, links: Links) -> None:
        """Draw ``links`` over ``colour`` (in place): receiver centre → source centre, by type."""
        if not len(links):
            return
        ends = np.stack([h.centre[links.receiver], h.centre[links.source]], axis=1).reshape(-1, 3)
        colours = np.repeat(np.array([LINK_COLOURS[t] for t in links.type.tolist()]), 2, axis=0)
        data = np.hstack([ends, colours]).astype(np.float32)
        self.ctx.make_current()
        gl = self.ctx.gl
        vbo = gl.buffer(data.tobytes())
        vao = gl.vertex_array(self.line_program, [(vbo, "3f 3f", "in_position", "in_colour")])
        fbo = self.ctx.framebuffer([colour])
        fbo.use()
        w, hh = colour.size
        fbo.viewport = (0, 0, w, hh)
        set_uniform(self.line_program, "view_matrix", view.view_matrix())
        set_uniform(self.line_program, "projection_matrix", view.projection_matrix(w / hh))
        vao.render(moderngl.LINES)
        vao.release()
        vbo.release()

    def release(self) -> None:
        if self._vaos or self._buffers:
            self.ctx.make_current()
        for vao in self._vaos.values():
            vao.release()
        for b in self._buffers:
            b.release()
        self._vaos, self._buffers = {}, []
