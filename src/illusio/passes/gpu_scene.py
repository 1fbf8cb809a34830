"""The GPU copy of a Scene: one vertex/index buffer per distinct mesh, one texture per material
texture, and the per-node uniforms. Built once, drawn by any program with the standard inputs
``in_position``, ``in_normal``, ``in_uv`` (those a program lacks are skipped)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..scene.scene import Node, Scene

__all__ = ["GpuScene", "GpuMesh"]


@dataclass
class GpuMesh:
    vbo: moderngl.Buffer
    ibo: moderngl.Buffer
    triangles: int
    has_uvs: bool


class GpuScene:
    """Buffers and textures of one scene on one context. ``draw(program, set_node)`` draws every
    visible node, calling ``set_node(index, node)`` first to set per-node uniforms."""

    def __init__(self, ctx: Context, scene: Scene):
        self.ctx = ctx
        self.scene = scene
        self._meshes: dict[int, GpuMesh] = {}
        self._textures: dict[int, moderngl.Texture] = {}
        self._vaos: dict[tuple[int, int], moderngl.VertexArray] = {}
        for node in scene.nodes:
            self._mesh(node)
            if node.material.texture is not None:
                self.texture(node)

    def _mesh(self, node: Node) -> GpuMesh:
        key = id(node.mesh)
        gm = self._meshes.get(key)
        if gm is None:
            m = node.mesh
            uvs = m.uvs if m.uvs is not None else np.zeros((len(m.vertices), 2), np.float32)
            data = np.hstack([m.vertices, m.normals, uvs]).astype(np.float32)
            gm = GpuMesh(self.ctx.gl.buffer(data.tobytes()), self.ctx.gl.buffer(m.faces.astype(np.int32).tobytes()),
                         len(m.faces), m.uvs is not None)
            self._meshes[key] = gm
        return gm

    def texture(self, node: Node) -> moderngl.Texture | None:
        tex_array = node.material.texture
        if tex_array is None:
            return None
        key = id(tex_array)
        tex = self._textures.get(key)
        if tex is None:
            tex = self.ctx.upload(tex_array.astype(np.float32), mipmaps=True, repeat=True)
            tex.anisotropy = 8.0
            self._textures[key] = tex
        return tex

    def vao(self, program: moderngl.Program, node: Node) -> moderngl.VertexArray:
        gm = self._mesh(node)
        key = (program.glo, id(node.mesh))
        vao = self._vaos.get(key)
        if vao is None:
            # interleaved position, normal, uv; attributes the program lacks are skipped as padding
            layout = (("in_position", 3), ("in_normal", 3), ("in_uv", 2))
            names = [n for n, _ in layout if program.get(n, None) is not None]
            fmt = " ".join(f"{k}f" if n in names else f"{4 * k}x" for n, k in layout)
            vao = self.ctx.gl.vertex_array(program, [(gm.vbo, fmt, *names)], gm.ibo)
            self._vaos[key] = vao
        return vao

    def draw(self, program: moderngl.Program, set_node=None) -> None:
        for index, node in enumerate(self.scene.nodes):
            if not node.visible:
                continue
            if set_node is not None:
                set_node(index, node)
            self.vao(program, node).render(moderngl.TRIANGLES)

    @property
    def triangle_count(self) -> int:
        return sum(self._mesh(n).triangles for n in self.scene.nodes if n.visible)

    def release(self) -> None:
        for vao in self._vaos.values():
            vao.release()
        for gm in self._meshes.values():
            gm.vbo.release()
            gm.ibo.release()
        for tex in self._textures.values():
            tex.release()
        self._vaos.clear()
        self._meshes.clear()
        self._textures.clear()


def set_uniform(program, name: str, value) -> None:
    """Set a uniform if the program uses it (drivers drop unused ones). Matrices (4×4, 3×3 numpy
    arrays, row-major like the rest of illusio) are transposed to GL's column-major order; other
    arrays are written flat as they are."""
    u = program.get(name, None)
    if u is None:
        return
    if isinstance(value, np.ndarray):
        a = np.asarray(value, dtype=np.int32 if value.dtype.kind in "iu" else np.float32)
        if a.ndim == 2 and a.shape in ((4, 4), (3, 3)) and u.dimension in (9, 16):
            a = a.T
        u.write(np.ascontiguousarray(a).tobytes())
    else:
        u.value = value
