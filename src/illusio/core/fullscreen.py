"""The one shared full-screen triangle (a single triangle covering the viewport, no buffers)."""

from __future__ import annotations

import moderngl

__all__ = ["FullscreenTriangle", "VERTEX_INCLUDE"]

#: include this in a program's .glsl to get the vertex stage (it defines ``out vec2 uv``)
VERTEX_INCLUDE = "common/fullscreen.glsl"


class FullscreenTriangle:
    """Draws any program whose vertex stage comes from ``common/fullscreen.glsl``."""

    def __init__(self, gl: moderngl.Context):
        self.gl = gl
        self._vaos: dict[int, moderngl.VertexArray] = {}

    def draw(self, program: moderngl.Program) -> None:
        vao = self._vaos.get(program.glo)
        if vao is None:
            vao = self.gl.vertex_array(program, [])
            self._vaos[program.glo] = vao
        vao.render(moderngl.TRIANGLES, vertices=3)
