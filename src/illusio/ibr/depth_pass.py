"""The first pass on the GPU: the reconstruction mesh drawn into the new view's linear depth
(shaders/reconstruct.glsl), the points it leaves out scattered over it by a compute pass
(shaders/points.glsl), then its holes filled from the nearest ring around them (shaders/fill.glsl).
References:
passes.reference.gbuffer (ray casting the mesh), ibr.reference.point_depth (the points) and
:func:`illusio.ibr.renderer.fill_holes`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .proxy_mesh import Reconstruction

__all__ = ["ReconstructPass"]

GL_R32UI = 0x8236  # the R32F depth seen as one word per texel (points.glsl's atomics)


class ReconstructPass:
    """``load(reconstruction)`` once per reference set; ``(view, size, fill_radius)`` → R32F depth (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("ibr/shaders/reconstruct.glsl")
        self.fill_program = ctx.program("ibr/shaders/fill.glsl")
        self.points_program = ctx.program("ibr/shaders/points.glsl")
        self._buffers = None

    def load(self, shape: Reconstruction) -> None:
        mesh, points, footprint = shape.mesh, shape.points, shape.footprint
        self.ctx.make_current()  # buffers belong to the context current when they are made
        self.release()
        gl = self.ctx.gl
        vbo = gl.buffer(np.ascontiguousarray(mesh.vertices, np.float32).tobytes())
        ibo = gl.buffer(np.ascontiguousarray(mesh.faces, np.int32).tobytes())
        vao = gl.vertex_array(self.program, [(vbo, "3f", "in_position")], ibo)
        self._buffers = (vbo, ibo, vao)
        if len(points):
            interleaved = np.concatenate(
                [np.asarray(points, np.float32).reshape(-1, 3), np.asarray(footprint, np.float32).reshape(-1, 1)],
                axis=1,
            )
            self._buffers += (gl.buffer(np.ascontiguousarray(interleaved).tobytes()),)

    def __call__(self, view: View, size: tuple[int, int], fill_radius: int = 0) -> moderngl.Texture:
        ctx = self.ctx
        w, h = size
        depth = ctx.acquire((w, h), 1, "f4")
        fbo = ctx.framebuffer([depth], depth=True)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        set_uniform(self.program, "view_matrix", view.view_matrix())
        set_uniform(self.program, "projection_matrix", view.projection_matrix(w / h))
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.disable(moderngl.CULL_FACE)
        self._buffers[2].render(moderngl.TRIANGLES)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        if len(self._buffers) > 3:
            self._scatter_points(view, depth)
        return self.fill(depth, fill_radius)

    def _scatter_points(self, view: View, depth: moderngl.Texture) -> None:
        """The points into ``depth`` after the mesh, nearest winning (shaders/points.glsl)."""
        w, h = depth.size
        prog, points = self.points_program, self._buffers[3]
        count = points.size // 16
        set_uniform(prog, "view_matrix", view.view_matrix())
        set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
        set_uniform(prog, "focal_px", float(view.projection_matrix(w / h)[0, 0] * w / 2))
        set_uniform(prog, "near", float(view.camera.near))
        set_uniform(prog, "count", count)
        points.bind_to_storage_buffer(0)
        depth.bind_to_image(0, read=True, write=True, format=GL_R32UI)
        prog.run(group_x=-(-count // 64))
        # the fill and the selection read it as a texture
        self.ctx.gl.memory_barrier(moderngl.TEXTURE_FETCH_BARRIER_BIT | moderngl.SHADER_IMAGE_ACCESS_BARRIER_BIT)

    def fill(self, depth: moderngl.Texture, radius: int) -> moderngl.Texture:
        """``depth`` (pooled; released) with holes up to ``radius`` pixels filled, in one draw: a new
        pooled texture."""
        if radius <= 0:
            return depth
        filled = self.ctx.draw_fullscreen(
            self.fill_program, depth.size, 1, textures={"depth": depth}, radius=int(radius)
        )
        self.ctx.release(depth)
        return filled

    def release(self) -> None:
        if self._buffers is not None:
            for b in self._buffers[::-1]:
                b.release()
            self._buffers = None
