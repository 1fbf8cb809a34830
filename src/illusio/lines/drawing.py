"""Line drawings: the LineRenderer combines the hybrid apparent ridges (GPU, two passes), image- or
object-space silhouettes, suggestive contours, ridges and valleys into one image, each line type in
its own colour and width. Call :meth:`LineRenderer.render` every frame with a new view or params;
the mesh's curvature and GPU buffers are kept between calls.

Thresholds are relative to the mesh's curvature scale (Curvature.scale(): the 90th percentile of
|k|), so the defaults suit meshes of any size and detail; ``relative=False`` gives the report's raw
τ (q = 2^τ q1 with q1 in 1/units)."""

from __future__ import annotations

from dataclasses import dataclass, field

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import InputError
from ..core.gl import set_uniform
from ..scene.camera import Camera, Pose, View
from ..scene.mesh import Mesh
from .curvature import Curvature, estimate_curvature
from .gpu_mesh import CurvatureMesh
from .object_space import Segments, apparent_ridges, contours, ridges, suggestive_contours, valleys
from .ridge_filter import REPORT_THRESHOLD, RidgeFilterPass
from .view_curvature import ViewCurvaturePass, view_dependent_curvature

__all__ = ["LINE_TYPES", "LineParams", "LineRenderer", "framing_view", "image_silhouettes", "Drawing"]

LINE_TYPES = ("apparent-ridges", "silhouettes", "suggestive", "ridges", "valleys")
METHODS = ("hybrid", "object-space")


@dataclass(frozen=True)
class LineParams:
    """lines: which line types to draw (LINE_TYPES). method: apparent ridges by the hybrid GPU method
    or Judd's object-space method. tau: τ, q = 2^τ q1 (/ curvature scale when relative).
    lam: λ of the adaptive Laplacian. threshold: the ridge filter's response threshold (0.2 in the
    report). object_threshold: q1 / scale above which object-space apparent ridges are kept.
    ridge_threshold: |k| / scale for ridges and valleys. suggestive_threshold: D_w κ_r / scale².
    silhouette_space: "object" (zero crossings of n·v) or "image" (depth discontinuities).
    min_ridge_pixels: hybrid ridge fragments of fewer pixels (8-connected; counted at 1024 px and
    scaled with the image's longer side) are dropped — a scan's small bumps otherwise hatch the
    surface, as Judd's length threshold prunes short object-space ridges; 0 keeps every fragment.
    colours (linear RGB) and widths (pixels, object-space lines) per line type."""

    lines: tuple[str, ...] = ("apparent-ridges", "silhouettes")
    method: str = "hybrid"
    tau: float = -2.0
    lam: float = 0.5
    threshold: float = REPORT_THRESHOLD
    relative: bool = True
    object_threshold: float = 0.2
    ridge_threshold: float = 1.0
    suggestive_threshold: float = 0.05
    silhouette_space: str = "object"
    depth_jump: float = 0.05
    min_ridge_pixels: int = 24
    colours: dict = field(default_factory=lambda: {"apparent-ridges": (0.0, 0.0, 0.0), "silhouettes": (0.0, 0.0, 0.0),
                                                   "suggestive": (0.05, 0.1, 0.45), "ridges": (0.55, 0.05, 0.05),
                                                   "valleys": (0.05, 0.35, 0.1)})
    widths: dict = field(default_factory=lambda: {"apparent-ridges": 1.5, "silhouettes": 2.0, "suggestive": 1.5,
                                                  "ridges": 1.5, "valleys": 1.5})

    def __post_init__(self):
        unknown = [t for t in self.lines if t not in LINE_TYPES]
        if unknown:
            raise InputError(f"unknown line type(s) {', '.join(unknown)}; choose from {', '.join(LINE_TYPES)}")
        if self.method not in METHODS:
            raise InputError(f"method must be one of {', '.join(METHODS)}, got {self.method!r}")
        if self.silhouette_space not in ("object", "image"):
            raise InputError(f"silhouette space must be 'object' or 'image', got {self.silhouette_space!r}")
        for name in ("tau", "lam", "threshold", "object_threshold", "ridge_threshold", "suggestive_threshold"):
            if not np.isfinite(getattr(self, name)):
                raise InputError(f"{name} must be a finite number")
        if self.lam < 0:
            raise InputError(f"λ must be ≥ 0, got {self.lam}")
        if self.min_ridge_pixels < 0:
            raise InputError(f"min_ridge_pixels must be ≥ 0, got {self.min_ridge_pixels}")


