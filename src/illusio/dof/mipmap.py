"""The mipmap method (section 2.2.3, shaders/mipmap.glsl). NumPy reference:
:func:`illusio.dof.reference.mipmap`."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["MipmapPass", "mipmapped"]


def mipmapped(ctx: Context, image: moderngl.Texture) -> moderngl.Texture:
    """A pooled RGBA32F copy of ``image`` with its mipmap levels built (trilinear sampling)."""
    copy = ctx.acquire(image.size, 4, "f4", filter="linear", mipmaps=True)
    ctx.gl.copy_framebuffer(ctx.framebuffer([copy]), ctx.framebuffer([image]))
    copy.build_mipmaps()
    copy.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    copy.repeat_x = copy.repeat_y = False
    return copy


class MipmapPass:
    """``(mipmapped image, coc)`` → each pixel at its circle's mipmap level, RGBA32F (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/mipmap.glsl")

    def __call__(self, image: moderngl.Texture, coc: moderngl.Texture) -> moderngl.Texture:
        w, h = coc.size
        out = self.ctx.acquire((w, h), 4, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        image.use(0)
        coc.use(1)
        set_uniform(self.program, "image", 0)
        set_uniform(self.program, "coc", 1)
        self.ctx.gl.disable(moderngl.DEPTH_TEST)
        self.ctx.fullscreen.draw(self.program)
        return out
