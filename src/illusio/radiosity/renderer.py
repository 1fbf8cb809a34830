"""``RadiosityRenderer``: the Renderer protocol over the engine. The subject is a Scene (or
Polygons); the solution is built on the first frame for the params' ``hierarchy`` and kept — a
frame whose params change only the lamp scales re-solves with the links kept (Loscos 4.4.2), one
that changes only the display draws again. ``show="links"`` draws the links lighting the chosen
element: those it receives and those its ancestors receive (pushed down to it). Maps: ``element`` (R32F, the leaf
index under each pixel,
−1 off the geometry)."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.renderer import Frame, Renderer
from ..scene.scene import Scene
from .display import DisplayPass, drawn_reflectance, leaf_mesh
from .engine import Radiosity
from .final_gather import final_gather
from .params import RadiosityParams
from .polygons import Polygons, scene_polygons
from .texture_modulation import TextureModulation

__all__ = ["RadiosityRenderer"]


class RadiosityRenderer(Renderer):
    Params = RadiosityParams
    channels = 3
    subject_name = "a scene (or Polygons)"

    def __init__(self, ctx):
        super().__init__(ctx)
        self.display = DisplayPass(ctx)
        self._solution: Radiosity | None = None
        self.polygons: Polygons | None = None
        self._scene: Scene | None = None
        self._state = None  # (hierarchy params, lamp scales, tolerance, smooth) of the loaded mesh
        self._textures: TextureModulation | None = None
        self._gather_key, self._gather_b = None, None  # the last final gather (see _gathered)

    def _load(self, subject) -> None:
        self._scene = subject if isinstance(subject, Scene) else None
        self._textures = TextureModulation(self.ctx, subject) if isinstance(subject, Scene) else None
        self.polygons = scene_polygons(subject) if isinstance(subject, Scene) else subject
        if not isinstance(self.polygons, Polygons):
            from ..core.errors import InputError

            raise InputError(f"RadiosityRenderer takes a Scene or Polygons, got {type(subject).__name__}")

    def _unload(self) -> None:
        super()._unload()
        self.display.release()
        if self._textures is not None:
            self._textures.release()
            self._textures = None
        self._solution = None
        self._state = None
        self._gather_key, self._gather_b = None, None

    def result(self) -> Radiosity | None:
        """The solution the last frame showed (hierarchy, links, B, stats), or None."""
        return self._solution

    def solve(self, params: RadiosityParams) -> Radiosity:
        """The solution for ``params`` (built, re-solved or kept as they require)."""
        self._require_subject()
        if (
            self._solution is None
            or self._solution.params != params.hierarchy
            or bool(self._solution.polygons.textures) != (params.textures and bool(self.polygons.textures))
        ):
            # --no-textures: each polygon solved with its own mean (as Mitsuba of the polygons is given)
            polygons = self.polygons if params.textures else self.polygons.without_textures()
            self._solution = Radiosity(polygons, params.hierarchy)
            self._solution.build(params.tolerance, params.max_iterations)
            self._state = None
        modulated = params.textures and self._textures is not None and self._textures.active
        state = (params.hierarchy, params.lamp_scales, params.tolerance, params.show == "mesh", modulated)
        if self._state != state:
            if self._state is None or self._state[1:3] != state[1:3]:
                self._solution.set_lamps(dict(params.lamp_scales), params.tolerance, params.max_iterations)
            solution = self._solution
            scale = solution.display_scale()  # the solve's factor on the reflected light, shown too
            self.display.load(
                leaf_mesh(
                    solution.hierarchy,
                    solution.links,
                    solution.display_exitance(),
                    smooth=params.show != "mesh",
                    textured=modulated and params.show != "mesh",
                    scale=scale,
                    lamp=None if scale is None else solution.lamp_radiosity(),
                )
            )
            self._state = state
        return self._solution

    def render_texture(self, frame: Frame, params: RadiosityParams | None = None) -> moderngl.Texture:
        params = self._params(params)
        solution = self.solve(params)
        view = frame.view
        if view is None:
            view = self._scene.camera() if self._scene is not None else _framing_view(self.polygons)
        colour, element = self.display(view, frame.size, params.exposure, edges=params.show == "mesh")
        if params.show == "radiosity" and params.gather_rays > 0:
            modulated = params.textures and self._textures is not None and self._textures.active
            self.ctx.upload_into(colour, self._gathered(view, element, params, modulated))
        if self._textures is not None and params.textures and params.show != "mesh":
            colour = self._textures(colour, view)
        if params.show == "links":
            chosen = params.element if params.element >= 0 else default_element(solution)
            self.display.links(colour, view, solution.hierarchy, lighting(solution, chosen))
        self._keep_maps({"element": element})
        return colour

    def _gathered(self, view, element: moderngl.Texture, params: RadiosityParams, modulated: bool) -> np.ndarray:
        """exposure × B/π (H, W, 4) of the final gather at the leaves the display drew
        (radiosity.final_gather), alpha 1 where a leaf is; the last one kept while the solution,
        the view, the size and the gather's params stay (a viewer's still frames)."""
        leaves = self.ctx.readback_image(element, 1, clip=False)[..., 0].astype(np.int64)
        key = (
            id(self._solution),
            self._state,
            view.view_matrix().tobytes(),
            view.projection_matrix(element.size[0] / element.size[1]).tobytes(),
            leaves.shape,
            params.gather_rays,
            params.shadow_rays,
            params.hierarchy.seed,
            modulated,
        )
        if self._gather_key != key:
            h = self._solution.hierarchy
            b = final_gather(
                self._solution,
                view,
                leaves,
                params.gather_rays,
                params.shadow_rays,
                params.hierarchy.seed,
                drawn_reflectance(h) if modulated else None,
            )
            self._gather_key, self._gather_b = key, b
        out = np.empty(leaves.shape + (4,), np.float32)
        out[..., :3] = self._gather_b * (params.exposure / np.pi)
        out[..., 3] = leaves >= 0
        return out

    def radiance(self, frame: Frame, params: RadiosityParams | None = None, supersample: int = 1):
        """(radiance × exposure, float32 (H, W, 3), unclipped; emitter mask (H, W) bool) of the frame,
        each pixel the box-filtered mean of supersample² samples (as a path tracer's box filter)."""
        params = self._params(params)
        k = int(supersample)
        w, h = frame.size
        big = Frame(frame.view, (w * k, h * k), frame.time, frame.index)
        tex = self.render_texture(big, params)
        try:
            image = self.ctx.readback_image(tex, 3, clip=False)
        finally:
            self.ctx.release(tex)
        element = self.ctx.readback_image(self._maps["element"], 1, clip=False)[..., 0].astype(np.int64)
        emitter = (element >= 0) & (self._solution.exitance()[np.maximum(element, 0)].max(axis=-1) > 0)
        image = image.reshape(h, k, w, k, 3).mean(axis=(1, 3))
        return image, emitter.reshape(h, k, w, k).any(axis=(1, 3))


def lighting(solution: Radiosity, element: int):
    """The links that light ``element``: those it receives and those its ancestors receive."""
    h = solution.hierarchy
    chain = [int(element)]
    while h.parent[chain[-1]] >= 0:
        chain.append(int(h.parent[chain[-1]]))
    return solution.links.take(np.isin(solution.links.receiver, chain))


def default_element(solution: Radiosity) -> int:
    """The receiver with the most links (the links view's default)."""
    counts = np.bincount(solution.links.receiver, minlength=len(solution.hierarchy))
    return int(counts.argmax())


def _framing_view(polygons: Polygons):
    from ..scene.camera import Camera, Pose, View

    pts = polygons.corners.reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo)) / 2
    return View(
        Pose(centre + np.array([0.0, 0.3, 1.0]) * 2.2 * radius, centre), Camera(45.0, radius * 0.01, radius * 10)
    )
