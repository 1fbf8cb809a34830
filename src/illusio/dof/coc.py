"""The circle of confusion map (shaders/coc.glsl): linear depth → pixels. NumPy reference:
:func:`illusio.dof.reference.coc`."""

from __future__ import annotations

import math

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["CocPass"]


class CocPass:
    """``(depth, focus_distance, aperture_m, fov_y, max_coc)`` → R32F circle of confusion (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/coc.glsl")

    def __call__(self, depth: moderngl.Texture, focus_distance: float, aperture_m: float, fov_y: float,
                 max_coc: float) -> moderngl.Texture:
        w, h = depth.size
        out = self.ctx.acquire((w, h), 1, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        depth.use(0)
        prog = self.program
        for name, value in (("depth", 0), ("aperture", float(aperture_m)), ("focus_distance", float(focus_distance)),
                            ("scale", h / (2 * math.tan(math.radians(fov_y) / 2))), ("max_coc", float(max_coc))):
            set_uniform(prog, name, value)
        self.ctx.gl.disable(moderngl.DEPTH_TEST)
        self.ctx.fullscreen.draw(prog)
        return out
