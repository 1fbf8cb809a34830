"""Object-space line segments drawn as screen-space quads ``width`` pixels wide (shaders/segments.glsl;
the core profile has no wide lines), depth-tested against the surface already in the bound
framebuffer, so hidden parts vanish. NumPy reference: :func:`illusio.lines.reference.segments`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .object_space import Segments

__all__ = ["SegmentsPass"]


class SegmentsPass:
    """``(segments, view, size, colour, width)``: draws into the currently bound framebuffer (the
    drawing's, with the view's depth attached), depth test on, depth writes off."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("lines/shaders/segments.glsl")

    def __call__(self, segments: Segments, view: View, size, colour, width: float) -> None:
        if len(segments) == 0:
            return
        ctx = self.ctx
        prog = self.program
        w, h = size
        set_uniform(prog, "view_matrix", view.view_matrix())
        set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
        set_uniform(prog, "model_matrix", np.eye(4, dtype=np.float32))
        set_uniform(prog, "viewport", (float(w), float(h)))
        set_uniform(prog, "width", float(width))
        set_uniform(prog, "colour", tuple(float(c) for c in colour))
        vbo = ctx.gl.buffer(np.ascontiguousarray(segments.points, np.float32).tobytes())
        vao = ctx.gl.vertex_array(prog, [(vbo, "3f", "in_position")])
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.depth_mask = False
        try:
            vao.render(moderngl.LINES)
        finally:
            ctx.gl.depth_mask = True
            ctx.gl.disable(moderngl.DEPTH_TEST)
            vao.release()
            vbo.release()
