"""The fast formulation, two layouts of the same recurrence (both give the sequential image):

* ``FastPass`` (the default ``fast`` algorithm): one compute dispatch, depth in, stereogram out. One
  invocation per row walks it, deriving each separation from the depth on the fly (no separation
  pass). Reference: :func:`.reference.sequential`.
* ``ChainPass``: one full-screen pass over a separation map where every pixel follows its chain
  x → x − s(x) back to the first strip on its own — all pixels in parallel, no order at all, the layout
  for GPUs with many more cores than rows. Reference: :func:`.reference.chain`.
"""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .inputs import StereogramInputs, pixel_widths
from .params import StereogramParams
from .separation import bind_depth_mapping

__all__ = ["FastPass", "ChainPass"]

GL_R32UI = 0x8236  # the RGBA8 output viewed as one word per texel


class FastPass:
    def __init__(self, ctx: Context, rows_per_group: int = 16):
        self.ctx = ctx
        self.rows_per_group = rows_per_group
        self.program = ctx.program("sis/shaders/sequential.glsl", FROM_DEPTH=1, ROWS_PER_GROUP=rows_per_group)

    def __call__(
        self,
        depth: moderngl.Texture,
        pattern: moderngl.Texture,
        params: StereogramParams,
        row_starts: moderngl.Texture | None = None,
        end_column: int | None = None,
    ) -> moderngl.Texture:
        """depth: D (R32F, logical width); returns RGBA8 at ``oversample`` times the width (pooled).
        With ``row_starts``, only the columns from each row's start on are computed, and with
        ``end_column`` (output pixels) only those before it (the others keep what the pooled texture
        held): what a host surface shows, at a fraction of the cost."""
        w, h = depth.size
        w *= params.oversample
        strip_width, first_strip = pixel_widths(params)
        prog = self.program
        out = self.ctx.acquire((w, h), 4, "f1")
        depth.use(0)
        bind_depth_mapping(prog, 0, params)
        pattern.use(1)
        set_uniform(prog, "pattern", 1)
        set_uniform(prog, "row_starts", 2)
        if row_starts is not None:
            row_starts.use(2)
        set_uniform(prog, "use_row_starts", row_starts is not None)
        set_uniform(prog, "image_height", h)
        set_uniform(prog, "image_width", w)
        set_uniform(prog, "strip_width", strip_width)
        set_uniform(prog, "first_strip", first_strip)
        set_uniform(prog, "end_column", int(w if end_column is None else end_column))
        out.bind_to_image(0, read=True, write=True, format=GL_R32UI)
        prog.run(group_x=-(-h // self.rows_per_group))
        self.ctx.gl.memory_barrier()
        return out


class ChainPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/chain.glsl")

    def __call__(self, inputs: StereogramInputs) -> moderngl.Texture:
        w, h = inputs.size
        out = self.ctx.acquire((w, h), 4, "f1")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        inputs.bind(self.program)
        self.ctx.fullscreen.draw(self.program)
        return out
