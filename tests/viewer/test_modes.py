"""Every viewer mode offscreen (no window, no X): what a person does changes the picture as it should."""

from pathlib import Path

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.viewer import MODES, CameraPath, Viewer
from illusio.viewer.offscreen import frame_count, record

SIZE = (320, 180)


def host_pixels(viewer: Viewer) -> int:
    """Pixels of the multi-scene host in the last frame (screen-space depth ≥ 0)."""
    return int((viewer.ctx.readback(viewer.mode.renderer.maps()["depth"])[..., 0] >= 0).sum())


def dark_pixels(image: np.ndarray) -> int:
    return int((image.max(axis=-1) < 0.5).sum())


def test_every_mode_and_view_draws_something_different(ctx):
    viewer = Viewer(ctx, "plain", size=SIZE)
    images = {}
    for name, mode in MODES.items():
        for variant in mode.variants:
            viewer.set_mode(name, variant)
            viewer.step()
            image = viewer.image()
            assert image.shape == (SIZE[1], SIZE[0], 3) and image.std() > 0.02, (name, variant)
            images[name, variant] = image
    keys = list(images)
    same = {(("ibr", "reconstruction"), ("ibr", "ground-truth"))}  # at a reference's own view: alike by design
    for i, a in enumerate(keys):
        for b in keys[i + 1 :]:
            if (a, b) in same:
                assert np.abs(images[a] - images[b]).mean() < 2e-3, (a, b)
            else:
                assert np.abs(images[a] - images[b]).mean() > 1e-3, (a, b)
    viewer.release()


def test_walking_toward_the_tv_grows_it_on_screen(ctx):
    viewer = Viewer(ctx, "sis", variant="tv", size=SIZE)
    viewer.step()
    counts = [host_pixels(viewer)]
    # face the TV (it stands at x = 0, z = -2.2) and walk to it
    walk = viewer.navigation
    eye = walk.position
    walk.yaw = float(np.degrees(np.arctan2(-(0 - eye[0]), -(-2.2 - eye[2]))))
    walk.pitch = -8.0
    viewer.key("w", True)
    for _ in range(3):
        viewer.step(0.5)
        counts.append(host_pixels(viewer))
    viewer.key("w", False)
    assert counts[1] < counts[2] < counts[3] and counts[3] > 2 * counts[0], counts
    # the snow is on the TV: its pixels vary from frame to frame where the TV is
    a = viewer.image()
    viewer.step(0.0)
    b = viewer.image()
    changed = np.abs(a - b).max(axis=-1) > 0.05
    assert changed.sum() > 0.3 * counts[-1]
    viewer.release()


def test_walking_around_the_interactive_wall_turns_the_hidden_scene(ctx):
    """Figure 25: in the interactive view, stepping sideways turns the hidden shape the wall shows;
    the plain wall view keeps it as it is."""
    shifts = {}
    for variant in ("interactive", "wall"):
        viewer = Viewer(ctx, "sis", variant=variant, size=SIZE)
        viewer.step()
        renderer = viewer.mode.renderer
        before = renderer.hidden_view(viewer.view(), viewer.mode.params, viewer.index)
        depth_before = ctx.readback(renderer.maps()["depth"])[..., 0]
        viewer.key("a", True)
        viewer.step(1.0)
        viewer.key("a", False)
        after = renderer.hidden_view(viewer.view(), viewer.mode.params, viewer.index)
        shifts[variant] = np.linalg.norm(np.subtract(after.pose.position, before.pose.position))
        if variant == "interactive":
            depth_after = ctx.readback(renderer.maps()["depth"])[..., 0]
            on = (depth_before >= 0) & (depth_after >= 0)
            assert np.abs(depth_after - depth_before)[on].max() > 0.05
        viewer.release()
    assert shifts["interactive"] > 0.1 and shifts["wall"] == 0.0, shifts


