"""``illusio view`` in a real window: moderngl-window's GLFW backend, the imgui panel, keyboard and
mouse navigation. Everything the window shows comes from a :class:`~illusio.viewer.viewer.Viewer`.
The panel is a column at the window's left (PANEL_WIDTH px) and the image fills the rest: a window
opened for an image of W×H is W + PANEL_WIDTH wide, so the image keeps the size and aspect asked
for; resizing the window resizes the image.

Keys: W A S D walk (orbit: turn), Q E down / up (orbit: zoom), mouse drag to look (orbit: turn),
wheel to zoom, Tab next technique, 1 2 3 4 5 a technique (plain, sis, lines, dof, ibr), V next view of the technique,
H home,
P screenshot, Esc quit.
"""

from __future__ import annotations

import atexit
import os
import time
from pathlib import Path

import moderngl
import numpy as np

from ..core.context import Context, release_current
from ..core.errors import GLUnavailable
from .modes import MODES
from .panel import PANEL_WIDTH
from .path import CameraPath, PathRecorder
from .viewer import Viewer

#: letter keys the window passes to the mode (the relight mode: L a lamp, O an object; the lines
#: mode: T the automatic choice of its parameters)
MODE_KEYS = "lot"

__all__ = ["ViewerWindow"]

_TERMINATE_AT_EXIT: list[bool] = []


