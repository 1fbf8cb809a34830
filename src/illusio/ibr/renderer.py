"""New views from reference views, frame after frame: the IbrRenderer (Renderer protocol) and the
one-shot ``render_views``. First pass: the reconstruction mesh drawn into the new view's depth and
its holes filled, on the GPU (only when the camera or the size changed); second pass: the per-pixel
choice of the reference (SelectPass), whose resolve draw lights the chosen attributes again with the
set's lights (moved by IbrParams.light_offset) as the shared deferred shading would; ``gbuffer()``
gives the chosen attributes themselves."""

from __future__ import annotations

from dataclasses import replace

import moderngl
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.renderer import Frame, Renderer
from ..passes.gbuffer import GBuffer
from ..passes.lights import emitters_from_lights
from ..passes.shading import MAX_EMITTERS, ShadingParams
from .depth_pass import ReconstructPass
from .params import IbrParams
from .proxy_mesh import reconstruction
from .reference_views import ReferenceSet
from .select import ReferenceArrays, SelectPass

__all__ = ["IbrRenderer", "render_views", "SOURCE_COLOURS", "source_view", "fill_holes", "fill_hits"]

#: the debug view's colour of each reference (Figure 4.5: red, green, blue first), holes magenta
SOURCE_COLOURS = np.array(
    [
        (0.9, 0.15, 0.1),
        (0.15, 0.75, 0.2),
        (0.15, 0.3, 0.95),
        (0.95, 0.8, 0.1),
        (0.1, 0.8, 0.85),
        (0.6, 0.35, 0.15),
        (0.5, 0.5, 0.5),
        (0.95, 0.55, 0.75),
    ],
    np.float32,
)
HOLE_COLOUR = np.array((1.0, 0.0, 1.0), np.float32)


def _fill_from_rings(source: np.ndarray, empty: np.ndarray, radius: int, key: int) -> np.ndarray:
    """``source`` (H, W, C; row 0 at the top) with each ``empty`` pixel replaced by the texel of the
    first square ring around it, nearest first, up to ``radius``, that holds anything (component
    ``key`` > 0): the one with the largest ``key`` there, the first in ring order on a tie (rings.glsl's
    order: rows from the bottom, as GL counts them). No ring holds anything: it stays."""
    out = source.copy()
    h, w = out.shape[:2]
    for y, x in zip(*np.nonzero(empty)):
        for r in range(1, int(radius) + 1):
            ring = [
                (y - dy, x + dx)
                for dy in range(-r, r + 1)
                for dx in range(-r, r + 1)  # GL rows go up
                if max(abs(dx), abs(dy)) == r
            ]
            found = [source[q] for q in ring if 0 <= q[0] < h and 0 <= q[1] < w and source[q][key] > 0]
            if found:
                out[y, x] = max(found, key=lambda texel: texel[key])  # max keeps the first of equals
                break
    return out


def fill_holes(depth: np.ndarray, radius: int) -> np.ndarray:
    """``depth`` (0 = nothing) with its holes filled: a hole pixel takes the farthest depth of the
    nearest ring around it holding depth, up to ``radius`` pixels away. Holes come from mesh
    triangles cut at occlusion edges, where the surface behind shows: the farthest neighbour finds
    it in the references."""
    z = np.asarray(depth, np.float32)[..., None]
    return _fill_from_rings(z, z[..., 0] <= 0, radius, 0)[..., 0]


def fill_hits(hits: np.ndarray, reconstructed: np.ndarray, radius: int) -> np.ndarray:
    """``hits`` (H, W, 4: uv, reference depth, reference index + 1, 0 = none; row 0 at the top) with
    its disocclusions — pixels where ``reconstructed`` (H, W) has depth and no reference saw the
    point — filled: such a pixel takes, from the nearest ring around it holding hits (up to
    ``radius``), the hit whose reference saw the farthest point (the background goes on behind the
    occluder)."""
    source = np.asarray(hits, np.float32)
    return _fill_from_rings(source, (source[..., 3] == 0) & (np.asarray(reconstructed) > 0), radius, 2)


def source_view(source: np.ndarray) -> np.ndarray:
    """(H, W) source indices (reference + 1, 0 = hole) → the debug colours (H, W, 3)."""
    s = np.asarray(source, np.int64)
    colours = SOURCE_COLOURS[(np.maximum(s, 1) - 1) % len(SOURCE_COLOURS)]
    return np.where((s == 0)[..., None], HOLE_COLOUR, colours).astype(np.float32)


