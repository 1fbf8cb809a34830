"""Textures on the displayed radiosity: each element is solved with the mean reflectance of the
texture it covers (texture_reflectance), far coarser than the texture, and the image is modulated
by the texture — each pixel's radiance times albedo(x) / the mean albedo of its node, the albedo
from the scene's G-buffer, where the displayed mesh carries B × that mean / ρ of the elements
(display.texture_factor) — so a textured floor shows its pattern under the light the solution gives
it (Loscos 1999, ch. 4, does the same with the photograph's textures)."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context
from ..passes.gbuffer import GBufferPass
from ..passes.gpu_scene import GpuScene
from ..scene.camera import View
from ..scene.scene import Scene
from .polygons import reflectance_image

__all__ = ["TextureModulation", "flat_albedo", "modulate"]

SHADER = "radiosity/shaders/texture_modulation.glsl"


def flat_albedo(scene: Scene) -> np.ndarray:
    """(nodes + 1, 3) float32: row 0 for "nothing", row i + 1 node i's mean reflectance (of its
    reflectance image, polygons.reflectance_image, when textured: the mean display.texture_factor uses)."""
    rows = [np.zeros(3)]
    for node in scene.nodes:
        textured = node.material.texture is not None and node.mesh.uvs is not None
        rows.append(
            reflectance_image(node.material).reshape(-1, 3).mean(axis=0) if textured else node.material.mean_albedo()
        )
    return np.asarray(rows, np.float32)


def modulate(radiance: np.ndarray, albedo: np.ndarray, object_id: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """The reference: ``radiance`` (H, W, C) times albedo / flat[object_id] per channel where the
    node's flat albedo is not zero and a node is hit (object_id (H, W) int, node index + 1)."""
    out = np.array(radiance, np.float32, copy=True)
    f = flat[object_id]
    ok = (object_id[..., None] > 0) & (f > 1e-6)
    ratio = np.where(ok, albedo[..., :3] / np.where(ok, f, 1.0), 1.0)
    out[..., :3] *= ratio.astype(np.float32)
    return out


class TextureModulation:
    """Keeps the scene's G-buffer pass and applies :func:`modulate` on the GPU. ``active``: whether
    the scene has a textured visible node (else the pass is skipped: nothing to modulate)."""

    def __init__(self, ctx: Context, scene: Scene):
        self.ctx = ctx
        self.active = any(n.visible and n.material.texture is not None for n in scene.nodes)
        self._gpu_scene = GpuScene(ctx, scene) if self.active else None
        self._gbuffer = GBufferPass(ctx) if self.active else None
        self._program = ctx.program(SHADER) if self.active else None
        self._flat = None
        if self.active:
            flat = flat_albedo(scene)
            self._flat = ctx.gl.texture((len(flat), 1), 3, flat.astype("f4").tobytes(), dtype="f4")
            self._flat.filter = (moderngl.NEAREST, moderngl.NEAREST)

    def __call__(self, radiance: moderngl.Texture, view: View) -> moderngl.Texture:
        """``radiance`` (pooled; released) modulated: a new pooled texture."""
        if not self.active:
            return radiance
        gbuffer = self._gbuffer(self._gpu_scene, view, radiance.size)
        try:
            out = self.ctx.draw_fullscreen(
                self._program,
                radiance.size,
                4,
                "f4",
                textures={
                    "radiance": radiance,
                    "albedo": gbuffer["colour"],
                    "object_id": gbuffer["object_id"],
                    "flat_albedo": self._flat,
                },
            )
        finally:
            gbuffer.release()
            self.ctx.release(radiance)
        return out

    def release(self) -> None:
        if self._gpu_scene is not None:
            self._gpu_scene.release()
            self._flat.release()
            self._gpu_scene = self._flat = None
        self.active = False
