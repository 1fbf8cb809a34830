"""The DofRenderer through the protocol: stereo outputs, the methods against the reference, focus."""

from dataclasses import replace

import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.dof import DofParams, DofRenderer, object_distance
from illusio.passes.scene_renderer import RenderSettings
from illusio.scene import load_scene
from tests.conftest import call_cli

SIZE = (160, 120)


@pytest.fixture(scope="module")
def museum():
    return load_scene("museum")


def test_stereo_outputs_and_maps(ctx, museum):
    renderer = DofRenderer(ctx)
    renderer.prepare(museum)
    frame = Frame(museum.camera(), SIZE)
    mono = renderer.render(frame, DofParams())
    assert mono.shape == (SIZE[1], SIZE[0], 3) and set(renderer.maps()) == {"coc", "depth"}
    for stereo, shape in (
        ("side-by-side", (SIZE[1], 2 * SIZE[0])),
        ("top-bottom", (2 * SIZE[1], SIZE[0])),
        ("anaglyph", (SIZE[1], SIZE[0])),
        ("left", (SIZE[1], SIZE[0])),
    ):
        image = renderer.render(frame, DofParams(stereo=stereo))
        assert image.shape[:2] == shape, stereo
    sbs = renderer.render(frame, DofParams(stereo="side-by-side", eye_separation=0.2))
    assert np.abs(sbs[:, : SIZE[0]] - sbs[:, SIZE[0] :]).mean() > 0.005  # two different eyes
    assert {"left", "right", "coc", "depth"} <= set(renderer.maps())
    renderer.release()


def test_focus_is_sharp_and_gather_follows_the_accumulation_reference(ctx, museum):
    """Against the accumulation reference (64 lens positions): where the circle of confusion is
    under a pixel both methods keep the sharp image; overall the gather is much closer to the
    reference than the sharp image is."""
    renderer = DofRenderer(ctx)
    renderer.prepare(museum)
    view = museum.camera()
    focus = object_distance(museum, "exhibit-blob", view)
    base = DofParams(focus_distance=focus, aperture_mm=250.0, max_coc=12.0, settings=RenderSettings(shadows=False))
    frame = Frame(view, SIZE)
    sharp = renderer.render(frame, replace(base, aperture_mm=0.0))
    gathered = renderer.render(frame, base)
    coc = ctx.readback(renderer.maps()["coc"])[..., 0]
    reference = renderer.render(frame, replace(base, method="accumulation", samples=64))
    in_focus = coc < 0.5
    blurred = coc > 3
    assert in_focus.mean() > 0.02 and blurred.mean() > 0.1
    assert np.abs(gathered - sharp)[in_focus].mean() < 0.01
    assert np.abs(reference - sharp)[in_focus].mean() < 0.02
    sharp_error = np.abs(sharp - reference)[blurred].mean()
    gather_error = np.abs(gathered - reference)[blurred].mean()
    assert gather_error < 0.6 * sharp_error, (gather_error, sharp_error)
    renderer.release()


def test_focus_on_an_object_puts_its_centre_at_the_focus_distance(museum):
    from illusio.core.errors import InputError

    view = museum.camera()
    d = object_distance(museum, "exhibit-torus", view)
    node = next(n for n in museum.nodes if n.name == "exhibit-torus")
    centre = node.transform[:3, 3]
    forward = np.subtract(view.pose.target, view.pose.position)
    assert d == pytest.approx(float(np.dot(centre - view.pose.position, forward / np.linalg.norm(forward))), rel=0.05)
    with pytest.raises(InputError, match="no object named 'ghost'"):
        object_distance(museum, "ghost", view)


