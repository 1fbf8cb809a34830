"""The depth-of-field mode: walk through a scene with blur from a thin-lens eye (method, focus
distance or policy, aperture and stereo output in the panel; the circle of confusion beside the
image on demand), or play a scenario (Figure 11) with a timeline scrubber."""

from __future__ import annotations

from dataclasses import replace

from ...core.renderer import Frame
from ...dof.params import DofParams
from ...dof.renderer import DofRenderer
from ...dof.scenario import load_scenario, shipped_scenario
from ...dof.timeline import ScenarioPlayer
from ...scene.builtin import SCENES, SHAPES
from ...scene.sources import resolve_scene
from .base import Mode

__all__ = ["DofMode"]


class DofMode(Mode):
    name = "dof"
    variants = ("walk", "scenario")
    source_help = "a built-in scene, a .yaml scene, a mesh file or a built-in shape (default museum)"
    source_label = "scene"
    source_choices = tuple(SCENES) + tuple(SHAPES)
    shares_params = False

    def __init__(self, ctx, source=None, variant=None):
        variant = variant or self.variants[0]
        default = "futuristic" if variant == "scenario" else "museum"
        super().__init__(ctx, source or default, variant)
        self.scene = resolve_scene(self.source)
        self.renderer = DofRenderer(ctx)
        self.renderer.prepare(self.scene)
        self.show_coc = False
        self.player = None
        # the command line's defaults (one source, the Params); the scenario as the command page's Figure 11 line
        # runs it (illusio dof futuristic --scenario futuristic --method planes --aperture 500)
        if variant == "scenario":
            self.player = ScenarioPlayer(load_scenario(shipped_scenario("futuristic")), self.scene)
            self.params = DofParams(method="planes", aperture_mm=500.0)
        else:
            self.params = DofParams()

    def home_view(self):
        return self.scene.camera()

    def image_size(self, size):
        return (max(1, size[0] // 2), size[1]) if self.show_coc else size

    def render(self, frame: Frame):
        if self.player is None:
            return super().render(frame)
        self.player.apply(self.scene, frame.time)  # the scripted motion, then the scene by value
        self.renderer.prepare(self.scene)
        focus = self.player.focus_distance(frame.view or self.scene.camera(), frame.time)
        params = replace(self.params, focus_distance=focus) if focus is not None else self.params
        return self.renderer.render_texture(frame, params)

    def aside(self):
        coc = self.renderer.maps().get("coc") if self.show_coc else None
        return (coc, "grey", 1.0 / self.params.max_coc) if coc is not None else None

    def panel(self, imgui, viewer) -> None:
        _, self.show_coc = imgui.checkbox("show the circle of confusion (black: in focus)", self.show_coc)
        if self.renderer.result() is not None:
            r = self.renderer.result()
            imgui.text_wrapped(
                f"focus {r.focus_distance:.2f} m, screen {r.screen_distance:.2f} m: "
                f"vergence–accommodation {r.conflict_dioptres:.2f} D"
            )
        if self.player is not None and self.player.loop:
            changed, t = imgui.slider_float("time (s)##scenario", viewer.time % self.player.loop, 0.0, self.player.loop)
            if changed:
                viewer.time = t
