"""A mesh with its curvature on the GPU: one interleaved vertex buffer (position, normal, e_min,
e_max, (k_min, k_max)) and an index buffer, drawn by the line passes."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..scene.mesh import Mesh
from .curvature import Curvature

__all__ = ["CurvatureMesh"]

_FORMAT = "3f 3f 3f 3f 2f"
_ATTRIBUTES = ("in_position", "in_normal", "in_e_min", "in_e_max", "in_k")


class CurvatureMesh:
    """Upload once, draw every frame with any program using some of the inputs above."""

    def __init__(self, ctx: Context, mesh: Mesh, curvature: Curvature):
        self.ctx = ctx
        self.mesh = mesh
        self.curvature = curvature
        data = np.hstack(
            [
                mesh.vertices,
                curvature.normals,
                curvature.e_min,
                curvature.e_max,
                np.c_[curvature.k_min, curvature.k_max],
            ]
        ).astype(np.float32)
        ctx.make_current()
        self.vbo = ctx.gl.buffer(np.ascontiguousarray(data).tobytes())
        self.ibo = ctx.gl.buffer(np.ascontiguousarray(mesh.faces, np.int32).tobytes())
        self.vertex_count = len(mesh.vertices)
        self._vaos: dict[int, moderngl.VertexArray] = {}

    def vao(self, program: moderngl.Program, indexed: bool = True) -> moderngl.VertexArray:
        key = (program.glo, indexed)
        vao = self._vaos.get(key)
        if vao is None:
            names = [n if n in program else None for n in _ATTRIBUTES]
            fmt = " ".join((f if n else f"{int(f[0]) * 4}x") for f, n in zip(_FORMAT.split(), names))
            content = [(self.vbo, fmt, *[n for n in names if n])]
            vao = self.ctx.gl.vertex_array(program, content, self.ibo if indexed else None)
            self._vaos[key] = vao
        return vao

    def release(self) -> None:
        for vao in self._vaos.values():
            vao.release()
        self._vaos.clear()
        self.vbo.release()
        self.ibo.release()
