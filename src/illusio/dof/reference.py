"""Depth of field stated plainly in NumPy: the specification the GPU passes are tested against, one
function per pass and named after it (``coc`` for CocPass, ``gather`` for GatherPass,
``accumulate`` for the accumulation method's average). Arrays have row 0 at the top."""

from __future__ import annotations

import numpy as np

from .lens import coc_pixels

__all__ = ["coc", "gather", "accumulate", "lens_samples", "DEPTH_SLACK"]

#: relative depth within which a neighbour counts as level with a pixel (not behind it)
DEPTH_SLACK = 0.02


def coc(depth: np.ndarray, focus_distance: float, aperture_m: float, fov_y: float, max_coc: float) -> np.ndarray:
    """CocPass: the circle of confusion in pixels of every pixel of a linear depth image (H, W),
    clamped to ``max_coc``; depth ≤ 0 is nothing there (infinitely far)."""
    d = np.asarray(depth, np.float64)
    return np.minimum(coc_pixels(d, focus_distance, aperture_m, fov_y, d.shape[0]), max_coc).astype(np.float32)


def gather(image: np.ndarray, coc_px: np.ndarray, depth: np.ndarray, radius: int,
           depth_slack: float = DEPTH_SLACK) -> np.ndarray:
    """GatherPass: for each pixel p, the weighted mean of the pixels q within ``radius`` (a square of
    offsets, Euclidean distance) whose circle covers p (|q − p| ≤ r_q = max(c_q/2, ½)), weight
    1/(π r_q²), leaving out a q behind p (z_q > z_p (1 + slack)) outside p's own circle. Depth ≤ 0
    is infinitely far. (H, W, 3) float32."""
    img = np.asarray(image, np.float64)[..., :3]
    h, w = img.shape[:2]
    r = np.maximum(np.asarray(coc_px, np.float64) / 2, 0.5)
    z = np.where(np.asarray(depth) > 0, np.asarray(depth, np.float64), 1e30)
    total = np.zeros((h, w))
    acc = np.zeros((h, w, 3))
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            dist = float(np.hypot(dx, dy))
            # q = p + (dx, dy) in GL's rows (up) = p + (dx, −dy) in array rows (down)
            ys0, ys1 = max(0, dy), min(h, h + dy)  # p rows whose q row p_y − dy is inside
            xs0, xs1 = max(0, -dx), min(w, w - dx)
            if ys0 >= ys1 or xs0 >= xs1:
                continue
            p = (slice(ys0, ys1), slice(xs0, xs1))
            q = (slice(ys0 - dy, ys1 - dy), slice(xs0 + dx, xs1 + dx))
            rq = r[q]
            keep = (dist <= rq) & ~((z[q] > z[p] * (1 + depth_slack)) & (dist > r[p]))
            weight = np.where(keep, 1.0 / (np.pi * rq * rq), 0.0)
            acc[p] += weight[..., None] * img[q]
            total[p] += weight
    return (acc / total[..., None]).astype(np.float32)


def accumulate(images) -> np.ndarray:
    """The accumulation method's image: the mean of the views through the lens samples."""
    return np.mean(np.stack([np.asarray(i, np.float64)[..., :3] for i in images]), axis=0).astype(np.float32)


def lens_samples(count: int, seed: int = 0) -> np.ndarray:
    """``count`` points (N, 2) spread evenly over the unit disk (Vogel's golden-angle spiral, the
    area-preserving radius √((i + ½)/N)), the whole pattern turned by an angle drawn from ``seed``."""
    i = np.arange(count, dtype=np.float64)
    radius = np.sqrt((i + 0.5) / count)
    turn = np.random.default_rng(seed).uniform(0, 2 * np.pi)
    angle = i * np.pi * (3 - np.sqrt(5)) + turn
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)
