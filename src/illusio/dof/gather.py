"""The depth-aware gather (shaders/gather.glsl). NumPy reference: :func:`illusio.dof.reference.gather`."""

from __future__ import annotations

import math

import moderngl

from ..core.context import Context
from .reference import DEPTH_SLACK

__all__ = ["GatherPass"]


class GatherPass:
    """``(image, coc, depth, max_coc)`` → the blurred image, RGBA float32 (pooled). The kernel spans
    ceil(max_coc / 2) pixels each way."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/gather.glsl")

    def __call__(self, image: moderngl.Texture, coc: moderngl.Texture, depth: moderngl.Texture, max_coc: float,
                 depth_slack: float = DEPTH_SLACK) -> moderngl.Texture:
        return self.ctx.draw_fullscreen(self.program, image.size, textures={"image": image, "coc": coc, "depth": depth},
                                        radius=int(math.ceil(max_coc / 2)), depth_slack=float(depth_slack))
