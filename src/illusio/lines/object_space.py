"""Object-space lines: zero crossings of a per-vertex scalar inside each triangle, kept where a line
type's condition holds. Every line type here is one scalar and one condition:

* occluding contours (silhouettes): n·(eye − p) = 0;
* suggestive contours (DeCarlo et al. 2003): radial curvature κ_r = 0 where D_w κ_r > 0 and the
  surface faces the viewer, with D_w κ_r = C(ŵ,ŵ,ŵ) − 2 τ_r² cot θ (ŵ: the view direction projected
  on the tangent plane, unit; τ_r = (k_max − k_min) u v its geodesic torsion; θ: angle between normal
  and view direction);
* ridges: D_{e_max} k_max = 0 where k_max > threshold and k_max decreases across (a maximum);
  valleys: D_{e_min} k_min = 0 where k_min < −threshold and k_min increases across (a minimum);
* apparent ridges (Judd et al. 2007, the original method): D_{t1} q1 = 0 where q1 > threshold and
  q1 is a maximum along t1 (D_{t1} q1 decreases across), with D q1 from per-face gradients averaged
  at the vertices.

Segments come back as (S, 2, 3) object-space points with, per segment, the two mesh edges they end
on (for chaining into polylines)."""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ..scene.mesh import Mesh, weld
from .curvature import Curvature

__all__ = [
    "Segments",
    "zero_crossings",
    "contours",
    "suggestive_contours",
    "suggestive_highlights",
    "dwkr_lines",
    "principal_highlights",
    "ridges",
    "valleys",
    "apparent_ridges",
    "boundaries",
    "parabolic_lines",
    "mean_zero_lines",
    "isophotes",
    "radial_curvature",
    "vertex_gradient",
    "chain",
]


@dataclass
class Segments:
    points: np.ndarray  # (S, 2, 3) float64
    edges: np.ndarray  # (S, 2, 2) int64: the sorted vertex pair of the mesh edge each end lies on
    strength: np.ndarray  # (S,) a per-segment strength (for fading or thresholds)

    def __len__(self) -> int:
        return len(self.points)

    @classmethod
    def empty(cls) -> Segments:
        return cls(np.zeros((0, 2, 3)), np.zeros((0, 2, 2), np.int64), np.zeros(0))


def zero_crossings(
    mesh: Mesh, values: np.ndarray, keep_face: np.ndarray | None = None, strength: np.ndarray | None = None
) -> Segments:
    """Segments where the per-vertex ``values`` (N,) change sign inside a triangle (linear
    interpolation). Triangles whose three values cross zero twice give one segment; ``keep_face``
    (F,) bool filters triangles; ``strength`` (N,) is interpolated to the segment (mean of ends)."""
    return _crossings(np.asarray(mesh.vertices), np.asarray(mesh.faces), values, keep_face, strength)


def _crossings(v, f, values, keep_face, strength) -> Segments:
    """:func:`_crossings_reference` as one numba loop over the faces (the same segments, in the same
    order): the drawing's object-space silhouettes of a 200k-face mesh went from 20 ms to 2."""
    val = np.ascontiguousarray(values, np.float64)
    keep = np.ones(len(f), np.bool_) if keep_face is None else np.ascontiguousarray(keep_face, np.bool_)
    st = np.zeros(len(val)) if strength is None else np.ascontiguousarray(strength, np.float64)
    # the mesh's own arrays (float32 vertices, int32 faces: no copy a frame); the kernel widens each value
    pts, edges, mean = _crossings_kernel(np.ascontiguousarray(v), np.ascontiguousarray(f), val, keep, st)
    return Segments(pts, edges, mean) if len(pts) else Segments.empty()


