"""Per-vertex principal curvatures and directions by fitting a local height function (a Monge-form
"jet") over a breadth-first neighbourhood, as the report's step 1 does with CGAL's Monge_form
(Figure 3.4), written here with numba.

Conventions: normals point outwards (the mesh's counter-clockwise winding); curvature is positive
where the surface bends away from its normal, so a sphere of radius R has k_min = k_max = +1/R and a
saddle has k_min < 0 < k_max. Units: 1/metres (1/mesh units). Directions e_min, e_max are unit
tangent vectors (signs arbitrary). ``dcurv`` holds the curvature derivative tensor C (the cubic
term of the jet, Rusinkiewicz 2004) in the (e_min, e_max) basis: C(e_min,e_min,e_min),
C(e_min,e_min,e_max), C(e_min,e_max,e_max), C(e_max,e_max,e_max); zero for a degree-2 fit.

Results cache to ``$ILLUSIO_CACHE`` (default ``~/.cache/illusio``)/curvature, one .npz per mesh
content and settings (the report's own suggested improvement: a second run skips the estimate).
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np

from ..core.errors import InputError
from ..core.images import atomic_output
from ..scene.mesh import Mesh

__all__ = ["Curvature", "estimate_curvature", "cache_dir", "CACHE_VERSION"]

CACHE_VERSION = 1


@dataclass
class Curvature:
    """Per-vertex arrays, N rows each (float32): normals (N,3), k_min, k_max (N,), e_min, e_max (N,3),
    dcurv (N,4) (see the module docstring), valid (N,) bool: False where no fit was possible
    (unreferenced or isolated vertices; their values are 0 and their normal the mesh's)."""

    normals: np.ndarray
    k_min: np.ndarray
    k_max: np.ndarray
    e_min: np.ndarray
    e_max: np.ndarray
    dcurv: np.ndarray
    valid: np.ndarray

    def scale(self, percentile: float = 90.0) -> float:
        """A curvature scale of the mesh (1/units): the ``percentile`` of max(|k_min|, |k_max|) over
        valid vertices. Thresholds relative to it transfer between meshes of any size and detail."""
        k = np.maximum(np.abs(self.k_min), np.abs(self.k_max))[self.valid]
        return float(np.percentile(k, percentile)) if len(k) else 1.0

    def save(self, path: str | os.PathLike) -> Path:
        p = Path(path)
        with atomic_output(p) as tmp:
            with open(tmp, "wb") as f:
                np.savez(f, **self.__dict__)
        return p

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Curvature":
        with np.load(path) as data:
            return cls(**{k: data[k] for k in cls.__dataclass_fields__})


def cache_dir() -> Path:
    return Path(os.environ.get("ILLUSIO_CACHE", Path.home() / ".cache" / "illusio")) / "curvature"


def estimate_curvature(mesh: Mesh, rings: int = 2, degree: int = 3, cache: bool = True) -> Curvature:
    """Fit a degree-``degree`` (2 or 3) jet at every vertex over its ``rings``-ring neighbourhood
    (grown ring by ring, up to rings + 2, until it holds at least twice the jet's unknowns)."""
    if degree not in (2, 3):
        raise InputError(f"jet degree must be 2 or 3, got {degree}")
    if not 1 <= rings <= 8:
        raise InputError(f"neighbourhood rings must be in 1..8, got {rings}")
    vertices = np.ascontiguousarray(mesh.vertices, np.float64)
    faces = np.ascontiguousarray(mesh.faces, np.int64)
    if not np.isfinite(vertices).all():
        raise InputError(f"{mesh.name}: vertices contain NaN or infinite coordinates")
    key = None
    if cache:
        h = hashlib.sha256()
        for part in (np.ascontiguousarray(mesh.vertices, np.float32), np.ascontiguousarray(mesh.faces, np.int32)):
            h.update(part.tobytes())
        h.update(f"v{CACHE_VERSION} rings={rings} degree={degree}".encode())
        key = cache_dir() / f"{h.hexdigest()[:32]}.npz"
        if key.exists():
            try:
                return Curvature.load(key)
            except Exception:  # a corrupt cache file: recompute and overwrite it
                pass
    normals = _area_normals(vertices, faces)
    offsets, neighbours = _adjacency(len(vertices), faces)
    out = _fit_all(vertices, normals, offsets, neighbours, rings, degree, numba.get_num_threads() * 8)
    result = Curvature(*(a.astype(np.float32) for a in out[:6]), valid=out[6])
    if key is not None:
        try:
            result.save(key)
        except Exception:  # a read-only home must not stop the estimate
            pass
    return result


def _area_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    fn = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    n = np.zeros_like(vertices)
    for c in range(3):
        np.add.at(n, faces[:, c], fn)
    return n  # not normalised: zero marks an unreferenced or degenerate vertex


def _adjacency(count: int, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CSR vertex adjacency (unique neighbours) from the faces' edges."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edges = np.concatenate([edges, edges[:, ::-1]])
    edges = edges[edges[:, 0] != edges[:, 1]]
    edges = np.unique(edges, axis=0)
    offsets = np.zeros(count + 1, np.int64)
    np.add.at(offsets, edges[:, 0] + 1, 1)
    return np.cumsum(offsets), edges[:, 1].astype(np.int64)


@numba.njit(cache=True)
def _bfs(root, rings, offsets, neighbours, stamp, queue, limit, mark):
    """Breadth-first ring neighbourhood of ``root`` into ``queue``; returns its length. ``mark``:
    a number never used before with this ``stamp`` array (visited vertices are stamped with it)."""
    queue[0] = root
    stamp[root] = mark
    head, tail = 0, 1
    for _ in range(rings):
        end = tail
        while head < end:
            v = queue[head]
            head += 1
            for k in range(offsets[v], offsets[v + 1]):
                u = neighbours[k]
                if stamp[u] != mark and tail < limit:
                    stamp[u] = mark
                    queue[tail] = u
                    tail += 1
        if head == tail:
            break
    return tail


@numba.njit(cache=True)
def _frame(n):
    """Two unit tangents completing the unit normal n to a right-handed frame."""
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = a - n * (a[0] * n[0] + a[1] * n[1] + a[2] * n[2])
    t1 /= np.sqrt((t1 * t1).sum())
    t2 = np.array([n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]])
    return t1, t2


@numba.njit(parallel=True, cache=True)
def _fit_all(vertices, normals, offsets, neighbours, rings, degree, chunks):
    n_vertices = len(vertices)
    out_n = np.zeros((n_vertices, 3))
    out_kmin = np.zeros(n_vertices)
    out_kmax = np.zeros(n_vertices)
    out_emin = np.zeros((n_vertices, 3))
    out_emax = np.zeros((n_vertices, 3))
    out_dcurv = np.zeros((n_vertices, 4))
    valid = np.zeros(n_vertices, np.bool_)
    limit = 512
    for chunk in numba.prange(chunks):
        stamp = np.full(n_vertices, -1, np.int64)
        queue = np.empty(limit, np.int64)
        for i in range(chunk, n_vertices, chunks):
            nn = normals[i]
            length = np.sqrt((nn * nn).sum())
            if length == 0.0 or offsets[i + 1] == offsets[i]:
                out_n[i] = np.array([0.0, 0.0, 1.0])
                continue
            n0 = nn / length
            unknowns = 10 if degree == 3 else 6
            count = 0
            deg = degree
            for r in range(rings, rings + 3):
                count = _bfs(i, r, offsets, neighbours, stamp, queue, limit, i * 4 + r - rings)
                if count >= 2 * unknowns or count == limit:
                    break
            if count < 2 * unknowns and deg == 3:
                deg = 2  # too few points for a cubic: fall back to a quadric
                unknowns = 6
            if count < unknowns + 1:
                out_n[i] = n0
                continue
            ok = _fit_one(i, vertices, n0, queue[:count], deg, out_n, out_kmin, out_kmax, out_emin, out_emax, out_dcurv)
            valid[i] = ok
    return out_n, out_kmin, out_kmax, out_emin, out_emax, out_dcurv, valid


@numba.njit(cache=True)
def _fit_one(i, vertices, n0, ring, degree, out_n, out_kmin, out_kmax, out_emin, out_emax, out_dcurv):
    t1, t2 = _frame(n0)
    p = vertices[i]
    m = len(ring)
    unknowns = 10 if degree == 3 else 6
    # local coordinates scaled by the neighbourhood radius for conditioning
    xs = np.empty(m)
    ys = np.empty(m)
    hs = np.empty(m)
    radius = 0.0
    for j in range(m):
        d = vertices[ring[j]] - p
        xs[j] = d[0] * t1[0] + d[1] * t1[1] + d[2] * t1[2]
        ys[j] = d[0] * t2[0] + d[1] * t2[1] + d[2] * t2[2]
        hs[j] = d[0] * n0[0] + d[1] * n0[1] + d[2] * n0[2]
        radius = max(radius, np.sqrt(xs[j] ** 2 + ys[j] ** 2))
    if radius == 0.0:
        out_n[i] = n0
        return False
    ata = np.zeros((unknowns, unknowns))
    atb = np.zeros(unknowns)
    row = np.empty(unknowns)
    for j in range(m):
        x = xs[j] / radius
        y = ys[j] / radius
        # h = c + a1 x + a2 y + ½(b0 x² + 2 b1 xy + b2 y²) + (c0 x³ + 3 c1 x²y + 3 c2 xy² + c3 y³)/6
        row[0] = 1.0
        row[1] = x
        row[2] = y
        row[3] = 0.5 * x * x
        row[4] = x * y
        row[5] = 0.5 * y * y
        if degree == 3:
            row[6] = x * x * x / 6.0
            row[7] = 0.5 * x * x * y
            row[8] = 0.5 * x * y * y
            row[9] = y * y * y / 6.0
        w = 1.0  # uniform weights: the rings already bound the support
        for a in range(unknowns):
            atb[a] += w * row[a] * hs[j] / radius
            for b in range(unknowns):
                ata[a, b] += w * row[a] * row[b]
    for a in range(unknowns):
        ata[a, a] += 1e-9  # keeps flat or degenerate neighbourhoods solvable
    coef = _cholesky_solve(ata, atb)
    # back to mesh units: first derivatives are scale-free, second divide by r, third by r²
    a1 = coef[1]
    a2 = coef[2]
    b0 = coef[3] / radius
    b1 = coef[4] / radius
    b2 = coef[5] / radius
    # the fitted surface's normal and shape operator at the vertex (x = y = 0)
    g2 = a1 * a1 + a2 * a2
    norm = np.sqrt(1.0 + g2)
    normal = (n0 - a1 * t1 - a2 * t2) / norm
    e11 = 1.0 + a1 * a1
    e12 = a1 * a2
    e22 = 1.0 + a2 * a2
    det = e11 * e22 - e12 * e12
    # S = I⁻¹ II with II = -H/|.|: negated so that a sphere with outward normals is positive
    l11 = -b0 / norm
    l12 = -b1 / norm
    l22 = -b2 / norm
    s11 = (e22 * l11 - e12 * l12) / det
    s12 = (e22 * l12 - e12 * l22) / det
    s21 = (e11 * l12 - e12 * l11) / det
    s22 = (e11 * l22 - e12 * l12) / det
    tr = s11 + s22
    disc = np.sqrt(max((s11 - s22) ** 2 / 4.0 + s12 * s21, 0.0))
    k_lo = tr / 2.0 - disc
    k_hi = tr / 2.0 + disc
    # eigenvector of S for k_hi in parameter space, then as a 3-D tangent X_u·u + X_v·v
    if abs(s12) > abs(s21) and abs(s12) > 1e-30:
        u, v = s12, k_hi - s11
    elif abs(s21) > 1e-30:
        u, v = k_hi - s22, s21
    else:
        u, v = (1.0, 0.0) if s11 >= s22 else (0.0, 1.0)
    emax = u * (t1 + a1 * n0) + v * (t2 + a2 * n0)
    emax -= normal * (emax * normal).sum()
    emax /= np.sqrt((emax * emax).sum())
    emin = np.array([normal[1] * emax[2] - normal[2] * emax[1], normal[2] * emax[0] - normal[0] * emax[2],
                     normal[0] * emax[1] - normal[1] * emax[0]])
    out_n[i] = normal
    out_kmin[i] = k_lo
    out_kmax[i] = k_hi
    out_emin[i] = emin
    out_emax[i] = emax
    if degree == 3:
        r2 = radius * radius
        c0 = -coef[6] / r2
        c1 = -coef[7] / r2
        c2 = -coef[8] / r2
        c3 = -coef[9] / r2
        # the principal directions in the (t1, t2) plane
        ax = (emin * t1).sum()
        ay = (emin * t2).sum()
        bx = (emax * t1).sum()
        by = (emax * t2).sum()
        out_dcurv[i, 0] = _cubic(c0, c1, c2, c3, ax, ay, ax, ay, ax, ay)
        out_dcurv[i, 1] = _cubic(c0, c1, c2, c3, ax, ay, ax, ay, bx, by)
        out_dcurv[i, 2] = _cubic(c0, c1, c2, c3, ax, ay, bx, by, bx, by)
        out_dcurv[i, 3] = _cubic(c0, c1, c2, c3, bx, by, bx, by, bx, by)
    return True


@numba.njit(cache=True)
def _cholesky_solve(a, b):
    """Solve a x = b for a small symmetric positive-definite a, in place (a LAPACK call per vertex
    costs more than the whole solve at this size)."""
    n = len(b)
    for j in range(n):
        d = a[j, j]
        for k in range(j):
            d -= a[j, k] * a[j, k]
        d = np.sqrt(max(d, 1e-300))
        a[j, j] = d
        for i in range(j + 1, n):
            s = a[i, j]
            for k in range(j):
                s -= a[i, k] * a[j, k]
            a[i, j] = s / d
    x = b.copy()
    for i in range(n):
        for k in range(i):
            x[i] -= a[i, k] * x[k]
        x[i] /= a[i, i]
    for i in range(n - 1, -1, -1):
        for k in range(i + 1, n):
            x[i] -= a[k, i] * x[k]
        x[i] /= a[i, i]
    return x


@numba.njit(cache=True)
def _cubic(c0, c1, c2, c3, ux, uy, vx, vy, wx, wy):
    """The symmetric trilinear form C(u, v, w) whose cubic is c0 x³ + 3c1 x²y + 3c2 xy² + c3 y³."""
    return (c0 * ux * vx * wx
            + c1 * (ux * vx * wy + ux * vy * wx + uy * vx * wx)
            + c2 * (ux * vy * wy + uy * vx * wy + uy * vy * wx)
            + c3 * uy * vy * wy)
