import os

import numpy as np
import pytest

from illusio.core import (
    InputError,
    OutputError,
    check_output_path,
    linear_to_srgb,
    read_image,
    srgb_to_linear,
    write_image,
)


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


def independent_exr(path) -> dict:
    """A small reader of scanline OpenEXR files written with ZIP/ZIPS compression or none, from the
    file format's documentation (not the library that wrote it): {channel: (H, W) float32}."""
    import struct
    import zlib

    with open(path, "rb") as f:
        data = f.read()
    assert data[:4] == b"\x76\x2f\x31\x01", "not an OpenEXR file"
    pos, attrs = 8, {}
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        size = struct.unpack_from("<i", data, type_end + 1)[0]
        attrs[data[pos:name_end].decode()] = data[type_end + 5 : type_end + 5 + size]
        pos = type_end + 5 + size
    pos += 1
    channels, raw, k = [], attrs["channels"], 0
    while raw[k] != 0:
        end = raw.index(b"\0", k)
        channels.append((raw[k:end].decode(), struct.unpack_from("<i", raw, end + 1)[0]))  # 1 half, 2 float
        k = end + 17
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    compression = attrs["compression"][0]  # 0 none, 2 ZIPS, 3 ZIP
    lines = {0: 1, 2: 1, 3: 16}[compression]
    blocks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{blocks}Q", data, pos)
    out = {name: np.zeros((h, w), np.float32) for name, _ in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<2i", data, offset)
        block = data[offset + 8 : offset + 8 + size]
        n = min(lines, y1 + 1 - y)
        expected = sum(w * n * (2 if t == 1 else 4) for _, t in channels)
        if compression and size < expected:
            t = np.frombuffer(zlib.decompress(block), np.uint8).astype(np.int32)
            t = (np.cumsum(np.r_[t[0], t[1:] - 128]) % 256).astype(np.uint8)  # undo the predictor
            half = (len(t) + 1) // 2
            block = np.empty(len(t), np.uint8)
            block[0::2], block[1::2] = t[:half], t[half:]  # undo the interleave
            block = block.tobytes()
        k = 0
        for row in range(n):
            for name, kind in sorted(channels):  # channels in name order
                dtype, step = (np.float16, 2) if kind == 1 else (np.float32, 4)
                out[name][y - y0 + row] = np.frombuffer(block, dtype, w, k)
                k += w * step
    return out


def test_exr_is_openexr_float_and_half_unclipped(tmp_path, rng):
    """-o x.exr writes a real OpenEXR file (read back here by a reader written from the format's
    documentation), linear values above 1 kept; float to the bit, half to half precision; RGBA and
    one channel too; .EXR is .exr."""
    img = (rng.random((37, 21, 3)) * 5).astype(np.float32)
    write_image(tmp_path / "x.exr", img)
    back = independent_exr(tmp_path / "x.exr")
    np.testing.assert_array_equal(np.stack([back[c] for c in "RGB"], axis=-1), img)
    np.testing.assert_array_equal(read_image(tmp_path / "x.exr"), img)
    write_image(tmp_path / "h.EXR", img, bit_depth=16)
    back = independent_exr(tmp_path / "h.EXR")
    np.testing.assert_allclose(np.stack([back[c] for c in "RGB"], axis=-1), img, rtol=1e-3)
    rgba = np.dstack([img, img[..., :1] / 5])
    write_image(tmp_path / "a.exr", rgba)
    assert sorted(independent_exr(tmp_path / "a.exr")) == ["A", "B", "G", "R"]
    np.testing.assert_array_equal(read_image(tmp_path / "a.exr"), rgba)
    grey = img[..., :1]
    write_image(tmp_path / "y.exr", grey)
    np.testing.assert_array_equal(independent_exr(tmp_path / "y.exr")["Y"], grey[..., 0])
    (tmp_path / "bad.exr").write_bytes(b"\x76\x2f\x31\x01" + bytes(40))
    with pytest.raises(InputError, match="OpenEXR"):
        read_image(tmp_path / "bad.exr")


@pytest.mark.parametrize(
    "ext, magic",
    [
        (".tiff", (b"II*\0", b"MM\0*")),
        (".bmp", (b"BM",)),
        (".webp", (b"RIFF",)),
        (".PNG", (b"\x89PNG",)),
        (".JPG", (b"\xff\xd8",)),
    ],
)
def test_every_extension_is_what_it_says(tmp_path, ext, magic):
    path = write_image(tmp_path / f"x{ext}", np.full((4, 4, 3), 0.5, np.float32))
    assert path.read_bytes().startswith(magic)


def test_writes_are_atomic_and_failures_leave_the_old_file(tmp_path):
    p = tmp_path / "keep.png"
    write_image(p, np.full((2, 2, 3), 0.5, np.float32))
    before = p.read_bytes()
    with pytest.raises(OutputError):
        write_image(p, np.full((2, 2, 3), np.nan, np.float32))
    assert p.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["keep.png"]


def test_a_killed_writers_temporary_is_removed_and_nothing_else(tmp_path):
    """What a batch worker killed inside atomic_output leaves (its temporary) goes; the output, other
    outputs' temporaries and look-alike names stay."""
    from illusio.core.images import atomic_output, remove_partial_outputs

    out = tmp_path / "gear-tau2.0.png"
    write_image(out, np.zeros((2, 2, 3), np.float32))
    left = [atomic_output(out).__enter__() for _ in range(2)]  # entered, never exited: killed mid-write
    other = atomic_output(tmp_path / "gear-tau0.5.png").__enter__()
    (tmp_path / ".gear-tau2.0.tmp-note.txt").write_text("another suffix")
    assert all(p.exists() for p in left)
    assert remove_partial_outputs(out) == 2
    assert sorted(os.listdir(tmp_path)) == sorted([".gear-tau2.0.tmp-note.txt", other.name, out.name])


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
