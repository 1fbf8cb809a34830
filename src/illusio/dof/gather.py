"""The depth-aware gather (shaders/gather.glsl). NumPy reference: :func:`illusio.dof.reference.gather`."""

from __future__ import annotations

import math

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .reference import DEPTH_SLACK

__all__ = ["GatherPass"]


class GatherPass:
    """``(image, coc, depth, max_coc)`` → the blurred image, RGBA float32 (pooled). The kernel spans
    ceil(max_coc / 2) pixels each way."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/gather.glsl")

    def __call__(self, image: moderngl.Texture, coc: moderngl.Texture, depth: moderngl.Texture, max_coc: float,
                 depth_slack: float = DEPTH_SLACK) -> moderngl.Texture:
        w, h = image.size
        out = self.ctx.acquire((w, h), 4, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        for unit, texture in enumerate((image, coc, depth)):
            texture.use(unit)
        prog = self.program
        for name, value in (("image", 0), ("coc", 1), ("depth", 2), ("radius", int(math.ceil(max_coc / 2))),
                            ("depth_slack", float(depth_slack))):
            set_uniform(prog, name, value)
        self.ctx.gl.disable(moderngl.DEPTH_TEST)
        self.ctx.fullscreen.draw(prog)
        return out
