"""``illusio view`` from the command line: offscreen recordings and the errors a user can make."""

import imageio.v3 as iio
import numpy as np

from illusio.core.images import read_image
from tests.conftest import call_cli

PATH = '[{"t": 0, "eye": [7, 2, 7], "target": [0, 0, 0]}, {"t": 1, "eye": [-7, 2, 7], "target": [0, 0, 0]}]'


def test_camera_path_recorded_to_a_gif_with_no_window(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    cam = tmp_path / "cam.json"
    cam.write_text(PATH)
    out, shot = tmp_path / "orbit.gif", tmp_path / "last.png"
    code, cap = call_cli(
        [
            "view",
            "torus-knot",
            "--technique",
            "lines",
            "--path",
            str(cam),
            "-o",
            str(out),
            "--fps",
            "4",
            "--size",
            "96x64",
            "--screenshot",
            str(shot),
        ],
        capsys,
    )
    assert code == 0, cap.err
    frames = iio.imread(out, index=None)
    assert frames.shape[:3] == (5, 64, 96)  # 1 s at 4 fps, both ends
    assert (frames.min(axis=-1) < 128).any(axis=(1, 2)).all()  # lines in every frame
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 1  # the camera went round
    assert "5 frames" in cap.out
    last = read_image(shot)
    assert last.shape[:2] == (64, 96) and (last.min(axis=-1) < 0.5).any()  # the last frame, with its lines


def test_view_errors_are_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text('[{"t": 0, "eye": [3, 1, 3], "target": [0, 0, 0]},\n  {"t": 1 "eye": [1, 1, 1]}]')
    cases = [
        (["view", "--path", str(bad), "-o", str(tmp_path / "a.mp4")], "line 2, column"),
        (["view", "--technique", "paint", "-o", str(tmp_path / "a.mp4")], "--technique must be one of"),
        (["view", "--technique", "sis", "--view", "ceiling", "-o", str(tmp_path / "a.mp4")], "no variant 'ceiling'"),
        (["view", "-o", str(tmp_path / "a.avi")], "must be an .mp4 or a .gif"),
        (["view", "--path", str(bad), "-o", str(bad)], "input"),
        (["view", "--fps", "0", "-o", str(tmp_path / "a.mp4")], "--fps must be positive"),
        (
            ["view", "-o", str(tmp_path / "a.mp4"), "--screenshot-window", str(tmp_path / "w.png")],
            "--screenshot-window needs the window",
        ),
    ]
    for args, message in cases:
        code, cap = call_cli(args, capsys)
        assert code == 2, (args, cap.err)
        assert message in cap.err and cap.err.count("\n") == 1 and "Traceback" not in cap.err, cap.err
    assert not (tmp_path / "a.mp4").exists() and not (tmp_path / "w.png").exists()
