"""The line-drawing mode: a mesh drawn with apparent ridges and the classic line types, orbiting
it; the panel sets line types, τ, λ and the thresholds, T chooses τ, λ and the threshold for the
view (matching its image edges), and the variants show the debug maps."""

from __future__ import annotations

import numpy as np

from ...core.renderer import Frame
from ...lines.debug import DEBUG_VIEWS, debug_view
from ...lines.drawing import LineRenderer, hugging_camera
from ...lines.params import LineParams
from ...scene.builtin import SHAPES
from ...scene.sources import resolve_mesh
from ..navigation import OrbitCamera
from .base import Mode

__all__ = ["LinesMode"]


class LinesMode(Mode):
    name = "lines"
    variants = ("drawing",) + DEBUG_VIEWS
    source_help = "a mesh file or a built-in shape (default torus-knot)"
    source_label = "mesh"
    source_choices = tuple(SHAPES)
    shares_params = True

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "torus-knot", variant)
        self.mesh = resolve_mesh(self.source)
        self.renderer = LineRenderer(ctx)
        self.renderer.prepare(self.mesh)
        self.params = LineParams()
        self._frame: Frame | None = None
        self.message = "T: choose τ, λ and the threshold that best match this view's image edges"

    def home_view(self):
        return self.renderer.default_view()

    def navigation(self):
        return OrbitCamera.from_view(self.home_view())

    def camera_at(self, eye):
        """The home lens with near and far planes hugging the mesh seen from ``eye``."""
        return hugging_camera(self.mesh, eye, self.home_view().camera.fov_y)

    def render(self, frame: Frame):
        self._frame = frame
        if self.variant == "drawing":
            return super().render(frame)
        drawing = self.renderer.drawing(frame, self.params)
        image = np.atleast_3d(
            debug_view(self.variant, drawing, self.mesh, self.renderer.curvature(self.params.curvature))
        )
        rgb = np.repeat(image, 3, axis=2) if image.shape[2] == 1 else image  # q1 is a grey map
        return self.ctx.acquire_upload(np.dstack([rgb, np.ones(rgb.shape[:2])]).astype(np.float32))

    def key(self, name: str) -> bool:
        """T: the automatic choice (lines.tuning.auto_parameters) against the Canny edges of the shaded
        mesh seen as now."""
        if name != "t" or self._frame is None or self._frame.view is None:
            return False
        from ...core.errors import InputError
        from ...lines.tuning import auto_parameters, edge_target

        frame = self._frame
        try:
            chosen = auto_parameters(
                self.renderer,
                frame.view,
                frame.size,
                edge_target(self.renderer, self.mesh, frame.view, frame.size),
                self.params,
            )
        except InputError as exc:
            self.message = str(exc)
            return True
        self.params = chosen.params
        self.message = f"auto: {chosen}"
        return True

    def panel(self, imgui, viewer) -> None:
        imgui.text_wrapped(self.message)
