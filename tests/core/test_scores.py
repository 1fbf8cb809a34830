"""Scores in the literature's convention (core.scores): PSNR and SSIM of the displayed sRGB image
by default, the linear figure only when asked, each saying which."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.images import linear_to_srgb
from illusio.core.scores import image_scores


def test_psnr_is_of_the_srgb_encoded_image_unless_linear_is_asked(rng):
    reference = rng.random((24, 32, 3)).astype(np.float32) * 0.8
    image = np.clip(reference + rng.normal(0, 0.02, reference.shape), 0, 1).astype(np.float32)
    mask = np.zeros((24, 32), bool)
    mask[4:20, 6:28] = True
    srgb = image_scores(image, reference, mask)
    encoded = (linear_to_srgb(image) - linear_to_srgb(reference))[mask]
    assert srgb.space == "srgb" and srgb.psnr == pytest.approx(-10 * np.log10(np.mean(encoded**2)), rel=1e-6)
    linear = image_scores(image, reference, mask, "linear")
    assert linear.psnr == pytest.approx(-10 * np.log10(np.mean((image - reference)[mask] ** 2)), rel=1e-6)
    assert abs(srgb.psnr - linear.psnr) > 0.5  # not the same figure: the space matters
    assert srgb.pixels == pytest.approx(mask.mean()) and "sRGB" in str(srgb) and "linear" in str(linear)
    with pytest.raises(InputError, match="score space"):
        image_scores(image, reference, space="log")
    with pytest.raises(InputError, match="cannot score"):
        image_scores(image[:10], reference)
