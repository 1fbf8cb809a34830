"""Algorithm 1 as the paper runs it (Figure 21): a render pass for the first strip, then one per strip
of W_s columns, ping-ponging between two textures (reference: :func:`.reference.strip`).

Pass k draws only the columns of strips k − 1 and k: it computes strip k from the other texture and
copies strip k − 1 across, so each texture is complete up to its newest strip and a pass costs two
strips of pixels, not a whole frame."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .inputs import StereogramInputs
from .reference import strip_passes

__all__ = ["StripPass"]


class StripPass:
    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/strip.glsl")
        self.passes_run = 0  # how many render passes the last call took

    def __call__(self, inputs: StereogramInputs, max_row_start: int = 0, min_row_start: int = 0) -> moderngl.Texture:
        """``min_row_start``, ``max_row_start``: the range of the rows' start columns (0 for a whole image)."""
        w, h = inputs.size
        targets = [self.ctx.acquire((w, h), 4, "f1") for _ in range(2)]
        for t in targets:
            t.filter = (moderngl.NEAREST, moderngl.NEAREST)
        prog = self.program
        unit = inputs.bind(prog)
        set_uniform(prog, "previous", unit)
        count = strip_passes(w + max_row_start, inputs.strip_width, inputs.first_strip)
        ws, first = inputs.strip_width, inputs.first_strip
        result = 0
        for k in range(count):
            target, previous = targets[k % 2], targets[(k + 1) % 2]
            fbo = self.ctx.framebuffer([target])
            fbo.use()
            if k == 0:
                x0, x1 = 0, max_row_start + first
            else:
                lo = first + (k - 1) * ws
                x0 = 0 if k == 1 else min_row_start + lo - ws
                x1 = max_row_start + lo + ws
            x0, x1 = max(0, x0), min(w, x1)
            if x1 <= x0:
                continue  # every row is finished before this strip: the other texture is complete
            fbo.viewport = (x0, 0, x1 - x0, h)
            previous.use(unit)
            set_uniform(prog, "pass_index", k)
            set_uniform(prog, "strip_lo", inputs.first_strip + (k - 1) * inputs.strip_width)
            self.ctx.fullscreen.draw(prog)
            result = k % 2
            self.passes_run = k + 1
        self.ctx.release(targets[1 - result])
        return targets[result]
