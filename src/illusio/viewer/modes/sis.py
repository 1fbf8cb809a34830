"""The autostereogram mode: the living room with the stereogram on its TV (Figure 23), on the wall
behind the sofa (Figure 24), the wall in the interaction mode of Figure 25 (walking around it turns
the hidden scene), or the raw stereogram full screen with its depth map beside it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...core.renderer import Frame
from ...scene.builtin import SHAPES
from ...scene.sources import is_mesh_source, resolve_mesh, resolve_scene
from ...sis.depth import depth_from_scene, hidden_scene
from ...sis.multiscene import MultiSceneParams, MultiSceneRenderer, MultiSceneSubject
from ...sis.params import StereogramParams
from ...sis.stereogram import StereogramRenderer
from ...sis.technique import DEFAULT_HIDDEN
from ..navigation import FixedCamera, WalkCamera
from .base import Mode

__all__ = ["SisMode"]

_WALL = dict(
    host="back-wall", emission=0.0, stereogram=StereogramParams(pattern="pink-noise", strip_width=100, depth_factor=40)
)


def _default_host(scene, wanted: str) -> str:
    """A node tagged ``host``, else the node with texture coordinates of the largest bounding box."""
    tagged = [n.name for n in scene.nodes if n.visible and "host" in n.tags]
    if tagged:
        return tagged[0]
    candidates = [n for n in scene.nodes if n.visible and n.mesh.uvs is not None]
    if not candidates:
        return wanted  # refused by the renderer with the nodes that could be hosts
    return max(
        candidates, key=lambda n: float(np.prod(np.ptp(n.mesh.vertices, axis=0)[np.ptp(n.mesh.vertices, axis=0) > 0]))
    ).name


class SisMode(Mode):
    name = "sis"
    variants = ("tv", "wall", "interactive", "raw")
    source_help = (
        "the hidden shape (a built-in shape or a mesh file, default torus-knot), or the scene whose "
        "host surfaces show the stereogram (a built-in or .yaml scene, default living-room)"
    )
    source_label = "hidden shape"
    source_choices = tuple(SHAPES)

    def __init__(self, ctx, source=None, variant=None, scene: str = "living-room"):
        if source is not None and not is_mesh_source(source):  # a scene: it hosts the default shape
            scene, source = source, None
        super().__init__(ctx, source or DEFAULT_HIDDEN, variant)
        self.hidden = hidden_scene(resolve_mesh(self.source))
        if self.variant == "raw":
            self.renderer = StereogramRenderer(ctx)
            self.params = StereogramParams(pattern="random-dot", strip_width=100, depth_factor=50)
            self._depth_size = None
            return
        self.scene = resolve_scene(scene)
        self.renderer = MultiSceneRenderer(ctx)
        self.renderer.prepare(MultiSceneSubject(self.scene, self.hidden))
        self.params = {
            "tv": MultiSceneParams(),
            "wall": MultiSceneParams(**_WALL),
            "interactive": MultiSceneParams(**_WALL, interactive=True),
        }[self.variant]
        if not any(n.name == self.params.host or self.params.host in n.tags for n in self.scene.nodes):
            # a scene of the user's, with no node of that name: its own host, else its largest surface
            # that can carry a stereogram (texture coordinates)
            self.params = replace(self.params, host=_default_host(self.scene, self.params.host))

    def home_view(self):
        return None if self.variant == "raw" else self.scene.camera()

    def navigation(self):
        # the source is the hidden shape: the viewer walks the room whatever it is
        return FixedCamera() if self.variant == "raw" else WalkCamera.from_view(self.home_view())

    def image_size(self, size):
        return (max(1, size[0] // 2), size[1]) if self.variant == "raw" else size

    def render(self, frame: Frame):
        if self.variant == "raw" and frame.size != self._depth_size:
            # the hidden shape's depth at the image's size: the subject of the stereogram
            self.renderer.prepare(depth_from_scene(self.ctx, self.hidden, frame.size))
            self._depth_size = frame.size
        return super().render(frame)

    def aside(self):
        if self.variant == "raw":
            return self.renderer.maps()["depth"], "depth"
        return None
