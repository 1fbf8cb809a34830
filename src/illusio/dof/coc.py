"""The circle of confusion map (shaders/coc.glsl): linear depth → pixels. NumPy reference:
:func:`illusio.dof.reference.coc`."""

from __future__ import annotations

import math

import moderngl

from ..core.context import Context

__all__ = ["CocPass"]


class CocPass:
    """``(depth, focus_distance, aperture_m, fov_y, max_coc)`` → R32F circle of confusion (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/coc.glsl")

    def __call__(
        self, depth: moderngl.Texture, focus_distance: float, aperture_m: float, fov_y: float, max_coc: float
    ) -> moderngl.Texture:
        w, h = depth.size
        return self.ctx.draw_fullscreen(
            self.program,
            (w, h),
            1,
            textures={"depth": depth},
            aperture=float(aperture_m),
            focus_distance=float(focus_distance),
            max_coc=float(max_coc),
            scale=h / (2 * math.tan(math.radians(fov_y) / 2)),
        )