@numba.njit(cache=True)
def _crossings_kernel(v, f, val, keep, strength):
    n = 0
    for k in range(len(f)):
        if keep[k]:
            a, b, c = val[f[k, 0]] > 0, val[f[k, 1]] > 0, val[f[k, 2]] > 0
            n += int(a != b) + int(b != c) + int(c != a) == 2
    pts = np.zeros((n, 2, 3))
    edges = np.zeros((n, 2, 2), np.int64)
    mean = np.zeros(n)
    s = 0
    for k in range(len(f)):
        if not keep[k]:
            continue
        a, b, c = val[f[k, 0]] > 0, val[f[k, 1]] > 0, val[f[k, 2]] > 0
        if int(a != b) + int(b != c) + int(c != a) != 2:
            continue
        slot = 0
        total = 0.0
        for e in range(3):
            ia, ib = np.int64(f[k, e]), np.int64(f[k, (e + 1) % 3])
            va, vb = val[ia], val[ib]
            if (va > 0) == (vb > 0):
                continue
            t = va / (va - vb)
            for d in range(3):
                pa, pb = np.float64(v[ia, d]), np.float64(v[ib, d])
                pts[s, slot, d] = pa + t * (pb - pa)
            edges[s, slot, 0], edges[s, slot, 1] = min(ia, ib), max(ia, ib)
            total += strength[ia] + t * (strength[ib] - strength[ia])
            slot += 1
        mean[s] = total / 2
        s += 1
    return pts, edges, mean


def _crossings_reference(v, f, values, keep_face, strength) -> Segments:
    """The plain NumPy statement of the zero crossings (what :func:`_crossings` is tested against)."""
    val = np.asarray(values, np.float64)
    fv = val[f]  # (F, 3)
    pairs = ((0, 1), (1, 2), (2, 0))
    cross = np.stack([(fv[:, a] > 0) != (fv[:, b] > 0) for a, b in pairs], 1)  # (F, 3)
    ok = cross.sum(1) == 2
    if keep_face is not None:
        ok &= keep_face
    faces = np.nonzero(ok)[0]
    if len(faces) == 0:
        return Segments.empty()
    cf = cross[faces]
    pts = np.zeros((len(faces), 2, 3))
    edges = np.zeros((len(faces), 2, 2), np.int64)
    st = np.zeros((len(faces), 2))
    slot = np.zeros(len(faces), np.int64)
    for e, (a, b) in enumerate(pairs):
        sel = cf[:, e]
        fi = faces[sel]
        ia, ib = f[fi, a], f[fi, b]
        va, vb = val[ia], val[ib]
        t = va / (va - vb)
        k = slot[sel]
        rows = np.nonzero(sel)[0]
        pts[rows, k] = v[ia] + t[:, None] * (v[ib] - v[ia])
        edges[rows, k] = np.sort(np.stack([ia, ib], 1), axis=1)
        if strength is not None:
            st[rows, k] = strength[ia] + t * (strength[ib] - strength[ia])
        slot[sel] += 1
    return Segments(pts, edges, st.mean(1))


def vertex_gradient(mesh: Mesh, values: np.ndarray) -> np.ndarray:
    """Per-vertex gradient (N, 3) of a piecewise-linear scalar: per-face gradients averaged at the
    vertices, weighted by face area."""
    v = np.asarray(mesh.vertices, np.float64)
    f = np.asarray(mesh.faces, np.int64)
    val = np.asarray(values, np.float64)
    p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    area2 = np.linalg.norm(n, axis=1)
    good = area2 > 1e-30
    unit = n / np.where(good, area2, 1)[:, None]
    # ∇B_i = unit × (edge opposite i) / (2A)
    grad = (
        np.cross(unit, p2 - p1) * val[f[:, 0], None]
        + np.cross(unit, p0 - p2) * val[f[:, 1], None]
        + np.cross(unit, p1 - p0) * val[f[:, 2], None]
    ) / np.where(good, area2, 1)[:, None]
    grad[~good] = 0
    out = np.zeros_like(v)
    weight = np.zeros(len(v))
    for c in range(3):
        np.add.at(out, f[:, c], grad * area2[:, None])
        np.add.at(weight, f[:, c], area2)
    return out / np.maximum(weight, 1e-30)[:, None]


def _view_vectors(mesh: Mesh, eye) -> np.ndarray:
    d = np.asarray(eye, np.float64)[None] - np.asarray(mesh.vertices, np.float64)
    return d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-30)


def contours(mesh: Mesh, curvature: Curvature, eye) -> Segments:
    """Occluding contours: zeros of n·v (perspective view from ``eye``, object space)."""
    ndotv = _n_dot_v(np.asarray(mesh.vertices), np.asarray(curvature.normals), np.asarray(eye, np.float64))
    return zero_crossings(mesh, ndotv, strength=np.ones(len(ndotv)))


