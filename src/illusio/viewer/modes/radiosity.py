"""The radiosity mode: walk through a scene lit by its hierarchical radiosity solution (built on the
first frame, kept); a slider per lamp re-solves with the links kept (Loscos 4.4.2); the element mesh
(Figure 4.6) and the links lighting the element under the pointer (Figure 4.8) are views."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ...core.renderer import Frame
from ...radiosity.params import RadiosityParams
from ...radiosity.renderer import RadiosityRenderer
from ...scene.builtin import SCENES
from ...scene.sources import resolve_scene
from .base import Mode

__all__ = ["RadiosityMode"]


class RadiosityMode(Mode):
    name = "radiosity"
    variants = ("radiosity", "mesh", "links")
    source_help = "a built-in scene or a .yaml scene, solved by radiosity (default office)"
    source_label = "scene"
    source_choices = tuple(SCENES)
    shares_params = True

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "office", variant)
        self.scene = resolve_scene(self.source)
        self.renderer = RadiosityRenderer(ctx)
        self.renderer.prepare(self.scene)
        # a walk draws the corner gather: the final gather (seconds a frame) is for a still, in the panel
        self.params = RadiosityParams(show=self.variant, gather_rays=0)

    def home_view(self):
        return self.scene.camera()

    def render(self, frame: Frame):
        params = replace(self.params, show=self.variant)
        if self.variant == "links":
            params = replace(params, element=self.element_under_pointer())
        self.params = params
        return self.renderer.render_texture(frame, params)

    def element_under_pointer(self) -> int:
        """The leaf under the pointer in the last frame (the element map), or the params' choice."""
        element = self.renderer.maps().get("element")
        if self.pointer is None or element is None:
            return self.params.element
        w, h = element.size
        x = min(int(self.pointer[0] * w), w - 1)
        y = min(int((1 - self.pointer[1]) * h), h - 1)  # GL rows start at the bottom
        raw = self.ctx.framebuffer([element]).read(viewport=(x, y, 1, 1), components=1, dtype="f4")
        picked = int(np.frombuffer(raw, np.float32)[0])
        return picked if picked >= 0 else self.params.element

    def panel(self, imgui, viewer) -> None:
        solution = self.renderer.result()
        if solution is None:
            return
        st = solution.stats
        imgui.text_wrapped(f"{st.elements} elements, {st.links} links, {st.iterations} iterations")
        self.lamp_sliders(imgui, solution.lamp_names)
        if self.variant == "links":
            imgui.text_wrapped(
                f"links lighting element {self.params.element} (green visible, yellow partial, red invisible)"
            )
