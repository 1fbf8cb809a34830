"""The viewer's state, with no window: the current mode, the camera controller, held keys, the clock,
a camera path to play or a recording, and the frame it shows. The window (window.py) and the
offscreen recorder (offscreen.py) both drive one of these, so a scripted run is the same code as a
person at the keyboard."""

from __future__ import annotations

import time
from pathlib import Path

import moderngl
import numpy as np

from ..core.context import Context
from ..core.errors import IllusioError, InputError
from ..core.gl import check_size
from ..core.images import write_image
from ..core.renderer import Frame
from .display import DisplayPass
from .modes import MODES, Mode
from .navigation import MOVE_KEYS
from .path import CameraPath, PathRecorder

__all__ = ["Viewer"]


class Viewer:
    """``step(dt)`` advances the clock by ``dt`` seconds, moves the camera by the held keys (or along
    the camera path), renders the mode's image and composes the frame shown (``self.frame_texture``,
    linear RGBA8 at the viewer's size). Input: :meth:`key`, :meth:`drag`, :meth:`scroll`;
    switching: :meth:`set_mode`, :meth:`set_variant`; the panel: :meth:`set_param`."""

    def __init__(
        self,
        ctx: Context,
        technique: str = "plain",
        source: str | None = None,
        variant: str | None = None,
        size: tuple[int, int] = (1280, 720),
        path: CameraPath | None = None,
        record: PathRecorder | None = None,
    ):
        self.ctx = ctx
        self.size = check_size(size)
        self.display = DisplayPass(ctx)
        self.sources: dict[str, str | None] = {name: None for name in MODES}
        self.mode: Mode | None = None
        #: the pointer over the window, (x, y) in [0, 1]² from the top left (None: outside)
        self.pointer: tuple[float, float] | None = None
        self.keys: set[str] = set()
        self.time = 0.0
        self.index = 0
        self.path = path
        self.recorder = record
        self.frame_ms = 0.0  # smoothed wall time of a step, for the readout
        self.last_error = ""  # the last refused panel value, shown in the panel
        self._stale_error = ""  # a frame that could not be drawn with values that drew before
        self.frame_texture: moderngl.Texture | None = None
        self.sources[self._check(technique)] = source
        self.set_mode(technique, variant)

    @staticmethod
    def _check(technique: str) -> str:
        if technique not in MODES:
            raise InputError(f"unknown technique {technique!r}; choose one of {', '.join(MODES)}")
        return technique

    # -- switching -----------------------------------------------------------------------------
    def set_mode(self, technique: str, variant: str | None = None, source: str | None = None) -> None:
        """Switch technique (and variant / source) without a restart; the camera goes home."""
        self._check(technique)
        if source is not None:
            self.sources[technique] = source
        mode = MODES[technique](self.ctx, self.sources[technique], variant)
        if self.mode is not None:
            self.mode.release()
        self.mode = mode
        self.navigation = mode.navigation()
        self.last_error = ""
        self._good_params = None  # the mode's last params that drew a frame

    def set_variant(self, variant: str) -> None:
        previous = self.mode
        params = previous.params
        self.set_mode(self.mode.name, variant)
        if self.mode.shares_params and type(params) is type(self.mode.params):
            self.mode.params = params  # e.g. the lines mode keeps τ, λ... across its debug views
            self.mode.keep_from(previous)

    def next_mode(self) -> None:
        names = list(MODES)
        self.set_mode(names[(names.index(self.mode.name) + 1) % len(names)])

    def next_variant(self) -> None:
        variants = self.mode.variants
        self.set_variant(variants[(variants.index(self.mode.variant) + 1) % len(variants)])

    def set_source(self, source: str) -> bool:
        """Show another scene / mesh / hidden shape in the current mode (what the panel's scene combo
        and file field call); one that cannot be loaded leaves the mode as it was, the reason in
        ``last_error``."""
        previous = self.sources[self.mode.name]
        try:
            self.set_mode(self.mode.name, self.mode.variant, source)
        except InputError as exc:
            self.sources[self.mode.name] = previous
            self.last_error = str(exc)
            return False
        return True

    def home(self) -> None:
        self.navigation = self.mode.navigation()

    def set_param(self, name: str, value) -> bool:
        """Set one field of the mode's params (what the panel calls); a refused value leaves them as
        they were and is kept in ``last_error``."""
        try:
            self.mode.set_param(name, value)
        except InputError as exc:
            self.last_error = str(exc)
            return False
        self.last_error = ""
        return True

    # -- input ---------------------------------------------------------------------------------
    def key(self, name: str, pressed: bool) -> None:
        """A movement key (w a s d q e) went down or up."""
        name = name.lower()
        if name in MOVE_KEYS:
            (self.keys.add if pressed else self.keys.discard)(name)

    def drag(self, dx: float, dy: float) -> None:
        self.mode.pointer = self.pointer
        if not self.mode.drag(dx, dy):
            self.navigation.look(dx, dy)

    def mode_key(self, name: str) -> bool:
        """A letter key the viewer does not use, offered to the mode (the relight mode's L and O)."""
        self.mode.pointer = self.pointer
        return self.mode.key(name.lower())

    def scroll(self, dy: float) -> None:
        self.navigation.zoom(dy)

    # -- frames --------------------------------------------------------------------------------
    def view(self):
        if self.path is not None and self.mode.home_view() is not None:
            eye, _ = self.path.at(self.time)
            return self.path.view(self.time, self.mode.camera_at(eye))
        return self.navigation.view()

    def resize(self, size: tuple[int, int]) -> None:
        self.size = check_size(size)

    def step(self, dt: float = 1 / 30) -> moderngl.Texture:
        """Advance by ``dt`` seconds and draw the frame (``self.frame_texture``)."""
        start = time.perf_counter()
        if self.index > 0:
            self.time += dt
        if self.path is None:
            self.navigation.move(self.keys, dt)
        view = self.view()
        if self.recorder is not None and view is not None:
            self.recorder.add(self.time, view)
        frame = Frame(view, self.mode.image_size(self.size), self.time, self.index)
        self.mode.pointer = self.pointer
        try:
            image = self.mode.render(frame)
        except IllusioError as exc:
            # params that passed their checks but cannot be drawn (a host the scene lacks): the
            # last values that drew come back, and the panel says why
            if self._good_params is None or self._good_params == self.mode.params:
                if self.frame_texture is None:
                    raise  # nothing drawn yet: the input itself is bad (a recording stops)
                # the same values drew before: the window changed (too narrow for one strip, say);
                # the last frame stays and the panel says why
                self.last_error = self._stale_error = exc.one_line()
                return self.frame_texture
            self.mode.params = self._good_params
            image = self.mode.render(frame)
            self.last_error = f"{exc.one_line()} (the last values that worked are back)"
        self._good_params = self.mode.params
        if self.last_error and self.last_error == self._stale_error:
            self.last_error = self._stale_error = ""  # it draws again: the reason no longer holds
        if self.frame_texture is None or self.frame_texture.size != self.size:
            self.ctx.release(self.frame_texture)
            self.frame_texture = self.ctx.acquire(self.size, 4, "f1")
        target = self.ctx.framebuffer([self.frame_texture])
        image.filter = (moderngl.LINEAR, moderngl.LINEAR)
        self.display(target, self.size, image, self.mode.aside())
        self.ctx.release(image)
        self.index += 1
        ms = (time.perf_counter() - start) * 1000
        self.frame_ms = ms if self.index == 1 else 0.9 * self.frame_ms + 0.1 * ms
        return self.frame_texture

    def image(self) -> np.ndarray:
        """The last frame, float32 (H, W, 3) linear, row 0 at the top."""
        if self.frame_texture is None:
            raise InputError("no frame drawn yet")
        return self.ctx.readback_image(self.frame_texture, 3)

    def screenshot(self, path: str | Path) -> Path:
        """Write the last frame (the technique's image, without the panel), atomically."""
        p = Path(path)
        write_image(p, self.image())
        return p

    def release(self) -> None:
        if self.mode is not None:
            self.mode.release()
        self.ctx.release(self.frame_texture)
        self.frame_texture = None
