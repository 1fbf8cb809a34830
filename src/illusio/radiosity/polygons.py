"""The radiosity input: a scene's surfaces as polygons (quads and triangles) with diffuse
reflectance ρ and exitance E.

Units: exitance E and radiosity B in W/m² (per RGB channel); the radiance a Lambertian surface shows
is B/π. A scene node's triangles are paired back into the quads they were cut from (two coplanar
triangles sharing their longest edge and forming a convex quad); what cannot be paired stays a
triangle. Lamps: a rectangular ``AreaLight`` of radiance L becomes an emitting quad of exitance
E = π·L (one-sided, along edge_u × edge_v); a ``PointLight`` of intensity I becomes a small emitting
cube (side ``point_lamp_size``) of the same power 4π·I. Nodes tagged ``lamp`` are the fittings of
those lamps and are left out (their glow is a display effect of the rasteriser); any other node whose
material emits is an emitter of exitance π × its emission (the office's monitor screens). A node
tagged ``two-sided`` (MGF's default) gives each face a reversed twin at the same place, lit on its
own side (Polygons.side); the twin of an emitting face emits nothing.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError
from ..scene.scene import AreaLight, PointLight, Scene
from .texture_reflectance import MAX_TEXEL_REFLECTANCE

__all__ = ["Polygons", "scene_polygons", "quads_from_triangles", "MAX_POLYGONS"]

#: the most input polygons a solution takes: every pair of roots that see each other is at least one
#: link (there is no clustering of small polygons), so the links grow with the square of this
MAX_POLYGONS = 4000


#: a polygon whose area is below this share of the scene's extent squared is degenerate
DEGENERATE_AREA = 1e-10


@dataclass(eq=False)
class Polygons:
    """Polygons in world space (metres).

    corners: (n, 4, 3) float64, counter-clockwise seen from the front; a triangle repeats its last
    corner (corner 3 = corner 2). triangle: (n,) bool. reflectance: ρ (n, 3) in [0, 1).
    exitance: E (n, 3) W/m², ≥ 0. group: (n,) int, the index in ``names`` of the node or lamp each
    polygon comes from; ``lamps`` lists the group indices that are scene lamps (for the sliders).
    uv: optional (n, 4, 2) texture coordinates at the corners (NaN where a polygon has none);
    textures: group → (H, W, 3) reflectance image (colour × texture, texels < 1) that a textured
    polygon's elements take their ρ from (:mod:`.texture_reflectance`).
    side: optional (n,) int8: 0 a one-sided polygon, 1 the front of a two-sided surface (as its
    file wrote it), 2 the reversed twin scene_polygons made for its back (same place and material,
    lit on the other side, emitting nothing).
    """

    corners: np.ndarray
    triangle: np.ndarray
    reflectance: np.ndarray
    exitance: np.ndarray
    group: np.ndarray
    names: list[str] = field(default_factory=list)
    lamps: list[int] = field(default_factory=list)
    uv: np.ndarray | None = None
    textures: dict[int, np.ndarray] = field(default_factory=dict)
    side: np.ndarray | None = None

    def __post_init__(self):
        self.corners = np.ascontiguousarray(self.corners, np.float64).reshape(-1, 4, 3)
        n = len(self.corners)
        if self.uv is not None:
            self.uv = np.asarray(self.uv, np.float64).reshape(n, 4, 2)
        if self.side is not None:
            self.side = np.asarray(self.side, np.int8).reshape(n)
        self.triangle = np.asarray(self.triangle, bool).reshape(n)
        self.reflectance = np.asarray(self.reflectance, np.float64).reshape(n, 3)
        self.exitance = np.asarray(self.exitance, np.float64).reshape(n, 3)
        self.group = np.asarray(self.group, np.int64).reshape(n)
        self.validate()

    def __len__(self) -> int:
        return len(self.corners)

    def where(self, k: int) -> str:
        g = int(self.group[k])
        return f"polygon {k} ({self.names[g]})" if g < len(self.names) else f"polygon {k}"

    def validate(self) -> None:
        if not np.isfinite(self.corners).all():
            bad = int(np.flatnonzero(~np.isfinite(self.corners).all(axis=(1, 2)))[0])
            raise InputError(f"{self.where(bad)} has non-finite corners")
        areas = polygon_areas(self.corners, self.triangle)
        scale = max(float(np.ptp(self.corners.reshape(-1, 3), axis=0).max()), 1e-9) if len(self) else 1.0
        degenerate = areas <= DEGENERATE_AREA * scale * scale
        if degenerate.any():
            k = int(np.flatnonzero(degenerate)[0])
            what = "zero-area emitter" if self.exitance[k].max() > 0 else "degenerate polygon (zero area)"
            raise InputError(f"{self.where(k)} is a {what}; remove it from the scene")
        bad = ~((self.reflectance >= 0) & (self.reflectance < 1)).all(axis=1)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"{self.where(k)} has reflectance {tuple(np.round(self.reflectance[k], 4))}: "
                "radiosity needs every channel in [0, 1) (energy must not grow)"
            )
        if not (np.isfinite(self.exitance) & (self.exitance >= 0)).all():
            k = int(np.flatnonzero(~(np.isfinite(self.exitance) & (self.exitance >= 0)).all(axis=1))[0])
            raise InputError(f"{self.where(k)} has exitance {tuple(self.exitance[k])}: it must be finite and ≥ 0")

    def sides(self) -> np.ndarray:
        """(n,) int8: :attr:`side`, 0 (one-sided) where not given."""
        return self.side if self.side is not None else np.zeros(len(self), np.int8)

    def twins(self) -> np.ndarray:
        """(n,) int64: each two-sided surface's front (side 1) and reversed twin (side 2) name each
        other — the same corners and group the other way round —; −1 for a one-sided polygon or one
        whose twin is missing. (A ray that meets a front from behind has met its twin.)"""
        side = self.sides()
        out = np.full(len(self), -1, np.int64)
        two = np.flatnonzero(side > 0)
        if not len(two):
            return out
        corners = self.corners[two].copy()
        corners[self.triangle[two], 3] = corners[self.triangle[two], 0]  # both twins' corners alike
        # the sum of each coordinate's sorted values: the same float for the same corners in any order
        centre = np.sort(corners, axis=1).sum(axis=1)
        extent = max(float(np.ptp(self.corners.reshape(-1, 3), axis=0).max()), 1e-9)
        key = np.c_[np.round(centre / (1e-7 * extent)).astype(np.int64), self.group[two]]
        _, place = np.unique(key, axis=0, return_inverse=True)
        order = np.lexsort((side[two], place.reshape(-1)))
        first, second = order[:-1], order[1:]
        pair = (
            (place.reshape(-1)[first] == place.reshape(-1)[second]) & (side[two][first] == 1) & (side[two][second] == 2)
        )
        out[two[first[pair]]] = two[second[pair]]
        out[two[second[pair]]] = two[first[pair]]
        return out

    def corner_uv(self) -> np.ndarray:
        """(n, 4, 2) uvs at the corners, NaN where there are none."""
        return self.uv if self.uv is not None else np.full((len(self), 4, 2), np.nan)

    def without_textures(self) -> Polygons:
        """The same polygons, each with one reflectance (its own) and no texture to refine it."""
        return Polygons(
            self.corners,
            self.triangle,
            self.reflectance,
            self.exitance,
            self.group,
            list(self.names),
            list(self.lamps),
            side=self.side,
        )

    def texture_reflectance(self):
        """The :class:`~.texture_reflectance.TextureReflectance` of these polygons' textures (kept)."""
        cached = getattr(self, "_texture_reflectance", None)
        if cached is None:
            from .texture_reflectance import TextureReflectance

            cached = self._texture_reflectance = TextureReflectance(self.textures)
        return cached

    def extended(self, other: Polygons, name: str, lamp: bool = False) -> Polygons:
        """These polygons followed by ``other``, all of which form one new group ``name`` (textured
        by ``other``'s first texture, if it has one)."""
        if name in self.names:
            raise InputError(f"there is already an object or lamp named {name!r}")
        g = len(self.names)
        textured = self.uv is not None or other.uv is not None
        return Polygons(
            np.concatenate([self.corners, other.corners]),
            np.r_[self.triangle, other.triangle],
            np.concatenate([self.reflectance, other.reflectance]),
            np.concatenate([self.exitance, other.exitance]),
            np.r_[self.group, np.full(len(other), g)],
            self.names + [name],
            self.lamps + ([g] if lamp else []),
            np.concatenate([self.corner_uv(), other.corner_uv()]) if textured else None,
            {**self.textures, **({g: next(iter(other.textures.values()))} if other.textures else {})},
            np.r_[self.sides(), other.sides()] if self.side is not None or other.side is not None else None,
        )

    def moved(self, group: int, matrix: np.ndarray) -> Polygons:
        """These polygons with group ``group``'s corners moved by the 4×4 world ``matrix`` (a new
        object: the caller's stay as they are). Where the matrix keeps angles (a rotation and a
        uniform scale) the surfaces are kept: a surface lies within one group, and such a move keeps
        its shared edges and the angles between its normals (a drag pays no fresh surfaces)."""
        matrix = np.asarray(matrix, np.float64)
        rows = np.flatnonzero(self.group == group)
        corners = self.corners.copy()
        corners[rows] = corners[rows] @ matrix[:3, :3].T + matrix[:3, 3]
        out = dataclasses.replace(self, corners=corners)
        linear = matrix[:3, :3] @ matrix[:3, :3].T
        cached = getattr(self, "_surfaces", None)
        if cached is not None and np.allclose(linear, linear[0, 0] * np.eye(3), rtol=0, atol=1e-9 * abs(linear[0, 0])):
            out._surfaces = cached
        return out

    def split_slivers(self, piece_length: float) -> Polygons:
        """Every quad longer than max(4 × its width, ``piece_length``) (m) cut across its length into
        equal pieces no shorter than that, in the same plane, group and material; triangles and
        other quads kept as they are (first, in their order; the pieces follow). Why: an element is
        not split below A_ε, so a strip narrower than √A_ε (a lamp's pole, a rug's side, a skirting's
        top) would stay one element however the light varies along it: a lamp at one end of a pole
        lit the whole pole, and the display's corners, gathered at the lamp's end, spread that over
        its length (the living room's pole 16–23× too bright against Mitsuba)."""
        c = self.corners
        first, second = np.linalg.norm(c[:, 1] - c[:, 0], axis=1), np.linalg.norm(c[:, 3] - c[:, 0], axis=1)
        length, width = np.maximum(first, second), np.minimum(first, second)
        pieces = np.where(
            self.triangle | (piece_length <= 0), 1, np.floor(length / np.maximum(4 * width, max(piece_length, 1e-12)))
        ).astype(np.int64)
        pieces = np.maximum(pieces, 1)
        cut = np.flatnonzero(pieces > 1)
        if not len(cut):
            return self
        parts = []
        uv = self.corner_uv()
        uv_parts = []
        for k in cut:
            order = [0, 1, 2, 3] if first[k] >= second[k] else [1, 2, 3, 0]  # edge 0→1 along the length
            t = np.linspace(0.0, 1.0, pieces[k] + 1)[:, None]
            for q, out in ((c[k][order], parts), (uv[k][order], uv_parts)):
                a, b = q[0] + t * (q[1] - q[0]), q[3] + t * (q[2] - q[3])
                out.append(np.stack([a[:-1], a[1:], b[1:], b[:-1]], axis=1))
        index = np.r_[np.flatnonzero(pieces == 1), np.repeat(cut, pieces[cut])]
        return Polygons(
            np.concatenate([c[pieces == 1]] + parts),
            self.triangle[index],
            self.reflectance[index],
            self.exitance[index],
            self.group[index],
            list(self.names),
            list(self.lamps),
            np.concatenate([uv[pieces == 1]] + uv_parts) if self.uv is not None else None,
            dict(self.textures),
            self.side[index] if self.side is not None else None,
        ).with_texture_reflectance()

    def with_texture_reflectance(self) -> Polygons:
        """These polygons with each textured one's ρ the mean of the texture it covers."""
        if self.uv is None or not self.textures:
            return self
        rho = self.texture_reflectance()(self.group, self.uv, self.triangle)
        ok = np.isfinite(rho).all(axis=1)
        if ok.any():
            self.reflectance = np.where(ok[:, None], rho, self.reflectance)
        return self

    def group_of(self, name: str) -> int:
        if name not in self.names:
            raise InputError(f"no object or lamp named {name!r}; there are: {', '.join(self.names)}")
        return self.names.index(name)

    @property
    def emitters(self) -> np.ndarray:
        return np.flatnonzero(self.exitance.max(axis=1) > 0)

    def normals(self) -> np.ndarray:
        """Unit front normals (n, 3): the diagonals' cross product of a quad, the edges' of a triangle."""
        c = self.corners
        n = np.where(
            self.triangle[:, None],
            np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]),
            np.cross(c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]),
        )
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    def surfaces(self, degrees: float = 1.0) -> np.ndarray:
        """A surface id per polygon (n,) int: polygons of one group (one node: one material) joined by
        a shared edge (both end points equal within 10⁻⁷ of the scene's extent) whose normals agree
        within ``degrees`` are one surface — a wall cut into triangles, a quad split in two. What
        relighting calls neighbours and the display smooths over is a surface, so a triangulated model
        behaves as its quads would, and a black window pane set in a white frame of the same plane
        keeps its black (B is not averaged across a change of material). (A T-junction, an edge
        meeting another's middle, does not join.) Kept once computed: the polygons do not change."""
        cached = getattr(self, "_surfaces", None)
        if cached is not None and cached[0] == degrees:
            return cached[1]
        from scipy.sparse import coo_matrix
        from scipy.sparse.csgraph import connected_components

        n = len(self)
        extent = max(float(np.ptp(self.corners.reshape(-1, 3), axis=0).max()), 1e-9) if n else 1.0
        q = np.round(self.corners / (1e-7 * extent)).astype(np.int64)  # (n, 4, 3)
        edges, owner = [], []
        for k in range(4):  # a triangle's corner 3 repeats corner 2: its edge 2–3 is a point
            a, b = q[:, k], q[:, (k + 1) % 4]
            diff = a - b
            real = np.flatnonzero(np.any(diff != 0, axis=1))
            first = np.argmax(diff[real] != 0, axis=1)
            swap = (diff[real, first] > 0)[:, None]  # each edge with its lexicographically smaller end first
            edges.append(np.c_[np.where(swap, b[real], a[real]), np.where(swap, a[real], b[real])])
            owner.append(real)
        edges, owner = np.concatenate(edges), np.concatenate(owner)
        order = np.lexsort(edges.T[::-1])
        edges, owner = edges[order], owner[order]
        # every pair of owners of one edge, not only neighbours in the sort: a two-sided wall's edge
        # has four (two faces and their twins), and its two fronts need not sort side by side
        pairs, gap = [], 1
        while gap < len(edges):
            same = np.all(edges[gap:] == edges[:-gap], axis=1)
            if not same.any():
                break
            pairs.append(np.c_[owner[:-gap][same], owner[gap:][same]])
            gap += 1
        a, b = np.concatenate(pairs, axis=0).T if pairs else (np.zeros(0, np.int64),) * 2
        normal = self.normals()
        # sharing an edge, two polygons whose normals agree lie in one plane (the edge is in both)
        flat = np.einsum("ij,ij->i", normal[a], normal[b]) > np.cos(np.radians(degrees))
        flat &= self.group[a] == self.group[b]
        graph = coo_matrix((np.ones(int(flat.sum())), (a[flat], b[flat])), shape=(n, n))
        surface = connected_components(graph, directed=False)[1] if n else np.zeros(0, np.int64)
        self._surfaces = (degrees, surface)
        return surface

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(vertices (m, 3) float32, faces (k, 3) int32): every polygon as one or two triangles."""
        quads = ~self.triangle
        v = self.corners.reshape(-1, 4, 3)
        base = np.arange(len(self)) * 4
        faces = [np.c_[base, base + 1, base + 2], np.c_[base[quads], base[quads] + 2, base[quads] + 3]]
        return v.reshape(-1, 3).astype(np.float32), np.concatenate(faces).astype(np.int32)


def polygon_areas(corners: np.ndarray, triangle: np.ndarray) -> np.ndarray:
    """Area (m²) of quads (half the cross product of the diagonals, exact when planar) and triangles."""
    quad = 0.5 * np.linalg.norm(np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1]), axis=1)
    tri = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    return np.where(triangle, tri, quad)


def quads_from_triangles(vertices: np.ndarray, faces: np.ndarray, tolerance: float = 1e-6, uvs=None):
    """Pair triangles back into quads: two coplanar triangles sharing the longest edge of both and
    forming a convex quad. Returns (corners (n, 4, 3), triangle (n,) bool), corners in the triangles'
    winding. Vertices are matched by position (a box's faces have their own copies of corners). With
    ``uvs`` (per vertex), the shared edge must also agree in uv (no seam across a quad), and the
    corners' uvs (n, 4, 2) come third."""
    v = np.asarray(vertices, np.float64)
    f = np.asarray(faces, np.int64)
    scale = max(float(np.ptp(v, axis=0).max()), 1e-9)
    key = np.round(v / (tolerance * scale)).astype(np.int64)
    if uvs is not None:
        key = np.c_[key, np.round(np.asarray(uvs, np.float64) / 1e-6).astype(np.int64)]
    _, ids = np.unique(key, axis=0, return_inverse=True)
    ids = ids.reshape(-1)
    p = v[f]  # (m, 3, 3)
    # the edge opposite corner k joins corners k+1 and k+2; the longest one is the diagonal
    lengths = np.stack([np.linalg.norm(p[:, (k + 2) % 3] - p[:, (k + 1) % 3], axis=1) for k in range(3)], axis=1)
    apex = lengths.argmax(axis=1)
    m = len(f)
    rows = np.arange(m)
    a = f[rows, apex]
    b = f[rows, (apex + 1) % 3]
    c = f[rows, (apex + 2) % 3]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    # the diagonal, and which way the triangle faces (its normal's largest axis and sign): a
    # two-sided surface's reversed twin shares the diagonal but faces the other way
    axis = np.abs(normal).argmax(axis=1)
    facing = 2 * axis + (normal[np.arange(len(normal)), axis] > 0)
    key = np.c_[np.sort(np.c_[ids[b], ids[c]], axis=1), facing]
    order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
    same = (key[order[1:]] == key[order[:-1]]).all(axis=1)
    partner = np.full(m, -1)
    first, second = order[:-1][same], order[1:][same]
    # an edge shared by more than two triangles is left unpaired
    count = np.zeros(m, int)
    np.add.at(count, first, 1)
    np.add.at(count, second, 1)
    ok = (count[first] == 1) & (count[second] == 1)
    first, second = first[ok], second[ok]
    d = f[second, apex[second]]
    # within about 0.8°: a slightly warped quad (the Cornell box's left wall, 3 mm over 55 cm) stays one
    coplanar = (normal[first] * normal[second]).sum(axis=1) > 1 - 1e-4
    quad = np.stack([v[a[first]], v[b[first]], v[d], v[c[first]]], axis=1)
    # convex: every corner turns the same way as the normal
    turn = np.stack(
        [np.cross(quad[:, (k + 1) % 4] - quad[:, k], quad[:, (k + 2) % 4] - quad[:, (k + 1) % 4]) for k in range(4)],
        axis=1,
    )
    convex = ((turn * normal[first][:, None]).sum(axis=2) > 0).all(axis=1)
    take = coplanar & convex
    partner[first[take]] = second[take]
    partner[second[take]] = first[take]
    quads = quad[take]
    # a slightly warped quad is flattened onto its mean plane: the ray caster sees two triangles, and
    # sample points on a warped (bilinear) surface could fall behind them
    mean_normal = normal[first[take]] + normal[second[take]]
    mean_normal /= np.linalg.norm(mean_normal, axis=1, keepdims=True)
    centre = quads.mean(axis=1, keepdims=True)
    quads = quads - ((quads - centre) * mean_normal[:, None]).sum(axis=2, keepdims=True) * mean_normal[:, None]
    singles = np.flatnonzero(partner < 0)
    tris = np.concatenate([p[singles], p[singles][:, 2:3]], axis=1)
    corners = np.concatenate([quads, tris]) if len(tris) else quads
    triangle = np.r_[np.zeros(len(quads), bool), np.ones(len(tris), bool)]
    if uvs is None:
        return corners, triangle
    index = np.concatenate(
        [
            np.stack([a[first], b[first], d, c[first]], axis=1)[take],
            np.c_[f[singles], f[singles][:, 2]],
        ]
    )
    return corners, triangle, np.asarray(uvs, np.float64)[index]


def rectangle(centre, u, v) -> np.ndarray:
    c, u, v = (np.asarray(x, np.float64) for x in (centre, u, v))
    return np.stack([c - u / 2 - v / 2, c + u / 2 - v / 2, c + u / 2 + v / 2, c - u / 2 + v / 2])


def _cube(centre, side: float) -> np.ndarray:
    """Six outward quads of an axis-aligned cube (counter-clockwise seen from outside)."""
    h = side / 2
    out = []
    for axis in range(3):
        for sign in (1, -1):
            n = np.zeros(3)
            n[axis] = sign
            u = np.zeros(3)
            u[(axis + 1) % 3] = side
            v = np.cross(n, u)
            out.append(rectangle(np.asarray(centre) + n * h, u, v))
    return np.stack(out)


def scene_polygons(scene: Scene, point_lamp_size: float = 0.05) -> Polygons:
    """The polygons of ``scene``'s visible nodes (ρ = material colour, or for a textured one the mean
    of colour × texture over the polygon, with its corner uvs and the image for its elements) and of its
    lamps (see the module docstring). Degenerate polygons (zero area) are dropped and counted in one
    warning; InputError on reflectances outside [0, 1)."""
    corners, triangle, rho, exitance, group, names, lamps, uvs, sides = [], [], [], [], [], [], [], [], []
    textures: dict[int, np.ndarray] = {}
    for node in scene.nodes:
        if not node.visible or "lamp" in node.tags:
            continue
        m = node.transform.astype(np.float64)
        world = (np.c_[node.mesh.vertices, np.ones(len(node.mesh.vertices))] @ m.T)[:, :3]
        faces = node.mesh.faces
        if np.linalg.det(m[:3, :3]) < 0:
            faces = faces[:, ::-1]
        material = node.material
        textured = material.texture is not None and node.mesh.uvs is not None
        if textured:
            c, t, uv = quads_from_triangles(world, faces, uvs=node.mesh.uvs)
            textures[len(names)] = reflectance_image(material)
        else:
            c, t = quads_from_triangles(world, faces)
            uv = np.full((len(c), 4, 2), np.nan)
        colour = material.mean_albedo()
        emitted = np.repeat(np.pi * np.asarray(node.material.emission, np.float64)[None], len(c), axis=0)
        side = np.zeros(len(c), np.int8)
        if "two-sided" in node.tags:  # each face and its reversed twin, lit on its own side (RenderPark's)
            back = np.where(t[:, None], [0, 2, 1, 1], [0, 3, 2, 1])  # a triangle repeats its last corner
            c = np.concatenate([c, np.take_along_axis(c, back[:, :, None], axis=1)])
            uv = np.concatenate([uv, np.take_along_axis(uv, back[:, :, None], axis=1)])
            emitted = np.concatenate([emitted, np.zeros_like(emitted)])  # the back emits nothing
            side = np.r_[np.ones(len(t), np.int8), np.full(len(t), 2, np.int8)]
            t = np.r_[t, t]
        g = len(names)
        names.append(node.name)
        corners.append(c)
        triangle.append(t)
        uvs.append(uv)
        sides.append(side)
        rho.append(np.repeat(np.minimum(colour, MAX_TEXEL_REFLECTANCE if textured else 1.0)[None], len(c), axis=0))
        exitance.append(emitted)
        group.append(np.full(len(c), g))
    for light in scene.lights:
        if isinstance(light, AreaLight):
            c = rectangle(light.centre, light.edge_u, light.edge_v)[None]
            e = np.pi * light.radiance * np.asarray(light.colour, np.float64)
        elif isinstance(light, PointLight):
            c = _cube(light.position, point_lamp_size)
            e = 4 * np.pi * light.intensity * np.asarray(light.colour, np.float64) / (6 * point_lamp_size**2)
        else:
            continue
        g = len(names)
        names.append(light.name)
        lamps.append(g)
        corners.append(c)
        uvs.append(np.full((len(c), 4, 2), np.nan))
        sides.append(np.zeros(len(c), np.int8))
        triangle.append(np.zeros(len(c), bool))
        rho.append(np.zeros((len(c), 3)))
        exitance.append(np.repeat(e[None], len(c), axis=0))
        group.append(np.full(len(c), g))
    if not corners:
        raise InputError(f"scene {scene.name!r} has no visible geometry for radiosity")
    arrays = [np.concatenate(a) for a in (corners, triangle, rho, exitance, group, uvs, sides)]
    areas = polygon_areas(arrays[0], arrays[1])
    scale = max(float(np.ptp(arrays[0].reshape(-1, 3), axis=0).max()), 1e-9)
    degenerate = areas <= DEGENERATE_AREA * scale * scale
    if degenerate.any():  # as RenderPark does: a scene of thousands is not refused for one sliver
        where = sorted({names[g] for g in arrays[4][degenerate]})
        warnings.warn(
            f"scene {scene.name!r}: dropped {int(degenerate.sum())} degenerate polygon"
            f"{'s' if degenerate.sum() > 1 else ''} (zero area) of {', '.join(where[:4])}"
            f"{' …' if len(where) > 4 else ''}",
            stacklevel=2,
        )
        arrays = [a[~degenerate] for a in arrays]
        if not len(arrays[0]):
            raise InputError(f"scene {scene.name!r}: every polygon has zero area")
    side = arrays.pop()
    uv = arrays.pop()
    return Polygons(
        *arrays, names, lamps, uv if textures else None, textures, side if side.any() else None
    ).with_texture_reflectance()


def reflectance_image(material) -> np.ndarray:
    """(H, W, 3) the reflectance a textured material's texels give: colour × texture, each texel
    capped at MAX_TEXEL_REFLECTANCE; texels its alpha mask cuts take the kept texels' mean."""
    image = np.asarray(material.colour, np.float64) * np.asarray(material.texture, np.float64)
    if material.opacity is not None:
        cut = material.opacity < material.alpha_cutoff
        image[cut] = material.mean_albedo()
    return np.minimum(image, MAX_TEXEL_REFLECTANCE)
