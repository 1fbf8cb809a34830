"""Deferred shading: Lambert + normalised Phong from point and area lights with cube shadow maps.
Reference: :func:`illusio.passes.reference.shading` (same equations, no shadows)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from .gbuffer import GBuffer
from .gpu_scene import set_uniform
from .lights import Emitters

__all__ = ["ShadingPass", "ShadingParams", "MAX_EMITTERS"]

SHADER = "passes/shaders/shading.glsl"
MAX_EMITTERS = 64


@dataclass(frozen=True)
class ShadingParams:
    """ambient: constant term multiplied by albedo; background: colour where nothing was hit;
    exposure: scale on the result; min_distance: r_min, clamps 1/r² near an emitter (metres)."""

    ambient: tuple[float, float, float] = (0.08, 0.08, 0.09)
    background: tuple[float, float, float] = (0.0, 0.0, 0.0)
    exposure: float = 1.0
    min_distance: float = 0.1


class ShadingPass:
    """G-buffer + emitters (+ shadow atlas) -> linear radiance, RGBA float32 (pooled texture)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.program = ctx.program(SHADER, MAX_EMITTERS=MAX_EMITTERS)

    def __call__(self, gbuffer: GBuffer, emitters: Emitters, camera_position, params: ShadingParams = ShadingParams(),
                 shadow_atlas: moderngl.Texture | None = None, shadow_matrices: np.ndarray | None = None,
                 shadow_tile_size: int = 512) -> moderngl.Texture:
        w, h = gbuffer.size
        out = self.ctx.acquire((w, h), 4, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        prog = self.program
        for unit, name in enumerate(("colour", "normal", "position", "emission")):
            gbuffer[name].use(unit)
            set_uniform(prog, f"g_{name}", unit)
        k = len(emitters)

        def padded(a, width, dtype=np.float32):
            out_a = np.zeros((MAX_EMITTERS, width) if width else MAX_EMITTERS, dtype)
            out_a[:k] = a
            return out_a

        set_uniform(prog, "emitter_count", k)
        set_uniform(prog, "emitter_position", padded(emitters.position, 3))
        set_uniform(prog, "emitter_normal", padded(emitters.normal, 3))
        set_uniform(prog, "emitter_weight", padded(emitters.weight, 3))
        set_uniform(prog, "emitter_shadow_row", padded(emitters.shadow_row, 0, np.int32))
        set_uniform(prog, "emitter_shadow_origin", padded(emitters.shadow_origin, 3))
        set_uniform(prog, "camera_position", np.asarray(camera_position, np.float32))
        set_uniform(prog, "ambient", tuple(params.ambient))
        set_uniform(prog, "background", tuple(params.background))
        set_uniform(prog, "exposure", float(params.exposure))
        set_uniform(prog, "min_distance", float(params.min_distance))
        use_shadows = shadow_atlas is not None
        set_uniform(prog, "use_shadows", use_shadows)
        if use_shadows:
            shadow_atlas.use(4)
            set_uniform(prog, "shadow_atlas", 4)
            set_uniform(prog, "shadow_face_matrices", np.ascontiguousarray(np.transpose(shadow_matrices, (0, 2, 1))))
            set_uniform(prog, "shadow_rows", int(shadow_atlas.height // shadow_tile_size))
            set_uniform(prog, "shadow_tile_size", float(shadow_tile_size))
        else:
            set_uniform(prog, "shadow_atlas", 4)
        self.ctx.fullscreen.draw(prog)
        return out
