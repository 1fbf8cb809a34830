"""The second pass (shaders/select.glsl): one full-screen draw per reference view, the depth test
keeping per pixel the reference whose back-projected point is nearest ours — the text's multi-pass
algorithm, which takes any number of views. NumPy reference: :func:`illusio.ibr.reference.select`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..passes.gbuffer import LAYOUT, GBuffer
from ..scene.camera import View

__all__ = ["SelectPass", "ReferenceTextures", "projection_terms"]


def projection_terms(view: View, size) -> tuple[float, float, float, float]:
    """(p00, p02, p11, p12) of ``view``'s projection at ``size``: what unprojection needs."""
    p = view.projection_matrix(size[0] / size[1]).astype(np.float64)
    return float(p[0, 0]), float(p[0, 2]), float(p[1, 1]), float(p[1, 2])


class ReferenceTextures:
    """One reference view on the GPU (albedo, normal, emission, depth)."""

    def __init__(self, ctx: Context, ref):
        self.view = ref.view
        self.size = ref.size
        self.albedo = ctx.upload(ref.albedo, filter="nearest")
        self.normal = ctx.upload(ref.normal, filter="nearest")
        self.emission = ctx.upload(ref.emission, filter="nearest")
        self.depth = ctx.upload(ref.depth, filter="nearest")

    def release(self) -> None:
        for t in (self.albedo, self.normal, self.emission, self.depth):
            t.release()


class SelectPass:
    """``(reconstructed depth, new view, references, use_3d, bilinear, max_distance)`` → a G-buffer
    of the new view (pooled textures: release it)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("ibr/shaders/select.glsl")

    def __call__(self, reconstructed: moderngl.Texture, view: View, references: list[ReferenceTextures],
                 use_3d: bool = False, bilinear: bool = True, max_distance: float = 3.0) -> GBuffer:
        ctx = self.ctx
        w, h = reconstructed.size
        textures = {name: ctx.acquire((w, h), comps, dtype) for name, comps, dtype in LAYOUT}
        fbo = ctx.framebuffer(list(textures.values()), depth=True)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        prog = self.program
        reconstructed.use(0)
        set_uniform(prog, "reconstructed", 0)
        set_uniform(prog, "new_inverse_view", np.linalg.inv(view.view_matrix().astype(np.float64)).astype(np.float32))
        set_uniform(prog, "new_view", view.view_matrix())
        set_uniform(prog, "new_view_projection", view.view_projection((w, h)))
        set_uniform(prog, "new_projection", projection_terms(view, (w, h)))
        set_uniform(prog, "use_3d", bool(use_3d))
        set_uniform(prog, "bilinear", bool(bilinear))
        set_uniform(prog, "max_distance", float(max_distance))
        set_uniform(prog, "new_eye", tuple(float(v) for v in view.pose.position))
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.depth_func = "<"
        try:
            for index, ref in enumerate(references):
                for unit, (name, tex) in enumerate((("ref_albedo", ref.albedo), ("ref_normal", ref.normal),
                                                    ("ref_emission", ref.emission), ("ref_depth", ref.depth)), start=1):
                    tex.use(unit)
                    set_uniform(prog, name, unit)
                set_uniform(prog, "ref_view_projection", ref.view.view_projection(ref.size))
                set_uniform(prog, "ref_inverse_view", np.linalg.inv(ref.view.view_matrix().astype(np.float64)).astype(np.float32))
                set_uniform(prog, "ref_projection", projection_terms(ref.view, ref.size))
                set_uniform(prog, "source", float(index + 1))
                ctx.fullscreen.draw(prog)
        finally:
            ctx.gl.disable(moderngl.DEPTH_TEST)
        return GBuffer(ctx, textures, (w, h))
