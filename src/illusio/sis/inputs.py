"""What every stereogram pass reads: the separation map, the pattern, each row's start and the two
whole-pixel widths, bound the same way for each program (``shaders/sis_common.glsl``)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl

from ..core.gl import set_uniform
from .params import StereogramParams

__all__ = ["StereogramInputs", "pixel_widths"]


def pixel_widths(params: StereogramParams) -> tuple[int, int]:
    """(W_s, W_s + β) in whole pixels of the (oversampled) stereogram: the smallest and largest
    rounded separation, i.e. Algorithm 1's strip width and first-strip width."""
    n = params.oversample
    return int(params.strip_width * n + 0.5), int(params.far_separation * n + 0.5)


@dataclass
class StereogramInputs:
    """separation: R32F texture (W, H); pattern: RGBA texture, tiled; row_starts: integer (H, 1)
    texture, each GL row's start column (R) and optionally one past the host's last column (G; 0 or
    absent: the image width), or None (every row starts at column 0); strip_width, first_strip:
    whole pixels."""

    separation: moderngl.Texture
    pattern: moderngl.Texture
    strip_width: int
    first_strip: int
    row_starts: moderngl.Texture | None = None

    @property
    def size(self) -> tuple[int, int]:
        return self.separation.size

    def bind(self, program, first_unit: int = 0) -> int:
        """Bind the textures from ``first_unit`` on and set the shared uniforms; returns the next free unit."""
        u = first_unit
        self.separation.use(u)
        set_uniform(program, "separation_map", u)
        self.pattern.use(u + 1)
        set_uniform(program, "pattern", u + 1)
        set_uniform(program, "row_starts", u + 2)
        if self.row_starts is not None:
            self.row_starts.use(u + 2)
        set_uniform(program, "use_row_starts", self.row_starts is not None)
        set_uniform(program, "image_height", int(self.size[1]))
        set_uniform(program, "image_width", int(self.size[0]))
        set_uniform(program, "strip_width", int(self.strip_width))
        set_uniform(program, "first_strip", int(self.first_strip))
        return u + 3
