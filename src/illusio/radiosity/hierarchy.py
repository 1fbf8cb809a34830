"""The element hierarchy: each input polygon is the root of a quadtree of elements (a quad splits
into 4 quads at its edge midpoints and centre, a triangle into 4 at its edge midpoints).

Elements live in flat arrays (structure of arrays, grown by doubling) so that refinement, gather and
push-pull are vectorised. Children are created after their parent, four in a row: ``child[i]`` is the
first, −1 for a leaf. Per element: corners, the uvs there (NaN untextured), area A (m²), centre, unit
normal, ρ (a textured element's: the mean of the texture it covers, :mod:`.texture_reflectance`),
E (W/m²), B (W/m²), the gathered irradiance H (W/m²) and its level; the links an element receives are the rows of
:class:`illusio.radiosity.links.Links` whose receiver is that element.
"""

from __future__ import annotations

import numba
import numpy as np

from .polygons import Polygons, polygon_areas

__all__ = ["Hierarchy", "FIELDS", "leaves_under", "leaf_of"]

# per-element arrays: name → (shape after the element axis, dtype)
FIELDS = {
    "corners": ((4, 3), np.float64),
    "uv": ((4, 2), np.float64),
    "triangle": ((), bool),
    "polygon": ((), np.int64),
    "parent": ((), np.int64),
    "child": ((), np.int64),
    "level": ((), np.int32),
    "area": ((), np.float64),
    "centre": ((3,), np.float64),
    "normal": ((3,), np.float64),
    "reflectance": ((3,), np.float64),
    "exitance": ((3,), np.float64),
    "radiosity": ((3,), np.float64),
    "irradiance": ((3,), np.float64),
    "active": ((), bool),
}
#: the per-element arrays by name, as radiosity exports them (relight.state saves them)
HIERARCHY_FIELDS = FIELDS


