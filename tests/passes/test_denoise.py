"""Open Image Denoise on Mitsuba's paths: a few paths a pixel denoised come closer to many paths
than the same few left noisy; bad input is refused in one line."""

import numpy as np
import pytest

from illusio.core.errors import InputError

pytest.importorskip("mitsuba", reason="the photo extra (pip install 'illusio[photo]')")
pytest.importorskip("pyoidn", reason="the photo extra (pip install 'illusio[photo]')")


def test_denoised_few_paths_come_closer_to_many_paths():
    from illusio.radiosity.mitsuba import render_mitsuba, score
    from illusio.radiosity.polygons import scene_polygons
    from illusio.scene.builtin import builtin_scene

    scene = builtin_scene("cornell-box")
    polygons, view = scene_polygons(scene), scene.camera("main")
    size = (64, 64)
    truth = render_mitsuba(polygons, view, size, 512, seed=11)
    noisy = render_mitsuba(polygons, view, size, 4, seed=3)
    clean = render_mitsuba(polygons, view, size, 4, seed=3, denoise=True)
    assert clean.shape == noisy.shape == (64, 64, 3) and clean.dtype == np.float32
    # scored off the lamp (its radiance, ~18, is not noisy and would swamp the rest)
    off_lamp = truth.mean(axis=2) < 1.0
    err_noisy = score(noisy, truth, off_lamp).mean_relative_error
    err_clean = score(clean, truth, off_lamp).mean_relative_error
    # 4 paths: the noise is most of the error (44 % seen); OIDN removes at least half of it (14 %)
    assert err_clean < 0.5 * err_noisy, (err_clean, err_noisy)
    # and keeps the picture's brightness (no bias from the filter)
    assert abs(clean[off_lamp].mean() / truth[off_lamp].mean() - 1) < 0.05


def test_denoise_refuses_bad_input():
    from illusio.passes.denoise import denoise

    image = np.zeros((8, 8, 3), np.float32)
    with pytest.raises(InputError, match="both albedo and normal"):
        denoise(image, albedo=image)
    with pytest.raises(InputError, match=r"\(H, W, 3\)"):
        denoise(np.zeros((8, 8), np.float32))
    with pytest.raises(InputError, match="albedo must be"):
        denoise(image, albedo=np.zeros((4, 4, 3)), normal=image)
    bad = image.copy()
    bad[2, 3, 1] = np.nan
    with pytest.raises(InputError, match="NaN"):
        denoise(bad)
