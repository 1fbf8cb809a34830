"""Form factors between elements.

The links use the receiver-averaged form factor: the exact form factor from a point to a polygon
(Lambert's contour integral, :func:`point_polygon`) averaged over sample points of the receiver
(:mod:`illusio.radiosity.visibility`). It stays exact for neighbours meeting at an edge, where any
centre-to-centre estimate fails (in a closed cube the point-to-disk estimate below gives row sums
from 0.84 to 1.3; the contour integral keeps them within a few per cent of 1).

Point to polygon (unoccluded), with R_e the vectors from the point x to the corners of the polygon
clipped to x's tangent plane and γ_e the angle between R_e and R_{e+1}; 0 when x is behind the
polygon's plane (a surface emits and reflects to its front only):

    F_x→j = (1/2π) |Σ_e γ_e · n_x · (R_e × R_{e+1}) / |R_e × R_{e+1}||

The cheap estimate, used to bound the transfer of a pair that straddles a plane:

F_ij, the fraction of what leaves element j that arrives at element i per unit area of i (the kernel
the receiver gathers with, H_i = Σ_j F_ij V_ij B_j), is taken at i's centre x_i with j seen as a disk
of area A_j facing along n_j at distance r:

    F_ij ≈ A_j · cos θ_i · cos θ_j / (π r² + A_j)

(the exact factor of a point to a coaxial disk, used off axis; bounded by 1 as r → 0). It is
consistent under refinement: splitting j into four sums to the same value up to O(A_j/r²), and
splitting i leaves each child the value at its own centre.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["point_to_disk", "point_polygon", "facing", "facing_pairs"]


#: atan(u)/u as a polynomial in u² for |u| ≤ tan(π/8): a least-squares Chebyshev fit of degree 9 on
#: 40,001 even steps of u², in powers of u²; u times it is within 1.5e-15 of atan (tested)
ATAN_SERIES = (
    0.9999999999999974,
    -0.3333333333321205,
    0.19999999978284935,
    -0.14285712667782785,
    0.11111049058368044,
    -0.09089531669899585,
    0.07673527678757021,
    -0.06505787877512925,
    0.050237144422531035,
    -0.025297825244395857,
)
_A0, _A1, _A2, _A3, _A4, _A5, _A6, _A7, _A8, _A9 = ATAN_SERIES
_TAN_PI_8 = 0.41421356237309503


@numba.njit(cache=True, inline="always")
def angle(y, x):
    """atan2(y, x) for y ≥ 0, in [0, π], within 3e-15 of libm's. Why not np.arctan2: libm's is a call
    the compiler cannot inline (17 ns here), and a contour integral's four would be two thirds of its
    time; this one is inlined (~7 ns) and the four edges' overlap. Reduced to u in [-tan(π/8), tan(π/8)]
    (by atan(t) = π/2 - atan(1/t) and atan(t) = π/4 + atan((t - 1)/(t + 1)), one division), then the
    polynomial, evaluated by Estrin's scheme (a short dependency chain)."""
    ax = abs(x)
    swap = y > ax
    low, high = (ax, y) if swap else (y, ax)
    if high == 0.0:
        return 0.0
    # one division either way: (low/high - 1)/(low/high + 1) = (low - high)/(low + high)
    if low > _TAN_PI_8 * high:
        t = (low - high) / (low + high)
        base = np.pi / 4
    else:
        t = low / high
        base = 0.0
    z = t * t
    z2 = z * z
    z4 = z2 * z2
    series = (
        (_A0 + _A1 * z)
        + z2 * (_A2 + _A3 * z)
        + z4 * ((_A4 + _A5 * z) + z2 * (_A6 + _A7 * z))
        + z4 * z4 * (_A8 + _A9 * z)
    )
    a = base + t * series
    if swap:
        a = np.pi / 2 - a
    return np.pi - a if x < 0.0 else a


