"""Deferred shading: Lambert + normalised Phong from point and area lights with cube shadow maps.
Reference: :func:`illusio.passes.reference.shading` (same equations, no shadows)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from .gbuffer import GBuffer
from .lights import Emitters

__all__ = ["ShadingPass", "ShadingParams", "MAX_EMITTERS", "bind_emitters"]

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
        # with and without the shadow lookups (emitters.glsl: a variant, not a uniform switch)
        self.programs = {
            shadows: ctx.program(SHADER, MAX_EMITTERS=MAX_EMITTERS, SHADOW_MAPS=int(shadows))
            for shadows in (False, True)
        }

    def __call__(
        self,
        gbuffer: GBuffer,
        emitters: Emitters,
        camera_position,
        params: ShadingParams = ShadingParams(),
        shadow_atlas: moderngl.Texture | None = None,
        shadow_matrices: np.ndarray | None = None,
        shadow_tile_size: int = 512,
    ) -> moderngl.Texture:
        w, h = gbuffer.size
        out = self.ctx.acquire((w, h), 4, "f4")
        fbo = self.ctx.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        prog = self.programs[shadow_atlas is not None]
        for unit, name in enumerate(("colour", "normal", "position", "emission")):
            gbuffer[name].use(unit)
            set_uniform(prog, f"g_{name}", unit)
        set_uniform(prog, "camera_position", np.asarray(camera_position, np.float32))
        set_uniform(prog, "background", tuple(params.background))
        bind_emitters(prog, emitters, params, shadow_atlas, shadow_matrices, shadow_tile_size, unit=4)
        self.ctx.fullscreen.draw(prog)
        return out


def bind_emitters(
    prog,
    emitters: Emitters,
    params: ShadingParams,
    shadow_atlas: moderngl.Texture | None,
    shadow_matrices: np.ndarray | None,
    shadow_tile_size: int,
    unit: int,
) -> None:
    """Set the uniforms of ``shaders/emitters.glsl`` (and the ambient term and exposure); the shadow
    atlas, if any, goes on texture ``unit`` (the program must be its SHADOW_MAPS=1 variant)."""
    k = len(emitters)

    def padded(a, width, dtype=np.float32):
        out = np.zeros((MAX_EMITTERS, width) if width else MAX_EMITTERS, dtype)
        out[:k] = a
        return out

    set_uniform(prog, "emitter_count", k)
    set_uniform(prog, "emitter_position", padded(emitters.position, 3))
    set_uniform(prog, "emitter_normal", padded(emitters.normal, 3))
    set_uniform(prog, "emitter_weight", padded(emitters.weight, 3))
    set_uniform(prog, "emitter_shadow_row", padded(emitters.shadow_row, 0, np.int32))
    set_uniform(prog, "emitter_shadow_origin", padded(emitters.shadow_origin, 3))
    set_uniform(prog, "ambient", tuple(params.ambient))
    set_uniform(prog, "exposure", float(params.exposure))
    set_uniform(prog, "min_distance", float(params.min_distance))
    if shadow_atlas is not None:  # (a program compiled with SHADOW_MAPS=1)
        shadow_atlas.use(unit)
        set_uniform(prog, "shadow_atlas", unit)
        set_uniform(prog, "shadow_face_matrices", np.ascontiguousarray(np.transpose(shadow_matrices, (0, 2, 1))))
        set_uniform(prog, "shadow_rows", int(shadow_atlas.height // shadow_tile_size))
        set_uniform(prog, "shadow_tile_size", float(shadow_tile_size))