@dataclass
class Drawing:
    """A rendered drawing: image (H, W, 3) float32 linear, row 0 at the top; segments per object-space
    line type (object space, before visibility); the view and size it was drawn with."""

    image: np.ndarray
    segments: dict[str, Segments]
    view: View
    size: tuple[int, int]
    q_t1: np.ndarray | None = None  # (H, W, 4) q, t1, view depth (0 = background), with keep_maps
    ridge_mask: np.ndarray | None = None  # (H, W) bool, the hybrid ridge pixels, with keep_maps


def framing_view(mesh: Mesh, azimuth: float = 30.0, elevation: float = 15.0, fov_y: float = 30.0, margin: float = 1.1) -> View:
    """A camera orbiting the mesh's bounding-box centre that fits its bounding sphere in view, with
    near and far planes hugging it (good depth precision for the line visibility test)."""
    lo, hi = mesh.bounds
    centre = (np.asarray(lo, np.float64) + hi) / 2
    radius = max(float(np.linalg.norm(np.asarray(hi, np.float64) - lo)) / 2, 1e-6)
    distance = radius * margin / np.sin(np.radians(fov_y) / 2)
    return View(Pose.orbit(tuple(centre), distance, azimuth, elevation),
                Camera(fov_y, max(distance - radius * 1.5, distance * 1e-3), distance + radius * 1.5))


def image_silhouettes(depth: np.ndarray, depth_jump: float = 0.05) -> np.ndarray:
    """NumPy reference of compose.glsl's silhouettes: depth (H, W), 0 = background; a covered pixel
    is on a silhouette where a 4-neighbour is background or farther by more than depth_jump × depth."""
    d = np.asarray(depth, np.float64)
    padded = np.pad(d, 1, mode="edge")
    h, w = d.shape
    out = np.zeros_like(d, bool)
    for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
        e = padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w]
        out |= (e <= 0) | (e - d > depth_jump * d)
    return out & (d > 0)


def drop_short_fragments(mask: np.ndarray, min_pixels: float) -> np.ndarray:
    """``mask`` (H, W) bool without its 8-connected pieces of fewer than ``min_pixels`` pixels."""
    from scipy import ndimage

    labels, count = ndimage.label(mask, structure=np.ones((3, 3), bool))
    if count == 0:
        return mask
    sizes = np.bincount(labels.ravel())
    keep = sizes >= min_pixels
    keep[0] = False
    return keep[labels]


