"""Ridge detection of the hybrid method (report section 3.3, Figure 3.8): the direction-adaptive 3×3
Laplacian of q, the GPU pass (shaders/ridge_filter.glsl). NumPy reference:
:func:`illusio.lines.reference.ridge_filter`."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .reference import REPORT_THRESHOLD

__all__ = ["RidgeFilterPass", "REPORT_THRESHOLD"]


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