def test_lines_panel_changes_show(ctx):
    """Turning silhouettes off removes line pixels; another τ changes the ridge pixel count."""
    viewer = Viewer(ctx, "lines", "torus-knot", size=(256, 256))
    viewer.step()
    both = dark_pixels(viewer.image())
    assert viewer.set_param("lines", ("apparent-ridges",))
    viewer.step()
    ridges_only = viewer.image()
    assert 0 < dark_pixels(ridges_only) < both
    ridge_count = int((ctx.readback(viewer.mode.renderer.maps()["ridges"])[..., 0] > 0.5).sum())
    assert viewer.set_param("tau", 1.0)
    viewer.step()
    other = int((ctx.readback(viewer.mode.renderer.maps()["ridges"])[..., 0] > 0.5).sum())
    assert other != ridge_count and abs(other - ridge_count) > 0.05 * ridge_count
    # a value out of its declared range is refused and leaves the params as they were
    assert not viewer.set_param("lam", -1.0)
    assert "out of range" in viewer.last_error and viewer.mode.params.lam == 0.5
    viewer.release()


def test_camera_path_to_video_offscreen(ctx, tmp_path):
    import imageio.v3 as iio

    path = CameraPath.parse(
        '[{"t": 0, "eye": [2.5, 1.6, 2.4], "target": [0, 1.08, -2.2]},'
        ' {"t": 1.0, "eye": [0.3, 1.2, -0.8], "target": [0, 1.08, -2.2]}]'
    )
    counts = []
    n = record(
        "sis",
        None,
        "tv",
        SIZE,
        path,
        6,
        tmp_path / "walk.mp4",
        tmp_path / "last.png",
        ctx=ctx,
        on_frame=lambda i, v: counts.append(host_pixels(v)),
    )
    assert n == frame_count(path, 6, None) == 7
    frames = np.stack(list(iio.imiter(tmp_path / "walk.mp4")))
    assert frames.shape == (7, SIZE[1], SIZE[0], 3)
    assert counts == sorted(counts) and counts[-1] > 3 * counts[0]  # the path walks up to the TV
    assert Path(tmp_path / "last.png").stat().st_size > 1000


