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

__all__ = ["DISTRIBUTIONS", "plane_distances", "plane_lods", "window_depth", "PlanesPass"]

#: how the planes are spread: "exponential" (the paper: geometric in distance from the focal plane
#: outwards, dense near it) or "linear"
DISTRIBUTIONS = ("exponential", "linear")


def plane_distances(focus: float, behind: int, front: int, near: float, far: float,
                    distribution: str = "exponential") -> np.ndarray:
    """View depths of the m + n + 1 planes, far to near: ``behind`` planes from the focal plane out to
    ``far`` (the last at ``far``, so every surface has a plane behind it), the focal plane, and
    ``front`` planes down to ``near``. Exponential: z_i = d_f·(far/d_f)^(i/m) behind and
    d_f·(near/d_f)^(j/n) in front — the paper's exponential spreading around the focal plane: behind,
    gaps grow with the distance from it; in front, the planes close in geometrically towards the
    camera, so their circles of confusion (linear in 1/z) grow by increasing steps."""
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"plane distribution must be one of {', '.join(DISTRIBUTIONS)}, got {distribution!r}")
    focus = float(np.clip(focus, near * 1.0001, far * 0.9999))
    i = np.arange(behind, 0, -1) / max(behind, 1)
    j = np.arange(1, front + 1) / max(front, 1)
    if distribution == "exponential":
        back, ahead = focus * (far / focus) ** i, focus * (near / focus) ** j
    else:
        back, ahead = focus + (far - focus) * i, focus - (focus - near) * j
    return np.concatenate([back, [focus], ahead])


def plane_lods(distances: np.ndarray, focus: float, aperture_m: float, fov_y: float, height: int, max_coc: float) -> np.ndarray:
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
    """``(mipmapped image, linear depth, camera, distances, lods)`` → the blurred image, RGBA32F."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program("dof/shaders/planes.glsl")
        self.depth_program = ctx.program("dof/shaders/planes.glsl", DEPTH_FROM_LINEAR=1)

    def __call__(self, image: moderngl.Texture, linear_depth: moderngl.Texture, camera: Camera,
                 distances: np.ndarray, lods: np.ndarray) -> moderngl.Texture:
        ctx = self.ctx
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
