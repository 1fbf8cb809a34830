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
    for stereo, shape in (("side-by-side", (SIZE[1], 2 * SIZE[0])), ("top-bottom", (2 * SIZE[1], SIZE[0])),
                          ("anaglyph", (SIZE[1], SIZE[0])), ("left", (SIZE[1], SIZE[0]))):
        image = renderer.render(frame, DofParams(stereo=stereo))
        assert image.shape[:2] == shape, stereo
    sbs = renderer.render(frame, DofParams(stereo="side-by-side", eye_separation=0.2))
    assert np.abs(sbs[:, :SIZE[0]] - sbs[:, SIZE[0]:]).mean() > 0.005  # two different eyes
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
    code, cap = call_cli(["dof", "museum", "-o", str(out), "--size", "96x72", "--focus-object", "exhibit-blob",
                          "--stereo", "side-by-side"], capsys)
    assert code == 0, cap.err
    from illusio.core import read_image

    assert read_image(out).shape[:2] == (72, 192)
    code, cap = call_cli(["dof", "museum", "-o", str(tmp_path / "pair.png"), "--size", "64x48", "--stereo", "left-right"], capsys)
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
    code, cap = call_cli(["dof", "futuristic", "--scenario", "futuristic", "--video", str(video), "--fps", "2",
                          "--duration", "3", "--size", "64x48", "--stereo", "side-by-side", "--method", "planes"], capsys)
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
