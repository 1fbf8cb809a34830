"""The line-drawing mode: a mesh drawn with apparent ridges and the classic line types, orbiting
it; the panel sets line types, τ, λ and the thresholds, and the variants show the debug maps."""

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

    def home_view(self):
        return self.renderer.default_view()

    def navigation(self):
        return OrbitCamera.from_view(self.home_view())

    def camera_at(self, eye):
        """The home lens with near and far planes hugging the mesh seen from ``eye``."""
        return hugging_camera(self.mesh, eye, self.home_view().camera.fov_y)

    def render(self, frame: Frame):
        if self.variant == "drawing":
            return super().render(frame)
        drawing = self.renderer.drawing(frame, self.params)
        image = np.atleast_3d(debug_view(self.variant, drawing, self.mesh, self.renderer.curvature(self.params.curvature)))
        rgb = np.repeat(image, 3, axis=2) if image.shape[2] == 1 else image  # q1 is a grey map
        return self.ctx.acquire_upload(np.dstack([rgb, np.ones(rgb.shape[:2])]).astype(np.float32))
