"""The paper's method (sections 3.1–3.2, shaders/planes.glsl): m planes behind and n in front of the
focal plane, each textured with the mipmap level of its own circle of confusion, drawn far to near
with depth writes off and the depth test GREATER against the scene's depth. NumPy reference:
:func:`illusio.dof.reference.planes`."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.gl import set_uniform
from ..scene.camera import Camera
from .lens import coc_pixels

__all__ = ["DISTRIBUTIONS", "plane_distances", "covering", "plane_lods", "window_depth", "PlanesPass"]

#: how the planes are spread: "exponential" (the paper's law, dense near the focal plane) or "linear"
#: (even gaps over the same range)
DISTRIBUTIONS = ("exponential", "linear")


def plane_distances(
    focus: float,
    behind: int,
    front: int,
    near: float,
    far: float,
    distribution: str = "exponential",
    scale: float = 0.0,
) -> np.ndarray:
    """View depths of the m + n + 1 planes, far to near, spread around the focal plane by the
    paper's law (section 3.1): the planes have the density f(x) = e^(−x/z0)/z0 in x, the distance
    from the focal plane, with z0 = ``scale`` (0: the focal plane's distance from the camera, as
    the paper has it). So the k-th of the m planes behind sits at the k/(m + 1) quantile of f,
    x_k = −z0·ln(1 − k/(m + 1)): the gaps grow away from the focus. In front, x cannot pass the
    near plane: the same law truncated to [0, d_f − near], x_j = −z0·ln(1 − j/(n + 1)·(1 −
    e^(−(d_f − near)/z0))). "linear": even gaps over the same two ranges.

    The farthest plane covers every surface beyond it: the renderer draws it at the far plane
    (:func:`covering`) while its blur stays that of its own distance."""
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"plane distribution must be one of {', '.join(DISTRIBUTIONS)}, got {distribution!r}")
    focus = float(np.clip(focus, near * 1.0001, far * 0.9999))
    z0 = float(scale) if scale > 0 else focus
    room = focus - near
    k = np.arange(behind, 0, -1) / (behind + 1)  # far to near
    j = np.arange(1, front + 1) / (front + 1)
    back = -z0 * np.log1p(-k)
    ahead = -z0 * np.log1p(-j * -np.expm1(-room / z0))
    if distribution == "linear":  # the outermost plane of each side where the law has it
        back = back[0] * k / k[0] if behind else back
        ahead = ahead[-1] * j / j[-1] if front else ahead
    return np.concatenate([np.minimum(focus + back, far * 0.9999), [focus], np.maximum(focus - ahead, near)])


def covering(distances: np.ndarray, far: float) -> np.ndarray:
    """The depths the planes are drawn at: the farthest moved to the far plane, so that a surface
    behind every plane still has one behind it (it takes the farthest plane's blur)."""
    drawn = np.array(distances, np.float64)
    drawn[0] = max(drawn[0], far)
    return drawn


def plane_lods(
    distances: np.ndarray, focus: float, aperture_m: float, fov_y: float, height: int, max_coc: float
) -> np.ndarray:
    """The mipmap level of each plane: log2(max(c_i, 1)), c_i its circle of confusion (≤ max_coc)."""
    c = np.minimum(coc_pixels(distances, focus, aperture_m, fov_y, height), max_coc)
    return np.log2(np.maximum(c, 1.0))


def window_depth(camera: Camera, aspect: float, z) -> np.ndarray:
    """Window depth in [0, 1] of view depth ``z`` (metres) through the camera's projection."""
    p = camera.projection(aspect).astype(np.float64)
    z = np.asarray(z, np.float64)
    clip_z = -p[2, 2] * z + p[2, 3]
    clip_w = z  # the last row is (0, 0, −1, 0)
    return (clip_z / clip_w) * 0.5 + 0.5


class PlanesPass:
    """``(mipmapped image, linear depth, camera, distances, lods)`` → the blurred image, RGBA32F. The
    farthest plane is drawn at the camera's far plane (:func:`covering`); the rest where given."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/planes.glsl")
        self.depth_program = ctx.program("dof/shaders/planes.glsl", DEPTH_FROM_LINEAR=1)

    def __call__(
        self,
        image: moderngl.Texture,
        linear_depth: moderngl.Texture,
        camera: Camera,
        distances: np.ndarray,
        lods: np.ndarray,
    ) -> moderngl.Texture:
        ctx = self.ctx
        distances = covering(distances, camera.far)  # every surface has a plane behind it
        w, h = linear_depth.size
        p = camera.projection(w / h).astype(np.float64)
        # window depth = 0.5 + 0.5 (−p22 z + p23) / z = (0.5 − 0.5 p22) + 0.5 p23 / z
        depth_map = (0.5 - 0.5 * p[2, 2], 0.5 * p[2, 3])
        out = ctx.acquire((w, h), 4, "f4")
        scene_depth = ctx.gl.depth_texture((w, h))
        fbo = ctx.gl.framebuffer(color_attachments=[out], depth_attachment=scene_depth)
        try:
            fbo.use()
            fbo.viewport = (0, 0, w, h)
            fbo.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
            # first pass, the scene's depth: written through the depth test ALWAYS
            ctx.gl.enable(moderngl.DEPTH_TEST)
            ctx.gl.depth_func = "1"
            linear_depth.use(0)
            set_uniform(self.depth_program, "linear_depth", 0)
            set_uniform(self.depth_program, "depth_map", tuple(float(v) for v in depth_map))
            fbo.color_mask = (False, False, False, False)
            ctx.fullscreen.draw(self.depth_program)
            fbo.color_mask = (True, True, True, True)
            # second pass: planes far to near, depth writes off, GREATER
            fbo.depth_mask = False
            ctx.gl.depth_func = ">"
            image.use(0)
            set_uniform(self.program, "image", 0)
            window = window_depth(camera, w / h, distances)
            for z_window, lod in zip(window, lods):
                set_uniform(self.program, "plane_depth", float(min(z_window, 1.0)))
                set_uniform(self.program, "lod", float(lod))
                ctx.fullscreen.draw(self.program)
        finally:
            fbo.depth_mask = True
            ctx.gl.depth_func = "<"
            ctx.gl.disable(moderngl.DEPTH_TEST)
            ctx.release_framebuffer(fbo)
            scene_depth.release()
        return out
