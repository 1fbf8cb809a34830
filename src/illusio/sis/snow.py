"""TV snow made on the GPU each frame (reference: :func:`.patterns.snow`)."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["SnowPass"]


class SnowPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/snow.glsl")

    def __call__(
        self, size: tuple[int, int], seed: int = 0, frame: int = 0, dot_size: int = 1, oversample: int = 1
    ) -> moderngl.Texture:
        """size: (width, height) of the texture, already ``oversample`` times the image width."""
        w, h = size
        out = self.ctx.acquire((w, h), 4, "f1")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        for name, value in (
            ("seed", int(seed) & 0xFFFFFFFF),
            ("frame", int(frame) & 0xFFFFFFFF),
            ("dot_size", int(dot_size)),
            ("image_height", h),
            ("oversample", int(oversample)),
        ):
            set_uniform(self.program, name, value)
        self.ctx.fullscreen.draw(self.program)
        return out
