"""Multi-scene images (Dehos et al. 2014, section 4, Figure 22): a stereogram computed in screen space
and shown on a surface of a 3D scene, so one image holds the main scene (eyes on the screen) and a
hidden scene (eyes focused behind it).

Per frame: (1) the hidden scene's depth D; (2) D projected to screen space through the host surface's
uvs, and (3)-(4) the pattern (TV snow, remade every frame, or a texture) projected the same way, in
one pass with two outputs; (5) the stereogram in screen space, each row starting at the host's left
edge; (6) the main scene in one forward pass, the stereogram as the host's albedo (and emission, for
a TV) sampled in screen space.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..passes.forward import ScreenMaterial
from ..passes.gpu_scene import GpuScene, set_uniform
from ..passes.scene_renderer import RenderSettings, SceneRenderer, check_size
from ..scene.camera import Pose, View
from ..scene.scene import Node, Scene
from ..scene.transforms import transform_points
from .depth import HiddenDepthPass
from .params import StereogramParams
from .separation import RowStartPass
from .stereogram import StereogramRenderer

__all__ = ["MultiSceneParams", "MultiSceneRenderer", "hidden_view_from_viewer"]


@dataclass(frozen=True)
class MultiSceneParams:
    """host: name or tag of the surface that shows the stereogram. stereogram: its parameters, with
    W_s and β given for a frame ``reference_width`` pixels wide (scaled to the frame actually drawn,
    so the physical separations hold at any size).
    hidden_size: pixels of the hidden depth image's longer side (its aspect is the host's).
    emission: how bright the host glows with its stereogram (a TV: > 0; a painted wall: 0).
    pattern_repeat: pattern tiles across the host (u, v). interactive: orient the hidden scene by
    where the viewer stands relative to the host (Figure 25). spin: degrees per frame the hidden
    scene turns (animated hidden scene). settings: lighting of the main scene (shadows off by
    default: hard shadows on a stereogram disturb it, section 6). reuse_static: while the main scene,
    the view and the settings stay the same from one frame to the next (a still camera on an animated
    TV), only the host is shaded again; the image is the same either way."""

    host: str = "tv-screen"
    stereogram: StereogramParams = field(default_factory=lambda: StereogramParams(pattern="snow", strip_width=100, depth_factor=40))
    reference_width: int = 1920
    hidden_size: int = 512
    emission: float = 0.9
    pattern_repeat: tuple[float, float] = (1.0, 1.0)
    interactive: bool = False
    spin: float = 0.0
    settings: RenderSettings = field(default_factory=lambda: RenderSettings(shadows=False))
    reuse_static: bool = True

    def scaled_stereogram(self, width: int) -> StereogramParams:
        """The stereogram parameters for a frame ``width`` pixels wide."""
        k = width / self.reference_width
        return replace(self.stereogram, strip_width=self.stereogram.strip_width * k,
                       depth_factor=self.stereogram.depth_factor * k,
                       screen=replace(self.stereogram.screen, width_px=int(round(self.stereogram.screen.width_px * k)), height_px=None))


def host_nodes(scene: Scene, host: str) -> list[tuple[int, Node]]:
    found = [(i, n) for i, n in enumerate(scene.nodes) if n.visible and (n.name == host or host in n.tags)]
    if not found:
        raise InputError(f"scene {scene.name!r} has no visible node named or tagged {host!r} to show the stereogram on")
    return found


def hidden_view_from_viewer(host: Node, viewer: View, hidden: Scene, base: View) -> View:
    """Figure 25: the hidden scene seen from the direction the viewer sees the host from. The host's
    local frame (its plane's normal is local +y, local −z is "up" on the surface) is mapped onto the
    hidden scene's frame (normal → +z towards the default camera, up → +y), and the hidden camera
    orbits the hidden scene's centre at its default distance."""
    inverse = np.linalg.inv(host.transform.astype(np.float64))
    local = transform_points(inverse, np.asarray([viewer.pose.position], np.float64))[0]
    direction = np.array([local[0], -local[2], local[1]], np.float64)
    if np.linalg.norm(direction) < 1e-9:
        return base
    direction /= np.linalg.norm(direction)
    lo, hi = hidden.bounds()
    centre = (np.asarray(lo) + np.asarray(hi)) / 2
    distance = float(np.linalg.norm(np.asarray(base.pose.position) - centre))
    azimuth = math.degrees(math.atan2(direction[0], direction[2]))
    elevation = math.degrees(math.asin(np.clip(direction[1], -1, 1)))
    return View(Pose.orbit(tuple(centre), distance, azimuth, elevation), base.camera)


class MultiSceneRenderer:
    """Keeps every pass of Figure 22 for one context; call :meth:`render_texture` or :meth:`render`
    every frame (frame number drives the snow and the spin)."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.scene_renderer = SceneRenderer(ctx)
        self.stereograms = StereogramRenderer(ctx)
        self.hidden_depth = HiddenDepthPass(ctx)
        self.row_start = RowStartPass(ctx)
        self.projection = ctx.program("sis/shaders/host_projection.glsl")
        self._hidden_gpu: GpuScene | None = None
        self.last_depth: np.ndarray | None = None  # set by render(..., keep_depth=True)

    def release(self) -> None:
        """Free the GPU copies of both scenes and the kept layers (the renderer stays usable)."""
        self.scene_renderer.invalidate()
        self.stereograms.release()
        if self._hidden_gpu is not None:
            self._hidden_gpu.release()
            self._hidden_gpu = None

    def _hidden(self, hidden: Scene) -> GpuScene:
        if self._hidden_gpu is None or self._hidden_gpu.scene is not hidden:
            if self._hidden_gpu is not None:
                self._hidden_gpu.release()
            self._hidden_gpu = GpuScene(self.ctx, hidden)
        return self._hidden_gpu

    def hidden_view(self, scene: Scene, hidden: Scene, view: View, params: MultiSceneParams, frame: int) -> View:
        base = hidden.camera()
        if params.interactive:
            base = hidden_view_from_viewer(host_nodes(scene, params.host)[0][1], view, hidden, base)
        if params.spin:
            lo, hi = hidden.bounds()
            centre = (np.asarray(lo) + np.asarray(hi)) / 2
            offset = np.asarray(base.pose.position) - centre
            a = math.radians(params.spin * frame)
            rotated = np.array([offset[0] * math.cos(a) + offset[2] * math.sin(a), offset[1],
                                -offset[0] * math.sin(a) + offset[2] * math.cos(a)])
            base = View(Pose(tuple(centre + rotated), tuple(centre), base.pose.up), base.camera)
        return base

    def render_texture(self, scene: Scene, hidden: Scene, view: View | None = None, size=(1920, 1080),
                       params: MultiSceneParams = MultiSceneParams(), frame: int = 0,
                       keep: dict | None = None) -> moderngl.Texture:
        """Linear radiance, RGBA float32 texture (pooled). ``keep``: a dict that receives the screen-space
        depth and stereogram as arrays (for figures and tests)."""
        w, h = check_size(size)
        view = view or scene.camera()
        hosts = host_nodes(scene, params.host)
        sis = params.scaled_stereogram(w)
        ctx = self.ctx
        extent = np.sort(np.ptp(np.asarray(hosts[0][1].mesh.bounds, np.float64), axis=0))[::-1]
        aspect = float(extent[0] / max(extent[1], 1e-9))
        hidden_size = (params.hidden_size, max(1, int(round(params.hidden_size / aspect))))

        gpu = self.scene_renderer.prepare(scene)
        # (1) the hidden scene's depth image
        hidden_depth = self.hidden_depth(self._hidden(hidden), self.hidden_view(scene, hidden, view, params, frame), hidden_size)
        hidden_depth.filter = (moderngl.LINEAR, moderngl.LINEAR)
        # (3) the pattern image: snow made for this frame, or the texture
        pattern, owned = self.stereograms.pattern_texture(sis, hidden_size, frame)
        pattern.repeat_x = pattern.repeat_y = True
        pattern.filter = (moderngl.NEAREST, moderngl.NEAREST)
        # (2) + (4) both projected to screen space through the host: the nearest host surface over
        # its whole extent, whatever stands in front of it (an occluder must not cut the rows)
        depth_screen = ctx.acquire((w, h), 1, "f4")
        pattern_screen = ctx.acquire((w, h), 4, "f1")
        fbo = ctx.framebuffer([depth_screen, pattern_screen], depth=True)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(-1.0, 0.0, 0.0, 0.0, depth=1.0)
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.disable(moderngl.CULL_FACE)
        prog = self.projection
        set_uniform(prog, "view_matrix", view.view_matrix())
        set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
        hidden_depth.use(0)
        pattern.use(1)
        for name, value in (("hidden_depth", 0), ("pattern", 1), ("pattern_repeat", tuple(float(v) for v in params.pattern_repeat))):
            set_uniform(prog, name, value)
        for index, node in hosts:
            if node.mesh.uvs is None:
                raise InputError(f"host {node.name!r} has no texture coordinates to carry a stereogram")
            set_uniform(prog, "uv_min", tuple(float(v) for v in node.mesh.uvs.min(axis=0)))
            set_uniform(prog, "uv_max", tuple(float(v) for v in node.mesh.uvs.max(axis=0)))
            set_uniform(prog, "model_matrix", node.transform)
            gpu.vao(prog, node).render(moderngl.TRIANGLES)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        ctx.release(hidden_depth)
        if owned:
            ctx.release(pattern)
        # (5) the stereogram in screen space, each row from the host's left edge
        span = self._host_columns(hosts, view, (w, h))
        row_starts = self.row_start(depth_screen, sis.oversample, span)
        stereo = self.stereograms.render_texture(depth_screen, sis, frame, row_starts,
                                                 max_row_start=span[1] * sis.oversample,
                                                 min_row_start=span[0] * sis.oversample, pattern=pattern_screen,
                                                 end_column=span[1] * sis.oversample)
        stereo.filter = (moderngl.LINEAR, moderngl.LINEAR)
        ctx.release(pattern_screen, row_starts)
        # (6) the main scene, lit in one forward pass, the host coloured (and, for a TV, lit) by the
        # stereogram as a screen-space texture
        tint = tuple(float(c) for c in hosts[0][1].material.colour) if params.emission == 0 else (1.0, 1.0, 1.0)
        material = ScreenMaterial(stereo, frozenset(i for i, _ in hosts), tint, float(params.emission))
        settings = replace(params.settings, forward=True)
        out, ids = self.scene_renderer.render_forward(scene, view, (w, h), settings, material, object_ids=keep is not None,
                                                      reuse_static=params.reuse_static)
        if keep is not None:
            keep["depth"] = ctx.readback(depth_screen)[..., 0]
            host_ids = np.array([i + 1 for i, _ in hosts], np.float32)
            keep["visible"] = np.isin(np.rint(ctx.readback(ids)[..., 0]), host_ids)
            keep["stereogram"] = ctx.readback(stereo, 3)
            ctx.release(ids)
        ctx.release(depth_screen, stereo)
        return out

    @staticmethod
    def _host_columns(hosts, view: View, size) -> tuple[int, int]:
        """Leftmost and rightmost screen column the hosts' bounding boxes project to (clamped)."""
        w, h = size
        xs = []
        for _, node in hosts:
            lo, hi = node.mesh.bounds
            corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
            px, depth = view.project(transform_points(node.transform, corners), (w, h))
            if (depth <= 0).any():
                return 0, w  # partly behind the eye: its screen extent is unbounded
            xs.extend(px[:, 0].tolist())
        xs = np.asarray(xs, np.float64)
        return int(np.clip(np.floor(xs.min()), 0, w)), int(np.clip(np.ceil(xs.max()), 0, w))

    def render(self, scene: Scene, hidden: Scene, view: View | None = None, size=(1920, 1080),
               params: MultiSceneParams = MultiSceneParams(), frame: int = 0, keep: dict | None = None) -> np.ndarray:
        """Float32 (H, W, 3) linear colour in [0, 1], row 0 on top."""
        tex = self.render_texture(scene, hidden, view, size, params, frame, keep)
        try:
            return np.clip(self.ctx.readback(tex, 3), 0.0, 1.0)
        finally:
            self.ctx.release(tex)