def test_frames_carry_time_and_index(ctx):
    """The mode's renderer gets the viewer's clock: frame index drives the snow."""
    viewer = Viewer(ctx, "sis", variant="raw", size=SIZE)
    seen = []
    real = viewer.mode.renderer.render_texture
    viewer.mode.renderer.render_texture = lambda frame, params=None: seen.append(frame) or real(frame, params)
    for _ in range(3):
        viewer.step(0.25)
    assert [f.index for f in seen] == [0, 1, 2] and [f.time for f in seen] == pytest.approx([0.0, 0.25, 0.5])
    assert all(isinstance(f, Frame) and f.size == (SIZE[0] // 2, SIZE[1]) for f in seen)
    viewer.release()


def test_the_lines_mode_keeps_its_settings_across_debug_views(ctx):
    viewer = Viewer(ctx, "lines", size=(64, 64))
    assert viewer.set_param("tau", 0.5)
    viewer.set_variant("q1")
    assert viewer.mode.variant == "q1" and viewer.mode.params.tau == 0.5
    viewer.set_mode("sis", "tv")
    viewer.set_param("emission", 0.2)
    viewer.set_variant("wall")  # another setup: the wall's own params
    assert viewer.mode.params.host == "back-wall"
    viewer.release()


def test_params_that_cannot_be_drawn_give_way_to_the_last_that_could(ctx):
    viewer = Viewer(ctx, "sis", variant="tv", size=SIZE)
    viewer.step()
    assert viewer.set_param("host", "aquarium")  # passes its checks, but the room has no aquarium
    viewer.step()
    assert viewer.mode.params.host == "tv-screen" and "aquarium" in viewer.last_error
    viewer.release()


def test_radiosity_links_follow_the_pointer(ctx):
    """In the links view the element under the pointer is the one whose links are drawn: two places
    on the floor pick two elements and two pictures."""
    viewer = Viewer(ctx, "radiosity", "cornell-box", "links", size=SIZE)
    pictures, picked = [], []
    for pointer in ((0.3, 0.9), (0.75, 0.2)):
        viewer.pointer = pointer
        viewer.step()  # the element map of this view
        viewer.step()  # drawn with the element under the pointer
        pictures.append(viewer.image())
        picked.append(viewer.mode.params.element)
        element = viewer.ctx.readback(viewer.mode.renderer.maps()["element"])[..., 0]
        h, w = element.shape
        assert picked[-1] == int(element[int(pointer[1] * h), int(pointer[0] * w)])
    assert picked[0] != picked[1]
    assert np.abs(pictures[0] - pictures[1]).mean() > 1e-3


def test_lamp_sliders_set_the_lamp_scales(ctx):
    """The radiosity and relight panels' lamp sliders write (name, factor) pairs into the params."""
    from illusio.viewer.modes import RadiosityMode

    class Imgui:
        def slider_float(self, label, value, lo, hi):
            return (label.startswith("lamp##"), 0.25) if label.startswith("lamp##") else (False, value)

    mode = RadiosityMode(ctx, "cornell-box")
    mode.lamp_sliders(Imgui(), ["lamp"])
    assert mode.params.lamp_scales == (("lamp", 0.25),)
    mode.release()


def test_relight_lamp_and_crate_follow_the_pointer(ctx):
    """Loscos 4.4 live: O stands a crate on the floor under the pointer (its shadow darkens the
    floor), a drag moves it to the new floor point under the pointer, L hangs a virtual lamp under
    the ceiling above the pointer (the room gets brighter); the per-pixel view says it shows none."""
    pytest.importorskip("mitsuba", reason="the relight mode's photograph is path-traced (photo extra)")
    viewer = Viewer(ctx, "relight", "office", "baseline", size=SIZE)
    viewer.step()
    before = viewer.image()
    viewer.pointer = (0.5, 0.85)
    assert viewer.mode_key("O")
    viewer.step()
    with_crate = viewer.image()
    assert np.abs(with_crate - before).mean() > 1e-3
    first = viewer.mode._placed["crate"].copy()
    viewer.pointer = (0.35, 0.85)
    viewer.drag(-20, 0)
    viewer.step()
    moved = viewer.mode._placed["crate"]
    assert moved[0] < first[0] - 0.1 and moved[1] == pytest.approx(first[1])
    assert np.abs(viewer.image() - with_crate).mean() > 1e-4
    viewer.pointer = (0.5, 0.7)
    assert viewer.mode_key("l") and not viewer.mode_key("z")
    viewer.step()
    session = viewer.mode.renderer.result()
    assert "virtual-lamp-0" in session.lamp_names and viewer.image().mean() > 1.02 * with_crate.mean()
    viewer.next_variant()  # per-pixel: no virtual things, and the panel says so
    viewer.step()
    assert "switch the view" in viewer.mode.message
    viewer.next_variant()  # loscos: the lamp and the crate are carried over
    viewer.step()
    session = viewer.mode.renderer.result()
    assert "virtual-lamp-0" in session.lamp_names and "crate" in session.solution.polygons.names
    viewer.release()


def test_a_window_too_small_to_draw_keeps_the_last_frame_and_says_why(ctx):
    """The raw stereogram needs a strip (W_s + β = 150 px) in its half of the window: shrunk below
    that, the viewer keeps the last frame and the panel says why instead of closing; grown back, it
    draws again. The first frame of a bad setup still raises (a recording stops with its error)."""
    viewer = Viewer(ctx, "sis", variant="raw", size=(640, 360))
    first = viewer.step()
    viewer.resize((200, 360))
    assert viewer.step() is first and "cannot hold one strip" in viewer.last_error
    viewer.resize((640, 360))
    viewer.step()
    assert viewer.index == 2 and viewer.last_error == ""
    viewer.release()
    small = Viewer(ctx, "sis", variant="raw", size=(200, 360))
    with pytest.raises(Exception, match="cannot hold one strip"):
        small.step()
    small.release()


def test_lines_t_chooses_parameters_that_match_the_view_edges(ctx):
    """T in the lines mode: τ, λ and the threshold chosen for the view as it is (the drawing then
    matches the shaded mesh's Canny edges at least as well as before), and the panel says what."""
    from dataclasses import replace

    from illusio.lines.compare import line_mask, score
    from illusio.lines.tuning import edge_target

    viewer = Viewer(ctx, "lines", "torus-knot", size=SIZE)
    viewer.mode.params = replace(viewer.mode.params, tau=-4.0, threshold=0.8)  # a poor start
    viewer.step()
    mode = viewer.mode
    target = edge_target(mode.renderer, mode.mesh, mode._frame.view, mode._frame.size)
    before = score(line_mask(viewer.image()), target).f1
    assert viewer.mode_key("T")
    assert mode.params.threshold != 0.8 and mode.message.startswith("auto: tau")
    viewer.step()
    assert score(line_mask(viewer.image()), target).f1 > before + 0.05
    assert not viewer.mode_key("z")
    viewer.release()


def test_lines_mode_draws_every_line_type(ctx):
    """Every line type the panel offers (LineParams.lines' choices) draws ink in the lines mode, and
    differently from the default drawing: on the blob every type but valleys (none past the default
    threshold) and boundaries (it is closed); in order, so a failure names the first."""
    from dataclasses import replace

    from illusio.lines.params import LINE_TYPES

    viewer = Viewer(ctx, "lines", "blob", size=SIZE)
    viewer.step()
    default = viewer.image()
    for kind in [k for k in LINE_TYPES if k not in ("valleys", "boundaries")]:
        viewer.mode.params = replace(viewer.mode.params, lines=(kind,))
        viewer.step()
        image = viewer.image()
        assert (image.min(axis=-1) < 0.6).sum() > 10 and np.abs(image - default).mean() > 1e-4, kind
    viewer.release()


def test_sis_wall_host_layout_from_the_panel(ctx):
    """The panel's host layout (MultiSceneParams.host_layout): "viewer" lays the hidden scene out in
    the viewer's image of the wall, a different stereogram from the uv one, on the same host pixels."""
    viewer = Viewer(ctx, "sis", variant="wall", size=SIZE)
    viewer.step()
    uv = viewer.image()
    hosts = host_pixels(viewer)
    viewer.mode.set_param("host_layout", "viewer")
    viewer.step()
    assert np.abs(viewer.image() - uv).mean() > 1e-3 and host_pixels(viewer) == hosts
    with pytest.raises(Exception, match="not one of"):
        viewer.mode.set_param("host_layout", "sideways")
    viewer.release()


def test_the_sis_mode_takes_a_scene_or_a_hidden_shape_as_its_source(ctx):
    """`illusio view living-room -t sis` failed ("not a built-in shape"): a scene source is the host
    scene (the default shape hidden), a shape or mesh source the hidden shape, as before."""
    from illusio.viewer.modes import SisMode

    by_scene = SisMode(ctx, "office", "wall")
    by_shape = SisMode(ctx, "torus", "tv")
    try:
        assert by_scene.source == "torus-knot"
        assert "lamp-0" in [light.name for light in by_scene.scene.lights]  # the office hosts it
        ctx.release(by_scene.render(Frame(by_scene.home_view(), SIZE)))  # the viewer releases what a mode draws
        assert (ctx.readback(by_scene.renderer.maps()["depth"])[..., 0] >= 0).sum() > 100  # on its back wall
        assert by_shape.source == "torus" and "tv-screen" in [n.name for n in by_shape.scene.nodes]
    finally:
        by_scene.release()
        by_shape.release()


def test_the_dof_mode_opens_with_the_command_lines_defaults(ctx):
    """One source of defaults: `illusio view -t dof` opens as `illusio dof` draws (DofParams()), its
    scenario view as the command page's Figure 11 line runs it."""
    from illusio.dof.params import DofParams
    from illusio.gallery.dof import FIGURE_11_PARAMS
    from illusio.viewer.modes import MODES

    walk = MODES["dof"](ctx, "cornell-box", "walk")
    scenario = MODES["dof"](ctx, None, "scenario")
    try:
        assert walk.params == DofParams()
        assert scenario.params.method == FIGURE_11_PARAMS.method
        assert scenario.params.aperture_mm == FIGURE_11_PARAMS.aperture_mm
    finally:
        walk.release()
        scenario.release()
