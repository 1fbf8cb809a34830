"""The image-based rendering mode: a free camera over reference views captured from a scene (three
along the main camera's right, at the window's size); the panel sets the selection and drags the
lights; the views show the reconstruction, its source views (Figure 4.5), or the ground truth."""

from __future__ import annotations

from ...core.renderer import Frame
from ...ibr.params import IbrParams
from ...ibr.reference_views import capture, orbit_views
from ...ibr.renderer import IbrRenderer
from ...passes.scene_renderer import RenderSettings, SceneRenderer
from ...scene.builtin import SCENES
from ...scene.sources import resolve_scene
from .base import Mode

__all__ = ["IbrMode"]


class IbrMode(Mode):
    name = "ibr"
    variants = ("reconstruction", "sources", "ground-truth")
    source_help = "the scene the references are captured from (default office)"
    source_label = "scene"
    source_choices = tuple(SCENES)
    shares_params = True
    reference_count = 3

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "office", variant)
        self.scene = resolve_scene(self.source)
        self.renderer = IbrRenderer(ctx)
        self.params = IbrParams()
        self.truth = SceneRenderer(ctx) if self.variant == "ground-truth" else None
        if self.truth is not None:
            self.truth.prepare(self.scene)
        self._captured_size = None

    def home_view(self):
        # the middle reference: the rig may stand ahead of the main camera (inside the room), and
        # from its own view a reference gives back what it recorded
        return orbit_views(self.scene, self.reference_count)[self.reference_count // 2]

    def render(self, frame: Frame):
        if self.truth is not None:
            return self.truth.render_texture(frame, RenderSettings(shadows=False))
        if frame.size != self._captured_size:  # references at the window's size
            self.renderer.prepare(
                capture(self.scene, orbit_views(self.scene, self.reference_count), frame.size, self.ctx)
            )
            self._captured_size = frame.size
        params = (
            self.params
            if self.variant == "reconstruction"
            else IbrParams(**{**self.params.__dict__, "show_sources": True})
        )
        return self.renderer.render_texture(frame, params)

    def release(self) -> None:
        super().release()
        if self.truth is not None:
            self.truth.release()