@numba.njit(cache=True)
def _n_dot_v(vertices, normals, eye):
    """n·v per vertex, v the unit vector to ``eye`` (what ``(normals * _view_vectors).sum(1)`` is)."""
    out = np.empty(len(vertices))
    for i in range(len(vertices)):
        d0, d1, d2 = eye[0] - vertices[i, 0], eye[1] - vertices[i, 1], eye[2] - vertices[i, 2]
        length = max(np.sqrt(d0 * d0 + d1 * d1 + d2 * d2), 1e-30)
        out[i] = (normals[i, 0] * d0 + normals[i, 1] * d1 + normals[i, 2] * d2) / length
    return out


def radial_curvature(curvature: Curvature, view: np.ndarray):
    """κ_r, D_w κ_r and n·v per vertex for unit view vectors ``view`` (N, 3) (towards the eye)."""
    n = curvature.normals.astype(np.float64)
    ndotv = (n * view).sum(1)
    u = (view * curvature.e_min).sum(1)
    v = (view * curvature.e_max).sum(1)
    w2 = u * u + v * v
    inv = np.where(w2 > 1e-12, 1 / np.maximum(w2, 1e-300), 0.0)
    uu, vv, uv = u * u * inv, v * v * inv, u * v * inv
    k1, k2 = curvature.k_min.astype(np.float64), curvature.k_max.astype(np.float64)
    kr = k1 * uu + k2 * vv
    un, vn = u * np.sqrt(inv), v * np.sqrt(inv)
    c = curvature.dcurv.astype(np.float64)
    cwww = un**3 * c[:, 0] + 3 * un * un * vn * c[:, 1] + 3 * un * vn * vn * c[:, 2] + vn**3 * c[:, 3]
    torsion = (k2 - k1) * uv
    cot = ndotv / np.sqrt(np.maximum(w2, 1e-12))
    return kr, cwww - 2 * torsion * torsion * cot, ndotv


def _radial_zeros(mesh: Mesh, curvature: Curvature, eye, threshold: float, scale: float, sign: float) -> Segments:
    """κ_r = 0 on faces facing the viewer where sign·D_w κ_r / scale² > ``threshold`` at every vertex."""
    view = _view_vectors(mesh, eye)
    kr, dwkr, ndotv = radial_curvature(curvature, view)
    f = mesh.faces
    strength = sign * dwkr / (scale * scale)
    keep = (strength[f].min(1) > threshold) & (ndotv[f].min(1) > 0.05)
    return zero_crossings(mesh, kr, keep, strength)


def suggestive_contours(mesh: Mesh, curvature: Curvature, eye, threshold: float, scale: float) -> Segments:
    """``threshold``: minimum D_w κ_r relative to scale² (scale: the mesh's curvature scale)."""
    return _radial_zeros(mesh, curvature, eye, threshold, scale, 1.0)


def suggestive_highlights(mesh: Mesh, curvature: Curvature, eye, threshold: float, scale: float) -> Segments:
    """rtsc's suggestive highlights (DeCarlo & Rusinkiewicz 2007): κ_r = 0 where D_w κ_r < 0 — n·v is
    a local maximum along w there, where suggestive contours are its minima — on the surface facing
    the viewer; ``threshold``: minimum −D_w κ_r relative to scale²."""
    return _radial_zeros(mesh, curvature, eye, threshold, scale, -1.0)


def dwkr_lines(mesh: Mesh, curvature: Curvature, eye, threshold: float, scale: float) -> Segments:
    """rtsc's "DwKr" lines: where D_w κ_r / scale² equals ``threshold`` (the suggestive contours'
    threshold) on the surface facing the viewer — the edge of the region the suggestive-contour test
    keeps; at threshold 0, where D_w κ_r changes sign."""
    view = _view_vectors(mesh, eye)
    _, dwkr, ndotv = radial_curvature(curvature, view)
    return zero_crossings(mesh, dwkr / (scale * scale) - threshold, ndotv[mesh.faces].min(1) > 0.05)


