"""The mipmap method (section 2.2.3, shaders/mipmap.glsl). NumPy reference:
:func:`illusio.dof.reference.mipmap`."""

from __future__ import annotations

import moderngl

from ..core.context import Context

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
        return self.ctx.draw_fullscreen(self.program, coc.size, textures={"image": image, "coc": coc})
