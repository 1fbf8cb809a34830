"""Per-vertex principal curvatures and directions by fitting a local height function (a Monge-form
"jet") over a breadth-first neighbourhood, as the report's step 1 does with CGAL's Monge_form
(Figure 3.4), written here with numba; then the fits' curvature tensors averaged over each vertex's
1-ring a few times (each rotated into the vertex's tangent plane), which removes most of the noise
a single fit keeps.

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

import contextlib
import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np

from ..core.errors import InputError
from ..core.images import atomic_output
from ..core.kernels import compile_note
from ..core.progress import phase
from ..scene.mesh import Mesh

__all__ = ["Curvature", "estimate_curvature", "cache_dir", "CACHE_VERSION"]

CACHE_VERSION = 5
#: the kernels' first compilation after an install, measured on 2 cores (`NUMBA_CACHE_DIR=EMPTY illusio
#: lines blob`: the curvature phase 16.6 s, the run 25.7 s against 3.7 s once compiled)
COMPILE_SECONDS = 20


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
        """A curvature scale of the mesh (1/units): the ``percentile`` of max(abs(k_min), abs(k_max)) over
        valid vertices. Thresholds relative to it transfer between meshes of any size and detail."""
        k = np.maximum(np.abs(self.k_min), np.abs(self.k_max))[self.valid]
        return float(np.percentile(k, percentile)) if len(k) else 1.0

    def save(self, path: str | os.PathLike, **extra: np.ndarray) -> Path:
        """Write the fields (and ``extra`` arrays beside them) to an .npz, atomically."""
        p = Path(path)
        with atomic_output(p) as tmp, open(tmp, "wb") as f:
            np.savez(f, **self.__dict__, **extra)
        return p

    @classmethod
    def load(cls, path: str | os.PathLike) -> Curvature:
        with np.load(path) as data:
            return cls(**{k: data[k] for k in cls.__dataclass_fields__})


def cache_dir() -> Path:
    return Path(os.environ.get("ILLUSIO_CACHE", Path.home() / ".cache" / "illusio")) / "curvature"


def estimate_curvature(
    mesh: Mesh,
    rings: int = 2,
    degree: int = 4,
    cache: bool = True,
    adaptive: bool = False,
    extra_rings: int = 1,
    confidence: float = 2.0,
    smoothing: int = 3,
) -> Curvature:
    """Fit a jet of ``degree`` (2, 3 or 4) at every vertex of ``mesh`` (illusio's Mesh or a
    trimesh.Trimesh) over the smallest neighbourhood of at least
    ``rings`` rings that holds twice the jet's unknowns (lower degrees where none does).

    ``adaptive``: then also fit every lower degree, each on those rings and on up to ``extra_rings``
    more (the quartic on the start rings, on one more, the cubic on both, the quadric on both), and
    let a fit join while the curvature confidence intervals k ± ``confidence``·std (std from each
    fit's residual and (AᵀA)⁻¹) of all fits so far intersect — the ICI rule of adaptive smoothing
    (Katkovnik) — then answer with the inverse-variance mean of the jets that joined (their
    coefficients share one frame, so normal, curvatures and directions stay consistent). On a clean
    surface the quartic's accuracy stands (the biased lower degrees do not join); on noise more
    support and lower degrees join and average it out.

    ``smoothing``: then average each vertex's curvature tensor with its 1-ring neighbours' this many
    times (0: the fits as they are; each neighbour's tensor rotated into the vertex's tangent plane
    first, so a sphere stays exact) and take the principal curvatures and directions from the
    average. Each quartic sees its own neighbourhood's noise; averaging the fits' tensors removes
    much of it without the bias of one low-degree fit over a wide patch (a quadric over most of a
    coarse torus's tube), which is why the default is the plain quartic with three passes rather
    than the adaptive fits (benchmarks/RESULTS.md: mean error 0.075 on the 24 analytic cases,
    against 0.106 adaptive alone and 0.093 adaptive with three passes; clean surfaces with varying
    curvature pay a little bias, ellipsoid-3 0.004 → 0.035). ``dcurv`` comes from the cubic terms of
    the fits that have them (zero when only quadrics joined), in the final principal frame."""
    from ..scene.mesh import as_mesh

    mesh = as_mesh(mesh)  # a trimesh.Trimesh is taken too
    if degree not in (2, 3, 4):
        raise InputError(f"jet degree must be 2, 3 or 4, got {degree}")
    if not 1 <= rings <= 8:
        raise InputError(f"neighbourhood rings must be in 1..8, got {rings}")
    if not 0 <= extra_rings <= 8:
        raise InputError(f"extra rings must be in 0..8, got {extra_rings}")
    if not 0 <= smoothing <= 8:
        raise InputError(f"curvature smoothing passes must be in 0..8, got {smoothing}")
    vertices = np.ascontiguousarray(mesh.vertices, np.float64)
    faces = np.ascontiguousarray(mesh.faces, np.int64)
    if not np.isfinite(vertices).all():
        raise InputError(f"{mesh.name}: vertices contain NaN or infinite coordinates")
    key = None
    if cache:
        h = hashlib.sha256()
        for part in (np.ascontiguousarray(mesh.vertices, np.float32), np.ascontiguousarray(mesh.faces, np.int32)):
            h.update(part.tobytes())
        h.update(
            f"v{CACHE_VERSION} rings={rings} degree={degree} adaptive={adaptive} extra={extra_rings} "
            f"confidence={confidence} smoothing={smoothing}".encode()
        )
        key = cache_dir() / f"{h.hexdigest()[:32]}.npz"
        if key.exists():
            try:
                return Curvature.load(key)
            except Exception:  # a corrupt cache file: recompute and overwrite it
                pass
    # numba compiles the kernels on the first call after an install (then loads them from disk)
    first = compile_note("the curvature kernels", COMPILE_SECONDS, _fit_all, _smooth_tensors, _derivatives)
    with phase(f"lines: curvature of {len(vertices):,} vertices{first}"):
        area_normals = _area_normals(vertices, faces)
        offsets, neighbours = _adjacency(len(vertices), faces)
        normals, k_min, k_max, e_min, e_max, cubic, valid = _fit_all(
            vertices,
            area_normals,
            offsets,
            neighbours,
            rings,
            degree,
            extra_rings,
            confidence if adaptive else 0.0,
            numba.get_num_threads() * 16,
        )
        if smoothing:
            _smooth_tensors(normals, k_min, k_max, e_min, e_max, valid, offsets, neighbours, smoothing)
        dcurv = _derivatives(area_normals, e_min, e_max, cubic, valid)
    result = Curvature(*(a.astype(np.float32) for a in (normals, k_min, k_max, e_min, e_max, dcurv)), valid=valid)
    if key is not None:
        with contextlib.suppress(Exception):  # a read-only home must not stop the estimate
            result.save(key)
    return result


@numba.njit(cache=True)
def _area_normals(vertices, faces):
    """Each vertex's sum of its faces' area-weighted normals (edge cross products): not normalised,
    zero marks an unreferenced or degenerate vertex."""
    n = np.zeros_like(vertices)
    for f in range(len(faces)):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        ux, uy, uz = vertices[b, 0] - vertices[a, 0], vertices[b, 1] - vertices[a, 1], vertices[b, 2] - vertices[a, 2]
        vx, vy, vz = vertices[c, 0] - vertices[a, 0], vertices[c, 1] - vertices[a, 1], vertices[c, 2] - vertices[a, 2]
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        for v in (a, b, c):
            n[v, 0] += nx
            n[v, 1] += ny
            n[v, 2] += nz
    return n


def area_normals_reference(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The plain statement of :func:`_area_normals` (the test's reference)."""
    fn = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    n = np.zeros_like(vertices)
    for axis in range(3):
        n[:, axis] = sum(np.bincount(faces[:, c], fn[:, axis], len(vertices)) for c in range(3))
    return n


@numba.njit(parallel=True, cache=True)
def _adjacency(count, faces):
    """CSR vertex adjacency from the faces' edges: each vertex's neighbours, unique and sorted
    (a counting sort of the edges both ways, then each vertex's short list sorted and deduplicated)."""
    degree = np.zeros(count + 1, np.int64)
    for f in range(len(faces)):
        for k in range(3):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            if a != b:
                degree[a + 1] += 1
                degree[b + 1] += 1
    start = np.cumsum(degree)
    raw = np.empty(start[-1], np.int64)
    fill = start[:-1].copy()
    for f in range(len(faces)):
        for k in range(3):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            if a != b:
                raw[fill[a]] = b
                fill[a] += 1
                raw[fill[b]] = a
                fill[b] += 1
    kept = np.zeros(count + 1, np.int64)
    for v in numba.prange(count):
        first, last = start[v], start[v + 1]
        for k in range(first + 1, last):  # insertion sort: a vertex has a handful of neighbours
            value = raw[k]
            j = k - 1
            while j >= first and raw[j] > value:
                raw[j + 1] = raw[j]
                j -= 1
            raw[j + 1] = value
        unique = 0
        for k in range(first, last):
            if k == first or raw[k] != raw[k - 1]:
                raw[first + unique] = raw[k]
                unique += 1
        kept[v + 1] = unique
    offsets = np.cumsum(kept)
    neighbours = np.empty(offsets[-1], np.int64)
    for v in numba.prange(count):
        neighbours[offsets[v] : offsets[v + 1]] = raw[start[v] : start[v] + offsets[v + 1] - offsets[v]]
    return offsets, neighbours


def adjacency_reference(count: int, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The plain statement of :func:`_adjacency`: CSR vertex adjacency (unique, sorted neighbours)."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edges = np.concatenate([edges, edges[:, ::-1]])
    edges = edges[edges[:, 0] != edges[:, 1]]
    keys = np.unique(edges[:, 0] * np.int64(count) + edges[:, 1])
    sources = keys // count
    offsets = np.zeros(count + 1, np.int64)
    offsets[1:] = np.cumsum(np.bincount(sources, minlength=count))
    return offsets, keys - sources * count


@numba.njit(cache=True)
def _grow_ring(queue, head, tail, offsets, neighbours, stamp, mark, limit):
    """Append the next breadth-first ring (the unvisited neighbours of queue[head:tail]) to
    ``queue``; visited vertices carry ``mark`` in ``stamp``. Returns the new tail."""
    end = tail
    for q in range(head, end):
        v = queue[q]
        for k in range(offsets[v], offsets[v + 1]):
            u = neighbours[k]
            if stamp[u] != mark and tail < limit:
                stamp[u] = mark
                queue[tail] = u
                tail += 1
    return tail


@numba.njit(cache=True)
def _frame_tangent(n):
    """The unit tangent t1 of :func:`_frame` for the unit normal n, as a tuple."""
    ax, ay = (1.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0)
    d = ax * n[0] + ay * n[1]
    x, y, z = ax - n[0] * d, ay - n[1] * d, -n[2] * d
    length = np.sqrt(x * x + y * y + z * z)
    return x / length, y / length, z / length


@numba.njit(cache=True)
def _frame(n, t1, t2):
    """Two unit tangents t1, t2 completing the unit normal n to a right-handed frame (written in place)."""
    ax, ay = (1.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0)
    d = ax * n[0] + ay * n[1]
    t1[0], t1[1], t1[2] = ax - n[0] * d, ay - n[1] * d, -n[2] * d
    length = np.sqrt(t1[0] ** 2 + t1[1] ** 2 + t1[2] ** 2)
    t1[0], t1[1], t1[2] = t1[0] / length, t1[1] / length, t1[2] / length
    t2[0] = n[1] * t1[2] - n[2] * t1[1]
    t2[1] = n[2] * t1[0] - n[0] * t1[2]
    t2[2] = n[0] * t1[1] - n[1] * t1[0]


@numba.njit(cache=True)
def _unknowns(degree):
    return (degree + 1) * (degree + 2) // 2


@numba.njit(parallel=True, cache=True)
def _fit_all(vertices, normals, offsets, neighbours, rings, degree, extra_rings, gamma, blocks):
    n_vertices = len(vertices)
    out_n = np.zeros((n_vertices, 3))
    out_k = np.zeros((n_vertices, 2))
    out_emin = np.zeros((n_vertices, 3))
    out_emax = np.zeros((n_vertices, 3))
    out_cubic = np.zeros((n_vertices, 4))
    valid = np.zeros(n_vertices, np.bool_)
    limit = 1024
    size = _unknowns(degree)
    per_block = (n_vertices + blocks - 1) // blocks
    for block in numba.prange(blocks):
        # per-thread work arrays, reused for every vertex of the block (contiguous vertices: the
        # neighbourhoods of consecutive vertices share cache lines)
        stamp = np.full(n_vertices, -1, np.int64)
        queue = np.empty(limit, np.int64)
        ends = np.zeros(rings + extra_rings + 4, np.int64)
        gram = np.empty((size, size))  # AᵀA, Aᵀh, hᵀh of the jet's monomials, summed ring by ring
        moment = np.empty(size)
        ata = np.empty((size, size))
        coef = np.empty(size)
        work = np.empty(size)
        scratch = (np.empty(45), np.empty(45), np.empty(15))  # _accumulate's powers and their sums
        fit = np.empty(15)  # one candidate: normal (3), k_min, k_max, e_min (3), e_max (3), cubic (4)
        best = np.empty(15)
        grams = np.empty((extra_rings + 1, size, size))  # normal equations per ring prefix
        moments = np.empty((extra_rings + 1, size))
        sums = np.empty(extra_rings + 1)
        mean = np.empty(10)  # inverse-variance mean of the jets that joined, up to the cubic terms
        n0 = np.empty(3)
        t1 = np.empty(3)
        t2 = np.empty(3)
        for i in range(block * per_block, min(n_vertices, (block + 1) * per_block)):
            length = np.sqrt(normals[i, 0] ** 2 + normals[i, 1] ** 2 + normals[i, 2] ** 2)
            if length == 0.0 or offsets[i + 1] == offsets[i]:
                out_n[i, 2] = 1.0
                continue
            n0[0], n0[1], n0[2] = normals[i, 0] / length, normals[i, 1] / length, normals[i, 2] / length
            out_n[i] = n0
            # breadth-first rings until the starting jet (`degree`, lower where the mesh is too small)
            # has twice its unknowns on at least `rings` rings; ends[r] = points within r rings
            queue[0] = i
            stamp[i] = i
            ends[0] = 1
            available = 0
            deg = degree
            while available < rings or ends[available] < 2 * _unknowns(deg):
                if available == len(ends) - 1 or ends[available] == limit:
                    if deg == 2:
                        break
                    deg -= 1
                    continue
                tail = _grow_ring(
                    queue,
                    ends[available - 1] if available else 0,
                    ends[available],
                    offsets,
                    neighbours,
                    stamp,
                    i,
                    limit,
                )
                if tail == ends[available]:  # the component is exhausted
                    if ends[available] >= 2 * _unknowns(deg) or deg == 2:
                        break
                    deg -= 1
                    continue
                available += 1
                ends[available] = tail
            start = available
            if ends[start] < _unknowns(deg) + 1:
                continue
            _frame(n0, t1, t2)
            # local coordinates scaled by the starting neighbourhood's radius (conditioning)
            radius = _radius(vertices, i, t1, t2, queue, ends[start])
            if radius == 0.0:
                continue
            gram[:] = 0.0
            moment[:] = 0.0
            block = _unknowns(deg)
            hh = _accumulate(vertices, i, n0, t1, t2, 1.0 / radius, queue, 0, ends[start], block, gram, moment, scratch)
            # the normal equations of the start rings and of each extra ring's prefix, kept for the
            # candidates below (the full block of the starting degree: lower degrees are its leading block)
            grams[0, :block, :block] = gram[:block, :block]
            moments[0, :block] = moment[:block]
            sums[0] = hh
            extra = 0
            while gamma > 0.0 and extra < extra_rings and ends[start + extra] < limit and start + extra + 1 < len(ends):
                r = start + extra
                tail = _grow_ring(queue, ends[r - 1] if r else 0, ends[r], offsets, neighbours, stamp, i, limit)
                if tail == ends[r]:
                    break
                ends[r + 1] = tail
                hh += _accumulate(
                    vertices, i, n0, t1, t2, 1.0 / radius, queue, ends[r], tail, block, gram, moment, scratch
                )
                extra += 1
                grams[extra, :block, :block] = gram[:block, :block]
                moments[extra, :block] = moment[:block]
                sums[extra] = hh
            # candidates of less variance and more bias, degree by degree, each on the start rings and
            # then on each extra ring: a fit joins while the confidence intervals k ± gamma·std of all
            # fits so far intersect (the ICI rule of adaptive smoothing: noise widens the intervals
            # and buys support and lower degrees; on a clean surface the biased fits do not join), and
            # the answer is the inverse-variance mean of the jets that joined (coefficients in one frame)
            lo_low, lo_high, hi_low, hi_high = -np.inf, np.inf, -np.inf, np.inf
            mean[:] = 0.0
            weight_all = 0.0
            weight_cubic = 0.0
            joined = False
            stop = False
            lowest = 2 if gamma > 0.0 else deg  # not adaptive: the one fit (extra is 0 then too)
            for d in range(deg, lowest - 1, -1):
                for j in range(extra + 1):
                    std = _fit_one(
                        grams[j],
                        moments[j],
                        sums[j],
                        ends[start + j],
                        d,
                        radius,
                        ata,
                        coef,
                        work,
                        n0,
                        t1,
                        t2,
                        fit,
                        gamma > 0.0,
                    )
                    lo_low = max(lo_low, fit[3] - gamma * std)
                    lo_high = min(lo_high, fit[3] + gamma * std)
                    hi_low = max(hi_low, fit[4] - gamma * std)
                    hi_high = min(hi_high, fit[4] + gamma * std)
                    if joined and (lo_low > lo_high or hi_low > hi_high):
                        stop = True
                        break
                    w = 1.0 / max(std * std, 1e-30)
                    for k in range(6):
                        mean[k] += w * coef[k]
                    weight_all += w
                    if d >= 3:
                        for k in range(6, 10):
                            mean[k] += w * coef[k]
                        weight_cubic += w
                    joined = True
                if stop:
                    break
            for k in range(6):
                mean[k] /= weight_all
            for k in range(6, 10):
                mean[k] = mean[k] / weight_cubic if weight_cubic > 0.0 else 0.0
            _shape(mean, radius, 3 if weight_cubic > 0.0 else 2, n0, t1, t2, best)
            valid[i] = True
            out_n[i] = best[0:3]
            out_k[i, 0] = best[3]
            out_k[i, 1] = best[4]
            out_emin[i] = best[5:8]
            out_emax[i] = best[8:11]
            out_cubic[i] = best[11:15]
    return out_n, out_k[:, 0].copy(), out_k[:, 1].copy(), out_emin, out_emax, out_cubic, valid


@numba.njit(parallel=True, cache=True)
def _smooth_tensors(normals, k_min, k_max, e_min, e_max, valid, offsets, neighbours, passes):
    """``passes`` rounds of averaging each valid vertex's curvature tensor k_min e_min e_minᵀ +
    k_max e_max e_maxᵀ (world space, 6 components) with its valid 1-ring neighbours' (uniform
    weights; each neighbour's rotated into this vertex's tangent plane), then each vertex's
    principal curvatures and directions from the average restricted to its tangent plane (``normals``: the fits' unit
    normals). e_max keeps the side of the fit's
    e_max, e_min = n × e_max as in :func:`_shape`. Arrays are updated in place."""
    n_vertices = len(k_min)
    tensor = np.zeros((n_vertices, 6))  # xx, xy, xz, yy, yz, zz
    for i in numba.prange(n_vertices):
        if valid[i]:
            for a in range(2):
                k = k_min[i] if a == 0 else k_max[i]
                e = e_min[i] if a == 0 else e_max[i]
                tensor[i, 0] += k * e[0] * e[0]
                tensor[i, 1] += k * e[0] * e[1]
                tensor[i, 2] += k * e[0] * e[2]
                tensor[i, 3] += k * e[1] * e[1]
                tensor[i, 4] += k * e[1] * e[2]
                tensor[i, 5] += k * e[2] * e[2]
    averaged = np.zeros((n_vertices, 6))
    for _ in range(passes):
        for i in numba.prange(n_vertices):
            if not valid[i]:
                continue
            count = 1.0
            for c in range(6):
                averaged[i, c] = tensor[i, c]
            for q in range(offsets[i], offsets[i + 1]):
                j = neighbours[q]
                if valid[j] and _add_transported(tensor[j], normals[j], normals[i], averaged[i]):
                    count += 1.0
            for c in range(6):
                averaged[i, c] /= count
        tensor, averaged = averaged, tensor
    for i in numba.prange(n_vertices):
        if not valid[i]:
            continue
        n = normals[i]
        u = _frame_tangent(n)  # a tuple (no allocation per vertex): _frame's t1 and t2
        w = (n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0])
        t = tensor[i]
        # the 2×2 restriction [[uᵀTu, uᵀTw], [wᵀTu, wᵀTw]]
        tu0 = t[0] * u[0] + t[1] * u[1] + t[2] * u[2]
        tu1 = t[1] * u[0] + t[3] * u[1] + t[4] * u[2]
        tu2 = t[2] * u[0] + t[4] * u[1] + t[5] * u[2]
        tw0 = t[0] * w[0] + t[1] * w[1] + t[2] * w[2]
        tw1 = t[1] * w[0] + t[3] * w[1] + t[4] * w[2]
        tw2 = t[2] * w[0] + t[4] * w[1] + t[5] * w[2]
        m11 = u[0] * tu0 + u[1] * tu1 + u[2] * tu2
        m12 = w[0] * tu0 + w[1] * tu1 + w[2] * tu2
        m22 = w[0] * tw0 + w[1] * tw1 + w[2] * tw2
        half = (m11 - m22) / 2.0
        disc = np.sqrt(half * half + m12 * m12)
        k_min[i] = (m11 + m22) / 2.0 - disc
        k_max[i] = (m11 + m22) / 2.0 + disc
        angle = 0.5 * np.arctan2(2.0 * m12, m11 - m22)  # of the eigenvector of the larger value
        cu, sw = np.cos(angle), np.sin(angle)
        ex, ey, ez = cu * u[0] + sw * w[0], cu * u[1] + sw * w[1], cu * u[2] + sw * w[2]
        if ex * e_max[i, 0] + ey * e_max[i, 1] + ez * e_max[i, 2] < 0.0:
            ex, ey, ez = -ex, -ey, -ez
        e_max[i, 0], e_max[i, 1], e_max[i, 2] = ex, ey, ez
        e_min[i, 0], e_min[i, 1], e_min[i, 2] = n[1] * ez - n[2] * ey, n[2] * ex - n[0] * ez, n[0] * ey - n[1] * ex


@numba.njit(cache=True)
def _add_transported(t, n_from, n_to, out):
    """Add the symmetric tensor ``t`` (xx, xy, xz, yy, yz, zz), tangent at a vertex of normal
    ``n_from``, to ``out`` after the smallest rotation that takes ``n_from`` to ``n_to`` (so a
    neighbour's curvature enters this vertex's tangent plane undistorted: on a sphere every
    transported tensor is the same). False, adding nothing, for nearly opposite normals."""
    c = n_from[0] * n_to[0] + n_from[1] * n_to[1] + n_from[2] * n_to[2]
    if c < -0.5:
        return False
    vx = n_from[1] * n_to[2] - n_from[2] * n_to[1]
    vy = n_from[2] * n_to[0] - n_from[0] * n_to[2]
    vz = n_from[0] * n_to[1] - n_from[1] * n_to[0]
    f = 1.0 / (1.0 + c)
    # Rodrigues: R = I + [v]x + [v]x² / (1 + c)
    r00 = 1.0 - f * (vy * vy + vz * vz)
    r01 = -vz + f * vx * vy
    r02 = vy + f * vx * vz
    r10 = vz + f * vx * vy
    r11 = 1.0 - f * (vx * vx + vz * vz)
    r12 = -vx + f * vy * vz
    r20 = -vy + f * vx * vz
    r21 = vx + f * vy * vz
    r22 = 1.0 - f * (vx * vx + vy * vy)
    # M = T Rᵀ (columns: T times each row of R), then R M, upper triangle
    m00 = t[0] * r00 + t[1] * r01 + t[2] * r02
    m10 = t[1] * r00 + t[3] * r01 + t[4] * r02
    m20 = t[2] * r00 + t[4] * r01 + t[5] * r02
    m01 = t[0] * r10 + t[1] * r11 + t[2] * r12
    m11 = t[1] * r10 + t[3] * r11 + t[4] * r12
    m21 = t[2] * r10 + t[4] * r11 + t[5] * r12
    m02 = t[0] * r20 + t[1] * r21 + t[2] * r22
    m12 = t[1] * r20 + t[3] * r21 + t[4] * r22
    m22 = t[2] * r20 + t[4] * r21 + t[5] * r22
    out[0] += r00 * m00 + r01 * m10 + r02 * m20
    out[1] += r00 * m01 + r01 * m11 + r02 * m21
    out[2] += r00 * m02 + r01 * m12 + r02 * m22
    out[3] += r10 * m01 + r11 * m11 + r12 * m21
    out[4] += r10 * m02 + r11 * m12 + r12 * m22
    out[5] += r20 * m02 + r21 * m12 + r22 * m22
    return True


@numba.njit(parallel=True, cache=True)
def _derivatives(area_normals, e_min, e_max, cubic, valid):
    """C in the principal frame (see the module docstring) from each fit's cubic (c0, c1, c2, c3),
    written in the (t1, t2) frame of the vertex's area normal (the frame the jet was fitted in)."""
    n_vertices = len(e_min)
    out = np.zeros((n_vertices, 4))
    for i in numba.prange(n_vertices):
        if not valid[i]:
            continue
        n0 = area_normals[i] / np.sqrt(area_normals[i, 0] ** 2 + area_normals[i, 1] ** 2 + area_normals[i, 2] ** 2)
        t1 = np.empty(3)
        t2 = np.empty(3)
        _frame(n0, t1, t2)
        ax = e_min[i, 0] * t1[0] + e_min[i, 1] * t1[1] + e_min[i, 2] * t1[2]
        ay = e_min[i, 0] * t2[0] + e_min[i, 1] * t2[1] + e_min[i, 2] * t2[2]
        bx = e_max[i, 0] * t1[0] + e_max[i, 1] * t1[1] + e_max[i, 2] * t1[2]
        by = e_max[i, 0] * t2[0] + e_max[i, 1] * t2[1] + e_max[i, 2] * t2[2]
        c0, c1, c2, c3 = cubic[i, 0], cubic[i, 1], cubic[i, 2], cubic[i, 3]
        out[i, 0] = _cubic(c0, c1, c2, c3, ax, ay, ax, ay, ax, ay)
        out[i, 1] = _cubic(c0, c1, c2, c3, ax, ay, ax, ay, bx, by)
        out[i, 2] = _cubic(c0, c1, c2, c3, ax, ay, bx, by, bx, by)
        out[i, 3] = _cubic(c0, c1, c2, c3, bx, by, bx, by, bx, by)
    return out


@numba.njit(cache=True)
def _radius(vertices, i, t1, t2, ring, m):
    """The largest tangent-plane distance from vertex i to the first m vertices of ``ring``."""
    radius = 0.0
    for j in range(m):  # scalar arithmetic: a temporary array per point would dominate the cost
        dx = vertices[ring[j], 0] - vertices[i, 0]
        dy = vertices[ring[j], 1] - vertices[i, 1]
        dz = vertices[ring[j], 2] - vertices[i, 2]
        x = dx * t1[0] + dy * t1[1] + dz * t1[2]
        y = dx * t2[0] + dy * t2[1] + dz * t2[2]
        radius = max(radius, x * x + y * y)
    return np.sqrt(radius)


#: sums may be reordered (and multiply-adds fused) so that LLVM vectorises them: a sum left in order
#: is one chain of dependent additions, and the fit waited on it; no other fast-math assumption is made
REASSOCIATE = {"reassoc", "contract"}

#: the jet's monomials f·x^p·y^q in the order of its unknowns (h = c + a1 x + a2 y + ½(b0 x² + 2 b1 xy
#: + b2 y²) + (c0 x³ + 3 c1 x²y + 3 c2 xy² + c3 y³)/6 + quartic/24): the exponents (p, q) and the
#: Taylor factor f; the cubic's and the quadric's are the leading 10 and 6
MONOMIALS = np.array(
    [
        (0, 0),
        (1, 0),
        (0, 1),
        (2, 0),
        (1, 1),
        (0, 2),
        (3, 0),
        (2, 1),
        (1, 2),
        (0, 3),
        (4, 0),
        (3, 1),
        (2, 2),
        (1, 3),
        (0, 4),
    ],
    np.int64,
)
FACTORS = np.array([1, 1, 1, 1 / 2, 1, 1 / 2, 1 / 6, 1 / 2, 1 / 2, 1 / 6, 1 / 24, 1 / 6, 1 / 4, 1 / 6, 1 / 24])


def jet_monomials(x: np.ndarray, y: np.ndarray, degree: int) -> np.ndarray:
    """The jet's monomials at points (x, y): the design matrix A, (len(x), unknowns), one row a point
    (the plain statement the normal equations of :func:`_accumulate` are tested against)."""
    count = (degree + 1) * (degree + 2) // 2
    p, q = MONOMIALS[:count].T
    return FACTORS[:count] * np.asarray(x, float)[:, None] ** p * np.asarray(y, float)[:, None] ** q


def _power_index(top: int) -> np.ndarray:
    """(top+1, top+1) → the flat index of x^p y^q among the powers with p + q ≤ top, p-major (-1 past)."""
    index = np.full((top + 1, top + 1), -1, np.int64)
    k = 0
    for p in range(top + 1):
        for q in range(top + 1 - p):
            index[p, q] = k
            k += 1
    return index


_POWERS_8, _POWERS_4 = _power_index(8), _power_index(4)
#: AᵀA[a, b] = GRAM_FACTOR[a, b] · Σ x^p y^q at flat power GRAM_POWER[a, b]; Aᵀh[a] = FACTORS[a] · Σ h x^p y^q
#: at flat power MOMENT_POWER[a] (p + q ≤ 4)
GRAM_POWER = _POWERS_8[MONOMIALS[:, None, 0] + MONOMIALS[None, :, 0], MONOMIALS[:, None, 1] + MONOMIALS[None, :, 1]]
GRAM_FACTOR = FACTORS[:, None] * FACTORS[None, :]
MOMENT_POWER = _POWERS_4[MONOMIALS[:, 0], MONOMIALS[:, 1]]
#: the flat index among the 45 powers (p + q ≤ 8) of each of the 15 with p + q ≤ 4, in their p-major order
LOW_POWERS = np.array([_POWERS_8[p, q] for p in range(5) for q in range(5 - p)], np.int64)


@numba.njit(cache=True)
def _accumulate(vertices, i, n0, t1, t2, scale, ring, first, last, size, gram, moment, scratch):
    """Add ring[first:last]'s points, in the frame (t1, t2, n0) at vertex i scaled by ``scale``, to
    the normal equations AᵀA (upper triangle of ``gram``) and Aᵀh (``moment``) of the jet's
    monomials; returns their Σh². An entry of AᵀA is f_a·f_b·Σ x^(p_a+p_b)·y^(q_a+q_b), so the points
    are summed into the 45 power sums Σ x^p y^q (p + q ≤ 8) and the 15 Σ h x^p y^q (p + q ≤ 4) rather
    than into AᵀA's 120 entries one by one (:func:`jet_monomials` states A plainly; the test compares).
    ``scratch``: (powers (45), sums (45), sums_h (15)), flat so that the sums vectorise."""
    powers, sums, sums_h = scratch
    sums[:] = 0.0
    sums_h[:] = 0.0
    hh = 0.0
    for j in range(first, last):
        dx = vertices[ring[j], 0] - vertices[i, 0]
        dy = vertices[ring[j], 1] - vertices[i, 1]
        dz = vertices[ring[j], 2] - vertices[i, 2]
        x = (dx * t1[0] + dy * t1[1] + dz * t1[2]) * scale
        y = (dx * t2[0] + dy * t2[1] + dz * t2[2]) * scale
        h = (dx * n0[0] + dy * n0[1] + dz * n0[2]) * scale
        hh += h * h
        k = 0
        xp = 1.0
        for p in range(9):  # x^p y^q, p-major
            v = xp
            for _q in range(9 - p):
                powers[k] = v
                v *= y
                k += 1
            xp *= x
        for k in range(45):
            sums[k] += powers[k]
        for k in range(15):  # those of degree ≤ 4, times h
            sums_h[k] += powers[LOW_POWERS[k]] * h
    for a in range(size):
        moment[a] += FACTORS[a] * sums_h[MOMENT_POWER[a]]
        for b in range(a, size):
            gram[a, b] += GRAM_FACTOR[a, b] * sums[GRAM_POWER[a, b]]
    return hh


@numba.njit(cache=True)
def _fit_one(gram, moment, hh, m, degree, radius, ata, coef, work, n0, t1, t2, fit, want_std):
    """Least-squares jet of ``degree`` from the accumulated normal equations of m points (its
    monomials are the leading block: the cubic's are a subset of the quartic's); writes ``fit`` (see
    _fit_all) and returns the standard deviation of its curvatures estimated from the residual.
    ``ata``, ``coef``, ``work``: scratch arrays (no allocation per vertex: it would dominate). Without
    ``want_std`` (one fit, nothing to weigh it against) the deviation is not computed: 1 is returned."""
    unknowns = _unknowns(degree)
    for a in range(unknowns):
        for b in range(a, unknowns):
            ata[a, b] = gram[a, b]
            ata[b, a] = gram[a, b]
        ata[a, a] += 1e-9  # keeps flat or degenerate neighbourhoods solvable
    _cholesky_solve(ata, moment, unknowns, coef)  # ata now holds the Cholesky factor L
    if not want_std:
        _shape(coef, radius, degree, n0, t1, t2, fit)
        return 1.0
    # residual Σ(h − A c)² = hᵀh − cᵀAᵀh at the solution; σ² diag((AᵀA)⁻¹) = σ² |L⁻¹ e_k|²
    rss = hh
    for a in range(unknowns):
        rss -= coef[a] * moment[a]
    variance = max(rss, 0.0) / max(m - unknowns, 1)
    spread = 0.0
    for k in range(3, 6):  # |δB|_F² = δb0² + 2δb1² + δb2² bounds the eigenvalues' change
        work[k] = 1.0 / ata[k, k]
        total = work[k] * work[k]
        for a in range(k + 1, unknowns):
            v = 0.0
            for b in range(k, a):
                v -= ata[a, b] * work[b]
            work[a] = v / ata[a, a]
            total += work[a] * work[a]
        spread += total * (2.0 if k == 4 else 1.0)
    _shape(coef, radius, degree, n0, t1, t2, fit)
    return np.sqrt(variance * spread) / radius


@numba.njit(cache=True)
def _shape(coef, radius, degree, n0, t1, t2, fit):
    """Normal, principal curvatures and directions of the fitted jet at x = y = 0, and its cubic
    terms, all in mesh units, into ``fit`` (scalar arithmetic: no temporaries)."""
    # back to mesh units: first derivatives are scale-free, second divide by r, third by r²
    a1 = coef[1]
    a2 = coef[2]
    b0 = coef[3] / radius
    b1 = coef[4] / radius
    b2 = coef[5] / radius
    norm = np.sqrt(1.0 + a1 * a1 + a2 * a2)
    nx = (n0[0] - a1 * t1[0] - a2 * t2[0]) / norm
    ny = (n0[1] - a1 * t1[1] - a2 * t2[1]) / norm
    nz = (n0[2] - a1 * t1[2] - a2 * t2[2]) / norm
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
    ex = u * (t1[0] + a1 * n0[0]) + v * (t2[0] + a2 * n0[0])
    ey = u * (t1[1] + a1 * n0[1]) + v * (t2[1] + a2 * n0[1])
    ez = u * (t1[2] + a1 * n0[2]) + v * (t2[2] + a2 * n0[2])
    d = ex * nx + ey * ny + ez * nz
    ex, ey, ez = ex - d * nx, ey - d * ny, ez - d * nz
    length = np.sqrt(ex * ex + ey * ey + ez * ez)
    ex, ey, ez = ex / length, ey / length, ez / length
    fit[0], fit[1], fit[2] = nx, ny, nz
    fit[3] = k_lo
    fit[4] = k_hi
    fit[5], fit[6], fit[7] = ny * ez - nz * ey, nz * ex - nx * ez, nx * ey - ny * ex  # e_min = n × e_max
    fit[8], fit[9], fit[10] = ex, ey, ez
    r2 = radius * radius
    for k in range(4):
        fit[11 + k] = -coef[6 + k] / r2 if degree >= 3 else 0.0


@numba.njit(cache=True, fastmath=REASSOCIATE)
def _cholesky_solve(a, b, n, x):
    """Solve a x = b for the leading n×n block of a small symmetric positive-definite a; a is
    overwritten by its Cholesky factor (a LAPACK call per vertex costs more than the whole solve)."""
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
    for i in range(n):
        x[i] = b[i]
        for k in range(i):
            x[i] -= a[i, k] * x[k]
        x[i] /= a[i, i]
    for i in range(n - 1, -1, -1):
        for k in range(i + 1, n):
            x[i] -= a[k, i] * x[k]
        x[i] /= a[i, i]


@numba.njit(cache=True)
def _cubic(c0, c1, c2, c3, ux, uy, vx, vy, wx, wy):
    """The symmetric trilinear form C(u, v, w) whose cubic is c0 x³ + 3c1 x²y + 3c2 xy² + c3 y³."""
    return (
        c0 * ux * vx * wx
        + c1 * (ux * vx * wy + ux * vy * wx + uy * vx * wx)
        + c2 * (ux * vy * wy + uy * vx * wy + uy * vy * wx)
        + c3 * uy * vy * wy
    )
