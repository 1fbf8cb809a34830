"""Sequential algorithm on the GPU: one compute invocation per row walks it left to right
(reference: :func:`.reference.sequential`, which says why the separation is W_s + βD and not the
paper's αD)."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from .inputs import StereogramInputs

__all__ = ["SequentialPass"]


class SequentialPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/sequential.glsl")

    def __call__(self, inputs: StereogramInputs) -> moderngl.Texture:
        w, h = inputs.size
        out = self.ctx.acquire((w, h), 4, "f1")
        inputs.bind(self.program)
        out.bind_to_image(0, read=True, write=True)
        self.program.run(group_x=-(-h // 64))
        self.ctx.gl.memory_barrier()
        return out