def principal_highlights(mesh: Mesh, curvature: Curvature, eye, threshold: float, scale: float) -> Segments:
    """rtsc's principal highlights (DeCarlo & Rusinkiewicz 2007; its ridge flavour): where the view
    direction seen in the tangent plane is perpendicular to the maximum principal direction
    (w·e_max = 0, so n·v is a maximum along e_max: a highlight line), on convex parts (k_max > 0 at
    the three vertices) facing the viewer, kept where (k_max² − k_min²)·(n·v) / scale² exceeds
    ``threshold``. e_max is sign-aligned per face; a face whose directions differ by more than 45°
    is skipped (rtsc's rule)."""
    view = _view_vectors(mesh, eye)
    f = np.asarray(mesh.faces, np.int64)
    k_max, k_min = curvature.k_max.astype(np.float64), curvature.k_min.astype(np.float64)
    ndotv = (curvature.normals * view).sum(1)
    along, dirs = _aligned_derivative(curvature.e_max, (view * curvature.e_max).sum(1), f)
    agree = ((dirs * dirs[:, :1]).sum(2) >= np.sqrt(0.5)).all(1)
    strength = (k_max * k_max - k_min * k_min) * ndotv / (scale * scale)
    keep = agree & (k_max[f].min(1) > 0) & (ndotv[f].min(1) > 0.05) & (strength[f].mean(1) > threshold)
    return _face_corner_crossings(mesh, along, keep, strength[f].mean(1))


def _aligned_derivative(directions: np.ndarray, derivative: np.ndarray, faces: np.ndarray):
    """Per-face copies of a derivative along a sign-ambiguous direction, flipped so that the three
    vertices' directions agree with the first's."""
    d = directions[faces]  # (F, 3, 3)
    sign = np.where((d * d[:, :1]).sum(2) >= 0, 1.0, -1.0)  # (F, 3)
    return derivative[faces] * sign, d * sign[..., None]


def _extremum_lines(
    mesh: Mesh,
    direction: np.ndarray,
    derivative: np.ndarray,
    keep_vertex: np.ndarray,
    maximum: bool,
    strength: np.ndarray,
) -> Segments:
    """Zeros of a directional derivative (with per-face sign alignment) where ``value`` is an
    extremum: the derivative decreases along the direction (maximum) or increases (minimum)."""
    f = np.asarray(mesh.faces, np.int64)
    fd, dirs = _aligned_derivative(direction, derivative, f)
    v = np.asarray(mesh.vertices, np.float64)[f]
    # gradient of the aligned derivative inside each face, dotted with the mean direction
    p0, p1, p2 = v[:, 0], v[:, 1], v[:, 2]
    n = np.cross(p1 - p0, p2 - p0)
    a2 = np.maximum(np.linalg.norm(n, axis=1), 1e-30)
    unit = n / a2[:, None]
    grad = (
        np.cross(unit, p2 - p1) * fd[:, :1] + np.cross(unit, p0 - p2) * fd[:, 1:2] + np.cross(unit, p1 - p0) * fd[:, 2:]
    ) / a2[:, None]
    along = (grad * dirs.mean(1)).sum(1)
    keep = keep_vertex[f].all(1) & ((along < 0) if maximum else (along > 0))
    return _face_corner_crossings(mesh, fd, keep, strength[f].mean(1))


def _face_corner_crossings(mesh: Mesh, values: np.ndarray, keep: np.ndarray, strength: np.ndarray) -> Segments:
    """Zero crossings of per-face-corner ``values`` (F, 3) (a sign-aligned quantity differs from face
    to face) on the faces ``keep``, ``strength`` per face; segment ends keyed by the mesh's edges."""
    f = np.asarray(mesh.faces, np.int64)
    v = np.asarray(mesh.vertices, np.float64)[f]
    segs = _crossings(
        v.reshape(-1, 3), np.arange(len(f) * 3).reshape(-1, 3), values.reshape(-1), keep, np.repeat(strength, 3)
    )
    if len(segs):
        segs.edges = np.sort(f.reshape(-1)[segs.edges], axis=2)  # corner ids back to vertex ids
    return segs


def ridges(mesh: Mesh, curvature: Curvature, threshold: float, scale: float) -> Segments:
    """Ridge lines: k_max maximal along e_max, k_max > threshold·scale."""
    k = curvature.k_max.astype(np.float64)
    return _extremum_lines(
        mesh, curvature.e_max, curvature.dcurv[:, 3].astype(np.float64), k > threshold * scale, True, k / scale
    )


