"""Input polygons cut where other polygons meet them (the first lines of a discontinuity mesh).

A model's floor and ceiling often run on under its walls (RenderPark's Graz office models 30 cm
walls as faces and lets the room's shell span the outer wall's faces: 21 % of the ceiling lies
inside the walls). The part under a wall gets no light, and the links' exposure probe, cast along
the normal, does not find it (under the ceiling inside a wall is the floor, metres away). An element
that straddles the wall's line averages its lit and unlit parts, so the strip anyone sees reads dark
and sends too little. Cut along the line where the wall meets it, the shell's part under the wall
is its own root: it stays dark, and no visible element averages it in.

``cut_at_contacts`` finds, for each quad large enough to be split by the refinement anyway, the
segments where other polygons touch or cross its plane inside it (a wall standing on the floor: its
bottom edge; a wall through the ceiling: the line they share), and cuts the quad along each such
line that runs across it — the segment covers at least half of the quad's chord along the line (a
wall, not a table's foot: what stands on a floor hides the floor under it from the exposure probe
already) — and crosses two of its opposite edges (the pieces stay quads; a line across two
adjacent edges would leave a pentagon and is not cut). A cut that would leave a piece smaller than
the minimum element area is not made.
"""

from __future__ import annotations

import numba
import numpy as np

from .polygons import Polygons, polygon_areas

__all__ = ["cut_at_contacts", "contact_segments"]

#: a corner within this share of the scene's extent of a plane lies in it
PLANE_TOLERANCE = 1e-6
#: only quads of at least this many minimum element areas are cut (smaller ones are split little)
CUT_AREA = 4.0
#: a line cuts a piece where what meets it covers at least this share of the piece's chord along it
CHORD_SHARE = 0.5


@numba.njit(cache=True)
def _clip(quad, normal, a, b, tol):
    """(t0, t1): the part of the segment a → b inside the convex quad (4, 3) of unit ``normal``, as
    parameters along it (Cyrus–Beck against the edges' inward half-planes; t0 ≥ t1 when none is). A
    segment on an edge's line is outside."""
    t0, t1 = 0.0, 1.0
    for e in range(4):
        c0 = quad[e]
        edge = quad[(e + 1) % 4] - c0
        inward = np.array(
            [
                normal[1] * edge[2] - normal[2] * edge[1],
                normal[2] * edge[0] - normal[0] * edge[2],
                normal[0] * edge[1] - normal[1] * edge[0],
            ]
        )
        inward /= max(np.sqrt((inward**2).sum()), 1e-300)
        fa = (inward * (a - c0)).sum()
        fb = (inward * (b - c0)).sum()
        if fa < tol and fb < tol:
            return 1.0, 0.0
        if fa < 0 or fb < 0:
            t = fa / (fa - fb)
            if fa < 0:
                t0 = max(t0, t)
            else:
                t1 = min(t1, t)
    return t0, t1


