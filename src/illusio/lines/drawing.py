"""Line drawings: the LineRenderer combines the hybrid apparent ridges (GPU, two passes), image- or
object-space silhouettes, suggestive contours, ridges and valleys into one image, each line type in
its own colour and width. It follows the Renderer protocol (illusio.core.renderer): ``prepare(mesh)``
once, then ``render(Frame(view, size), LineParams(...))`` every frame; the mesh's curvature (keyed by
its CurvatureParams) and GPU buffers are kept between frames.

Thresholds are relative to the mesh's curvature scale (Curvature.scale(): the 90th percentile of
|k|), so the defaults suit meshes of any size and detail; ``relative=False`` gives the report's raw
τ (q = 2^τ q1 with q1 in 1/units)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numba
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.renderer import Frame, Renderer
from ..scene.camera import Camera, Pose, View
from ..scene.mesh import Mesh
from .compose import ComposePass
from .curvature import Curvature, estimate_curvature
from .gpu_mesh import CurvatureMesh
from .object_space import (
    Segments,
    apparent_ridges,
    boundaries,
    contours,
    dwkr_lines,
    isophotes,
    mean_zero_lines,
    parabolic_lines,
    principal_highlights,
    ridges,
    suggestive_contours,
    suggestive_highlights,
    valleys,
)
from .params import LINE_TYPES, CurvatureParams, LineParams
from .reference import view_curvature
from .ridge_filter import RidgeFilterPass
from .segments import SegmentsPass
from .view_curvature import ViewCurvaturePass

__all__ = [
    "LINE_TYPES",
    "LineParams",
    "LineRenderer",
    "framing_view",
    "hugging_camera",
    "Drawing",
    "drop_short_fragments",
    "line_drawing",
]


@dataclass
class Drawing:
    """A rendered drawing: image (H, W, 3) float32 linear, row 0 at the top; segments per object-space
    line type (object space, before visibility); the view and size it was drawn with; q_t1 (H, W, 4):
    q, t1 and view depth (0 = background); ridge_mask (H, W) bool: the hybrid ridge pixels kept (None
    without hybrid apparent ridges)."""

    image: np.ndarray
    segments: dict[str, Segments]
    view: View
    size: tuple[int, int]
    q_t1: np.ndarray | None = None
    ridge_mask: np.ndarray | None = None


def _bounding_sphere(mesh: Mesh) -> tuple[np.ndarray, float]:
    lo, hi = mesh.bounds
    centre = (np.asarray(lo, np.float64) + hi) / 2
    return centre, max(float(np.linalg.norm(np.asarray(hi, np.float64) - lo)) / 2, 1e-6)


def hugging_camera(mesh: Mesh, eye, fov_y: float = 30.0) -> Camera:
    """A lens whose near and far planes hug the mesh's bounding sphere seen from ``eye`` (good
    depth precision for the line visibility test)."""
    centre, radius = _bounding_sphere(mesh)
    distance = float(np.linalg.norm(np.asarray(eye, np.float64) - centre))
    return Camera(fov_y, max(distance - radius * 1.5, distance * 1e-3), distance + radius * 1.5)


def framing_view(
    mesh: Mesh, azimuth: float = 30.0, elevation: float = 15.0, fov_y: float = 30.0, margin: float = 1.1
) -> View:
    """A camera orbiting the mesh's bounding-box centre that fits its bounding sphere in view, with
    near and far planes hugging it (:func:`hugging_camera`)."""
    centre, radius = _bounding_sphere(mesh)
    distance = radius * margin / np.sin(np.radians(fov_y) / 2)
    pose = Pose.orbit(tuple(centre), distance, azimuth, elevation)
    return View(pose, hugging_camera(mesh, pose.position, fov_y))


def paper_and_ridges(mask: np.ndarray, ridge_colour) -> np.ndarray:
    """(H, W, 4) uint8: white paper, ``ridge_colour`` (linear RGB) where ``mask``, alpha 1 — what
    the compose pass (shaders/compose.glsl) writes without image-space silhouettes."""
    ink = np.round(np.clip(np.asarray(ridge_colour, np.float64), 0, 1) * 255).astype(np.uint8)
    return _paper(np.ascontiguousarray(mask, np.bool_), ink)


@numba.njit(cache=True)
def _paper(mask, ink):
    h, w = mask.shape
    out = np.empty((h, w, 4), np.uint8)
    for y in range(h):
        for x in range(w):
            for c in range(3):
                out[y, x, c] = ink[c] if mask[y, x] else 255
            out[y, x, 3] = 255
    return out


def drop_short_fragments_reference(mask: np.ndarray, min_pixels: float) -> np.ndarray:
    """``mask`` (H, W) bool without its 8-connected pieces of fewer than ``min_pixels`` pixels, by
    scipy's labelling: the plain statement :func:`drop_short_fragments` is tested against."""
    from scipy import ndimage

    labels, count = ndimage.label(mask, structure=np.ones((3, 3), bool))
    if count == 0:
        return mask
    sizes = np.bincount(labels.ravel())
    keep = sizes >= min_pixels
    keep[0] = False
    return keep[labels]