def valleys(mesh: Mesh, curvature: Curvature, threshold: float, scale: float) -> Segments:
    """Valley lines: k_min minimal along e_min, k_min < −threshold·scale."""
    k = curvature.k_min.astype(np.float64)
    return _extremum_lines(
        mesh, curvature.e_min, curvature.dcurv[:, 0].astype(np.float64), k < -threshold * scale, False, -k / scale
    )


def apparent_ridges(mesh: Mesh, q1: np.ndarray, w1: np.ndarray, threshold: float, scale: float) -> Segments:
    """Judd's object-space apparent ridges from per-vertex q1 and its object-space direction w1 (see
    view_curvature.view_dependent_curvature): zeros of D_{w1} q1 where q1 > threshold·scale and q1 is
    a maximum along w1."""
    grad = vertex_gradient(mesh, q1)
    dq = (grad * w1).sum(1)
    return _extremum_lines(mesh, w1, dq, q1 > threshold * scale, True, q1 / scale)


def parabolic_lines(mesh: Mesh, curvature: Curvature) -> Segments:
    """rtsc's "K = 0" curves: zeros of the Gaussian curvature K = k_min·k_max, where the surface turns
    from dome to saddle (a torus: its top and bottom circles). View-independent."""
    return zero_crossings(mesh, curvature.k_min.astype(np.float64) * curvature.k_max)


def mean_zero_lines(mesh: Mesh, curvature: Curvature) -> Segments:
    """rtsc's "H = 0" curves: zeros of the mean curvature H = (k_min + k_max)/2, where the saddle is
    balanced (a fat torus, R < 2r: one circle on each side of its hole). View-independent."""
    return zero_crossings(mesh, curvature.k_min.astype(np.float64) + curvature.k_max)


def isophotes(mesh: Mesh, normals: np.ndarray, light: np.ndarray, level: float) -> Segments:
    """rtsc's isophotes: where the diffuse shading n·l of a directional light ``light`` (unit, towards
    the light; a headlight is the direction towards the camera) equals ``level``."""
    light = np.asarray(light, np.float64)
    return zero_crossings(mesh, np.asarray(normals, np.float64) @ (light / np.linalg.norm(light)) - level)


def boundaries(mesh: Mesh) -> Segments:
    """Mesh boundaries (one of rtsc's line types): the edges only one face uses, once vertices at
    the same position are taken as one (a shape stored as separate faces, for its uvs or flat
    normals, has no boundary where those faces meet). View-independent. Each end of a segment is a
    vertex, keyed as the pair (v, v) so that :func:`chain` joins consecutive edges."""
    position, welded = weld(np.asarray(mesh.vertices, np.float64))
    f = welded[np.asarray(mesh.faces, np.int64)]
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]  # faces degenerate once welded
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    single = unique[counts == 1]
    if not len(single):
        return Segments.empty()
    ends = np.stack([single, single], axis=2)  # (S, 2 ends, 2): the vertex as a degenerate edge
    return Segments(position[single], ends, np.ones(len(single)))


def chain(segments: Segments) -> list[np.ndarray]:
    """Join segments that share a mesh-edge end into polylines; returns a list of (K, 3) arrays."""
    if len(segments) == 0:
        return []
    keys = segments.edges.reshape(-1, 2)
    _, ids = np.unique(keys, axis=0, return_inverse=True)
    ids = ids.reshape(-1, 2)
    ends: dict[int, list[int]] = {}
    for s, (a, b) in enumerate(ids):
        ends.setdefault(int(a), []).append(s)
        ends.setdefault(int(b), []).append(s)
    used = np.zeros(len(ids), bool)
    lines = []
    for start in range(len(ids)):
        if used[start]:
            continue
        used[start] = True
        seq = [int(ids[start, 0]), int(ids[start, 1])]
        pts = [segments.points[start, 0], segments.points[start, 1]]
        for forward in (True, False):
            while True:
                node = seq[-1] if forward else seq[0]
                nxt = next((s for s in ends.get(node, []) if not used[s]), None)
                if nxt is None:
                    break
                used[nxt] = True
                a, b = int(ids[nxt, 0]), int(ids[nxt, 1])
                other, p = (b, segments.points[nxt, 1]) if a == node else (a, segments.points[nxt, 0])
                if forward:
                    seq.append(other)
                    pts.append(p)
                else:
                    seq.insert(0, other)
                    pts.insert(0, p)
        lines.append(np.asarray(pts))
    return lines
