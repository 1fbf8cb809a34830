"""The relighting mode: the office's photograph (or a user's real-scene folder) relit live — a slider per real lamp,
the method
(per-pixel, the chapter's, or the baseline of 4.2) as the view, so the three compare on the same
edits; it opens with the back lamps off. L puts a virtual lamp under the ceiling above the floor
point under the pointer, O a crate on the floor there, and a drag moves the crate along the floor
with its shadow (Loscos 4.4; the element methods only). The photograph is path-traced once per
process (Mitsuba: the photo extra)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ...core.renderer import Frame
from ...relight.params import VIRTUAL_LAMP_SIZE, RelightParams
from ...relight.photograph import builtin_real_scene, load_real_scene
from ...relight.renderer import RelightRenderer
from ..navigation import FixedCamera
from .base import Mode

__all__ = ["RelightMode"]

#: the photograph's size and paths a pixel in the viewer (small: it is made on the first frame)
PHOTOGRAPH = ((320, 240), 32)
#: the virtual crate's side (m) and a virtual lamp's side (m)
CRATE, LAMP = 0.5, VIRTUAL_LAMP_SIZE
_PHOTOGRAPHS: dict = {}


class RelightMode(Mode):
    name = "relight"
    variants = ("per-pixel", "loscos", "baseline")
    source_help = (
        "the real scene whose photograph is relit: the built-in office, or your own folder (scene.yaml, "
        "photograph, camera.json: illusio relight calibrate)"
    )
    source_label = "scene"
    source_choices = ("office",)
    shares_params = True

    def __init__(self, ctx, source=None, variant=None):
        super().__init__(ctx, source or "office", variant)
        folder = Path(self.source).is_dir()
        key = (self.source,) + PHOTOGRAPH
        if key not in _PHOTOGRAPHS:  # a user's folder is read as it is; the office photographed once
            _PHOTOGRAPHS[key] = load_real_scene(self.source) if folder else builtin_real_scene(self.source, *PHOTOGRAPH)
        self.real = _PHOTOGRAPHS[key]
        self.renderer = RelightRenderer(ctx)
        self.renderer.prepare(self.real)
        # the office opens on Figure 4.17b (the back lamps off), so the three methods show their
        # difference; any other scene as photographed
        opening = (("lamp-0", 0.0), ("lamp-1", 0.0)) if self.source == "office" else ()
        self.params = RelightParams(method=self.variant, lamp_scales=opening)
        corners = self.real.polygons.corners.reshape(-1, 3)
        self.floor, self.ceiling = float(corners[:, 1].min()), float(corners[:, 1].max())
        self.lamps: list[tuple[float, float, float]] = []  # virtual lamps asked for
        self.crate: np.ndarray | None = None  # where the crate should stand
        self.message = ""
        self._session = None
        self._placed = {"lamps": 0, "crate": None}  # what the current session has

    def keep_from(self, previous) -> None:
        self.lamps, self.crate = list(previous.lamps), previous.crate

    def floor_point(self) -> np.ndarray | None:
        """The floor point under the pointer (the photograph's camera ray met with the floor's
        plane), or None."""
        if self.pointer is None:
            return None
        w, h = self.real.size
        col, row = min(int(self.pointer[0] * w), w - 1), min(int(self.pointer[1] * h), h - 1)
        direction = self.real.view.ray_directions((w, h))[row, col]
        eye = np.asarray(self.real.view.pose.position, np.float64)
        if direction[1] >= -1e-6:
            return None
        return eye + direction * (self.floor - eye[1]) / direction[1]

    def key(self, name: str) -> bool:
        point = self.floor_point()
        if name not in ("l", "o") or point is None:
            return False
        if name == "l":
            self.lamps.append((float(point[0]), self.ceiling - 0.05, float(point[2])))
        else:
            self.crate = point
        return True

    def drag(self, dx: float, dy: float) -> bool:
        if self.crate is None:
            return False
        point = self.floor_point()
        if point is not None:
            self.crate = point
        return True

    def _sync(self, session) -> None:
        """Give the session the virtual lamps and the crate asked for; one crate move per frame."""
        if session is not self._session:
            self._session, self._placed = session, {"lamps": 0, "crate": None}
        if not (self.lamps or self.crate is not None):
            return
        if session.params.method == "per-pixel":
            self.message = "virtual lamps and objects: switch the view (V) to loscos or baseline"
            return
        self.message = ""
        m = session.model
        exitance = float(m.exitance[np.isin(m.group, m.lamps)].mean())  # a lamp like the real ones
        for k in range(self._placed["lamps"], len(self.lamps)):
            session.add_lamp(self.lamps[k], LAMP, (exitance,) * 3, f"virtual-lamp-{k}")
        self._placed["lamps"] = len(self.lamps)
        target = self.crate + np.array([0.0, CRATE / 2, 0.0])
        if self._placed["crate"] is None:
            from ...scene.builtin import shapes

            session.add_object(shapes.box((CRATE,) * 3), "crate", at=tuple(target))
            self._placed["crate"] = target
        elif np.abs(target - self._placed["crate"]).max() > 0.01:
            session.move_object("crate", tuple(target - self._placed["crate"]))
            self._placed["crate"] = target

    def home_view(self):
        return self.real.view

    def navigation(self):
        return FixedCamera()

    def render(self, frame: Frame):
        # the fresh solution of 4.3.3 belongs to loscos: the other views drop it
        self.params = replace(
            self.params, method=self.variant, fresh_solution=self.params.fresh_solution and self.variant == "loscos"
        )
        self._sync(self.renderer.session_for(self.params))
        # the photograph's camera at its own size: the viewer's display scales it to the window
        return self.renderer.render_texture(Frame(None, self.real.size, frame.time, frame.index), self.params)

    def panel(self, imgui, viewer) -> None:
        session = self.renderer.result()
        if session is None:
            return
        self.lamp_sliders(imgui, session.lamp_names, 3.0)
        imgui.text_wrapped(
            f"prepared in {session.times['prepare']:.1f} s; last edit {session.times.get('edit', 0) * 1000:.0f} ms"
        )
        imgui.text_wrapped("L: a lamp above the pointer; O: a crate there, drag it with the mouse")
        if "move object" in session.times:
            imgui.text_wrapped(f"last crate move {session.times['move object'] * 1000:.0f} ms")
        if self.message:
            imgui.text_wrapped(self.message)