@numba.njit(cache=True)
def _contact_segments(corners, triangle, normal, candidates, lo, hi, tol):
    """Per candidate quad p: the segments (p, a, b) where another polygon meets p's plane, clipped
    to p (:func:`_clip`), longer than ``tol``."""
    out_p = []
    out_a = []
    out_b = []
    n = corners.shape[0]
    for p in candidates:
        np_ = normal[p]
        d = np_[0] * corners[p, 0, 0] + np_[1] * corners[p, 0, 1] + np_[2] * corners[p, 0, 2]
        for q in range(n):
            if q == p:
                continue
            if (
                lo[q, 0] > hi[p, 0] + tol
                or lo[q, 1] > hi[p, 1] + tol
                or lo[q, 2] > hi[p, 2] + tol
                or hi[q, 0] < lo[p, 0] - tol
                or hi[q, 1] < lo[p, 1] - tol
                or hi[q, 2] < lo[p, 2] - tol
            ):
                continue
            m = 3 if triangle[q] else 4
            s = np.empty(4)
            smin, smax, amax = 1e300, -1e300, 0.0
            for i in range(m):
                s[i] = np_[0] * corners[q, i, 0] + np_[1] * corners[q, i, 1] + np_[2] * corners[q, i, 2] - d
                smin = min(smin, s[i])
                smax = max(smax, s[i])
                amax = max(amax, abs(s[i]))
            if amax <= tol or smin > tol or smax < -tol:
                continue  # coplanar with p, or wholly on one side of its plane
            # where q meets the plane: its corners in it and its edges across it
            pts = np.empty((8, 3))
            k = 0
            for i in range(m):
                j = (i + 1) % m
                if abs(s[i]) <= tol:
                    pts[k] = corners[q, i]
                    k += 1
                elif abs(s[j]) > tol and s[i] * s[j] < 0:
                    t = s[i] / (s[i] - s[j])
                    pts[k] = corners[q, i] + t * (corners[q, j] - corners[q, i])
                    k += 1
            if k < 2:
                continue
            best, ia, ib = 0.0, 0, 0
            for i in range(k):
                for j in range(i + 1, k):
                    dd = ((pts[i] - pts[j]) ** 2).sum()
                    if dd > best:
                        best, ia, ib = dd, i, j
            if best <= tol * tol:
                continue
            a, b = pts[ia].copy(), pts[ib].copy()
            t0, t1 = _clip(corners[p], np_, a, b, tol)
            if (t1 - t0) * np.sqrt(best) <= tol:
                continue
            out_p.append(p)
            out_a.append(a + t0 * (b - a))
            out_b.append(a + t1 * (b - a))
    m_ = len(out_p)
    ps = np.empty(m_, np.int64)
    sa = np.empty((m_, 3))
    sb = np.empty((m_, 3))
    for i in range(m_):
        ps[i] = out_p[i]
        sa[i] = out_a[i]
        sb[i] = out_b[i]
    return ps, sa, sb


def _tolerance(polygons: Polygons) -> float:
    """PLANE_TOLERANCE × the scene's extent (m)."""
    extent = float(np.ptp(polygons.corners.reshape(-1, 3), axis=0).max()) if len(polygons) else 1.0
    return PLANE_TOLERANCE * max(extent, 1e-9)


def contact_segments(polygons: Polygons, min_area: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(polygon (m,), a (m, 3), b (m, 3)): each segment, inside a quad of at least CUT_AREA × ``min_area``
    m², where another polygon touches or crosses the quad's plane (not one in the same plane)."""
    c = polygons.corners
    areas = polygon_areas(c, polygons.triangle)
    candidates = np.flatnonzero(~polygons.triangle & (areas >= CUT_AREA * min_area))
    if not len(candidates):
        return np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3))
    return _contact_segments(  # a triangle's corner 3 repeats its corner 2: the boxes need no case
        np.ascontiguousarray(c),
        polygons.triangle,
        np.ascontiguousarray(polygons.normals()),
        candidates.astype(np.int64),
        c.min(axis=1),
        c.max(axis=1),
        _tolerance(polygons),
    )


def _cut(quad: np.ndarray, uv: np.ndarray, normal: np.ndarray, a: np.ndarray, b: np.ndarray, tol: float):
    """The quad (4, 3) and its uvs (4, 2) in two along the line a → b where the line crosses two of
    its opposite edges strictly inside them, else None."""
    side = np.cross(normal, b - a)
    side /= np.linalg.norm(side)
    s = (quad - a) @ side
    if np.any(np.abs(s) <= tol):
        return None
    for first in (0, 1):
        i0, i1, i2, i3 = first, first + 1, first + 2, (first + 3) % 4
        if s[i0] * s[i1] < 0 and s[i2] * s[i3] < 0 and s[i0] * s[i3] > 0:
            t01, t23 = s[i0] / (s[i0] - s[i1]), s[i2] / (s[i2] - s[i3])
            p01, p23 = quad[i0] + t01 * (quad[i1] - quad[i0]), quad[i2] + t23 * (quad[i3] - quad[i2])
            u01, u23 = uv[i0] + t01 * (uv[i1] - uv[i0]), uv[i2] + t23 * (uv[i3] - uv[i2])
            return (
                (np.array([quad[i0], p01, p23, quad[i3]]), np.array([uv[i0], u01, u23, uv[i3]])),
                (np.array([p01, quad[i1], quad[i2], p23]), np.array([u01, uv[i1], uv[i2], u23])),
            )
    return None


