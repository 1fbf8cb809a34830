"""The depth-of-field mode: walk through a scene with blur from a thin-lens eye; the panel sets the
method, the focus distance, the aperture and the stereo output."""

from __future__ import annotations

from ...dof.params import DofParams
from ...dof.renderer import DofRenderer
from ...scene.builtin import SCENES, SHAPES
from ...scene.sources import is_mesh_source, resolve_scene
from ..navigation import OrbitCamera
from .base import Mode

__all__ = ["DofMode"]


class DofMode(Mode):
    name = "dof"
    source_help = "a built-in scene, a .yaml scene, a mesh file or a built-in shape (default museum)"
    source_label = "scene"
    source_choices = tuple(SCENES) + tuple(SHAPES)

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "museum", variant)
        self.scene = resolve_scene(self.source)
        self.renderer = DofRenderer(ctx)
        self.renderer.prepare(self.scene)
        self.params = DofParams(focus_distance=3.0, max_coc=16.0)

    def home_view(self):
        return self.scene.camera()

    def navigation(self):
        if is_mesh_source(self.source):
            return OrbitCamera.from_view(self.home_view())
        return super().navigation()

    def aside(self):
        return None
