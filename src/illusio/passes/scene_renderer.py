"""Scene -> image: G-buffer, cube shadow maps and deferred shading composed in plain Python.

``SceneRenderer`` follows the Renderer protocol (core/renderer.py): ``prepare(scene)`` once, then
``render(Frame(view, size), RenderSettings(...))`` every frame with a changed view or settings at no
set-up cost. Techniques that draw a scene keep one inside their own renderer.
"""

from __future__ import annotations

import warnings

import moderngl
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.gl import MAX_SIZE, check_size
from ..core.renderer import Frame, Renderer
from ..scene.scene import Scene
from .forward import ForwardPass, ScreenMaterial
from .gbuffer import GBuffer, GBufferPass
from .gpu_scene import GpuScene
from .lights import Emitters, emitters_from_lights
from .settings import RenderSettings
from .shading import MAX_EMITTERS, ShadingParams, ShadingPass
from .shadows import ShadowPass

__all__ = ["SceneRenderer", "RenderSettings", "render_scene", "MAX_SIZE", "check_size", "UnlitSceneWarning"]


class UnlitSceneWarning(UserWarning):
    """A scene the rasteriser is given with no lamp and no ambient light: it draws only what emitting
    surfaces give off themselves (an MGF scene's light comes from its emitting surfaces, which only
    radiosity and path tracing carry to the rest)."""