class LineRenderer:
    """Keeps the passes, the mesh on the GPU and its curvature for one context."""

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self.view_curvature = ViewCurvaturePass(ctx)
        self.ridge_filter = RidgeFilterPass(ctx)
        self.compose = ctx.program("lines/shaders/compose.glsl")
        self.segments_program = ctx.program("lines/shaders/segments.glsl")
        self._mesh: CurvatureMesh | None = None
        self._depth: moderngl.Texture | None = None

    def prepare(self, mesh: Mesh, curvature: Curvature | None = None) -> CurvatureMesh:
        if self._mesh is None or self._mesh.mesh is not mesh:
            if self._mesh is not None:
                self._mesh.release()
            self._mesh = CurvatureMesh(self.ctx, mesh, curvature or estimate_curvature(mesh))
        return self._mesh

    def depth_texture(self, size) -> moderngl.Texture:
        """The depth texture of the last frame (kept, remade when the size changes)."""
        if self._depth is None or self._depth.size != tuple(size):
            if self._depth is not None:
                self._depth.release()
            self.ctx.make_current()
            self._depth = self.ctx.gl.depth_texture(tuple(size))
        return self._depth

    def render(self, mesh: Mesh, view: View | None = None, size=(1024, 1024), params: LineParams = LineParams(),
               curvature: Curvature | None = None, keep_maps: bool = False) -> Drawing:
        ctx = self.ctx
        w, h = (int(v) for v in size)
        gm = self.prepare(mesh, curvature)
        curv = gm.curvature
        view = view or framing_view(mesh)
        scale = curv.scale() if params.relative else 1.0
        depth = self.depth_texture((w, h))
        # pass 1: q, t1 and depth of the visible surface
        q_t1 = self.view_curvature(gm, view, (w, h), params.tau, scale, depth=depth)
        maps = ctx.readback(q_t1) if keep_maps else None
        hybrid = "apparent-ridges" in params.lines and params.method == "hybrid"
        ridge_tex = self.ridge_filter(q_t1, params.lam, params.threshold) if hybrid else None
        ridge_mask = cleaned = None
        if ridge_tex is not None and (params.min_ridge_pixels > 0 or keep_maps):
            ridge_mask = ctx.readback_u8(ridge_tex, 1)[..., 0] > 127  # R: the thresholded ridge flag
            if params.min_ridge_pixels > 0:
                ridge_mask = drop_short_fragments(ridge_mask, params.min_ridge_pixels * max(w, h) / 1024)
                cleaned = ctx.upload(ridge_mask.astype(np.uint8) * 255, filter="nearest")
        # base image: paper, hybrid ridges, image-space silhouettes
        colour = ctx.acquire((w, h), 4, "f1")
        fbo = ctx.framebuffer([colour], depth=depth)
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        prog = self.compose
        q_t1.use(0)
        (cleaned or ridge_tex or q_t1).use(1)
        image_sil = "silhouettes" in params.lines and params.silhouette_space == "image"
        for name, value in (("q_t1", 0), ("ridges", 1), ("show_ridges", hybrid), ("show_silhouettes", image_sil),
                            ("ridge_colour", tuple(params.colours["apparent-ridges"])),
                            ("silhouette_colour", tuple(params.colours["silhouettes"])), ("depth_jump", float(params.depth_jump))):
            set_uniform(prog, name, value)
        ctx.gl.disable(moderngl.DEPTH_TEST)
        ctx.fullscreen.draw(prog)
        # object-space lines, hidden by the surface
        segments = self.object_space_segments(mesh, curv, view, params, scale)
        ctx.gl.enable(moderngl.DEPTH_TEST)
        ctx.gl.depth_mask = False
        for kind, segs in segments.items():
            self._draw_segments(segs, view, (w, h), params.colours[kind], params.widths[kind])
        ctx.gl.depth_mask = True
        ctx.gl.disable(moderngl.DEPTH_TEST)
        image = ctx.readback(colour, 3)
        ctx.release(q_t1, colour)
        if ridge_tex is not None:
            ctx.release(ridge_tex)
        if cleaned is not None:
            cleaned.release()
        return Drawing(image, segments, view, (w, h), maps, ridge_mask if keep_maps else None)

    def object_space_segments(self, mesh: Mesh, curv: Curvature, view: View, params: LineParams, scale: float) -> dict[str, Segments]:
        eye = view.pose.position
        out: dict[str, Segments] = {}
        for kind in params.lines:
            if kind == "apparent-ridges" and params.method == "object-space":
                vc = view_dependent_curvature(mesh.vertices, curv.normals, curv.e_min, curv.e_max, curv.k_min, curv.k_max, view)
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
        return out

    def _draw_segments(self, segs: Segments, view: View, size, colour, width: float) -> None:
        if len(segs) == 0:
            return
        ctx = self.ctx
        prog = self.segments_program
        w, h = size
        set_uniform(prog, "view_matrix", view.view_matrix())
        set_uniform(prog, "projection_matrix", view.projection_matrix(w / h))
        set_uniform(prog, "model_matrix", np.eye(4, dtype=np.float32))
        set_uniform(prog, "viewport", (float(w), float(h)))
        set_uniform(prog, "width", float(width))
        set_uniform(prog, "colour", tuple(float(c) for c in colour))
        vbo = ctx.gl.buffer(segs.points.astype(np.float32).tobytes())
        vao = ctx.gl.vertex_array(prog, [(vbo, "3f", "in_position")])
        try:
            vao.render(moderngl.LINES)
        finally:
            vao.release()
            vbo.release()

    def release(self) -> None:
        if self._mesh is not None:
            self._mesh.release()
            self._mesh = None
        if self._depth is not None:
            self._depth.release()
            self._depth = None
