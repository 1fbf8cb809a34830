"""Scene -> image: G-buffer, cube shadow maps and deferred shading composed in plain Python.

``SceneRenderer`` keeps compiled passes and the GPU copy of the last scene, so a window can call
:meth:`SceneRenderer.render` every frame with a changed view or parameters at no set-up cost.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..scene.camera import View
from ..scene.scene import Scene
from .forward import ForwardPass, ScreenMaterial
from .gbuffer import GBuffer, GBufferPass
from .gpu_scene import GpuScene
from .lights import Emitters, emitters_from_lights
from .shading import MAX_EMITTERS, ShadingParams, ShadingPass
from .shadows import ShadowPass

__all__ = ["SceneRenderer", "RenderSettings", "render_scene", "MAX_SIZE"]

MAX_SIZE = 8192


@dataclass(frozen=True)
class RenderSettings:
    """shadows: cube shadow maps on/off; shadow_tile_size: pixels per cube face;
    exposure: scale on the linear result; forward: light the surfaces in the pass that draws them
    instead of through the G-buffer (same image; faster where G-buffer bandwidth dominates, as on a
    CPU rasteriser at high resolution)."""

    shadows: bool = True
    shadow_tile_size: int = 512
    exposure: float = 1.0
    forward: bool = False


def check_size(size) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in size)
    except (TypeError, ValueError):
        raise InputError(f"image size must be (width, height), got {size!r}") from None
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise InputError(f"image size {w}×{h} is out of range (1..{MAX_SIZE} per side)")
    return w, h


class SceneRenderer:
    """Owns the G-buffer, shadow and shading passes for one context."""

    def __init__(self, ctx: Context, settings: RenderSettings = RenderSettings()):
        self.ctx = ctx
        self.settings = settings
        self.gbuffer_pass = GBufferPass(ctx)
        self.shading_pass = ShadingPass(ctx)
        self.forward_pass = ForwardPass(ctx)
        self._shadow_passes: dict[int, ShadowPass] = {}
        self._gpu_scene: GpuScene | None = None
        self._static: tuple[bytes, moderngl.Texture, moderngl.Texture] | None = None  # see render_forward
        self._last_key: bytes | None = None  # the static key of the last reuse_static frame

    def prepare(self, scene: Scene) -> GpuScene:
        """The GPU copy of ``scene``, uploaded on first use (call :meth:`invalidate` after edits)."""
        if self._gpu_scene is None or self._gpu_scene.scene is not scene:
            self.invalidate()
            self._gpu_scene = GpuScene(self.ctx, scene)
        return self._gpu_scene

    def invalidate(self) -> None:
        self._drop_static()
        self._last_key = None
        if self._gpu_scene is not None:
            self._gpu_scene.release()
            self._gpu_scene = None

    def gbuffer(self, scene: Scene, view: View, size) -> GBuffer:
        """The G-buffer textures (pooled: release them)."""
        return self.gbuffer_pass(self.prepare(scene), view, check_size(size))

    def render_texture(self, scene: Scene, view: View, size, settings: RenderSettings | None = None,
                       gbuffer_hook=None) -> moderngl.Texture:
        """Linear radiance as an RGBA float32 texture (pooled: release it).

        ``gbuffer_hook(gbuffer)``, if given, runs between the G-buffer and shading and may replace
        G-buffer textures (a technique re-texturing a surface in screen space; it releases what it
        replaces). It needs the deferred path: ``settings.forward`` must be off."""
        s = settings or self.settings
        if s.forward:
            if gbuffer_hook is not None:
                raise InputError("a G-buffer hook needs the deferred path (RenderSettings(forward=False))")
            return self.render_forward(scene, view, size, s)[0]
        size = check_size(size)
        gpu = self.prepare(scene)
        gbuf = self.gbuffer_pass(gpu, view, size)
        if gbuffer_hook is not None:
            gbuffer_hook(gbuf)
        emitters, atlas, matrices = self._lights(scene, gpu, s)
        params = ShadingParams(scene.ambient, scene.background, s.exposure)
        out = self.shading_pass(gbuf, emitters, view.pose.position, params, atlas, matrices, s.shadow_tile_size)
        gbuf.release()
        if atlas is not None:
            self.ctx.release(atlas)
        return out

    def render_forward(self, scene: Scene, view: View, size, settings: RenderSettings | None = None,
                       screen_material: ScreenMaterial | None = None, object_ids: bool = False,
                       reuse_static: bool = False) -> tuple[moderngl.Texture, moderngl.Texture | None]:
        """The forward path: (radiance RGBA float32, object ids R32F or None), both pooled.
        ``screen_material``: nodes coloured from a screen-space texture (see :class:`ScreenMaterial`).
        ``reuse_static``: frame after frame where only the screen texture changes (a stereogram on a TV
        seen by a still camera), keep the rest of the image and its depth and shade only the
        screen-material nodes. The rest is kept from the second frame with an unchanged scene, lights,
        view, size and settings (a frame that differs from the last is drawn whole in one pass: a
        moving camera gains nothing from a layer used once); the same image either way."""
        s = settings or self.settings
        size = check_size(size)
        gpu = self.prepare(scene)
        emitters, atlas, matrices = self._lights(scene, gpu, s)
        params = ShadingParams(scene.ambient, scene.background, s.exposure)
        try:
            if reuse_static and screen_material is not None and not object_ids:
                key = _static_key(scene, view, size, s, emitters, screen_material.nodes)
                kept = self._static is not None and self._static[0] == key
                if not kept and key == self._last_key:  # the view stood still: keep the rest from now on
                    self._drop_static()
                    base, depth = self.forward_pass.static_layer(gpu, view, size, emitters, params, atlas, matrices,
                                                                 s.shadow_tile_size, screen_material.nodes)
                    self._static = (key, base, depth)
                    kept = True
                self._last_key = key
                if kept:
                    _, base, depth = self._static
                    out = self.forward_pass.dynamic_layer(base, depth, gpu, view, emitters, params, atlas, matrices,
                                                          s.shadow_tile_size, screen_material)
                    return out, None
                # a moving view: one whole pass is cheaper than building a layer used once
                self._drop_static()
            return self.forward_pass(gpu, view, size, emitters, params, atlas, matrices, s.shadow_tile_size,
                                     screen_material, object_ids)
        finally:
            if atlas is not None:
                self.ctx.release(atlas)

    def _drop_static(self) -> None:
        if self._static is not None:
            self.ctx.release(self._static[1])
            self._static[2].release()
            self._static = None

    def _lights(self, scene: Scene, gpu: GpuScene, s: RenderSettings) -> tuple[Emitters, moderngl.Texture | None, np.ndarray | None]:
        """The scene's emitters and, with shadows on, their shadow atlas (pooled) and face matrices."""
        emitters = emitters_from_lights(scene.lights, s.shadows, MAX_EMITTERS)
        if not (s.shadows and (emitters.shadow_row >= 0).any()):
            return emitters, None, None
        lo, hi = scene.bounds()
        far = float(np.linalg.norm(hi - lo)) * 2 + 1.0
        shadow = self._shadow_passes.setdefault(s.shadow_tile_size, ShadowPass(self.ctx, s.shadow_tile_size))
        atlas, matrices = shadow(gpu, emitters.shadow_positions, 0.02, far)
        return emitters, atlas, matrices

    def render(self, scene: Scene, view: View | None = None, size=(640, 480), settings: RenderSettings | None = None) -> np.ndarray:
        """Float32 (H, W, 3) linear colour in [0, 1], row 0 on top."""
        tex = self.render_texture(scene, view or scene.camera(), size, settings)
        try:
            return np.clip(self.ctx.readback(tex, 3), 0.0, 1.0)
        finally:
            self.ctx.release(tex)