class Hierarchy:
    """Quadtrees over ``polygons``; element i's fields are ``self.<field>[i]`` for i < ``len(self)``."""

    def __init__(self, polygons: Polygons):
        self.polygons = polygons
        self.size = 0
        self._capacity = 0
        self._grow(max(4 * len(polygons), 64))
        self.roots = self._append(
            polygons.corners, polygons.triangle, np.arange(len(polygons)), np.full(len(polygons), -1), 0
        )
        self._uv[self.roots] = polygons.corner_uv()
        self.reflectance[self.roots] = polygons.reflectance
        self.exitance[self.roots] = polygons.exitance
        self.radiosity[self.roots] = polygons.exitance

    def __len__(self) -> int:
        return self.size

    def arrays(self) -> dict[str, np.ndarray]:
        """Every field (first ``len(self)`` rows) and the roots: what :meth:`from_arrays` takes back."""
        out = {name: getattr(self, name).copy() for name in FIELDS}
        out["roots"] = np.asarray(self.roots, np.int64)
        return out

    @classmethod
    def from_arrays(cls, polygons: Polygons, arrays: dict[str, np.ndarray]) -> Hierarchy:
        """A hierarchy saved by :meth:`arrays` (a saved relighting session)."""
        from ..core.errors import InputError

        h = cls.__new__(cls)
        h.polygons = polygons
        n = len(arrays["active"])
        for name, (shape, dtype) in FIELDS.items():
            if name == "uv" and name not in arrays:  # saved before uvs were kept: untextured
                arrays = {**arrays, "uv": np.full((n, 4, 2), np.nan)}
            a = np.asarray(arrays[name])
            if a.shape != (n,) + shape:
                raise InputError(f"saved hierarchy: field {name} has shape {a.shape}, expected {(n,) + shape}")
            setattr(h, "_" + name, a.astype(dtype, copy=True))
        h.size = h._capacity = n
        h.roots = np.asarray(arrays["roots"], np.int64)
        h._check_tree()
        return h

    def _check_tree(self) -> None:
        """InputError unless parent, child, level and roots describe quadtrees: roots without a
        parent, every other active element one of the four consecutive children of its parent, one
        level below it (a saved hierarchy is read back only if it is one)."""
        from ..core.errors import InputError

        n = len(self)
        parent, child, level = self.parent, self.child, self.level
        if ((parent < -1) | (parent >= n) | (child < -1) | (child > n - 4)).any() or (
            (self.roots < 0) | (self.roots >= n)
        ).any():
            raise InputError("saved hierarchy: an index points outside the elements")
        is_root = np.zeros(n, bool)
        is_root[self.roots] = True
        # inactive elements (a collapsed split's, a removed object's) keep stale links: not checked
        others = np.flatnonzero(~is_root & self.active)
        if (parent[is_root] != -1).any() or (parent[others] < 0).any():
            raise InputError("saved hierarchy: roots must have no parent and every other element one")
        first = child[parent[others]]
        if ((first < 0) | (others < first) | (others >= first + 4)).any() or (
            level[others] != level[parent[others]] + 1
        ).any():
            raise InputError("saved hierarchy: an element is not among its parent's four children")
        with_children = np.flatnonzero((child >= 0) & self.active)
        if (parent[child[with_children][:, None] + np.arange(4)] != with_children[:, None]).any():
            raise InputError("saved hierarchy: a parent's children do not name it as their parent")

    def add_roots(self, polygons: Polygons, first_polygon: int) -> np.ndarray:
        """New roots for ``polygons``, which are rows ``first_polygon``… of the (extended) input."""
        roots = self._append(
            polygons.corners, polygons.triangle, first_polygon + np.arange(len(polygons)), np.full(len(polygons), -1), 0
        )
        self._uv[roots] = polygons.corner_uv()
        self.reflectance[roots] = polygons.reflectance
        self.exitance[roots] = polygons.exitance
        self.radiosity[roots] = polygons.exitance
        self.roots = np.r_[self.roots, roots]
        return roots

    def transform(self, elements: np.ndarray, matrix: np.ndarray) -> None:
        """Move ``elements`` (all of an object's, children included) by the 4×4 ``matrix``."""
        elements = np.asarray(elements, np.int64)
        m = np.asarray(matrix, np.float64)
        c = self._corners[elements]
        moved = c @ m[:3, :3].T + m[:3, 3]
        self._set_geometry(elements, moved)

    def _set_geometry(self, idx: np.ndarray, corners: np.ndarray) -> None:
        triangle = self._triangle[idx]
        self._corners[idx] = corners
        self._area[idx] = polygon_areas(corners, triangle)
        self._centre[idx] = np.where(triangle[:, None], corners[:, :3].mean(axis=1), corners.mean(axis=1))
        n_quad = np.cross(corners[:, 2] - corners[:, 0], corners[:, 3] - corners[:, 1])
        n_tri = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normal = np.where(triangle[:, None], n_tri, n_quad)
        self._normal[idx] = normal / np.linalg.norm(normal, axis=1, keepdims=True)

    def _grow(self, capacity: int) -> None:
        for name, (shape, dtype) in FIELDS.items():
            new = np.zeros((capacity,) + shape, dtype)
            if self._capacity:
                new[: self.size] = getattr(self, "_" + name)[: self.size]
            setattr(self, "_" + name, new)
        self._capacity = capacity

    def __getattr__(self, name):
        if name in FIELDS:
            return self.__dict__["_" + name][: self.__dict__["size"]]
        raise AttributeError(name)

    def _append(self, corners, triangle, polygon, parent, level) -> np.ndarray:
        n = len(corners)
        if self.size + n > self._capacity:
            self._grow(max(2 * self._capacity, self.size + n))
        idx = np.arange(self.size, self.size + n)
        self.size += n
        self._corners[idx] = corners
        self._triangle[idx] = triangle
        self._polygon[idx] = polygon
        self._parent[idx] = parent
        self._child[idx] = -1
        self._level[idx] = level
        self._active[idx] = True
        self._set_geometry(idx, corners)
        return idx

    def subdivide(self, elements: np.ndarray) -> np.ndarray:
        """Give each of ``elements`` (those without) four children; returns the first child of every
        element asked for, (n,). Children inherit ρ, E and B (refined later by the solver)."""
        elements = np.asarray(elements, np.int64)
        todo = np.unique(elements[self._child[elements] < 0])
        if len(todo):
            tri = self._triangle[todo]
            children = _split(self._corners[todo], tri)  # (n, 4, 4, 3)
            n = len(todo)
            rep = np.repeat(todo, 4)
            first = self._append(
                children.reshape(-1, 4, 3),
                np.repeat(tri, 4),
                self._polygon[rep],
                rep,
                np.repeat(self._level[todo] + 1, 4),
            )[::4]
            self._child[todo] = first
            new = np.repeat(first, 4) + np.tile(np.arange(4), n)
            self._uv[new] = _split(self._uv[todo], tri).reshape(-1, 4, 2)
            for name in ("reflectance", "exitance", "radiosity"):
                arr = getattr(self, "_" + name)
                arr[new] = arr[rep]
            textured = np.isfinite(self._uv[new]).all(axis=(1, 2))
            if textured.any() and self.polygons.textures:  # each child its own share of the texture
                t = new[textured]
                rho = self.polygons.texture_reflectance()(
                    self.polygons.group[self._polygon[t]], self._uv[t], self._triangle[t]
                )
                ok = np.isfinite(rho).all(axis=1)
                self._reflectance[t[ok]] = rho[ok]
        return self._child[elements]

    def collapse(self, elements: np.ndarray) -> None:
        """Undo the subdivision of ``elements``: their descendants go inactive and each is a leaf again
        (Loscos Figure 4.7's undo; the caller moves any links the descendants held)."""
        elements = np.asarray(elements, np.int64)
        inner = elements[self._child[elements] >= 0]
        if len(inner):
            below = self.descendants(inner)
            self._active[below[~np.isin(below, inner)]] = False
            self._child[inner] = -1

    def children(self, elements: np.ndarray) -> np.ndarray:
        """(n, 4) children of elements that have them."""
        return self._child[np.asarray(elements)][:, None] + np.arange(4)

    @property
    def leaf(self) -> np.ndarray:
        return self.child < 0

    def leaves(self, elements: np.ndarray | None = None) -> np.ndarray:
        """Leaf indices (active), all of them or those below ``elements`` (each element's own if a leaf)."""
        if elements is None:
            return np.flatnonzero(self.leaf & self.active)
        out, frontier = [], np.asarray(elements, np.int64)
        while len(frontier):
            is_leaf = self._child[frontier] < 0
            out.append(frontier[is_leaf])
            frontier = self.children(frontier[~is_leaf]).reshape(-1)
        return np.concatenate(out) if out else frontier

    def descendants(self, roots: np.ndarray) -> np.ndarray:
        """Every element below and including ``roots``."""
        out, frontier = [], np.asarray(roots, np.int64)
        while len(frontier):
            out.append(frontier)
            inner = frontier[self._child[frontier] >= 0]
            frontier = self.children(inner).reshape(-1)
        return np.concatenate(out) if out else frontier

    def by_level(self) -> list[np.ndarray]:
        """Element indices grouped by level (0 = roots), active ones only."""
        lv = self.level
        act = self.active
        return [np.flatnonzero((lv == k) & act) for k in range(int(lv.max()) + 1 if len(lv) else 0)]

    def sample_points(self, elements: np.ndarray, uv: np.ndarray) -> np.ndarray:
        """Points on ``elements`` (n,) at parameters ``uv`` (n, k, 2) in [0, 1)²: bilinear on quads,
        folded barycentric on triangles. Returns (n, k, 3)."""
        out = np.empty(uv.shape[:2] + (3,))
        _sample_points(
            self._corners, self._triangle, np.asarray(elements, np.int64), np.ascontiguousarray(uv, np.float64), out
        )
        return out

    def leaf_at(self, roots: np.ndarray, points: np.ndarray) -> np.ndarray:
        """The leaf of each of ``roots`` (n,) that holds each of ``points`` (n, 3) (on the root's plane,
        metres): the root's parameters (u, v) at the point — :func:`point_on` inverted —, then down
        the quadtree, each split halving them; −1 where the root is −1. A point off the root is taken
        at its nearest parameters (clamped to the root)."""
        out = np.empty(len(roots), np.int64)
        _leaves_at(
            self._corners,
            self._triangle,
            self._child,
            np.ascontiguousarray(roots, np.int64),
            np.ascontiguousarray(points, np.float64),
            out,
        )
        return out


