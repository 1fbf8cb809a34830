import numpy as np
import pytest

from illusio.core import TextureSpec, readback, upload
from tests.conftest import tolerance


@pytest.mark.parametrize(
    "dtype,channels", [(np.float32, 1), (np.float32, 3), (np.float32, 4), (np.uint8, 4), (np.float16, 2)]
)
def test_upload_readback_round_trip_keeps_row_zero_on_top(ctx, rng, dtype, channels):
    h, w = rng.integers(3, 40, size=2)
    a = (rng.random((h, w, channels)) * (255 if dtype == np.uint8 else 1)).astype(dtype)
    back = readback(upload(ctx.gl, a))
    expected = a.astype(np.float32) / (255 if dtype == np.uint8 else 1)
    np.testing.assert_allclose(back, expected, **tolerance("float32"))


def test_gl_sees_the_array_bottom_row_at_uv_zero(ctx, tmp_path):
    """The one row flip: uv (0, 0) in a shader samples the array's last row, first column."""
    a = np.zeros((4, 5, 4), np.float32)
    a[-1, 0] = (1, 0, 0, 1)  # bottom-left of the image
    a[0, 0] = (0, 1, 0, 1)  # top-left
    src = tmp_path / "probe.glsl"
    src.write_text(
        '#version 430\n#include "common/fullscreen.glsl"\n#if defined(FRAGMENT_SHADER)\n'
        "uniform sampler2D image;\nin vec2 uv;\nout vec4 c;\nvoid main() { c = texture(image, uv); }\n#endif\n"
    )
    tex = upload(ctx.gl, a, filter="nearest")
    gl_rows = np.frombuffer(tex.read(), np.float32).reshape(4, 5, 4)
    np.testing.assert_array_equal(gl_rows[0], a[-1])  # GL's row 0 is the image's bottom row
    out = ctx.acquire((5, 4), 4, "f4")
    fbo = ctx.framebuffer([out])
    fbo.use()
    fbo.viewport = (0, 0, 5, 4)
    tex.use(0)
    prog = ctx.programs.get(src)
    prog["image"].value = 0
    ctx.fullscreen.draw(prog)
    np.testing.assert_array_equal(ctx.readback(out), a)  # same orientation after the round trip
    ctx.release(out)


def test_fullscreen_triangle_covers_every_pixel_with_centred_uv(ctx, tmp_path):
    src = tmp_path / "uv.glsl"
    src.write_text(
        '#version 430\n#include "common/fullscreen.glsl"\n#if defined(FRAGMENT_SHADER)\n'
        "in vec2 uv;\nout vec4 c;\nvoid main() { c = vec4(uv, 1.0, 1.0); }\n#endif\n"
    )
    w, h = 7, 5
    out = ctx.acquire((w, h), 4, "f4")
    fbo = ctx.framebuffer([out])
    fbo.use()
    fbo.viewport = (0, 0, w, h)
    fbo.clear(0, 0, 0, 0)
    ctx.fullscreen.draw(ctx.programs.get(src))
    img = ctx.readback(out)
    assert (img[..., 3] == 1).all()
    np.testing.assert_allclose(img[0, :, 0], (np.arange(w) + 0.5) / w, **tolerance("same arithmetic"))
    np.testing.assert_allclose(
        img[:, 0, 1], 1 - (np.arange(h) + 0.5) / h, **tolerance("same arithmetic")
    )  # row 0 on top = uv.y near 1
    ctx.release(out)


def test_pool_reuses_released_textures(ctx):
    spec = TextureSpec((16, 8), 2, "f4")
    a = ctx.textures.acquire(spec)
    b = ctx.textures.acquire(spec)
    assert a.glo != b.glo
    ctx.textures.release(a)
    c = ctx.textures.acquire(spec)
    assert c.glo == a.glo
    ctx.textures.release(b, c)


def test_readback_u8_reads_the_first_channels_as_bytes_top_row_first(ctx, rng):
    a = rng.uniform(-0.5, 1.5, (13, 21, 4)).astype(np.float32)
    tex = ctx.upload(a, filter="nearest")
    got = ctx.readback_u8(tex, 2)
    tex.release()
    want = np.round(np.clip(a[..., :2], 0, 1) * 255)
    assert got.dtype == np.uint8 and got.shape == (13, 21, 2)
    assert np.abs(got.astype(int) - want).max() <= 1