def test_dof_command(tmp_path, capsys):
    out = tmp_path / "dof.png"
    code, cap = call_cli(
        [
            "dof",
            "museum",
            "-o",
            str(out),
            "--size",
            "96x72",
            "--focus-object",
            "exhibit-blob",
            "--stereo",
            "side-by-side",
        ],
        capsys,
    )
    assert code == 0, cap.err
    from illusio.core import read_image

    assert read_image(out).shape[:2] == (72, 192)
    code, cap = call_cli(
        ["dof", "museum", "-o", str(tmp_path / "pair.png"), "--size", "64x48", "--stereo", "left-right"], capsys
    )
    assert code == 0, cap.err
    left, right = read_image(tmp_path / "pair-left.png"), read_image(tmp_path / "pair-right.png")
    assert left.shape[:2] == right.shape[:2] == (48, 64) and np.abs(left - right).mean() > 1e-3
    code, cap = call_cli(["dof", "museum", "-o", str(tmp_path / "x.png"), "--method", "bokeh"], capsys)
    assert code == 2 and cap.err.count("\n") == 1 and "bokeh" in cap.err
    code, cap = call_cli(["dof", "museum", "-o", str(tmp_path / "x.png"), "--aperture", "-3"], capsys)
    assert code == 2 and "aperture" in cap.err


def test_a_scenario_plays_as_a_stereo_video_and_a_bad_one_says_where(tmp_path, capsys):
    import imageio.v3 as iio

    video = tmp_path / "fut.gif"
    code, cap = call_cli(
        [
            "dof",
            "futuristic",
            "--scenario",
            "futuristic",
            "--video",
            str(video),
            "--fps",
            "2",
            "--duration",
            "3",
            "--size",
            "64x48",
            "--stereo",
            "side-by-side",
            "--method",
            "planes",
        ],
        capsys,
    )
    assert code == 0, cap.err
    frames = iio.imread(video, index=None)
    assert frames.shape[:3] == (6, 48, 128)
    bad = tmp_path / "bad.txt"
    bad.write_text("temps 0\naffiche objet 1\nnettete objet 99\n")
    code, cap = call_cli(["dof", "futuristic", "--scenario", str(bad), "--video", str(tmp_path / "x.mp4")], capsys)
    assert code == 2 and f"{bad}:3:1: no object 99" in cap.err and cap.err.count("\n") == 1
    bad.write_text("temps 0\naffiche objet 1 vecteur\n")
    code, cap = call_cli(["dof", "futuristic", "--scenario", str(bad), "--video", str(tmp_path / "x.mp4")], capsys)
    assert code == 2 and f"{bad}:2:17:" in cap.err
    assert not (tmp_path / "x.mp4").exists()


#: a view where blur is large: the unblurred image scores under 30 dB against the accumulation
STRONG = dict(focus_distance=4.5, aperture_mm=500.0, max_coc=16.0)


def _psnr(a, b):
    return float(10 * np.log10(1.0 / np.mean((a - b) ** 2)))


def _sharpness(image, mask):
    """Mean |discrete Laplacian| of the luminance over ``mask``: a local measure of detail."""
    y = image[..., :3].mean(axis=-1)
    lap = np.abs(4 * y[1:-1, 1:-1] - y[:-2, 1:-1] - y[2:, 1:-1] - y[1:-1, :-2] - y[1:-1, 2:])
    return float(lap[mask[1:-1, 1:-1]].mean())


@pytest.fixture(scope="module")
def strong_view(ctx, museum):
    """The museum's main view, its accumulation reference (128 lens positions), the unblurred image
    and the circle of confusion map, made once for the method tests."""
    renderer = DofRenderer(ctx)
    renderer.prepare(museum)
    base = DofParams(**STRONG, settings=RenderSettings(shadows=False))
    frame = Frame(museum.camera(), SIZE)
    reference = renderer.render(frame, replace(base, method="accumulation", samples=128))
    sharp = renderer.render(frame, replace(base, aperture_mm=0.0))
    renderer.render(frame, base)
    coc = ctx.readback(renderer.maps()["coc"])[..., 0]
    yield ctx, renderer, frame, base, reference, sharp, coc
    renderer.release()


