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
from dataclasses import dataclass, replace

import moderngl
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError, did_you_mean
from ..core.renderer import Frame, Renderer
from ..passes.forward import ScreenMaterial
from ..passes.gpu_scene import GpuScene
from ..passes.scene_renderer import SceneRenderer
from ..scene.camera import Pose, View
from ..scene.scene import Node, Scene
from ..scene.transforms import transform_points
from .depth import HiddenDepthPass
from .host_projection import HostProjectionPass
from .params import MultiSceneParams
from .separation import RowStartPass
from .stereogram import StereogramRenderer

__all__ = ["MultiSceneParams", "MultiSceneRenderer", "MultiSceneSubject", "hidden_view_from_viewer", "multiscene"]


def host_nodes(scene: Scene, host: str) -> list[tuple[int, Node]]:
    found = [(i, n) for i, n in enumerate(scene.nodes) if n.visible and (n.name == host or host in n.tags)]
    if not found:
        hosts = sorted({n.name for n in scene.nodes if n.visible and "host" in n.tags})
        named = sorted({n.name for n in scene.nodes if n.visible} | {t for n in scene.nodes for t in n.tags})
        raise InputError(
            f"scene {scene.name!r} has no visible node named or tagged {host!r} to show the stereogram on"
            f"{did_you_mean(host, named)}; its hosts: {', '.join(hosts) or 'none tagged'}"
        )
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


@dataclass(frozen=True)
class MultiSceneSubject:
    """What a multi-scene image draws: the main scene (with the host surface) and the hidden scene
    whose depth the stereogram encodes."""

    main: Scene
    hidden: Scene


