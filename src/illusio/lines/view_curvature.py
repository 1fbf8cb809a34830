"""View-dependent curvature (Judd et al. 2007) per vertex: the first pass of the hybrid method, which
rasterises it (shaders/view_curvature.glsl). NumPy reference: :func:`illusio.lines.reference.view_curvature`
(the same maths serves Judd's object-space method).

Q, for a surface point seen along the unit view direction v (towards the eye), in the principal
frame (e1 = e_min, e2 = e_max), with u, v the components of the view direction along e1, e2
normalised by u² + v² = sin²θ and s = sec θ − 1 (θ: angle between normal and view direction):
    Q = [[k1 (1 + s u²), k1 s uv], [k2 s uv, k2 (1 + s v²)]]
q1 = largest singular value of Q; its right singular vector s1 gives the tangent w1 = s1₁ e1 + s1₂ e2,
and t1 = w1 projected on the screen (sign fixed so that it points away from the viewer's side).
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .gpu_mesh import CurvatureMesh

__all__ = ["ViewCurvaturePass"]


class ViewCurvaturePass:
    """Renders (q, t1.x, t1.y, view depth) of a CurvatureMesh into an RGBA32F texture (pooled; depth 0
    marks the background), testing against ``depth`` (a depth texture the caller keeps, so that
    lines drawn later can be hidden by the surface; pushed back by a slope-scaled offset)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("lines/shaders/view_curvature.glsl")

    def __call__(
        self,
        mesh: CurvatureMesh,
        view: View,
        size,
        tau: float = 0.0,
        curvature_scale: float = 1.0,
        model_matrix=None,
        depth: moderngl.Texture | bool = True,
    ) -> moderngl.Texture:
        ctx = self.ctx
        w, h = size
        out = ctx.acquire((w, h), 4, "f4")
        fbo = ctx.framebuffer([out], depth=depth)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.disable(moderngl.CULL_FACE)
        ctx.gl.polygon_offset = (1.0, 1.0)
        self.set_uniforms(self.program, view, (w, h), tau, curvature_scale, model_matrix)
        mesh.vao(self.program).render(moderngl.TRIANGLES)
        ctx.gl.polygon_offset = (0.0, 0.0)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        return out

    @staticmethod
    def set_uniforms(program, view: View, size, tau: float, curvature_scale: float, model_matrix=None) -> None:
        w, h = size
        set_uniform(program, "view_matrix", view.view_matrix())
        set_uniform(program, "projection_matrix", view.projection_matrix(w / h))
        set_uniform(program, "model_matrix", np.eye(4, dtype=np.float32) if model_matrix is None else model_matrix)
        set_uniform(program, "tau", float(tau))
        set_uniform(program, "curvature_scale", float(curvature_scale))

    def per_vertex(
        self, mesh: CurvatureMesh, view: View, size, tau: float = 0.0, curvature_scale: float = 1.0
    ) -> np.ndarray:
        """The vertex stage's (q, t1.x, t1.y, view depth) for every vertex, captured by transform feedback
        (to check the shader against :func:`reference.view_curvature`)."""
        ctx = self.ctx
        prog = ctx.program("lines/shaders/view_curvature.glsl", varyings=("q_t1",))
        self.set_uniforms(prog, view, size, tau, curvature_scale)
        out = ctx.gl.buffer(reserve=mesh.vertex_count * 16)
        scratch = ctx.acquire((1, 1), 4, "f1")
        ctx.framebuffer([scratch]).use()  # a draw needs a complete framebuffer, even with nothing rasterised
        try:
            mesh.vao(prog, indexed=False).transform(out, moderngl.POINTS, vertices=mesh.vertex_count)
            return np.frombuffer(out.read(), np.float32).reshape(-1, 4).copy()
        finally:
            out.release()
            ctx.release(scratch)
