"""The line-drawing passes stated plainly in NumPy: the specification the GPU passes are tested
against, one function per pass and named after it (``view_curvature`` for ViewCurvaturePass,
``ridge_filter`` for RidgeFilterPass, ``compose`` for ComposePass).

View-dependent curvature Q (Judd et al. 2007), for a surface point seen along the unit view
direction v (towards the eye), in the principal frame (e1 = e_min, e2 = e_max), with u, v the
components of the view direction along e1, e2 normalised by u² + v² = sin²θ and s = sec θ − 1
(θ: angle between normal and view direction):
    Q = [[k1 (1 + s u²), k1 s uv], [k2 s uv, k2 (1 + s v²)]]
q1 = largest singular value of Q; its right singular vector s1 gives the tangent w1 = s1₁ e1 + s1₂ e2,
and t1 = w1 projected on the screen (sign fixed so that it points away from the viewer's side).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene.camera import View

__all__ = [
    "ViewCurvature",
    "view_curvature",
    "ridge_filter",
    "image_silhouettes",
    "compose",
    "segments",
    "REPORT_THRESHOLD",
]


@dataclass
class ViewCurvature:
    """Per-vertex results: q (N,) scaled and clamped as the shader stores it, q1 (N,) raw singular
    value (1/units), t1 (N, 2) unit screen direction in camera x (right), y (up) or 0, w1 (N, 3) the
    object-space tangent of maximum view-dependent curvature (unit, sign arbitrary), ndotv (N,)."""

    q: np.ndarray
    q1: np.ndarray
    t1: np.ndarray
    w1: np.ndarray
    ndotv: np.ndarray


def view_curvature(
    positions,
    normals,
    e_min,
    e_max,
    k_min,
    k_max,
    view: View,
    tau: float = 0.0,
    curvature_scale: float = 1.0,
    model_matrix=None,
) -> ViewCurvature:
    """The vertex shader's maths in NumPy (float64). Arrays are per vertex, object space."""
    model = np.eye(4) if model_matrix is None else np.asarray(model_matrix, np.float64)
    mv = view.view_matrix().astype(np.float64) @ model
    rot = mv[:3, :3]
    eye = np.c_[np.asarray(positions, np.float64), np.ones(len(positions))] @ mv.T
    n = np.asarray(normals, np.float64) @ np.linalg.inv(rot)  # (R⁻¹)ᵀ n, as rows
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    e1 = np.asarray(e_min, np.float64) @ rot.T
    e2 = np.asarray(e_max, np.float64) @ rot.T
    k1 = np.asarray(k_min, np.float64)
    k2 = np.asarray(k_max, np.float64)
    view_dir = -eye[:, :3]
    view_dir /= np.maximum(np.linalg.norm(view_dir, axis=1, keepdims=True), 1e-30)
    ndotv = (view_dir * n).sum(1)
    u = (view_dir * e1).sum(1)
    v = (view_dir * e2).sum(1)
    w2 = u * u + v * v
    csc2 = np.where(w2 > 1e-12, 1.0 / np.maximum(w2, 1e-300), 0.0)
    u2, v2, uv = u * u * csc2, v * v * csc2, u * v * csc2
    s = 1.0 / np.maximum(np.abs(ndotv), 1e-4) - 1.0
    q11 = k1 * (1 + s * u2)
    q12 = k1 * s * uv
    q21 = k2 * s * uv
    q22 = k2 * (1 + s * v2)
    a11 = q11 * q11 + q21 * q21
    a12 = q11 * q12 + q21 * q22
    a22 = q12 * q12 + q22 * q22
    lam = 0.5 * (a11 + a22) + np.sqrt(a12 * a12 + (0.5 * (a22 - a11)) ** 2)
    ra = np.stack([a22 - lam, -a12], 1)
    rb = np.stack([-a12, a11 - lam], 1)
    s1 = np.where(((ra * ra).sum(1) >= (rb * rb).sum(1))[:, None], ra, rb)
    length = np.linalg.norm(s1, axis=1)
    fallback = np.where((a11 >= a22)[:, None], [1.0, 0.0], [0.0, 1.0])
    s1 = np.where((length * length > 1e-30)[:, None], s1 / np.maximum(length, 1e-300)[:, None], fallback)
    w1_eye = s1[:, :1] * e1 + s1[:, 1:] * e2
    t1 = np.where((w1_eye[:, 2] >= 0)[:, None], -w1_eye[:, :2], w1_eye[:, :2])
    tl = np.linalg.norm(t1, axis=1)
    t1 = np.where((tl * tl > 1e-16)[:, None], t1 / np.maximum(tl, 1e-300)[:, None], 0.0)
    q1 = np.sqrt(lam)
    q = np.clip(2.0**tau * q1 / curvature_scale, 0.0, 1.0)
    w1 = s1[:, :1] * np.asarray(e_min, np.float64) + s1[:, 1:] * np.asarray(e_max, np.float64)
    return ViewCurvature(q, q1, t1, w1, ndotv)


REPORT_THRESHOLD = 0.2  # annex B: a pixel is an edge where the response exceeds 0.2
_COS_PI_8 = 0.92387953251080
_A = 0.70710678118655


