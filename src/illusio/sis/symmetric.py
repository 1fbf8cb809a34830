"""Symmetric algorithm with hidden-surface removal (Thimbleby, Inglis & Witten 1994) on the GPU: one
compute invocation per row (reference: :func:`.reference.symmetric`)."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .inputs import StereogramInputs

__all__ = ["SymmetricPass"]


class SymmetricPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/symmetric.glsl")

    def __call__(self, inputs: StereogramInputs, near_separation: float, eye_separation: float) -> moderngl.Texture:
        """near_separation: W_s (times the oversampling); eye_separation: e_p in the same pixels."""
        w, h = inputs.size
        out = self.ctx.acquire((w, h), 4, "f1")
        links = self.ctx.acquire((w, h), 1, "i4")
        inputs.bind(self.program)
        set_uniform(self.program, "near_separation", float(near_separation))
        set_uniform(self.program, "eye_separation_px", float(eye_separation))
        out.bind_to_image(0, read=True, write=True)
        links.bind_to_image(1, read=True, write=True)
        self.program.run(group_x=-(-h // 64))
        self.ctx.gl.memory_barrier()
        self.ctx.release(links)
        return out
