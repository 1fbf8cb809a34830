"""Stereo composites of a left and a right image: side by side (parallel or cross-eyed), top-bottom,
and anaglyphs (Dubois's red-cyan matrices, colour, half-colour, grey). Shared by the techniques that
make stereo pairs (depth of field, image-based rendering) and the viewer. NumPy reference:
:func:`illusio.passes.reference.stereo_composite`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.gl import set_uniform
from .settings import COMPOSITES

__all__ = ["StereoCompositePass", "COMPOSITES", "ANAGLYPH_MATRICES", "composite_size"]


_LUMA = np.array([0.2126, 0.7152, 0.0722])
_RED = np.array([[1.0, 0, 0], [0, 0, 0], [0, 0, 0]])
_CYAN = np.array([[0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
_GREY_TO_RED = np.outer([1.0, 0, 0], _LUMA)
_GREY_TO_CYAN = np.outer([0, 1.0, 1.0], _LUMA)

#: anaglyph scheme -> (left matrix, right matrix) on linear RGB, rows are output channels. "anaglyph"
#: is Dubois's least-squares red-cyan projection (E. Dubois, "A projection method to generate anaglyph
#: stereo images", ICASSP 2001).
ANAGLYPH_MATRICES = {
    "anaglyph": (
        np.array([[0.456, 0.500, 0.176], [-0.040, -0.038, -0.016], [-0.015, -0.021, -0.005]]),
        np.array([[-0.043, -0.088, -0.002], [0.378, 0.734, -0.018], [-0.072, -0.113, 1.226]]),
    ),
    "anaglyph-colour": (_RED, _CYAN),
    "anaglyph-half-colour": (_GREY_TO_RED, _CYAN),
    "anaglyph-grey": (_GREY_TO_RED, _GREY_TO_CYAN),
}

_LAYOUT = {"side-by-side": 1, "cross-eyed": 2, "top-bottom": 3}


def composite_size(mode: str, size: tuple[int, int]) -> tuple[int, int]:
    """The composite's (width, height) for two images of ``size``."""
    w, h = size
    if mode not in COMPOSITES:
        raise InputError(f"unknown stereo composite {mode!r}; choose one of {', '.join(COMPOSITES)}")
    return {"side-by-side": (2 * w, h), "cross-eyed": (2 * w, h), "top-bottom": (w, 2 * h)}.get(mode, (w, h))


class StereoCompositePass:
    """``(left, right, mode)`` → the composite, RGBA8 texture (pooled). Both inputs the same size."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("passes/shaders/stereo.glsl")

    def __call__(self, left: moderngl.Texture, right: moderngl.Texture, mode: str) -> moderngl.Texture:
        if left.size != right.size:
            raise InputError(f"stereo images differ in size: {left.size} and {right.size}")
        size = composite_size(mode, left.size)
        out = self.ctx.acquire(size, 4, "f1")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, *size)
        left.use(0)
        right.use(1)
        prog = self.program
        set_uniform(prog, "left_image", 0)
        set_uniform(prog, "right_image", 1)
        set_uniform(prog, "layout_mode", _LAYOUT.get(mode, 0))
        lm, rm = ANAGLYPH_MATRICES.get(mode, (np.eye(3), np.eye(3)))
        set_uniform(prog, "left_matrix", np.asarray(lm, np.float32))
        set_uniform(prog, "right_matrix", np.asarray(rm, np.float32))
        self.ctx.gl.disable(moderngl.DEPTH_TEST)
        self.ctx.fullscreen.draw(prog)
        return out