def ridge_filter(q_t1: np.ndarray, lam: float, threshold: float = REPORT_THRESHOLD) -> tuple[np.ndarray, np.ndarray]:
    """q_t1: (H, W, ≥3) float, row 0 at the top, channels q, t1.x (right), t1.y (up).
    lam: λ. Returns (response (H, W), ridge mask (H, W) bool).

    For each pixel with t1 ≠ 0, t1 is quantised to 0°, 45°, 90° or 135° (the first whose |cos| with
    t1 exceeds cos 22.5°); the neighbours along that direction weigh 1 + 2λ, the two across it 1,
    the other four 1 + λ, and response = (8 + 8λ)·q − Σ weight·q_neighbour (edges clamped)."""
    q = np.asarray(q_t1[..., 0], np.float64)
    tx = np.asarray(q_t1[..., 1], np.float64)
    ty = np.asarray(q_t1[..., 2], np.float64)
    h, w = q.shape
    padded = np.pad(q, 1, mode="edge")

    def at(dx, dy):  # neighbour dx right, dy up (up = one row towards row 0)
        return padded[1 - dy : 1 - dy + h, 1 + dx : 1 + dx + w]

    length = np.hypot(tx, ty)
    has = length * length > 1e-12
    ux = np.where(has, tx / np.where(has, length, 1), 0)
    uy = np.where(has, ty / np.where(has, length, 1), 0)
    l1, l2 = 1 + lam, 1 + 2 * lam
    case_h = np.abs(ux) > _COS_PI_8
    case_d = ~case_h & (np.abs(_A * ux + _A * uy) > _COS_PI_8)
    case_v = ~case_h & ~case_d & (np.abs(uy) > _COS_PI_8)
    case_a = ~case_h & ~case_d & ~case_v
    w_h = np.select([case_h, case_v], [l2, 1.0], l1)
    w_v = np.select([case_v, case_h], [l2, 1.0], l1)
    w_d = np.select([case_d, case_a], [l2, 1.0], l1)
    w_a = np.select([case_a, case_d], [l2, 1.0], l1)
    total = (
        w_h * (at(1, 0) + at(-1, 0))
        + w_v * (at(0, 1) + at(0, -1))
        + w_d * (at(1, 1) + at(-1, -1))
        + w_a * (at(-1, 1) + at(1, -1))
    )
    response = np.where(has, (8 + 8 * lam) * q - total, 0.0)
    return response, response > threshold


def image_silhouettes(depth: np.ndarray, depth_jump: float = 0.05) -> np.ndarray:
    """NumPy reference of compose.glsl's silhouettes: depth (H, W), 0 = background; a covered pixel
    is on a silhouette where a 4-neighbour is background or farther by more than depth_jump × depth."""
    d = np.asarray(depth, np.float64)
    padded = np.pad(d, 1, mode="edge")
    h, w = d.shape
    out = np.zeros_like(d, bool)
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        e = padded[1 + dy : 1 + dy + h, 1 + dx : 1 + dx + w]
        out |= (e <= 0) | (e - d > depth_jump * d)
    return out & (d > 0)


def compose(
    q_t1: np.ndarray,
    ridge_mask: np.ndarray | None,
    show_ridges: bool,
    show_silhouettes: bool,
    ridge_colour,
    silhouette_colour,
    depth_jump: float,
) -> np.ndarray:
    """The drawing's base (ComposePass): white paper, the hybrid ridge pixels in ``ridge_colour``, the
    image-space silhouettes of the view depth (``q_t1[..., 3]``, 0 = background) in
    ``silhouette_colour`` over them. (H, W, 3) float32 linear."""
    h, w = q_t1.shape[:2]
    image = np.ones((h, w, 3), np.float32)
    if show_ridges and ridge_mask is not None:
        image[np.asarray(ridge_mask, bool)] = ridge_colour
    if show_silhouettes:
        image[image_silhouettes(q_t1[..., 3], depth_jump)] = silhouette_colour
    return image


def segments(points: np.ndarray, view: View, size, width: float) -> np.ndarray:
    """The pixels SegmentsPass covers (no surface to hide them): (H, W) bool. ``points``: (2N, 3)
    object-space end points, segment i from points[2i] to points[2i+1]. Each segment, projected to
    pixels, becomes a rectangle ``width`` wide, extended by width/2 past each end; a pixel is covered
    when its centre lies inside one. Segments with an end behind the eye are skipped."""
    w, h = size
    pts = np.asarray(points, np.float64).reshape(-1, 2, 3)
    flat = pts.reshape(-1, 3)
    clip = (
        np.c_[flat, np.ones(len(flat))]
        @ (view.projection_matrix(w / h).astype(np.float64) @ view.view_matrix().astype(np.float64)).T
    )
    # pixel coordinates: x right from the left edge, y up from the bottom (GL), then flipped
    xy = (clip[:, :2] / clip[:, 3:4] * 0.5 + 0.5) * (w, h)
    xy = xy.reshape(-1, 2, 2)
    behind = (clip[:, 3] <= 0).reshape(-1, 2).any(axis=1)
    ys, xs = np.mgrid[0:h, 0:w]
    centres = np.stack([xs + 0.5, ys + 0.5], -1)
    covered = np.zeros((h, w), bool)
    half = width / 2
    for (a, b), skip in zip(xy, behind):
        if skip:
            continue
        d = b - a
        length = float(np.hypot(*d))
        direction = d / length if length > 1e-6 else np.array([1.0, 0.0])
        rel = centres - a
        along = rel @ direction
        across = rel @ np.array([-direction[1], direction[0]])
        covered |= (along >= -half) & (along <= length + half) & (np.abs(across) <= half)
    return covered[::-1]
