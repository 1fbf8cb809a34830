"""Ridge detection of the hybrid method (report section 3.3, Figure 3.8): the direction-adaptive 3×3
Laplacian of q. NumPy reference and the GPU pass (shaders/ridge_filter.glsl)."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["adaptive_laplacian", "RidgeFilterPass", "REPORT_THRESHOLD"]

REPORT_THRESHOLD = 0.2  # annex B: a pixel is an edge where the response exceeds 0.2
_COS_PI_8 = 0.92387953251080
_A = 0.70710678118655


def adaptive_laplacian(q_t1: np.ndarray, lam: float, threshold: float = REPORT_THRESHOLD) -> tuple[np.ndarray, np.ndarray]:
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
        return padded[1 - dy:1 - dy + h, 1 + dx:1 + dx + w]

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
    total = (w_h * (at(1, 0) + at(-1, 0)) + w_v * (at(0, 1) + at(0, -1))
             + w_d * (at(1, 1) + at(-1, -1)) + w_a * (at(-1, 1) + at(1, -1)))
    response = np.where(has, (8 + 8 * lam) * q - total, 0.0)
    return response, response > threshold


class RidgeFilterPass:
    """q_t1 texture in, (ridge 0/1, response, 0, 1) RGBA32F texture out (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("lines/shaders/ridge_filter.glsl")

    def __call__(self, q_t1: moderngl.Texture, lam: float, threshold: float = REPORT_THRESHOLD) -> moderngl.Texture:
        ctx = self.ctx
        out = ctx.acquire(q_t1.size, 4, "f4")
        fbo = ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, *q_t1.size)
        q_t1.use(0)
        set_uniform(self.program, "q_t1", 0)
        set_uniform(self.program, "lambda", float(lam))
        set_uniform(self.program, "threshold", float(threshold))
        ctx.fullscreen.draw(self.program)
        return out
