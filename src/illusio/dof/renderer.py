"""Stereoscopic depth of field frame after frame: the DofRenderer (Renderer protocol) and the one-shot
``depth_of_field``. Both eyes share one focus (the paper's constraint); the pair is composed by the
shared stereo pass."""

from __future__ import annotations

from dataclasses import dataclass, replace

import moderngl
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.renderer import Frame, Renderer
from ..passes.scene_renderer import SceneRenderer
from ..passes.stereo import StereoCompositePass
from ..scene.camera import StereoRig, View
from ..scene.scene import Scene
from .accumulation import AccumulatePass, lens_offsets, lens_view
from .coc import CocPass
from .focus import gaze_focus, largest_focus, nearest_exhibit_focus, speed_focus
from .gather import CocTilesPass, GatherPass, SampledGatherPass
from .lens import fov_for_focal_length
from .mipmap import MipmapPass, mipmapped
from .params import DofParams
from .planes import PlanesPass, covering, plane_distances, plane_lods
from .reference import lens_samples

__all__ = ["DofRenderer", "DofResult", "depth_of_field"]


@dataclass(frozen=True)
class DofResult:
    """What a depth-of-field frame used beside its image (``DofRenderer.result()``).

    focus_distance: d_f in metres (the policy's choice when one drives the focus).
    screen_distance: metres to the zero-parallax plane the eyes converge on.
    planes: the plane distances of a planes frame, far to near (metres), else ()."""

    focus_distance: float
    screen_distance: float
    planes: tuple[float, ...] = ()

    @property
    def conflict_dioptres(self) -> float:
        """The vergence–accommodation difference |1/d_screen − 1/d_f|, dioptres (1/m)."""
        return abs(1.0 / self.screen_distance - 1.0 / self.focus_distance)