def render_scene(scene: Scene, view: View | None = None, size=(640, 480), ctx: Context | None = None,
                 settings: RenderSettings = RenderSettings()) -> np.ndarray:
    """One-shot render of ``scene`` (its ``main`` camera by default); creates a context if needed."""
    own = ctx is None
    ctx = ctx or Context()
    try:
        return SceneRenderer(ctx, settings).render(scene, view, size)
    finally:
        if own:
            ctx.release_all()


def _static_key(scene: Scene, view: View, size, settings: RenderSettings, emitters: Emitters, dynamic) -> bytes:
    """A digest of everything the static layer of a forward frame depends on."""
    h = hashlib.sha256()
    h.update(repr((id(scene), tuple(size), settings, sorted(dynamic), scene.ambient, scene.background)).encode())
    h.update(view.view_matrix().tobytes())
    h.update(view.projection_matrix(size[0] / size[1]).tobytes())
    for node in scene.nodes:
        m = node.material
        h.update(repr((node.visible, id(node.mesh), m.colour, m.specular, m.shininess, m.emission, id(m.texture))).encode())
        h.update(node.transform.tobytes())
    for a in (emitters.position, emitters.normal, emitters.weight, emitters.shadow_row):
        h.update(np.ascontiguousarray(a).tobytes())
    return h.digest()
