"""RelightRenderer's frame handling: the image resampled to the frame's size, another view refused."""

import numpy as np
import pytest
from scipy import ndimage

from illusio.relight.renderer import resample_bilinear


def test_resample_bilinear_matches_scipy_at_the_pixel_centres(rng):
    image = rng.random((13, 17, 4)).astype(np.float32)
    out = resample_bilinear(image, (29, 7))
    y = np.clip((np.arange(7) + 0.5) * 13 / 7 - 0.5, 0, 12)
    x = np.clip((np.arange(29) + 0.5) * 17 / 29 - 0.5, 0, 16)
    yy, xx = np.meshgrid(y, x, indexing="ij")
    expected = np.stack([ndimage.map_coordinates(image[..., c], [yy, xx], order=1) for c in range(4)], axis=-1)
    assert out.shape == (7, 29, 4) and out.dtype == np.float32
    assert np.abs(out - expected).max() < 1e-5
    assert np.array_equal(resample_bilinear(image, (17, 13)), image)  # the same size: the same pixels
    ramp = np.tile(np.arange(8, dtype=np.float32)[None, :, None], (2, 1, 1))
    assert np.allclose(resample_bilinear(ramp, (4, 2))[0, :, 0], [0.5, 2.5, 4.5, 6.5])  # pairs averaged


def test_another_view_than_the_photographs_is_refused(ctx):
    pytest.importorskip("mitsuba", reason="the built-in photograph is path-traced (photo extra)")
    from illusio.core.errors import InputError
    from illusio.core.renderer import Frame
    from illusio.relight import RelightRenderer, builtin_real_scene
    from illusio.scene.camera import Pose, View

    real = builtin_real_scene("office", (64, 48), 4)
    renderer = RelightRenderer(ctx)
    renderer.prepare(real)
    try:
        moved = View(Pose((0.0, 1.5, 0.0), (0.0, 1.5, -1.0)), real.view.camera)
        with pytest.raises(InputError, match="photograph's own camera"):
            renderer.render(Frame(moved, (64, 48)))
        assert renderer.render(Frame(real.view, (64, 48))).shape == (48, 64, 3)  # its own camera is fine
    finally:
        renderer.release()