class MultiSceneRenderer(Renderer):
    """Every pass of Figure 22 for one context (the Renderer protocol).

    Subject: :class:`MultiSceneSubject` (or a ``(main, hidden)`` pair). Params:
    :class:`MultiSceneParams`. ``frame.view`` is the main scene's camera (None: its main camera);
    ``frame.index`` drives the snow and the spin. ``maps()``: "depth" (the hidden scene's D in screen
    space, −1 off the host), "stereogram" (RGBA8, at oversample × the width) and, with
    ``object_ids = True``, "object_id" (node index + 1; then every frame is drawn whole)."""

    Params = MultiSceneParams
    subject_name = "a MultiSceneSubject(main, hidden)"

    def __init__(self, ctx: Context):
        super().__init__(ctx)
        self.scene_renderer = SceneRenderer(ctx)
        self.stereograms = StereogramRenderer(ctx)
        self.hidden_depth = HiddenDepthPass(ctx)
        self.row_start = RowStartPass(ctx)
        self.host_projection = HostProjectionPass(ctx)
        self._hidden_gpu: GpuScene | None = None
        self.subject: MultiSceneSubject | None = None
        self.object_ids = False

    def prepare(self, subject) -> bool:
        if isinstance(subject, tuple) and len(subject) == 2:
            subject = MultiSceneSubject(*subject)
        if not isinstance(subject, MultiSceneSubject):
            raise InputError(
                f"MultiSceneRenderer draws a MultiSceneSubject(main, hidden), got {type(subject).__name__}"
            )
        return super().prepare(subject)

    def _load(self, subject: MultiSceneSubject) -> None:
        self.subject = subject
        self.scene_renderer.prepare(subject.main)
        self._hidden_gpu = GpuScene(self.ctx, subject.hidden)

    def _unload(self) -> None:
        super()._unload()
        self.scene_renderer.release()
        if self._hidden_gpu is not None:
            self._hidden_gpu.release()
            self._hidden_gpu = None
        self.subject = None

    def release(self) -> None:
        super().release()
        self.stereograms.release()

    def hidden_view(self, view: View, params: MultiSceneParams, frame: int) -> View:
        scene, hidden = self.subject.main, self.subject.hidden
        base = hidden.camera()
        if params.interactive:
            base = hidden_view_from_viewer(host_nodes(scene, params.host)[0][1], view, hidden, base)
        if params.spin:
            lo, hi = hidden.bounds()
            centre = (np.asarray(lo) + np.asarray(hi)) / 2
            offset = np.asarray(base.pose.position) - centre
            a = math.radians(params.spin * frame)
            rotated = np.array(
                [
                    offset[0] * math.cos(a) + offset[2] * math.sin(a),
                    offset[1],
                    -offset[0] * math.sin(a) + offset[2] * math.cos(a),
                ]
            )
            base = View(Pose(tuple(centre + rotated), tuple(centre), base.pose.up), base.camera)
        return base

    def render_texture(self, frame: Frame, params: MultiSceneParams | None = None) -> moderngl.Texture:
        """Linear radiance, RGBA float32 texture (pooled)."""
        params = self._params(params)
        self._require_subject()
        scene = self.subject.main
        w, h = frame.size
        view = frame.view or scene.camera()
        hosts = host_nodes(scene, params.host)
        sis = params.scaled_stereogram(w)
        ctx = self.ctx
        extent = np.sort(np.ptp(np.asarray(hosts[0][1].mesh.bounds, np.float64), axis=0))[::-1]
        aspect = float(extent[0] / max(extent[1], 1e-9))
        hidden_size = (params.hidden_size, max(1, int(round(params.hidden_size / aspect))))

        # (1) the hidden scene's depth image
        hidden_depth = self.hidden_depth(self._hidden_gpu, self.hidden_view(view, params, frame.index), hidden_size)
        # (3) the pattern image: snow made for this frame, or the texture
        pattern, owned = self.stereograms.pattern_texture(sis, hidden_size, frame.index)
        # (2) + (4) both projected to screen space through the host
        box = self.viewer_box(hosts, view, (w, h), hidden_size) if params.host_layout == "viewer" else None
        depth_screen, pattern_screen = self.host_projection(
            self.scene_renderer.gpu_scene, hosts, view, (w, h), hidden_depth, pattern, params.pattern_repeat, box
        )
        ctx.release(hidden_depth)
        if owned:
            ctx.release(pattern)
        # (5) the stereogram in screen space, each row from the host's left edge
        span = self._host_columns(hosts, view, (w, h))
        row_starts = self.row_start(depth_screen, sis.oversample, span)
        stereo = self.stereograms.stereogram_texture(
            depth_screen,
            sis,
            frame.index,
            row_starts,
            max_row_start=span[1] * sis.oversample,
            min_row_start=span[0] * sis.oversample,
            pattern=pattern_screen,
            end_column=span[1] * sis.oversample,
        )
        stereo.filter = (moderngl.LINEAR, moderngl.LINEAR)
        ctx.release(pattern_screen, row_starts)
        # (6) the main scene, lit in one forward pass, the host coloured (and, for a TV, lit) by the
        # stereogram as a screen-space texture
        tint = tuple(float(c) for c in hosts[0][1].material.colour) if params.emission == 0 else (1.0, 1.0, 1.0)
        material = ScreenMaterial(
            stereo, frozenset(i for i, _ in hosts), tint, float(params.emission), params.host_shadows
        )
        settings = replace(params.settings, forward=True)
        out, ids = self.scene_renderer.render_forward(
            Frame(view, (w, h), frame.time, frame.index),
            settings,
            material,
            object_ids=self.object_ids,
            reuse_static=params.reuse_static,
        )
        self._keep_maps({"depth": depth_screen, "stereogram": stereo, "object_id": ids})
        return out

    def host_mask(self, params: MultiSceneParams | None = None) -> np.ndarray:
        """(H, W) bool: where the last frame shows the host (needs ``object_ids = True``)."""
        params = self._params(params)
        ids = self._maps.get("object_id")
        if ids is None:
            raise InputError("host_mask needs object ids: set renderer.object_ids = True before the frame")
        host_ids = np.array([i + 1 for i, _ in host_nodes(self.subject.main, params.host)], np.float32)
        return np.isin(np.rint(self.ctx.readback(ids)[..., 0]), host_ids)

    def decode_frame(self, image: np.ndarray, params: MultiSceneParams | None = None):
        """Self-check of the last frame ``image`` (H, W, 3) as a viewer sees it: decoded where the host
        is seen (needs ``object_ids = True``), after one global exposure gain (the host's 99th
        percentile to 1, not a relighting), against the separations its screen-space depth asks for,
        each row from the host's left edge. Returns (the sis.decode report, that depth: −1 off the host)."""
        from .decode import check
        from .reference import separation

        params = self._params(params)
        depth = self.ctx.readback(self._maps["depth"])[..., 0]
        seen, on_host = self.host_mask(params), depth >= 0
        sis = params.scaled_stereogram(image.shape[1])
        sep = separation(np.where(on_host, depth, 1.0), sis.strip_width, sis.depth_factor)
        rows = np.where(on_host.any(axis=1), on_host.argmax(axis=1), image.shape[1]).astype(np.int32)
        gain = 1.0 / max(float(np.percentile(image[seen], 99)), 1e-6) if seen.any() else 1.0
        report = check(
            np.where(seen[..., None], np.clip(image * gain, 0, 1), 0),
            sep,
            int(sis.far_separation + 0.5),
            "left",
            row_start=rows,
        )
        return report, np.where(on_host, depth, -1.0)

    @staticmethod
    def viewer_box(hosts, view: View, size, hidden_size) -> tuple[float, float, float, float]:
        """The "viewer" layout's rectangle (x0, y0, x1, y1 pixels, row 0 on top): the hidden depth
        image's aspect, as large as fits in the screen rectangle around the hosts' bounding boxes
        (clipped to the screen), centred in it."""
        w, h = size
        px = _host_screen_corners(hosts, view, size)
        if px is None:
            x0, y0, x1, y1 = 0.0, 0.0, float(w), float(h)  # partly behind the eye: the screen
        else:
            x0, y0 = np.clip(px.min(axis=0), 0, (w, h))
            x1, y1 = np.clip(px.max(axis=0), 0, (w, h))
        aspect = hidden_size[0] / hidden_size[1]
        bw, bh = max(x1 - x0, 1e-6), max(y1 - y0, 1e-6)
        fw, fh = (bh * aspect, bh) if bw / bh > aspect else (bw, bw / aspect)
        cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
        return (float(cx - fw / 2), float(cy - fh / 2), float(cx + fw / 2), float(cy + fh / 2))

    @staticmethod
    def _host_columns(hosts, view: View, size) -> tuple[int, int]:
        """Leftmost and rightmost screen column the hosts' bounding boxes project to (clamped)."""
        w = size[0]
        px = _host_screen_corners(hosts, view, size)
        if px is None:
            return 0, w  # partly behind the eye: its screen extent is unbounded
        return int(np.clip(np.floor(px[:, 0].min()), 0, w)), int(np.clip(np.ceil(px[:, 0].max()), 0, w))


def _host_screen_corners(hosts, view: View, size) -> np.ndarray | None:
    """Pixel coordinates (x right, y down) of the corners of every host's bounding box, or None when
    one is behind the eye (its screen extent is then unbounded)."""
    points = []
    for _, node in hosts:
        lo, hi = node.mesh.bounds
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        points.append(transform_points(node.transform, corners))
    px, depth = view.project(np.concatenate(points), size)
    return None if (depth <= 0).any() else px


def multiscene(
    main: Scene,
    hidden: Scene,
    frame: Frame = Frame(),
    params: MultiSceneParams = MultiSceneParams(),
    ctx: Context | None = None,
) -> np.ndarray:
    """One multi-scene image: float32 (H, W, 3) linear, row 0 on top. Without ``ctx`` the process's
    default headless context is used; the context keeps one renderer for these calls."""
    renderer = (ctx or default_context()).kept(MultiSceneRenderer)
    renderer.prepare(MultiSceneSubject(main, hidden))
    return renderer.render(frame, params)