class IbrRenderer(Renderer):
    """Subject: a :class:`ReferenceSet`. Params: :class:`IbrParams`. ``frame.view``: the new camera
    (None: the first reference's). ``maps()``: "depth" (the reconstructed depth) and "source" (reference
    index + 1 per pixel, 0 = hole, R32F); :meth:`gbuffer`: the new view's G-buffer."""

    Params = IbrParams
    subject_name = "a ReferenceSet"

    def __init__(self, ctx: Context):
        super().__init__(ctx)
        self.reconstruct = ReconstructPass(ctx)
        self.select = SelectPass(ctx)
        self.refs: ReferenceSet | None = None
        self._arrays: ReferenceArrays | None = None
        self._mesh_key = None
        self._depth: tuple | None = None  # (view, size, mesh key, texture): the first pass's result

    def _load(self, refs: ReferenceSet) -> None:
        if not isinstance(refs, ReferenceSet):
            raise InputError(f"IbrRenderer draws a ReferenceSet, got {type(refs).__name__}")
        self.refs = refs
        self._arrays = ReferenceArrays(self.ctx, refs.views)

    def _unload(self) -> None:
        super()._unload()
        if self._arrays is not None:
            self._arrays.release()
            self._arrays = None
        self._drop_depth()
        self.reconstruct.release()
        self.select.release()
        self._mesh_key = None
        self.refs = None

    def _drop_depth(self) -> None:
        if self._depth is not None:
            self._forget_map(self._depth[4])
            self.ctx.release(self._depth[4])
            self._depth = None

    def reconstructed_depth(self, view, size, params: IbrParams) -> moderngl.Texture:
        """The first pass: the reconstruction mesh's linear depth in ``view``, holes filled (kept while
        the view, the size and the mesh settings stay the same)."""
        mesh_key = (params.mesh_step, params.grazing)
        if mesh_key != self._mesh_key:
            self.reconstruct.load(reconstruction(self.refs, params.mesh_step, params.grazing))
            self._mesh_key = mesh_key
        key = (view, tuple(size), mesh_key, params.fill_radius)
        if self._depth is None or self._depth[:4] != key:
            self._drop_depth()
            self._depth = (*key, self.reconstruct(view, size, params.fill_radius))
        return self._depth[4]

    def _selection(self, params: IbrParams) -> dict:
        """SelectPass's arguments after the new view, its depth and the references."""
        return dict(
            use_3d=params.distance == "3d",
            bilinear=params.bilinear_depth,
            max_distance=params.max_distance,
            photographic=not params.relight,
            single_pass=params.selection == "single-pass",
            fill=0 if params.show_sources else params.fill_disocclusions,
        )

    def gbuffer(self, frame: Frame, params: IbrParams | None = None) -> GBuffer:
        """The new view's G-buffer (the chosen reference's albedo, normal, emission; the corrected
        depth and position; the source index as object id): release it."""
        params = self._params(params)
        self._require_subject()
        view = frame.view or self.refs.views[0].view
        return self.select(
            self.reconstructed_depth(view, frame.size, params), view, self._arrays, **self._selection(params)
        )

    def render_texture(self, frame: Frame, params: IbrParams | None = None) -> moderngl.Texture:
        params = self._params(params)
        self._require_subject()
        view = frame.view or self.refs.views[0].view
        depth = self.reconstructed_depth(view, frame.size, params)
        lights = [
            replace(light, position=tuple(np.asarray(light.position) + params.light_offset))
            if hasattr(light, "position")
            else replace(light, centre=tuple(np.asarray(light.centre) + params.light_offset))
            for light in self.refs.lights
        ]
        emitters = emitters_from_lights(lights if params.relight else [], False, MAX_EMITTERS)
        ambient = self.refs.ambient if params.relight else (0.0, 0.0, 0.0)
        shading = ShadingParams(ambient, self.refs.background, params.settings.exposure)
        out, source = self.select.shaded(depth, view, self._arrays, emitters, shading, **self._selection(params))
        self._keep_maps({"depth": depth, "source": source})
        if params.show_sources:
            self.ctx.release(out)
            index = np.rint(self.ctx.readback(source)[..., 0]).astype(np.int64)
            out = self.ctx.acquire_upload(np.dstack([source_view(index), np.ones(index.shape, np.float32)]))
        return out


def render_views(
    refs: ReferenceSet, frame: Frame, params: IbrParams = IbrParams(), ctx: Context | None = None
) -> np.ndarray:
    """One new view from ``refs``: float32 (H, W, 3) linear, row 0 on top (the context keeps the
    renderer and its last reference set)."""
    renderer = (ctx or default_context()).kept(IbrRenderer)
    renderer.prepare(refs)
    return renderer.render(frame, params)
