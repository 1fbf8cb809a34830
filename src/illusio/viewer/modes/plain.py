"""The plain mode: a scene (or a mesh on the turntable) through the shared scene renderer, with its
lighting settings in the panel."""

from __future__ import annotations

from ...passes.scene_renderer import RenderSettings, SceneRenderer
from ...scene.builtin import SCENES, SHAPES
from ...scene.sources import resolve_scene
from .base import Mode

__all__ = ["PlainMode"]


class PlainMode(Mode):
    name = "plain"
    source_help = "a built-in scene, a .yaml scene, a mesh file or a built-in shape (default living-room)"
    source_label = "scene"
    source_choices = tuple(SCENES) + tuple(SHAPES)

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "living-room", variant)
        self.scene = resolve_scene(self.source)
        self.renderer = SceneRenderer(ctx)
        self.renderer.prepare(self.scene)
        self.params = RenderSettings()

    def home_view(self):
        return self.scene.camera()
