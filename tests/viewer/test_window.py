"""The real window under a virtual X server: start it, walk, look around, switch every technique and
view, change panel values, take screenshots, and check each changed the picture as it should.

Events go through the callbacks the window registered with GLFW (the functions GLFW calls when X
delivers a key or a mouse event), so everything from there on is the code a person exercises."""

import glfw
import numpy as np
import pytest

from illusio.core.images import linear_to_srgb, read_image
from illusio.viewer.panel import PANEL_WIDTH

SIZE = (640, 360)


@pytest.fixture
def window(x_display, tmp_path):
    from illusio.viewer.window import ViewerWindow

    w = ViewerWindow("sis", None, "tv", SIZE, screenshot_dir=tmp_path)
    yield w
    w.close()


def press(w, key):
    w.window.glfw_key_event_callback(w.window._window, key, 0, glfw.PRESS, 0)


def release(w, key):
    w.window.glfw_key_event_callback(w.window._window, key, 0, glfw.RELEASE, 0)


def tap(w, key):
    press(w, key)
    release(w, key)


def host_pixels(w) -> int:
    return int((w.ctx.readback(w.viewer.mode.renderer.maps()["depth"])[..., 0] >= 0).sum())


def test_window_shows_the_frame_beside_its_panel(window):
    """The panel is a column left of the image: the window is the image's width plus the panel's, and
    the image is the size asked for (its aspect kept), drawn whole right of the panel."""
    window.frame(1 / 30)
    window.frame(1 / 30)  # imgui sizes an auto-sized window on its first frame and shows it on the next
    screen = np.frombuffer(window.window.ctx.screen.read(components=3), np.uint8)
    bw, bh = window.window.buffer_size
    assert (bw, bh) == (SIZE[0] + PANEL_WIDTH, SIZE[1]) and window.viewer.size == SIZE
    screen = screen.reshape(bh, bw, 3)[::-1].astype(np.float32) / 255
    expected = linear_to_srgb(window.viewer.image())
    assert np.abs(screen[:, PANEL_WIDTH:] - expected).mean() < 2 / 255
    assert screen[:, :PANEL_WIDTH].std() > 0.02  # the panel's text and widgets


def test_a_window_screenshot_holds_the_panel_and_the_frame(window, tmp_path):
    """--screenshot-window: the whole window as drawn, the panel (its settings) in its column, the
    frame right of it; --screenshot keeps the frame without the panel."""
    window.frame(1 / 30)
    window.frame(1 / 30, grab=tmp_path / "window.png")
    whole = linear_to_srgb(read_image(tmp_path / "window.png"))
    frame = linear_to_srgb(window.viewer.image())
    bw, bh = window.window.buffer_size
    assert whole.shape[:2] == (bh, bw)
    assert np.abs(whole[:, PANEL_WIDTH:] - frame).mean() < 2 / 255
    assert whole[:, :PANEL_WIDTH].std() > 0.02  # the panel


def test_walking_looking_switching_and_screenshots(window, tmp_path):
    w = window
    w.frame(1 / 30)
    start = host_pixels(w)
    press(w, glfw.KEY_W)
    for _ in range(4):
        w.frame(0.25)
    release(w, glfw.KEY_W)
    assert host_pixels(w) > 1.3 * start  # walked towards the TV
    assert w.viewer.keys == set()
    # a mouse drag to the right turns the head right (yaw decreases by 0.2° a pixel)
    yaw = w.viewer.navigation.yaw
    glfw.set_cursor_pos(w.window._window, 500, 200)
    w.window.glfw_mouse_event_callback(w.window._window, 500, 200)
    w.window.glfw_mouse_button_callback(w.window._window, glfw.MOUSE_BUTTON_LEFT, glfw.PRESS, 0)
    w.window.glfw_mouse_event_callback(w.window._window, 540, 200)
    w.window.glfw_mouse_button_callback(w.window._window, glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE, 0)
    w.frame(1 / 30)
    assert w.viewer.navigation.yaw == pytest.approx(yaw - 40 * 0.2)
    # every technique and view, a screenshot of each (P), all different
    shots = []
    for number, technique in (
        (glfw.KEY_1, "plain"),
        (glfw.KEY_2, "sis"),
        (glfw.KEY_3, "lines"),
        (glfw.KEY_4, "dof"),
        (glfw.KEY_5, "ibr"),
        (glfw.KEY_6, "radiosity"),
        (glfw.KEY_7, "relight"),
    ):
        tap(w, number)
        for _ in w.viewer.mode.variants:
            w.frame(1 / 30)
            tap(w, glfw.KEY_P)
            shots.append((technique, w.viewer.mode.variant))
            tap(w, glfw.KEY_V)
        assert w.viewer.mode.name == technique
    files = sorted(tmp_path.glob("illusio-*.png"))
    assert len(files) == len(shots) == 1 + 4 + 4 + 2 + 3 + 3 + 3
    assert w.viewer.pointer is not None  # the mouse moves above told the viewer where it is
    images = [read_image(f) for f in files]
    for i in range(len(images) - 1):
        assert np.abs(images[i] - images[i + 1]).mean() > 1e-3, (shots[i], shots[i + 1])
    tap(w, glfw.KEY_TAB)
    assert w.viewer.mode.name == "plain"