class SceneRenderer(Renderer):
    """Owns the G-buffer, shadow and shading passes for one context; its subject is a Scene, its
    params a :class:`RenderSettings`. ``maps()`` holds the last deferred frame's G-buffer (colour,
    depth, normal, position, object_id, emission)."""

    Params = RenderSettings
    subject_name = "a scene"

    def __init__(self, ctx: Context, settings: RenderSettings = RenderSettings()):
        super().__init__(ctx)
        self.settings = settings  # used when a frame is rendered with params=None
        self.gbuffer_pass = GBufferPass(ctx)
        self.shading_pass = ShadingPass(ctx)
        self.forward_pass = ForwardPass(ctx)
        self._shadow_passes: dict[int, ShadowPass] = {}
        self._gpu_scene: GpuScene | None = None
        self.scene: Scene | None = None
        self._static: tuple[tuple, moderngl.Texture, moderngl.Texture] | None = None  # see render_forward
        self._last_key: tuple | None = None  # the static key of the last reuse_static frame
        self._shadows: tuple[tuple, moderngl.Texture, np.ndarray] | None = None  # see _lights

    def _load(self, scene: Scene) -> None:
        if not isinstance(scene, Scene):
            raise InputError(f"SceneRenderer draws a Scene, got {type(scene).__name__}")
        self.scene = scene
        self._gpu_scene = GpuScene(self.ctx, scene)
        if not scene.lights and not any(scene.ambient):
            glows = any(node.visible and max(node.material.emission) > 0 for node in scene.nodes)
            warnings.warn(
                f"{scene.name}: no lamp and no ambient light: "
                + (
                    "the rasteriser draws only its emitting surfaces' own glow (their light reaches the "
                    "rest by radiosity: illusio radiosity, or a path-traced capture)"
                    if glows
                    else "the rasteriser draws it black"
                ),
                UnlitSceneWarning,
                stacklevel=3,
            )

    def _unload(self) -> None:
        super()._unload()
        self._drop_static()
        self._drop_shadows()
        self._last_key = None
        if self._gpu_scene is not None:
            self._gpu_scene.release()
            self._gpu_scene = None
        self.scene = None

    @property
    def gpu_scene(self) -> GpuScene:
        """The GPU copy of the prepared scene."""
        self._require_subject()
        return self._gpu_scene

    def _params(self, params):
        return super()._params(params if params is not None else self.settings)

    def _view(self, frame: Frame):
        return frame.view if frame.view is not None else self.scene.camera()

    def gbuffer(self, frame: Frame) -> GBuffer:
        """The G-buffer textures (pooled: release them)."""
        return self.gbuffer_pass(self.gpu_scene, self._view(frame), frame.size)

    def render_texture(self, frame: Frame, params: RenderSettings | None = None, gbuffer_hook=None) -> moderngl.Texture:
        """Linear radiance as an RGBA float32 texture (pooled: release it).

        ``gbuffer_hook(gbuffer)``, if given, runs between the G-buffer and shading and may replace
        G-buffer textures (a technique re-texturing a surface in screen space; it releases what it
        replaces). It needs the deferred path: ``settings.forward`` must be off."""
        s = self._params(params)
        if s.forward:
            if gbuffer_hook is not None:
                raise InputError("a G-buffer hook needs the deferred path (RenderSettings(forward=False))")
            self._keep_maps({})
            return self.render_forward(frame, s)[0]
        gpu = self.gpu_scene
        view = self._view(frame)
        gbuf = self.gbuffer_pass(gpu, view, frame.size)
        if gbuffer_hook is not None:
            gbuffer_hook(gbuf)
        emitters, atlas, matrices = self._lights(gpu, s)
        params = ShadingParams(self.scene.ambient, self.scene.background, s.exposure)
        out = self.shading_pass(gbuf, emitters, view.pose.position, params, atlas, matrices, s.shadow_tile_size)
        self._keep_maps(dict(gbuf.textures))  # the G-buffer stays readable until the next frame
        return out

    def render_forward(
        self,
        frame: Frame,
        settings: RenderSettings | None = None,
        screen_material: ScreenMaterial | None = None,
        object_ids: bool = False,
        reuse_static: bool = False,
    ) -> tuple[moderngl.Texture, moderngl.Texture | None]:
        """The forward path: (radiance RGBA float32, object ids R32F or None), both pooled.
        ``screen_material``: nodes coloured from a screen-space texture (see :class:`ScreenMaterial`).
        ``reuse_static``: frame after frame where only the screen texture changes (a stereogram on a TV
        seen by a still camera), keep the rest of the image and its depth and shade only the
        screen-material nodes. The rest is kept from the second frame with an unchanged scene (by
        value, as prepared), view, size and settings (a frame that differs from the last is drawn
        whole in one pass: a moving camera gains nothing from a layer used once); the same image
        either way."""
        s = self._params(settings)
        gpu = self.gpu_scene
        view = self._view(frame)
        size = frame.size
        emitters, atlas, matrices = self._lights(gpu, s)
        params = ShadingParams(self.scene.ambient, self.scene.background, s.exposure)
        if reuse_static and screen_material is not None and not object_ids:
            key = (self._subject_key, view, size, s, screen_material.nodes)
            kept = self._static is not None and self._static[0] == key
            if not kept and key == self._last_key:  # the view stood still: keep the rest from now on
                self._drop_static()
                base, depth = self.forward_pass.static_layer(
                    gpu, view, size, emitters, params, atlas, matrices, s.shadow_tile_size, screen_material.nodes
                )
                self._static = (key, base, depth)
                kept = True
            self._last_key = key
            if kept:
                _, base, depth = self._static
                out = self.forward_pass.dynamic_layer(
                    base, depth, gpu, view, emitters, params, atlas, matrices, s.shadow_tile_size, screen_material
                )
                return out, None
            # a moving view: one whole pass is cheaper than building a layer used once
            self._drop_static()
        return self.forward_pass(
            gpu, view, size, emitters, params, atlas, matrices, s.shadow_tile_size, screen_material, object_ids
        )

    @property
    def static_layer_kept(self) -> bool:
        """Whether a forward static layer is kept for the next frame (see render_forward)."""
        return self._static is not None

    def _drop_static(self) -> None:
        if self._static is not None:
            self.ctx.release(self._static[1])
            self._static[2].release()
            self._static = None

    def _lights(self, gpu: GpuScene, s: RenderSettings) -> tuple[Emitters, moderngl.Texture | None, np.ndarray | None]:
        """The scene's emitters and, with shadows on, their shadow atlas and face matrices. The atlas
        depends only on the scene (lights and geometry) and the tile size, so it is kept from frame
        to frame until either changes (the renderer owns it: callers do not release it)."""
        scene = self.scene
        emitters = emitters_from_lights(scene.lights, s.shadows, MAX_EMITTERS)
        if not (s.shadows and (emitters.shadow_row >= 0).any()):
            return emitters, None, None
        key = (self._subject_key, s.shadow_tile_size)
        if self._shadows is None or self._shadows[0] != key:
            self._drop_shadows()
            lo, hi = scene.bounds()
            far = float(np.linalg.norm(hi - lo)) * 2 + 1.0
            shadow = self._shadow_passes.setdefault(s.shadow_tile_size, ShadowPass(self.ctx, s.shadow_tile_size))
            atlas, matrices = shadow(gpu, emitters.shadow_positions, 0.02, far)
            self._shadows = (key, atlas, matrices)
        return emitters, self._shadows[1], self._shadows[2]

    def _drop_shadows(self) -> None:
        if self._shadows is not None:
            self.ctx.release(self._shadows[1])
            self._shadows = None


def render_scene(
    scene: Scene, view=None, size=(640, 480), ctx: Context | None = None, settings: RenderSettings = RenderSettings()
) -> np.ndarray:
    """One-shot render of ``scene`` (its ``main`` camera by default): float32 (H, W, 3), row 0 on
    top. Without ``ctx``, the process's default headless context is used (and kept). The context
    keeps one renderer for these calls, holding the last scene: called again with a scene equal by
    value, nothing is uploaded again."""
    renderer = (ctx or default_context()).kept(SceneRenderer)
    renderer.prepare(scene)
    return renderer.render(Frame(view, size), settings)