def drop_short_fragments(mask: np.ndarray, min_pixels: float) -> np.ndarray:
    """``mask`` (H, W) bool without its 8-connected pieces of fewer than ``min_pixels`` pixels: one
    raster scan with union-find over the mask's pixels (numba; a ridge mask is a few % of the image,
    and labelling the whole image with scipy then indexing by label cost 4× as much per frame)."""
    mask = np.ascontiguousarray(mask, np.bool_)
    return _drop_short(mask, float(min_pixels)) if mask.any() else mask


@numba.njit(cache=True)
def _root(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@numba.njit(cache=True)
def _drop_short(mask, min_pixels):
    h, w = mask.shape
    parent = np.arange(h * w, dtype=np.int32)
    for y in range(h):
        for x in range(w):
            if not mask[y, x]:
                continue
            i = y * w + x
            # the neighbours already scanned: left, and the three above
            for dy, dx in ((0, -1), (-1, -1), (-1, 0), (-1, 1)):
                yy, xx = y + dy, x + dx
                if yy >= 0 and 0 <= xx < w and mask[yy, xx]:
                    a, b = _root(parent, i), _root(parent, yy * w + xx)
                    if a != b:
                        parent[max(a, b)] = min(a, b)
    size = np.zeros(h * w, np.int32)
    for y in range(h):
        for x in range(w):
            if mask[y, x]:
                size[_root(parent, y * w + x)] += 1
    out = np.zeros_like(mask)
    for y in range(h):
        for x in range(w):
            if mask[y, x] and size[_root(parent, y * w + x)] >= min_pixels:
                out[y, x] = True
    return out


class LineRenderer(Renderer):
    """Keeps the passes, the mesh on the GPU and its curvature for one context.

    Subject: a Mesh, or a ``(mesh, curvature)`` pair to draw with a curvature computed elsewhere
    (then ``params.curvature`` is not used). Params: :class:`LineParams`. ``frame.view`` None frames
    the mesh (:func:`framing_view`). ``render_texture``: RGBA8 drawing. ``maps()``: "q_t1" (q, t1,
    view depth), "ridges" (red = 1 on a kept ridge pixel), "depth" (the view's depth texture).
    :meth:`drawing` returns the image with its object-space segments and maps as arrays."""

    Params = LineParams
    subject_name = "a mesh"

    def __init__(self, ctx: Context):
        super().__init__(ctx)
        self.view_curvature = ViewCurvaturePass(ctx)
        self.ridge_filter = RidgeFilterPass(ctx)
        self.compose = ComposePass(ctx)
        self.draw_segments = SegmentsPass(ctx)
        self.mesh: Mesh | None = None
        self._given: Curvature | None = None
        self._gpu_mesh: CurvatureMesh | None = None
        self._curvature_params: CurvatureParams | None = None
        self._depth: moderngl.Texture | None = None
        self._segments: dict[str, Segments] = {}  # the last frame's object-space lines
        self.ridge_mask: np.ndarray | None = None  # the last frame's kept hybrid ridge pixels, when read back
        self.last_view: View | None = None

    # -- subject -------------------------------------------------------------------------------
    def _subject(self, subject):
        """A mesh (illusio's or a trimesh.Trimesh), or (mesh, Curvature)."""
        from ..scene.mesh import as_mesh

        if isinstance(subject, tuple) and len(subject) == 2:
            return as_mesh(subject[0]), subject[1]
        return as_mesh(subject)

    def _load(self, subject) -> None:
        mesh, curvature = subject if isinstance(subject, tuple) else (subject, None)
        if not isinstance(mesh, Mesh):
            raise InputError(f"LineRenderer draws a Mesh, got {type(mesh).__name__}")
        if curvature is not None and len(curvature.k_min) != len(mesh.vertices):
            raise InputError(f"curvature has {len(curvature.k_min)} vertices, the mesh {len(mesh.vertices)}")
        self.mesh, self._given = mesh, curvature

    def _unload(self) -> None:
        super()._unload()
        if self._gpu_mesh is not None:
            self._gpu_mesh.release()
            self._gpu_mesh = None
        if self._depth is not None:
            self._forget_map(self._depth)
            self._depth.release()
            self._depth = None
        self.mesh = self._given = self._curvature_params = None
        self._segments, self.ridge_mask = {}, None

    def gpu_mesh(self, curvature: CurvatureParams = CurvatureParams()) -> CurvatureMesh:
        """The mesh and its curvature on the GPU; estimated again only when ``curvature`` differs by
        value from the last frame's (estimates are also cached on disk by content)."""
        self._require_subject()
        if self._gpu_mesh is None or (self._given is None and curvature != self._curvature_params):
            if self._gpu_mesh is not None:
                self._gpu_mesh.release()
            curv = self._given or estimate_curvature(
                self.mesh,
                curvature.rings,
                curvature.degree,
                adaptive=curvature.adaptive,
                extra_rings=curvature.extra_rings,
                confidence=curvature.confidence,
                smoothing=curvature.smoothing,
            )
            self._gpu_mesh = CurvatureMesh(self.ctx, self.mesh, curv)
            self._curvature_params = curvature
            self._curvature_scale = curv.scale()  # a percentile over every vertex: once, not per frame
        return self._gpu_mesh

    def curvature(self, params: CurvatureParams = CurvatureParams()) -> Curvature:
        return self.gpu_mesh(params).curvature

    def default_view(self) -> View:
        self._require_subject()
        return framing_view(self.mesh)

    def depth_texture(self, size) -> moderngl.Texture:
        """The depth texture of the last frame (kept, remade when the size changes)."""
        if self._depth is None or self._depth.size != tuple(size):
            if self._depth is not None:
                self._forget_map(self._depth)
                self._depth.release()
            self.ctx.make_current()
            self._depth = self.ctx.gl.depth_texture(tuple(size))
        return self._depth

    # -- frames --------------------------------------------------------------------------------
    def render_texture(
        self, frame: Frame, params: LineParams | None = None, read_ridges: bool = False
    ) -> moderngl.Texture:
        """The drawing as an RGBA8 texture (pooled). ``read_ridges``: keep the ridge mask as an array
        in ``self.ridge_mask`` even when no fragment filtering needs it."""
        params = self._params(params)
        ctx = self.ctx
        w, h = frame.size
        gm = self.gpu_mesh(params.curvature)
        curv = gm.curvature
        view = frame.view or self.default_view()
        scale = self._curvature_scale if params.relative else 1.0
        depth = self.depth_texture((w, h))
        # pass 1: q, t1 and depth of the visible surface
        q_t1 = self.view_curvature(gm, view, (w, h), params.tau, scale, depth=depth)
        hybrid = "apparent-ridges" in params.lines and params.method == "hybrid"
        ridges = self.ridge_filter(q_t1, params.lam, params.threshold) if hybrid else None
        # the object-space lines on the CPU while the passes above run (before anything is read back)
        self._segments = self.object_space_segments(curv, view, params, scale)
        self.ridge_mask = None
        if ridges is not None and (params.min_ridge_pixels > 0 or read_ridges):
            # R: the thresholded ridge flag
            self.ridge_mask = ctx.readback_red(ridges) > 0.5
            if params.min_ridge_pixels > 0:
                self.ridge_mask = drop_short_fragments(self.ridge_mask, params.min_ridge_pixels * max(w, h) / 1024)
                ctx.release(ridges)
                ridges = ctx.acquire_upload(self.ridge_mask.astype(np.uint8) * 255)
        # base image: paper, hybrid ridges, image-space silhouettes
        colour = ctx.acquire((w, h), 4, "f1")
        image_silhouettes = "silhouettes" in params.lines and params.silhouette_space == "image"
        if self.ridge_mask is not None and params.min_ridge_pixels > 0 and not image_silhouettes:
            # the filtered mask is on the CPU already: paper and ridges written from it, one upload
            # instead of the compose pass (a full-screen pass costs more on llvmpipe than the upload)
            ctx.upload_into(colour, paper_and_ridges(self.ridge_mask, params.colour("apparent-ridges")))
            fbo = ctx.framebuffer([colour], depth=depth)
            fbo.use()
            fbo.viewport = (0, 0, w, h)
        else:
            self.compose(
                q_t1,
                ridges,
                colour,
                depth,
                hybrid,
                image_silhouettes,
                params.colour("apparent-ridges"),
                params.colour("silhouettes"),
                params.depth_jump,
            )
        # object-space lines, hidden by the surface
        for kind, segs in self._segments.items():
            self.draw_segments(segs, view, (w, h), params.colour(kind), params.width(kind))
        self.last_view = view
        self._keep_maps({"q_t1": q_t1, "ridges": ridges, "depth": depth})
        return colour

    def drawing(self, frame: Frame, params: LineParams | None = None) -> Drawing:
        """The frame as a :class:`Drawing`: image, object-space segments, q_t1 and the ridge mask."""
        params = self._params(params)
        tex = self.render_texture(frame, params, read_ridges=True)
        try:
            image = self.ctx.readback_image(tex, 3)
        finally:
            self.ctx.release(tex)
        q_t1 = self.ctx.readback(self._maps["q_t1"])
        return Drawing(image, self._segments, self.last_view, frame.size, q_t1, self.ridge_mask)

    def object_space_segments(
        self, curv: Curvature, view: View, params: LineParams, scale: float
    ) -> dict[str, Segments]:
        mesh = self.mesh
        eye = view.pose.position
        out: dict[str, Segments] = {}
        for kind in params.lines:
            if kind == "apparent-ridges" and params.method == "object-space":
                vc = view_curvature(mesh.vertices, curv.normals, curv.e_min, curv.e_max, curv.k_min, curv.k_max, view)
                q1 = vc.q1 * 2.0**params.tau
                # only where the surface faces the viewer
                q1 = np.where(vc.ndotv > 0.05, q1, 0.0)
                out[kind] = apparent_ridges(mesh, q1, vc.w1, params.object_threshold, scale)
            elif kind == "silhouettes" and params.silhouette_space == "object":
                out[kind] = contours(mesh, curv, eye)
            elif kind == "suggestive":
                out[kind] = suggestive_contours(mesh, curv, eye, params.suggestive_threshold, scale)
            elif kind == "ridges":
                out[kind] = ridges(mesh, curv, params.ridge_threshold, scale)
            elif kind == "valleys":
                out[kind] = valleys(mesh, curv, params.ridge_threshold, scale)
            elif kind == "boundaries":
                out[kind] = boundaries(mesh)
            elif kind == "k-zero":
                out[kind] = parabolic_lines(mesh, curv)
            elif kind == "h-zero":
                out[kind] = mean_zero_lines(mesh, curv)
            elif kind == "isophotes":  # a headlight: towards the camera, along its axis
                out[kind] = isophotes(mesh, curv.normals, -view.pose.axes()[2], params.isophote_level)
            elif kind == "suggestive-highlights":
                out[kind] = suggestive_highlights(mesh, curv, eye, params.highlight_threshold, scale)
            elif kind == "principal-highlights":
                out[kind] = principal_highlights(mesh, curv, eye, params.highlight_threshold, scale)
            elif kind == "dwkr":
                out[kind] = dwkr_lines(mesh, curv, eye, params.suggestive_threshold, scale)
        return out


def line_drawing(
    mesh: Mesh,
    params: LineParams = LineParams(),
    view: View | None = None,
    size=(1024, 1024),
    ctx: Context | None = None,
) -> np.ndarray:
    """One drawing of ``mesh`` (illusio's Mesh or a trimesh.Trimesh): float32 (H, W, 3) linear, row 0
    on top. Without ``ctx`` the process's default headless context is used; the context keeps one
    renderer for these calls."""
    renderer = (ctx or default_context()).kept(LineRenderer)
    renderer.prepare(mesh)
    return renderer.render(Frame(view, size), params)
