"""View-dependent curvature (Judd et al. 2007) per vertex: the NumPy reference of the first pass of
the hybrid method, the GPU pass that rasterises it (shaders/view_curvature.glsl), and the same maths
in object space for Judd's original method.

Q, for a surface point seen along the unit view direction v (towards the eye), in the principal
frame (e1 = e_min, e2 = e_max), with u, v the components of the view direction along e1, e2
normalised by u² + v² = sin²θ and s = sec θ − 1 (θ: angle between normal and view direction):
    Q = [[k1 (1 + s u²), k1 s uv], [k2 s uv, k2 (1 + s v²)]]
q1 = largest singular value of Q; its right singular vector s1 gives the tangent w1 = s1₁ e1 + s1₂ e2,
and t1 = w1 projected on the screen (sign fixed so that it points away from the viewer's side).
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from .gpu_mesh import CurvatureMesh

__all__ = ["view_dependent_curvature", "ViewCurvature", "ViewCurvaturePass"]


@dataclass
class ViewCurvature:
    """Per-vertex results: q (N,) scaled and clamped as the shader stores it, q1 (N,) raw singular
    value (1/units), t1 (N, 2) unit screen direction in camera x (right), y (up) or 0, w1 (N, 3) the
    object-space tangent of maximum view-dependent curvature (unit, sign arbitrary), ndotv (N,)."""

    q: np.ndarray
    q1: np.ndarray
    t1: np.ndarray
    w1: np.ndarray
    ndotv: np.ndarray


def view_dependent_curvature(positions, normals, e_min, e_max, k_min, k_max, view: View,
                             tau: float = 0.0, curvature_scale: float = 1.0, model_matrix=None) -> ViewCurvature:
    """The vertex shader's maths in NumPy (float64). Arrays are per vertex, object space."""
    model = np.eye(4) if model_matrix is None else np.asarray(model_matrix, np.float64)
    mv = view.view_matrix().astype(np.float64) @ model
    rot = mv[:3, :3]
    eye = np.c_[np.asarray(positions, np.float64), np.ones(len(positions))] @ mv.T
    n = np.asarray(normals, np.float64) @ np.linalg.inv(rot)  # (R⁻¹)ᵀ n, as rows
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    e1 = np.asarray(e_min, np.float64) @ rot.T
    e2 = np.asarray(e_max, np.float64) @ rot.T
    k1 = np.asarray(k_min, np.float64)
    k2 = np.asarray(k_max, np.float64)
    view_dir = -eye[:, :3]
    view_dir /= np.maximum(np.linalg.norm(view_dir, axis=1, keepdims=True), 1e-30)
    ndotv = (view_dir * n).sum(1)
    u = (view_dir * e1).sum(1)
    v = (view_dir * e2).sum(1)
    w2 = u * u + v * v
    csc2 = np.where(w2 > 1e-12, 1.0 / np.maximum(w2, 1e-300), 0.0)
    u2, v2, uv = u * u * csc2, v * v * csc2, u * v * csc2
    s = 1.0 / np.maximum(np.abs(ndotv), 1e-4) - 1.0
    q11 = k1 * (1 + s * u2)
    q12 = k1 * s * uv
    q21 = k2 * s * uv
    q22 = k2 * (1 + s * v2)
    a11 = q11 * q11 + q21 * q21
    a12 = q11 * q12 + q21 * q22
    a22 = q12 * q12 + q22 * q22
    lam = 0.5 * (a11 + a22) + np.sqrt(a12 * a12 + (0.5 * (a22 - a11)) ** 2)
    ra = np.stack([a22 - lam, -a12], 1)
    rb = np.stack([-a12, a11 - lam], 1)
    s1 = np.where(((ra * ra).sum(1) >= (rb * rb).sum(1))[:, None], ra, rb)
    length = np.linalg.norm(s1, axis=1)
    fallback = np.where((a11 >= a22)[:, None], [1.0, 0.0], [0.0, 1.0])
    s1 = np.where((length * length > 1e-30)[:, None], s1 / np.maximum(length, 1e-300)[:, None], fallback)
    w1_eye = s1[:, :1] * e1 + s1[:, 1:] * e2
    t1 = np.where((w1_eye[:, 2] >= 0)[:, None], -w1_eye[:, :2], w1_eye[:, :2])
    tl = np.linalg.norm(t1, axis=1)
    t1 = np.where((tl * tl > 1e-16)[:, None], t1 / np.maximum(tl, 1e-300)[:, None], 0.0)
    q1 = np.sqrt(lam)
    q = np.clip(2.0**tau * q1 / curvature_scale, 0.0, 1.0)
    w1 = s1[:, :1] * np.asarray(e_min, np.float64) + s1[:, 1:] * np.asarray(e_max, np.float64)
    return ViewCurvature(q, q1, t1, w1, ndotv)


class ViewCurvaturePass:
    """Renders (q, t1.x, t1.y, view depth) of a CurvatureMesh into an RGBA32F texture (pooled; depth 0
    marks the background), testing against ``depth`` (a depth texture the caller keeps, so that
    lines drawn later can be hidden by the surface; pushed back by a slope-scaled offset)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("lines/shaders/view_curvature.glsl")

    def __call__(self, mesh: CurvatureMesh, view: View, size, tau: float = 0.0, curvature_scale: float = 1.0,
                 model_matrix=None, depth: moderngl.Texture | bool = True) -> moderngl.Texture:
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

    def per_vertex(self, mesh: CurvatureMesh, view: View, size, tau: float = 0.0, curvature_scale: float = 1.0) -> np.ndarray:
        """The vertex stage's (q, t1.x, t1.y, view depth) for every vertex, captured by transform feedback
        (to check the shader against :func:`view_dependent_curvature`)."""
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