@pytest.mark.parametrize("method", ["gather", "gather-exact", "mipmap", "planes"])
def test_every_method_follows_the_accumulation_where_blur_is_large(strong_view, method):
    """The whole renderer, not a pass against its NumPy twin: against an accumulation of the same
    view, each method is closer than the unblurred image by its table gain; where the circle of
    confusion is under a pixel the detail stays (sharpness ≥ 0.7 of the sharp image's), where it is
    over 6 px it goes (≤ 0.4; the accumulation itself keeps 0.24); both eyes of a stereo pair alike."""
    from tests.conftest import tolerance

    _, renderer, frame, base, reference, sharp, coc = strong_view
    params = replace(base, method="gather", gather_taps=0) if method == "gather-exact" else replace(base, method=method)
    image = renderer.render(frame, params)
    unblurred = _psnr(sharp, reference)
    assert unblurred <= 30.0  # the view is a hard one
    gain = _psnr(image, reference) - unblurred
    assert gain >= tolerance(f"dof gain {method}")["min_db"], gain
    in_focus, far_off = coc < 1.0, coc > 6.0
    assert in_focus.mean() > 0.03 and far_off.mean() > 0.3
    assert _sharpness(image, in_focus) >= 0.7 * _sharpness(sharp, in_focus)
    assert _sharpness(image, far_off) <= 0.4 * _sharpness(sharp, far_off)
    pair = renderer.render(frame, replace(params, stereo="left-right"))
    sharp_pair = renderer.render(frame, replace(params, stereo="left-right", aperture_mm=0.0))
    w = SIZE[0]
    for eye in (slice(0, w), slice(w, 2 * w)):
        ratio = _sharpness(pair[:, eye], far_off) / _sharpness(sharp_pair[:, eye], far_off)
        assert ratio <= 0.4, (method, eye, ratio)


def test_zero_parallax_stays_at_the_screen_while_the_focus_moves(ctx, museum):
    """The paper's premise: the eyes converge on the screen whatever they focus on. The eyes' views
    depend on the screen distance, not on the focus; the difference is reported in dioptres."""
    renderer = DofRenderer(ctx)
    renderer.prepare(museum)
    frame = Frame(museum.camera(), SIZE)
    views = [renderer.views(frame, DofParams(stereo="left-right", focus_distance=f)) for f in (1.5, 6.0)]
    for a, b in zip(*views):
        assert np.allclose(a.projection_matrix(SIZE[0] / SIZE[1]), b.projection_matrix(SIZE[0] / SIZE[1]))
    renderer.render(frame, DofParams(stereo="left-right", focus_distance=4.0, method="gather"))
    result = renderer.result()
    assert result.screen_distance == pytest.approx(1.0)
    assert result.conflict_dioptres == pytest.approx(abs(1 / 1.0 - 1 / 4.0))
    moved = renderer.views(frame, DofParams(stereo="left-right", screen_distance=3.0))
    assert not np.allclose(moved[0].projection_matrix(1.0), views[0][0].projection_matrix(1.0))
    renderer.release()


def test_figure_11_shows_depth_of_field():
    """The command page's Figure 11 command is the gallery's; the script's focus changes by metres when the
    robot fires (it went from 28.1 to 27.0 m), and the aperture blurs the far end of the ship's
    loop by many pixels while the robot is in focus."""
    from pathlib import Path

    from illusio.dof.lens import coc_pixels
    from illusio.dof.scenario import load_scenario, shipped_scenario
    from illusio.dof.timeline import ScenarioPlayer
    from illusio.gallery.dof import FIGURE_11_APERTURE, FIGURE_11_COMMAND
    from illusio.scene.builtin import builtin_scene

    commands = (Path(__file__).resolve().parents[2] / "docs" / "commands.md").read_text()
    assert FIGURE_11_COMMAND in " ".join(commands.split())
    scene = builtin_scene("futuristic")
    view = scene.camera()
    player = ScenarioPlayer(load_scenario(shipped_scenario("futuristic")), scene)
    focuses = []
    for t in np.arange(0.0, player.loop, 0.25):
        player.apply(scene, t)
        f = player.focus_distance(view, t)
        if f is not None:
            focuses.append(f)
    near, far = min(focuses), max(focuses)
    assert far - near > 10.0, (near, far)
    player.apply(scene, 2.4)
    ship = player.focus_distance(view, 2.4)  # just before the robot fires, then (the focus moved) on the robot
    player.apply(scene, 3.4)
    assert ship - player.focus_distance(view, 3.4) > 8.0
    largest = coc_pixels(np.array([far]), near, FIGURE_11_APERTURE / 1000, view.camera.fov_y, 384)[0]
    assert largest > 6.0
