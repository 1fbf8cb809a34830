"""The relighting mode: the office's photograph relit live — a slider per real lamp, the method
(per-pixel, the chapter's, or the baseline of 4.2) as the view, so the three compare on the same
edits; it opens with the back lamps off. The photograph is path-traced once per process (Mitsuba:
the photo extra)."""

from __future__ import annotations

from dataclasses import replace

from ...core.renderer import Frame
from ...relight.params import RelightParams
from ...relight.photograph import builtin_real_scene
from ...relight.renderer import RelightRenderer
from ..navigation import FixedCamera
from .base import Mode

__all__ = ["RelightMode"]

#: the photograph's size and paths a pixel in the viewer (small: it is made on the first frame)
PHOTOGRAPH = ((320, 240), 32)
_PHOTOGRAPHS: dict = {}


class RelightMode(Mode):
    name = "relight"
    variants = ("per-pixel", "loscos", "baseline")
    source_help = "the built-in real scene whose photograph is relit (office)"
    source_label = "scene"
    source_choices = ("office",)
    shares_params = True

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "office", variant)
        key = (self.source,) + PHOTOGRAPH
        if key not in _PHOTOGRAPHS:
            _PHOTOGRAPHS[key] = builtin_real_scene(self.source, *PHOTOGRAPH)
        self.real = _PHOTOGRAPHS[key]
        self.renderer = RelightRenderer(ctx)
        self.renderer.prepare(self.real)
        # it opens on Figure 4.17b (the back lamps off), so the three methods show their difference
        self.params = RelightParams(method=self.variant, lamp_scales=(("lamp-0", 0.0), ("lamp-1", 0.0)))

    def home_view(self):
        return self.real.view

    def navigation(self):
        return FixedCamera()

    def render(self, frame: Frame):
        self.params = replace(self.params, method=self.variant)
        return self.renderer.render_texture(frame, self.params)

    def panel(self, imgui, viewer) -> None:
        session = self.renderer.session
        if session is None:
            return
        self.lamp_sliders(imgui, session.lamp_names, 3.0)
        imgui.text(f"prepared in {session.times['prepare']:.1f} s; last edit {session.times.get('edit', 0) * 1000:.0f} ms")