@numba.njit(cache=True, inline="always")
def _edge_sum(x0, x1, x2, n0, n1, n2, corners, m):
    """Σ_e γ_e · n_x · (R_e × R_{e+1}) / |R_e × R_{e+1}| over the first ``m`` rows of ``corners``."""
    total = 0.0
    for e in range(m):
        f = (e + 1) % m
        a0, a1, a2 = corners[e, 0] - x0, corners[e, 1] - x1, corners[e, 2] - x2
        b0, b1, b2 = corners[f, 0] - x0, corners[f, 1] - x1, corners[f, 2] - x2
        c0, c1, c2 = a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0
        cn = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
        if cn < 1e-300:
            continue
        dot = a0 * b0 + a1 * b1 + a2 * b2
        gamma = angle(cn, dot)
        total += gamma * (n0 * c0 + n1 * c1 + n2 * c2) / cn
    return total


@numba.njit(cache=True, inline="always")
def contour_integral(x0, x1, x2, n0, n1, n2, corners, m):
    """F from the point (x0, x1, x2) with normal (n0, n1, n2) to the polygon of the first ``m`` rows
    of ``corners`` (4, 3): the formula of the module docstring, for numba kernels. One-sided (0 when
    x lies behind the polygon's plane, its normal by the corners' right-hand winding) and clipped to
    x's tangent plane first (the part behind it would count negatively)."""
    s0, s1, s2 = corners[1, 0] - corners[0, 0], corners[1, 1] - corners[0, 1], corners[1, 2] - corners[0, 2]
    t0, t1, t2 = corners[m - 1, 0] - corners[0, 0], corners[m - 1, 1] - corners[0, 1], corners[m - 1, 2] - corners[0, 2]
    side = (
        (s1 * t2 - s2 * t1) * (x0 - corners[0, 0])
        + (s2 * t0 - s0 * t2) * (x1 - corners[0, 1])
        + (s0 * t1 - s1 * t0) * (x2 - corners[0, 2])
    )
    if side <= 0.0:
        return 0.0
    behind = 0
    for e in range(m):
        if (corners[e, 0] - x0) * n0 + (corners[e, 1] - x1) * n1 + (corners[e, 2] - x2) * n2 < 0.0:
            behind += 1
    if behind == m:
        return 0.0
    if behind == 0:
        total = _edge_sum(x0, x1, x2, n0, n1, n2, corners, m)
    else:  # Sutherland–Hodgman against the tangent plane: at most m + 1 corners
        clipped = np.empty((5, 3))
        k = 0
        for e in range(m):
            f = (e + 1) % m
            ha = (corners[e, 0] - x0) * n0 + (corners[e, 1] - x1) * n1 + (corners[e, 2] - x2) * n2
            hb = (corners[f, 0] - x0) * n0 + (corners[f, 1] - x1) * n1 + (corners[f, 2] - x2) * n2
            if ha >= 0.0:
                for c in range(3):
                    clipped[k, c] = corners[e, c]
                k += 1
            if (ha >= 0.0) != (hb >= 0.0):
                t = ha / (ha - hb)
                for c in range(3):
                    clipped[k, c] = corners[e, c] + t * (corners[f, c] - corners[e, c])
                k += 1
        if k < 3:
            return 0.0
        total = _edge_sum(x0, x1, x2, n0, n1, n2, clipped, k)
    return min(abs(total) / (2 * np.pi), 1.0)


@numba.njit(parallel=True, cache=True, fastmath=False)
def _point_polygon(points, normals, corners, triangle, out):
    n, k = points.shape[0], points.shape[1]
    for p in numba.prange(n):
        m = 3 if triangle[p] else 4
        for s in range(k):
            out[p, s] = contour_integral(
                points[p, s, 0],
                points[p, s, 1],
                points[p, s, 2],
                normals[p, 0],
                normals[p, 1],
                normals[p, 2],
                corners[p],
                m,
            )


