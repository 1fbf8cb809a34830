"""Depth → separation map, and each row's start column (reference: :func:`.reference.separation`)."""

from __future__ import annotations

import moderngl

from ..core.context import Context
from ..core.gl import set_uniform
from .params import StereogramParams

__all__ = ["SeparationPass", "RowStartPass", "bind_depth_mapping"]


def bind_depth_mapping(program, unit: int, params: StereogramParams) -> None:
    """Set the uniforms of ``shaders/depth_to_separation.glsl`` (the depth texture is on ``unit``)."""
    near, far = params.depth_range_cm
    for name, value in (
        ("depth_map", unit),
        ("strip_width_px", float(params.strip_width)),
        ("depth_factor", float(params.depth_factor)),
        ("invert", params.invert != params.cross_eyed),
        ("exact", bool(params.exact)),
        ("near_cm", near),
        ("far_cm", far),
        ("eye_separation_px", float(params.eye_separation_px)),
        ("viewing_distance_cm", float(params.screen.viewing_distance_cm)),
        ("oversample", int(params.oversample)),
    ):
        set_uniform(program, name, value)


class SeparationPass:
    """depth (R32F, D in [0, 1], 0 = near, < 0 off the host) → separation (R32F, pixels) at
    ``oversample`` times the width."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/separation.glsl")

    def __call__(self, depth: moderngl.Texture, params: StereogramParams) -> moderngl.Texture:
        w, h = depth.size
        n = params.oversample
        out = self.ctx.acquire((w * n, h), 1, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w * n, h)
        depth.use(0)
        bind_depth_mapping(self.program, 0, params)
        self.ctx.fullscreen.draw(self.program)
        return out


class RowStartPass:
    """depth with negative values off the host → RG32I (H, 1): each GL row's first host column and one
    past its last, times the oversampling factor (both the width if the row has none)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("sis/shaders/row_start.glsl")

    def __call__(
        self, depth: moderngl.Texture, oversample: int = 1, columns: tuple[int, int] | None = None
    ) -> moderngl.Texture:
        """``columns``: (first, end) — the host lies within these columns of ``depth`` (fewer to search)."""
        w, h = depth.size
        first, end = columns if columns is not None else (0, w)
        out = self.ctx.acquire((h, 1), 2, "i4")
        depth.use(0)
        set_uniform(self.program, "depth_map", 0)
        set_uniform(self.program, "oversample", int(oversample))
        set_uniform(self.program, "first_column", int(first))
        set_uniform(self.program, "end_column", int(end))
        out.bind_to_image(0, read=False, write=True)
        self.program.run(group_x=-(-h // 64))
        self.ctx.gl.memory_barrier()
        return out
