"""illusio sis / sis-decode from the command line: outputs that decode back, clear errors, exit 2."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.images import read_image, write_image
from illusio.sis.params import StereogramParams
from illusio.sis.stereogram import stereogram_cpu
from tests.conftest import call_cli as call


def test_sis_then_decode_round_trip(tmp_path, capsys):
    ys, xs = np.mgrid[0:120, 0:400]
    height = np.clip(1 - ((xs - 220) ** 2 + (ys - 60) ** 2) / 50**2, 0, 1) * 0.8  # white = near
    write_image(tmp_path / "depth.png", np.repeat(height[..., None], 3, 2).astype(np.float32), bit_depth=16, srgb=False)
    code, _ = call(
        [
            "sis",
            str(tmp_path / "depth.png"),
            "-o",
            str(tmp_path / "sis.png"),
            "--strip-width",
            "60",
            "--depth-factor",
            "30",
            "--seed",
            "7",
        ],
        capsys,
    )
    assert code == 0
    assert read_image(tmp_path / "sis.png").shape[:2] == (120, 400)
    code, out = call(
        [
            "sis-decode",
            str(tmp_path / "sis.png"),
            "--strip-width",
            "60",
            "--depth-factor",
            "30",
            "-o",
            str(tmp_path / "decoded.png"),
            "--expected",
            str(tmp_path / "depth.png"),
        ],
        capsys,
    )
    assert code == 0
    matched = float(out.out.split("self-check: ")[1].split("%")[0])
    assert matched >= 99.0, out.out


def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    (tmp_path / "bad.png").write_bytes(b"not a png")
    for args in (
        ["sis", str(tmp_path / "bad.png"), "-o", str(tmp_path / "o.png")],
        ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--strip-width", "300"],
        ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--algorithm", "magic"],
        ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--print-size", "500x300cm"],
        ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--print-size", "100x50cm"],
    ):
        code, out = call(args, capsys)
        assert code == 2
        assert out.err.count("\n") == 1 and out.err.startswith("illusio: error:"), out.err
    assert not (tmp_path / "o.png").exists()


def test_a_stereogram_carries_its_parameters(tmp_path, capsys):
    """The PNG of `illusio sis` holds its parameters as text; sis-decode reads them (no options
    given), cross-eyed included, so the decoded depth is the depth given (near stays near); against
    the wrong depth the self-check fails with exit 1."""
    from illusio.core.images import read_png_text

    ys, xs = np.mgrid[0:100, 0:360]
    height = np.clip(1 - ((xs - 200) ** 2 + (ys - 50) ** 2) / 40**2, 0, 1) * 0.8
    write_image(tmp_path / "depth.png", np.repeat(height[..., None], 3, 2).astype(np.float32), bit_depth=16, srgb=False)
    code, _ = call(
        [
            "sis",
            str(tmp_path / "depth.png"),
            "-o",
            str(tmp_path / "sis.png"),
            "--strip-width",
            "50",
            "--depth-factor",
            "25",
            "--cross-eyed",
            "--seed",
            "3",
        ],
        capsys,
    )
    assert code == 0
    text = read_png_text(tmp_path / "sis.png")
    assert (
        text["illusio:strip_width"] == "50.0" and text["illusio:cross_eyed"] == "True" and text["illusio:seed"] == "3"
    )
    code, out = call(
        [
            "sis-decode",
            str(tmp_path / "sis.png"),
            "-o",
            str(tmp_path / "decoded.png"),
            "--expected",
            str(tmp_path / "depth.png"),
        ],
        capsys,
    )
    assert code == 0, out.err
    assert float(out.out.split("self-check: ")[1].split("%")[0]) >= 99.0
    decoded = read_image(tmp_path / "decoded.png")[..., 0]
    inside, outside = height > 0.6, height == 0
    assert decoded[inside].mean() > decoded[outside].mean() + 0.3  # near is white
    flat = np.zeros_like(height)
    flat[:, 180:] = 0.8
    write_image(tmp_path / "wrong.png", np.repeat(flat[..., None], 3, 2).astype(np.float32), bit_depth=16, srgb=False)
    code, out = call(
        [
            "sis-decode",
            str(tmp_path / "sis.png"),
            "-o",
            str(tmp_path / "d2.png"),
            "--expected",
            str(tmp_path / "wrong.png"),
        ],
        capsys,
    )
    assert code == 1 and "self-check failed" in out.err


def test_a_colour_depth_map_is_read_as_luminance_with_a_warning(tmp_path):
    import pytest

    from illusio.sis.depth import read_depth

    colour = np.zeros((8, 8, 3), np.float32)
    colour[..., 1] = np.linspace(0.2, 1.0, 8)[None, :]  # green: luminance 0.7152 × G
    write_image(tmp_path / "green.png", colour, srgb=False)
    with pytest.warns(UserWarning, match="colour image"):
        d = read_depth(tmp_path / "green.png")
    assert np.allclose(d, 1 - 0.7152 * colour[..., 1], atol=0.01)


def test_inputs_too_small_or_too_large_are_refused_up_front(tmp_path, capsys):
    """A depth map narrower than one strip (W_s + β), and an oversampling past the texture limit, are
    refused before anything is drawn, naming the minimum or the limit; nothing is written."""
    write_image(tmp_path / "narrow.png", np.full((40, 60, 3), 0.5, np.float32), srgb=False)
    code, out = call(
        [
            "sis",
            str(tmp_path / "narrow.png"),
            "-o",
            str(tmp_path / "o.png"),
            "--strip-width",
            "50",
            "--depth-factor",
            "20",
        ],
        capsys,
    )
    assert code == 2 and "at least 71 px wide" in out.err, out.err
    code, out = call(
        ["sis", "sphere", "-o", str(tmp_path / "o.png"), "--size", "4000x100", "--oversample", "4"], capsys
    )
    assert code == 2 and "8192 px texture limit" in out.err, out.err
    assert not (tmp_path / "o.png").exists()
    with pytest.raises(InputError, match="at least 71 px"):
        stereogram_cpu(np.zeros((10, 70), np.float32), StereogramParams(strip_width=50, depth_factor=20))
