"""The depth-aware gather (shaders/gather.glsl) and its sampled estimate (shaders/coc_tiles.glsl,
shaders/gather_taps.glsl). NumPy references: :func:`illusio.dof.reference.gather`,
:func:`~illusio.dof.reference.coc_tiles`, :func:`~illusio.dof.reference.gather_taps`."""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ..core.context import Context
from .reference import DEPTH_SLACK, MAX_TAPS, disk_spiral, tile_size

__all__ = ["GatherPass", "CocTilesPass", "SampledGatherPass"]


class GatherPass:
    """``(image, coc, depth, max_coc)`` → the blurred image, RGBA float32 (pooled). The kernel spans
    ceil(max_coc / 2) pixels each way."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/gather.glsl")

    def __call__(
        self,
        image: moderngl.Texture,
        coc: moderngl.Texture,
        depth: moderngl.Texture,
        max_coc: float,
        depth_slack: float = DEPTH_SLACK,
    ) -> moderngl.Texture:
        return self.ctx.draw_fullscreen(
            self.program,
            image.size,
            textures={"image": image, "coc": coc, "depth": depth},
            radius=int(math.ceil(max_coc / 2)),
            depth_slack=float(depth_slack),
        )


class CocTilesPass:
    """``(coc, max_coc)`` → R32F, one texel per tile of ``tile_size(max_coc)`` pixels: the largest
    covering radius max(c/2, ½) over the tile and its eight neighbours (pooled)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/coc_tiles.glsl")

    def __call__(self, coc: moderngl.Texture, max_coc: float) -> moderngl.Texture:
        tile = tile_size(max_coc)
        w, h = coc.size
        return self.ctx.draw_fullscreen(
            self.program, (-(-w // tile), -(-h // tile)), 1, textures={"coc": coc}, tile=tile
        )


class SampledGatherPass:
    """``(mipmapped image, coc, depth, tiles, max_coc, taps)`` → the gather estimated from ``taps``
    points of a disk per pixel, RGBA float32 (pooled). ``tiles``: :class:`CocTilesPass`'s output."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/gather_taps.glsl")

    def __call__(
        self,
        image: moderngl.Texture,
        coc: moderngl.Texture,
        depth: moderngl.Texture,
        tiles: moderngl.Texture,
        max_coc: float,
        taps: int,
        depth_slack: float = DEPTH_SLACK,
    ) -> moderngl.Texture:
        if not 1 <= taps <= MAX_TAPS:
            raise ValueError(f"taps must be in [1, {MAX_TAPS}], got {taps}")
        spiral = np.zeros((MAX_TAPS, 2), np.float32)
        spiral[:taps] = disk_spiral(taps)
        self.program["spiral"].write(spiral.tobytes())
        return self.ctx.draw_fullscreen(
            self.program,
            image.size,
            textures={"image": image, "coc": coc, "depth": depth, "tiles": tiles},
            tile=tile_size(max_coc),
            taps=int(taps),
            depth_slack=float(depth_slack),
        )
