import os

import numpy as np
import pytest

from illusio.core import InputError, OutputError, check_output_path, linear_to_srgb, read_image, srgb_to_linear, write_image


def test_srgb_transfer_round_trip(rng):
    x = rng.random(1000).astype(np.float32)
    np.testing.assert_allclose(srgb_to_linear(linear_to_srgb(x)), x, atol=1e-5)


@pytest.mark.parametrize("channels", [1, 3, 4])
def test_png8_round_trip_within_one_code(tmp_path, rng, channels):
    img = rng.random((9, 13, channels)).astype(np.float32)
    p = write_image(tmp_path / "a.png", img)
    back = read_image(p)
    assert back.shape == img.shape
    rgb = slice(0, 3)  # colour is sRGB-encoded, alpha is stored linearly
    np.testing.assert_allclose(linear_to_srgb(back[..., rgb]), linear_to_srgb(img[..., rgb]), atol=0.5 / 255 + 1e-6)
    np.testing.assert_allclose(back[..., 3:], img[..., 3:], atol=0.5 / 255 + 1e-6)


@pytest.mark.parametrize("channels", [1, 3])
def test_png16_is_linear_and_exact_to_one_code(tmp_path, rng, channels):
    img = rng.random((6, 11, channels)).astype(np.float32)
    back = read_image(write_image(tmp_path / "d.png", img, bit_depth=16))
    np.testing.assert_allclose(back, img, atol=0.5 / 65535 + 1e-7)


def test_npy_keeps_values_exactly(tmp_path, rng):
    img = (rng.random((4, 5, 3)) * 7 - 2).astype(np.float32)
    np.testing.assert_array_equal(read_image(write_image(tmp_path / "x.npy", img)), img)


def test_exr_where_imageio_supports_it(tmp_path, rng):
    img = rng.random((4, 5, 3)).astype(np.float32)
    try:
        write_image(tmp_path / "x.exr", img)
    except OutputError as exc:
        assert "EXR" in str(exc)
        pytest.skip("no EXR backend for imageio here")
    np.testing.assert_allclose(read_image(tmp_path / "x.exr"), img, atol=1e-3)


def test_writes_are_atomic_and_failures_leave_the_old_file(tmp_path):
    p = tmp_path / "keep.png"
    write_image(p, np.full((2, 2, 3), 0.5, np.float32))
    before = p.read_bytes()
    with pytest.raises(OutputError):
        write_image(p, np.full((2, 2, 3), np.nan, np.float32))
    assert p.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["keep.png"]


def test_output_equal_to_input_is_refused(tmp_path):
    src = tmp_path / "in.png"
    write_image(src, np.zeros((2, 2, 3), np.float32))
    with pytest.raises(OutputError, match="overwrite the input"):
        check_output_path(tmp_path / "." / "in.png", [src])
    assert check_output_path(tmp_path / "out.png", [src]).name == "out.png"


def test_bad_image_files_raise_input_error(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        read_image(tmp_path / "missing.png")
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"not a png at all")
    with pytest.raises(InputError):
        read_image(bad)