def _crosses(quad: np.ndarray, normal: np.ndarray, a: np.ndarray, b: np.ndarray, tol: float) -> bool:
    """Does the segment a → b run inside the convex quad over at least CHORD_SHARE of the quad's
    chord along its line (a wall across a floor, not a table's foot on it)?"""
    quad = np.ascontiguousarray(quad, np.float64)
    length = float(np.linalg.norm(b - a))
    t0, t1 = _clip(quad, normal, a, b, tol)
    inside = (t1 - t0) * length
    if inside <= tol:
        return False
    reach = float(np.ptp(quad, axis=0).max()) / max(length, 1e-300)  # the line, past the quad both ways
    u0, u1 = _clip(quad, normal, a - reach * (b - a), b + reach * (b - a), tol)
    return inside >= CHORD_SHARE * (u1 - u0) * (1 + 2 * reach) * length


def cut_at_contacts(polygons: Polygons, min_area: float) -> Polygons:
    """``polygons`` with every quad of at least CUT_AREA × ``min_area`` m² cut along the lines where
    other polygons meet it (see the module docstring), each piece in the quad's plane, group and
    material; uncut polygons first, in their order, the pieces after them. No piece is smaller than
    ``min_area``. The same polygons when nothing is cut."""
    owner, seg_a, seg_b = contact_segments(polygons, min_area)
    if not len(owner):
        return polygons
    tol = _tolerance(polygons)
    normals = polygons.normals()
    uv_all = polygons.corner_uv()
    cut_quads, cut_uv, cut_from = [], [], []
    order = np.argsort(owner, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(owner[order]) != 0])
    for start, end in zip(starts, np.r_[starts[1:], len(order)]):
        rows = order[start:end]
        p = int(owner[rows[0]])
        pieces = [(polygons.corners[p], uv_all[p])]
        for a, b in zip(seg_a[rows], seg_b[rows]):
            next_pieces = []
            for quad, uv in pieces:
                halves = _cut(quad, uv, normals[p], a, b, tol) if _crosses(quad, normals[p], a, b, tol) else None
                if (
                    halves is not None
                    and polygon_areas(np.stack([h[0] for h in halves]), np.zeros(2, bool)).min() >= min_area
                ):
                    next_pieces.extend(halves)
                else:
                    next_pieces.append((quad, uv))
            pieces = next_pieces
        if len(pieces) > 1:
            cut_quads += [q for q, _ in pieces]
            cut_uv += [u for _, u in pieces]
            cut_from += [p] * len(pieces)
    if not cut_from:
        return polygons
    cut_from = np.asarray(cut_from, np.int64)
    kept = np.setdiff1d(np.arange(len(polygons)), cut_from)
    index = np.r_[kept, cut_from]
    return Polygons(
        np.concatenate([polygons.corners[kept], np.stack(cut_quads)]),
        polygons.triangle[index],
        polygons.reflectance[index],
        polygons.exitance[index],
        polygons.group[index],
        list(polygons.names),
        list(polygons.lamps),
        np.concatenate([uv_all[kept], np.stack(cut_uv)]) if polygons.uv is not None else None,
        dict(polygons.textures),
        polygons.side[index] if polygons.side is not None else None,
    ).with_texture_reflectance()