class DofRenderer(Renderer):
    """Subject: a Scene. Params: :class:`DofParams`. ``frame.view``: the cyclopean view (None: the
    scene's main camera). ``render_texture``: the image or stereo composite, linear RGBA. ``maps()``:
    "coc" (pixels, of the left eye in stereo) and "depth" (metres) of the last frame's gather, and
    "left", "right" (the two eyes) in stereo."""

    Params = DofParams
    subject_name = "a scene"

    def __init__(self, ctx: Context):
        super().__init__(ctx)
        self.scene_renderer = SceneRenderer(ctx)
        self.coc = CocPass(ctx)
        self.gather = GatherPass(ctx)
        self.coc_tiles = CocTilesPass(ctx)
        self.sampled_gather = SampledGatherPass(ctx)
        self.mipmap = MipmapPass(ctx)
        self.planes = PlanesPass(ctx)
        self.accumulate = AccumulatePass(ctx)
        self.composite = StereoCompositePass(ctx)
        self.scene: Scene | None = None
        self._last_focus: tuple[float, float, np.ndarray] | None = None  # (time, focus, eye) for the policies

    def _load(self, scene: Scene) -> None:
        if not isinstance(scene, Scene):
            raise InputError(f"DofRenderer draws a Scene, got {type(scene).__name__}")
        self.scene = scene
        self.scene_renderer.prepare(scene)

    def _unload(self) -> None:
        super()._unload()
        self._last_focus = None
        self.scene_renderer.release()
        self.scene = None

    def views(self, frame: Frame, params: DofParams) -> list[View]:
        """The views drawn: the cyclopean one, or the left and right eyes (zero parallax at
        ``screen_distance``, or at the focus distance when that is 0)."""
        self._require_subject()
        view = frame.view or self.scene.camera()
        if params.focal_length_mm > 0:
            view = View(view.pose, replace(view.camera, fov_y=fov_for_focal_length(params.focal_length_mm)))
        if params.stereo == "none":
            return [view]
        rig = StereoRig(view, params.eye_separation, params.screen_distance or params.focus_distance)
        return {"left": [rig.left], "right": [rig.right]}.get(params.stereo, [rig.left, rig.right])

    def focus(self, frame: Frame, params: DofParams) -> float:
        """The focus distance of this frame: DofParams.focus_distance, or the policy's choice followed
        with the accommodation time constant (in dioptres, from the last frame's focus)."""
        if params.policy == "none":
            return params.focus_distance
        view = frame.view or self.scene.camera()
        position = np.asarray(view.pose.position, np.float64)
        target = None
        if params.policy in ("gaze", "largest"):
            gbuffer = self.scene_renderer.gbuffer(Frame(view, frame.size))
            ids = np.rint(self.ctx.readback(gbuffer["object_id"])[..., 0]).astype(np.int64)
            depth = self.ctx.readback(gbuffer["depth"])[..., 0]
            gbuffer.release()
            if params.policy == "gaze":
                target = gaze_focus(ids, depth)
            else:
                exhibits = {i + 1 for i, n in enumerate(self.scene.nodes) if "exhibit" in n.tags}
                target = largest_focus(ids, depth, exhibits or None)
        elif params.policy == "speed":
            speed = 0.0
            if self._last_focus is not None and frame.time > self._last_focus[0]:
                speed = float(np.linalg.norm(position - self._last_focus[2])) / (frame.time - self._last_focus[0])
            target = speed_focus(speed)
        else:
            target = nearest_exhibit_focus(self.scene, view)
        target = target if target is not None else (self._last_focus[1] if self._last_focus else params.focus_distance)
        focus = target
        if self._last_focus is not None and params.accommodation > 0 and frame.time >= self._last_focus[0]:
            last_time, last_focus, _ = self._last_focus
            k = 1.0 - np.exp(-(frame.time - last_time) / params.accommodation)
            focus = 1.0 / (1.0 / last_focus + k * (1.0 / target - 1.0 / last_focus))
        self._last_focus = (frame.time, focus, position)
        return focus

    def render_texture(self, frame: Frame, params: DofParams | None = None) -> moderngl.Texture:
        params = self._params(params)
        if params.policy != "none":
            params = replace(params, focus_distance=self.focus(frame, params))
        self._result = DofResult(params.focus_distance, params.screen_distance or params.focus_distance)
        maps: dict[str, moderngl.Texture] = {}
        eyes = [
            self._eye(Frame(view, frame.size, frame.time, frame.index), params, maps, first=i == 0)
            for i, view in enumerate(self.views(frame, params))
        ]
        if len(eyes) == 1:
            self._keep_maps(maps)
            return eyes[0]
        out = self.composite(eyes[0], eyes[1], "side-by-side" if params.stereo == "left-right" else params.stereo)
        maps.update(left=eyes[0], right=eyes[1])
        self._keep_maps(maps)
        return out

    def _eye(self, frame: Frame, params: DofParams, maps: dict, first: bool) -> moderngl.Texture:
        settings = params.settings
        if params.method == "accumulation":
            target = self.accumulate.begin(frame.size)
            samples = lens_offsets(lens_samples(params.samples, params.seed), params.aperture_m)
            for offset in samples:
                view = lens_view(frame.view, tuple(offset), params.focus_distance)
                image = self.scene_renderer.render_texture(Frame(view, frame.size, frame.time, frame.index), settings)
                self.accumulate.add(target, image, 1.0 / len(samples))
                self.ctx.release(image)
            return target
        # the others blur the sharp image by its G-buffer depth and the circle of confusion
        sharp = self.scene_renderer.render_texture(frame, replace(settings, forward=False))
        depth = self.scene_renderer.maps()["depth"]
        camera = frame.view.camera
        coc = self.coc(depth, params.focus_distance, params.aperture_m, camera.fov_y, params.max_coc)
        if params.method == "gather" and params.gather_taps == 0:
            out = self.gather(sharp, coc, depth, params.max_coc)
        else:
            mip = mipmapped(self.ctx, sharp)
            if params.method == "gather":
                tiles = self.coc_tiles(coc, params.max_coc)
                out = self.sampled_gather(mip, coc, depth, tiles, params.max_coc, params.gather_taps)
                self.ctx.release(tiles)
            elif params.method == "mipmap":
                out = self.mipmap(mip, coc)
            else:  # the paper's planes
                distances = plane_distances(
                    params.focus_distance,
                    params.planes_behind,
                    params.planes_front,
                    camera.near,
                    camera.far,
                    params.distribution,
                    params.plane_scale,
                )
                drawn = covering(distances, camera.far)
                self._result = replace(self._result, planes=tuple(float(d) for d in drawn))
                lods = plane_lods(
                    distances, params.focus_distance, params.aperture_m, camera.fov_y, frame.size[1], params.max_coc
                )
                out = self.planes(mip, depth, camera, drawn, lods)
            self.ctx.release(mip)
        self.ctx.release(sharp)
        if first:
            depth_copy = self.ctx.acquire(depth.size, 1, "f4")
            self.ctx.gl.copy_framebuffer(self.ctx.framebuffer([depth_copy]), self.ctx.framebuffer([depth]))
            maps.update(coc=coc, depth=depth_copy)
        else:
            self.ctx.release(coc)
        return out


def depth_of_field(scene: Scene, params: DofParams = DofParams(), frame: Frame = Frame(), ctx: Context | None = None):
    """One image (or stereo composite) with depth of field: float32 (H, W, 3) linear, row 0 on top.
    Without ``ctx`` the process's default headless context is used; it keeps one renderer for these
    calls, holding the last scene."""
    renderer = (ctx or default_context()).kept(DofRenderer)
    renderer.prepare(scene)
    return renderer.render(frame, params)