@numba.njit(cache=True, inline="always")
def point_on(corners, triangle, e, u, v):
    """The point of element ``e`` at parameters (u, v) in [0, 1)²: bilinear on a quad, folded
    barycentric on a triangle (x, y, z)."""
    if triangle[e]:
        if u + v > 1:
            u, v = 1 - u, 1 - v
        return (
            corners[e, 0, 0] + u * (corners[e, 1, 0] - corners[e, 0, 0]) + v * (corners[e, 2, 0] - corners[e, 0, 0]),
            corners[e, 0, 1] + u * (corners[e, 1, 1] - corners[e, 0, 1]) + v * (corners[e, 2, 1] - corners[e, 0, 1]),
            corners[e, 0, 2] + u * (corners[e, 1, 2] - corners[e, 0, 2]) + v * (corners[e, 2, 2] - corners[e, 0, 2]),
        )
    w0, w1, w2, w3 = (1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v
    return (
        w0 * corners[e, 0, 0] + w1 * corners[e, 1, 0] + w2 * corners[e, 2, 0] + w3 * corners[e, 3, 0],
        w0 * corners[e, 0, 1] + w1 * corners[e, 1, 1] + w2 * corners[e, 2, 1] + w3 * corners[e, 3, 1],
        w0 * corners[e, 0, 2] + w1 * corners[e, 1, 2] + w2 * corners[e, 2, 2] + w3 * corners[e, 3, 2],
    )


@numba.njit(cache=True)
def _sample_points(corners, triangle, elements, uv, out):
    for p in range(elements.shape[0]):
        for s in range(uv.shape[1]):
            out[p, s, 0], out[p, s, 1], out[p, s, 2] = point_on(
                corners, triangle, elements[p], uv[p, s, 0], uv[p, s, 1]
            )


@numba.njit(cache=True)
def _parameters(c, triangle, p):
    """(u, v) of point ``p`` on the element with corners ``c`` (4, 3), as :func:`point_on` maps them:
    least squares on the edges from corner 0 (exact on a triangle and a parallelogram), then Newton
    on the bilinear map of a quad (scalars throughout: no temporary arrays in the loop)."""
    last = 2 if triangle else 3
    e1x, e1y, e1z = c[1, 0] - c[0, 0], c[1, 1] - c[0, 1], c[1, 2] - c[0, 2]
    e2x, e2y, e2z = c[last, 0] - c[0, 0], c[last, 1] - c[0, 1], c[last, 2] - c[0, 2]
    # a quad's departure from a parallelogram
    tx, ty, tz = (
        c[2, 0] - c[1, 0] - c[3, 0] + c[0, 0],
        c[2, 1] - c[1, 1] - c[3, 1] + c[0, 1],
        c[2, 2] - c[1, 2] - c[3, 2] + c[0, 2],
    )
    dx, dy, dz = p[0] - c[0, 0], p[1] - c[0, 1], p[2] - c[0, 2]
    a11, a12, a22 = (
        e1x * e1x + e1y * e1y + e1z * e1z,
        e1x * e2x + e1y * e2y + e1z * e2z,
        e2x * e2x + e2y * e2y + e2z * e2z,
    )
    det = a11 * a22 - a12 * a12
    if det <= 0:
        return 0.0, 0.0
    b1, b2 = dx * e1x + dy * e1y + dz * e1z, dx * e2x + dy * e2y + dz * e2z
    u, v = (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det
    if triangle or tx * tx + ty * ty + tz * tz <= 1e-24 * a11:
        return u, v
    for _ in range(6):
        ux, uy, uz = e1x + v * tx, e1y + v * ty, e1z + v * tz
        vx, vy, vz = e2x + u * tx, e2y + u * ty, e2z + u * tz
        fx = u * e1x + v * e2x + u * v * tx - dx
        fy = u * e1y + v * e2y + u * v * ty - dy
        fz = u * e1z + v * e2z + u * v * tz - dz
        a11, a12, a22 = ux * ux + uy * uy + uz * uz, ux * vx + uy * vy + uz * vz, vx * vx + vy * vy + vz * vz
        det = a11 * a22 - a12 * a12
        if det <= 0:
            break
        b1, b2 = -(fx * ux + fy * uy + fz * uz), -(fx * vx + fy * vy + fz * vz)
        u, v = u + (a22 * b1 - a12 * b2) / det, v + (a11 * b2 - a12 * b1) / det
    return u, v


@numba.njit(cache=True)
def leaf_of(corners, triangle, child, root, point):
    """The leaf under ``root`` holding ``point`` (3,) (Hierarchy.leaf_at, one point). The children's
    order is _split's — a quad's 0: u, v < ½, 1: u ≥ ½ > v, 2: both ≥ ½, 3: v ≥ ½ > u; a triangle's
    0, 1, 2 at its corners and 3 in the middle (upside down)."""
    e = root
    tri = triangle[e]
    u, v = _parameters(corners[e], tri, point)
    u, v = min(max(u, 0.0), 1.0), min(max(v, 0.0), 1.0)
    if tri and u + v > 1:
        s = u + v
        u, v = u / s, v / s
    while child[e] >= 0:
        first = child[e]
        if tri:
            if u >= 0.5:
                e, u, v = first + 1, 2 * u - 1, 2 * v
            elif v >= 0.5:
                e, u, v = first + 2, 2 * u, 2 * v - 1
            elif u + v < 0.5:
                e, u, v = first, 2 * u, 2 * v
            else:  # the middle child's corners are the midpoints 01, 12, 20
                e, u, v = first + 3, 2 * u + 2 * v - 1, 1 - 2 * u
        else:
            right, up = u >= 0.5, v >= 0.5
            e = first + (2 if right and up else 1 if right else 3 if up else 0)
            u, v = 2 * u - (1.0 if right else 0.0), 2 * v - (1.0 if up else 0.0)
    return e


@numba.njit(cache=True)
def _leaves_at(corners, triangle, child, roots, points, out):
    for i in range(len(roots)):
        out[i] = -1 if roots[i] < 0 else leaf_of(corners, triangle, child, roots[i], points[i])


def _split(c: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(n, 4, 4, d): the four children's corners of elements with corners ``c`` (n, 4, d) — a quad
    at its edge midpoints and centre, a triangle at its edge midpoints (positions and uvs alike)."""
    m01, m12, m23, m30 = ((c[:, k] + c[:, (k + 1) % 4]) / 2 for k in range(4))
    m20 = (c[:, 2] + c[:, 0]) / 2
    centre = c.mean(axis=1)
    quad_children = np.stack(
        [
            np.stack(q, axis=1)
            for q in (
                (c[:, 0], m01, centre, m30),
                (m01, c[:, 1], m12, centre),
                (centre, m12, c[:, 2], m23),
                (m30, centre, m23, c[:, 3]),
            )
        ],
        axis=1,
    )
    tri_children = np.stack(
        [
            np.stack(q, axis=1)
            for q in (
                (c[:, 0], m01, m20, m20),
                (m01, c[:, 1], m12, m12),
                (m20, m12, c[:, 2], c[:, 2]),
                (m01, m12, m20, m20),
            )
        ],
        axis=1,
    )
    return np.where(tri[:, None, None, None], tri_children, quad_children)


def leaves_under(h: Hierarchy, leaves: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every (element, leaf under it) of ``leaves`` and their ancestors, sorted by element: (element
    (m,), leaf (m,)); the leaves under element e are ``leaf[searchsorted(element, e) : …right]``."""
    element_of, leaf_of = [], []
    element, leaf = leaves.copy(), leaves.copy()
    while len(element):
        element_of.append(element)
        leaf_of.append(leaf)
        up = h.parent[element] >= 0
        element, leaf = h.parent[element[up]], leaf[up]
    element, leaf = np.concatenate(element_of), np.concatenate(leaf_of)
    order = np.argsort(element, kind="stable")
    return element[order], leaf[order]
