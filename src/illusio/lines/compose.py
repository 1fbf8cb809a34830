"""The drawing's base as a pass (shaders/compose.glsl): white paper, the hybrid ridge pixels and the
image-space silhouettes, each in its colour. NumPy reference: :func:`illusio.lines.reference.compose`."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform

__all__ = ["ComposePass"]


class ComposePass:
    """``(q_t1, ridges, target, ...)``: draws into ``target`` (an RGBA texture of q_t1's size) through a
    framebuffer that shares ``depth`` (the view's depth texture), so that object-space lines drawn
    after it are hidden by the surface. ``ridges``: a texture whose red channel is 1 on a ridge."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("lines/shaders/compose.glsl")

    def __call__(
        self,
        q_t1: moderngl.Texture,
        ridges: moderngl.Texture | None,
        target: moderngl.Texture,
        depth: moderngl.Texture | None = None,
        show_ridges: bool = True,
        show_silhouettes: bool = False,
        ridge_colour=(0.0, 0.0, 0.0),
        silhouette_colour=(0.0, 0.0, 0.0),
        depth_jump: float = 0.05,
    ) -> moderngl.Framebuffer:
        ctx = self.ctx
        w, h = target.size
        fbo = ctx.framebuffer([target], depth=depth if depth is not None else False)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        prog = self.program
        q_t1.use(0)
        (ridges or q_t1).use(1)
        for name, value in (
            ("q_t1", 0),
            ("ridges", 1),
            ("show_ridges", bool(show_ridges and ridges is not None)),
            ("show_silhouettes", bool(show_silhouettes)),
            ("ridge_colour", tuple(float(c) for c in ridge_colour)),
            ("silhouette_colour", tuple(float(c) for c in silhouette_colour)),
            ("depth_jump", float(depth_jump)),
        ):
            set_uniform(prog, name, value)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        ctx.fullscreen.draw(prog)
        return fbo
