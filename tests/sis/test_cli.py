"""illusio sis / sis-decode from the command line: outputs that decode back, clear errors, exit 2."""

import numpy as np

from tests.conftest import call_cli as call
from illusio.core.images import read_image, write_image




def test_sis_then_decode_round_trip(tmp_path, capsys):
    ys, xs = np.mgrid[0:120, 0:400]
    height = np.clip(1 - ((xs - 220) ** 2 + (ys - 60) ** 2) / 50**2, 0, 1) * 0.8  # white = near
    write_image(tmp_path / "depth.png", np.repeat(height[..., None], 3, 2).astype(np.float32), bit_depth=16, srgb=False)
    code, _ = call(["sis", str(tmp_path / "depth.png"), "-o", str(tmp_path / "sis.png"), "--strip-width", "60",
                    "--depth-factor", "30", "--seed", "7"], capsys)
    assert code == 0
    assert read_image(tmp_path / "sis.png").shape[:2] == (120, 400)
    code, out = call(["sis-decode", str(tmp_path / "sis.png"), "--strip-width", "60", "--depth-factor", "30",
                      "-o", str(tmp_path / "decoded.png"), "--expected", str(tmp_path / "depth.png")], capsys)
    assert code == 0
    matched = float(out.out.split("self-check: ")[1].split("%")[0])
    assert matched >= 99.0, out.out


def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    (tmp_path / "bad.png").write_bytes(b"not a png")
    for args in (["sis", str(tmp_path / "bad.png"), "-o", str(tmp_path / "o.png")],
                 ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--strip-width", "300"],
                 ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--algorithm", "magic"]):
        code, out = call(args, capsys)
        assert code == 2
        assert out.err.count("\n") == 1 and out.err.startswith("illusio: error:"), out.err
    assert not (tmp_path / "o.png").exists()