def test_panel_values_change_the_line_drawing(window):
    w = window
    tap(w, glfw.KEY_3)
    w.frame(1 / 30)

    def dark():
        return int((w.viewer.image().max(axis=-1) < 0.5).sum())

    def ridges():
        return int((w.ctx.readback(w.viewer.mode.renderer.maps()["ridges"])[..., 0] > 0.5).sum())

    both, ridge_count = dark(), ridges()
    assert w.viewer.set_param("lines", ("apparent-ridges",))  # what the panel's check box calls
    w.frame(1 / 30)
    assert dark() < both
    assert w.viewer.set_param("tau", 1.0)
    w.frame(1 / 30)
    assert ridges() != ridge_count
    # orbiting with keys moves around the mesh
    before = w.viewer.view().pose.position
    press(w, glfw.KEY_D)
    w.frame(0.5)
    release(w, glfw.KEY_D)
    assert np.linalg.norm(np.subtract(w.viewer.view().pose.position, before)) > 0.1


def test_escape_closes_and_the_recorded_walk_is_saved(x_display, tmp_path):
    from illusio.viewer.path import CameraPath
    from illusio.viewer.window import ViewerWindow

    w = ViewerWindow("plain", "living-room", None, SIZE, record=tmp_path / "walk.json")
    press(w, glfw.KEY_W)
    for _ in range(6):
        w.frame(0.2)
    release(w, glfw.KEY_W)
    tap(w, glfw.KEY_ESCAPE)
    assert w.window.is_closing
    w.run(screenshot=tmp_path / "last.png")  # closes at once: saves the screenshot and the walk
    path = CameraPath.load(tmp_path / "walk.json")
    assert len(path.keyframes) >= 4 and path.duration == pytest.approx(1.0)
    last = read_image(tmp_path / "last.png")
    assert last.ndim == 3 and last.shape[0] > 16 and last.std() > 0.01  # a picture, not a blank


def test_switching_the_scene_and_a_bad_file_in_the_panel(window, tmp_path):
    w = window
    tap(w, glfw.KEY_1)
    w.frame(1 / 30)
    room = w.viewer.image()
    assert w.viewer.set_source("office")  # the panel's scene combo
    w.frame(1 / 30)
    assert w.viewer.mode.source == "office" and np.abs(w.viewer.image() - room).mean() > 0.02
    broken = tmp_path / "broken.obj"
    broken.write_text("v 0 0 0\nf 1 2 3\n")
    assert not w.viewer.set_source(str(broken))  # the panel's file field
    assert "broken.obj" in w.viewer.last_error and w.viewer.mode.source == "office"
    w.frame(1 / 30)


def test_the_command_opens_the_window_and_saves_the_last_frame(x_display, tmp_path):
    import subprocess
    import sys

    shot = tmp_path / "shot.png"
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "illusio",
            "view",
            "--technique",
            "lines",
            "--size",
            "320x240",
            "--exit-after",
            "3",
            "--screenshot",
            str(shot),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        env={**__import__("os").environ, "DISPLAY": x_display, "XDG_CONFIG_HOME": str(tmp_path / "config")},
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    # the panel's layout goes to the user's config folder, not into the folder the viewer started in
    assert not (tmp_path / "imgui.ini").exists() and (tmp_path / "config" / "illusio" / "imgui.ini").is_file()
    image = read_image(shot)
    assert image.shape[:2] == (240, 320) and (image.max(axis=-1) < 0.5).sum() > 200  # a line drawing


def test_no_display_and_no_video_is_one_clear_line(tmp_path, monkeypatch):
    import subprocess
    import sys

    env = {k: v for k, v in __import__("os").environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = subprocess.run([sys.executable, "-m", "illusio", "view"], capture_output=True, text=True, timeout=300, env=env)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "no display" in r.stderr and "-o OUT.mp4" in r.stderr