class ViewerWindow:
    """A window driving one Viewer. :meth:`frame` draws one frame and handles the events that
    arrived; :meth:`run` loops until the window closes (or ``exit_after`` frames)."""

    def __init__(
        self,
        technique: str = "plain",
        source: str | None = None,
        variant: str | None = None,
        size: tuple[int, int] = (1280, 720),
        path: CameraPath | None = None,
        record: Path | None = None,
        screenshot_dir: Path = Path("."),
    ):
        if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
            raise GLUnavailable(
                "no display to open a window on (DISPLAY is not set); record a camera path "
                "offscreen instead: illusio view --path CAMERA.json -o OUT.mp4"
            )
        try:
            import moderngl_window
            from imgui_bundle import imgui
            from moderngl_window.context.glfw import Window
            from moderngl_window.integrations.imgui_bundle import ModernglWindowRenderer
        except ImportError as exc:
            raise GLUnavailable(
                f"the window needs the viewer extras ({exc.name} is missing): "
                "pip install 'illusio[viewer]' (or record offscreen with -o OUT.mp4)"
            ) from None

        release_current()  # a headless context of this process must not stay current beside the window's
        try:
            # the image at the size asked for, beside the panel's column
            window_size = (int(size[0]) + PANEL_WIDTH, int(size[1]))
            self.window = Window(title="illusio", size=window_size, gl_version=(4, 3), vsync=False, resizable=True)
        except Exception as exc:  # glfw raises plain exceptions when no GL 4.3 window can be made
            raise GLUnavailable(
                f"cannot open an OpenGL 4.3 window ({' '.join(str(exc).split())}); "
                "on Debian/Ubuntu: apt-get install -y --no-install-recommends libgl1 libgl1-mesa-dri"
            ) from None
        moderngl_window.activate_context(window=self.window)
        self.imgui = imgui
        self.imgui_context = imgui.create_context()
        imgui.set_current_context(self.imgui_context)  # create_context makes only the first one current
        # the panel's place and size are kept in the user's config folder, not written into whatever
        # folder the viewer was started from
        settings = Path(os.environ.get("XDG_CONFIG_HOME") or Path.home() / ".config") / "illusio" / "imgui.ini"
        settings.parent.mkdir(parents=True, exist_ok=True)
        imgui.get_io().set_ini_filename(str(settings))
        from .panel import load_panel_font

        load_panel_font(imgui)  # before the renderer builds the font texture
        self.gui = ModernglWindowRenderer(self.window)
        import glfw

        handle = self.window._window
        self.ctx = Context.wrap(
            self.window.ctx,
            activate=lambda: glfw.make_context_current(handle),
            deactivate=lambda: glfw.make_context_current(None),
        )
        self.record_path = record
        self.viewer = Viewer(
            self.ctx, technique, source, variant, self.image_size(), path, PathRecorder() if record else None
        )
        self.screenshot_dir = Path(screenshot_dir)
        self.screenshots = 0
        self.panel_state: dict = {}
        keys = self.window.keys
        self._move = {keys.W: "w", keys.A: "a", keys.S: "s", keys.D: "d", keys.Q: "q", keys.E: "e"}
        self._modes = {getattr(keys, f"NUMBER_{i}"): name for i, name in enumerate(MODES, 1) if i <= 9}
        w = self.window
        w.key_event_func = self.on_key
        w.mouse_drag_event_func = self.on_drag
        w.mouse_scroll_event_func = self.on_scroll
        w.mouse_position_event_func = self.on_pointer
        w.mouse_press_event_func = self.gui.mouse_press_event
        w.mouse_release_event_func = self.gui.mouse_release_event
        w.unicode_char_entered_func = self.gui.unicode_char_entered
        w.resize_func = self.on_resize
        self._last = time.perf_counter()

    # -- events --------------------------------------------------------------------------------
    def on_key(self, key, action, modifiers) -> None:
        self.gui.key_event(key, action, modifiers)
        keys = self.window.keys
        if self.imgui.get_io().want_capture_keyboard:
            return
        if key in self._move:
            self.viewer.key(self._move[key], action == keys.ACTION_PRESS)
            return
        if action != keys.ACTION_PRESS:
            return
        if key == keys.TAB:
            self.viewer.next_mode()
        elif key in self._modes:
            self.viewer.set_mode(self._modes[key])
        elif key == keys.V:
            self.viewer.next_variant()
        elif key == keys.H:
            self.viewer.home()
        elif key == keys.P:
            self.screenshot()
        else:
            letter = next((c for c in MODE_KEYS if key == getattr(keys, c.upper(), None)), None)
            if letter is not None:
                self.viewer.mode_key(letter)

    def panel_pixels(self) -> int:
        """The panel column's width in pixels of the frame buffer (PANEL_WIDTH window px, scaled)."""
        scale = self.window.buffer_size[0] / max(self.window.size[0], 1)
        return int(round(PANEL_WIDTH * scale))

    def image_size(self) -> tuple[int, int]:
        """The image's size (pixels): the frame buffer right of the panel."""
        bw, bh = self.window.buffer_size
        return max(1, bw - self.panel_pixels()), bh

    def on_pointer(self, x, y, dx, dy) -> None:
        self.gui.mouse_position_event(x, y, dx, dy)
        w, h = self.window.size
        x -= PANEL_WIDTH  # over the image, right of the panel
        w -= PANEL_WIDTH
        self.viewer.pointer = (x / max(w, 1), y / max(h, 1)) if 0 <= x < w and 0 <= y < h else None

    def on_drag(self, x, y, dx, dy) -> None:
        self.gui.mouse_drag_event(x, y, dx, dy)
        if not self.imgui.get_io().want_capture_mouse and self.window.mouse_states.left:
            self.viewer.drag(dx, dy)

    def on_scroll(self, x_offset, y_offset) -> None:
        self.gui.mouse_scroll_event(x_offset, y_offset)
        if not self.imgui.get_io().want_capture_mouse:
            self.viewer.scroll(y_offset)

    def on_resize(self, width, height) -> None:
        self.gui.resize(width, height)
        if min(self.window.buffer_size) >= 1:  # a minimised window has no pixels: keep the last size
            self.viewer.resize(self.image_size())

    def grab_window(self, path: Path) -> Path:
        """Write what the window shows now (the frame and the panel), atomically: the back buffer,
        sRGB-encoded as drawn, row 0 at the top."""
        from ..core.images import srgb_to_linear, write_image

        w, h = self.window.buffer_size
        pixels = np.frombuffer(self.window.ctx.screen.read((0, 0, w, h), components=3), np.uint8)
        image = srgb_to_linear(pixels.reshape(h, w, 3)[::-1].astype(np.float32) / 255.0)
        write_image(path, image)
        return Path(path)

    def screenshot(self, path: Path | None = None) -> Path:
        if path is None:
            self.screenshots += 1
            path = self.screenshot_dir / f"illusio-{self.viewer.mode.name}-{self.screenshots:03d}.png"
        return self.viewer.screenshot(path)

    # -- frames --------------------------------------------------------------------------------
    def frame(self, dt: float | None = None, grab: Path | None = None) -> None:
        """One frame of the window; ``grab``: also write the whole window, panel included, there
        (read before the buffers swap)."""
        now = time.perf_counter()
        dt = now - self._last if dt is None else dt
        self._last = now
        self.ctx.make_current()
        self.window.use()
        frame = self.viewer.step(min(dt, 0.25))
        screen = self.window.ctx.screen
        screen.use()
        screen.clear(0.1, 0.1, 0.1)  # under the panel
        self.viewer.display(screen, self.image_size(), frame, encode_srgb=True, origin=(self.panel_pixels(), 0))
        imgui = self.imgui
        imgui.new_frame()
        from .panel import draw_panel

        draw_panel(self.viewer, imgui, {"screenshot": self.screenshot}, self.panel_state, self.window.size[1])
        imgui.render()
        self.gui.render(imgui.get_draw_data())
        self.window.ctx.enable_only(moderngl.NOTHING)  # imgui leaves blending on; the passes expect it off
        if grab is not None:
            self.grab_window(grab)
        self.window.title = (
            f"illusio — {self.viewer.mode.name} ({self.viewer.mode.variant}) — {self.viewer.frame_ms:.0f} ms"
        )
        self.window.swap_buffers()

    def run(
        self, exit_after: int | None = None, screenshot: Path | None = None, window_screenshot: Path | None = None
    ) -> None:
        """Frames until the window closes (or ``exit_after`` of them, or a played path ends); then
        ``screenshot`` gets the last frame, ``window_screenshot`` the window with its panel."""
        frames = 0
        try:
            while not self.window.is_closing and (exit_after is None or frames < exit_after):
                self.frame()
                frames += 1
                if (
                    self.viewer.path is not None
                    and self.viewer.time >= self.viewer.path.duration
                    and exit_after is None
                ):
                    break
            if screenshot is not None:
                self.screenshot(screenshot)
            if window_screenshot is not None:
                self.frame(grab=window_screenshot)
            if self.record_path is not None and self.viewer.recorder.keyframes:
                self.viewer.recorder.save(self.record_path)
        finally:
            self.close()

    def close(self) -> None:
        self.ctx.make_current()
        self.viewer.release()
        self.gui.shutdown()
        self.imgui.destroy_context(self.imgui_context)
        # only the window: GLFW itself stays initialised until the process ends, because a second
        # glfw.init() after glfw.terminate() in one process failed to reopen the X display here
        import glfw

        release_current()
        glfw.destroy_window(self.window._window)
        if not _TERMINATE_AT_EXIT:
            atexit.register(glfw.terminate)
            _TERMINATE_AT_EXIT.append(True)
