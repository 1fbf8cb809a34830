"""The accumulation method (section 2.2.2, [WN99]): the scene seen through N points of the lens,
averaged. Each view moves the eye within the lens disk and shears its frustum so the focal plane
stays where it is — the off-axis maths of the stereo eyes (scene.camera.StereoRig). NumPy
reference of the average: :func:`illusio.dof.reference.accumulate`."""

from __future__ import annotations

from dataclasses import replace

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View

__all__ = ["lens_view", "lens_offsets", "AccumulatePass"]


def lens_view(view: View, offset: tuple[float, float], focus_distance: float) -> View:
    """``view`` with the eye moved by ``offset`` (metres along the camera's right and up) and the
    frustum sheared by −offset / d_f, so that every point at the focus distance projects where it did."""
    right, up, _ = view.pose.axes()
    ox, oy = offset
    sx, sy = view.camera.shift
    camera = replace(view.camera, shift=(sx - ox / focus_distance, sy - oy / focus_distance))
    return View(view.pose.translated(right * ox + up * oy), camera)


class AccumulatePass:
    """Adds views into a float target: ``begin(size)`` → target, ``add(target, image, weight)``."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/accumulate.glsl")

    def begin(self, size: tuple[int, int]) -> moderngl.Texture:
        target = self.ctx.acquire(size, 4, "f4")
        fbo = self.ctx.framebuffer([target])
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        return target

    def add(self, target: moderngl.Texture, image: moderngl.Texture, weight: float) -> None:
        ctx = self.ctx
        fbo = ctx.framebuffer([target])
        fbo.use()
        fbo.viewport = (0, 0, *target.size)
        image.use(0)
        set_uniform(self.program, "image", 0)
        set_uniform(self.program, "weight", float(weight))
        ctx.gl.disable(moderngl.DEPTH_TEST)
        ctx.gl.enable(moderngl.BLEND)
        ctx.gl.blend_func = moderngl.ONE, moderngl.ONE
        try:
            ctx.fullscreen.draw(self.program)
        finally:
            ctx.gl.disable(moderngl.BLEND)
            ctx.gl.blend_func = moderngl.DEFAULT_BLENDING


def lens_offsets(samples: np.ndarray, aperture_m: float) -> np.ndarray:
    """Lens positions (N, 2) in metres from unit-disk samples: the disk of diameter A."""
    return np.asarray(samples, np.float64) * aperture_m / 2