def point_polygon(
    points: np.ndarray, normals: np.ndarray, corners: np.ndarray, triangle: np.ndarray, average: bool = True
) -> np.ndarray:
    """The form factor from each of ``points`` (n, k, 3), oriented by ``normals`` (n, 3), to the
    polygon ``corners`` (n, 4, 3) (``triangle``: corner 3 unused): (n,) averaged over the k points,
    or (n, k) with ``average=False``."""
    out = np.empty(points.shape[:2])
    if len(points):
        _point_polygon(
            np.ascontiguousarray(points, np.float64),
            np.ascontiguousarray(normals, np.float64),
            np.ascontiguousarray(corners, np.float64),
            np.ascontiguousarray(triangle, np.bool_),
            out,
        )
    return out.mean(axis=1) if average else out


def point_to_disk(receiver_centre, receiver_normal, source_centre, source_normal, source_area) -> np.ndarray:
    """F_ij for arrays of pairs: centres and unit normals (n, 3), source areas (n,). Zero when either
    element faces away from the other at the centres."""
    d = source_centre - receiver_centre
    r2 = np.maximum((d * d).sum(axis=1), 1e-300)
    r = np.sqrt(r2)
    cos_i = np.clip((receiver_normal * d).sum(axis=1) / r, 0, None)
    cos_j = np.clip(-(source_normal * d).sum(axis=1) / r, 0, None)
    return source_area * cos_i * cos_j / (np.pi * r2 + source_area)


def facing(
    receiver_corners,
    receiver_normal,
    receiver_centre,
    source_corners,
    source_normal,
    source_centre,
    tolerance: float = 1e-6,
) -> tuple[np.ndarray, np.ndarray]:
    """(some, every) per pair: does some corner of the source lie in front of the receiver's plane and
    some corner of the receiver in front of the source's — and is no corner of either behind the
    other's plane (``tolerance`` metres)? A pair without ``some`` exchanges no light; one with
    ``some`` but not ``every`` straddles a plane, where the centre-to-centre estimate is unreliable."""
    height_j = ((source_corners - receiver_centre[:, None]) * receiver_normal[:, None]).sum(axis=2)
    height_i = ((receiver_corners - source_centre[:, None]) * source_normal[:, None]).sum(axis=2)
    some = (height_j > tolerance).any(axis=1) & (height_i > tolerance).any(axis=1)
    every = (height_j > -tolerance).all(axis=1) & (height_i > -tolerance).all(axis=1)
    return some, every


def facing_pairs(corners, normal, centre, receivers, sources, tolerance: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    """:func:`facing` for the pairs (receivers[p], sources[p]) of the element arrays ``corners`` (n, 4,
    3), ``normal`` and ``centre`` (n, 3), in one numba pass (refinement's first test of every round:
    gathering the pairs' corners for NumPy cost more than the test)."""
    n = len(receivers)
    some, every = np.empty(n, np.bool_), np.empty(n, np.bool_)
    if n:
        _facing_pairs(
            np.ascontiguousarray(corners, np.float64),
            np.ascontiguousarray(normal, np.float64),
            np.ascontiguousarray(centre, np.float64),
            np.asarray(receivers, np.int64),
            np.asarray(sources, np.int64),
            float(tolerance),
            some,
            every,
        )
    return some, every


@numba.njit(cache=True)
def _heights(corners, e, centre, normal, f, tolerance):
    """(some corner of e above f's plane, no corner of e below it), within ``tolerance``."""
    above, behind = False, False
    for c in range(4):
        height = (
            (corners[e, c, 0] - centre[f, 0]) * normal[f, 0]
            + (corners[e, c, 1] - centre[f, 1]) * normal[f, 1]
            + (corners[e, c, 2] - centre[f, 2]) * normal[f, 2]
        )
        above |= height > tolerance
        behind |= height <= -tolerance
    return above, not behind


@numba.njit(cache=True)
def _facing_pairs(corners, normal, centre, receivers, sources, tolerance, some, every):
    for p in range(len(receivers)):
        i, j = receivers[p], sources[p]
        j_above, j_in_front = _heights(corners, j, centre, normal, i, tolerance)
        i_above, i_in_front = _heights(corners, i, centre, normal, j, tolerance)
        some[p] = j_above and i_above
        every[p] = j_in_front and i_in_front
