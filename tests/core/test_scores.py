"""Scores in the literature's convention (core.scores): PSNR and SSIM of the displayed sRGB image
by default, the linear figure only when asked, each saying which."""

import contextlib
import sys
import types

import numpy as np
import pytest

from illusio.core import scores
from illusio.core.errors import InputError
from illusio.core.images import linear_to_srgb
from illusio.core.scores import image_scores, psnr


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


def test_psnr_of_equal_images_is_infinite_and_of_a_known_error_its_formula(rng):
    reference = rng.random((8, 8, 3)).astype(np.float32)
    assert psnr(reference, reference) == float("inf")
    shifted = reference + np.float32(0.01)
    assert psnr(shifted, reference, space="linear") == pytest.approx(40.0, abs=1e-3)  # 10 log10(1 / 1e-4)


class _FakeTensor:
    def __init__(self, array):
        self.array = array

    def numpy(self):
        return self.array


class _FakeLpips:
    """lpips.LPIPS's calling convention (N×3×H×W in [-1, 1] → N×1×H×W with spatial=True), scoring
    the mean absolute difference, so the plumbing around it can be checked without PyTorch."""

    seen: list = []

    def __init__(self, net, spatial, verbose):
        assert net == "alex" and spatial

    def eval(self):
        return self

    def __call__(self, x, y):
        self.seen.extend([x.array, y.array])
        return _FakeTensor(np.abs(x.array - y.array).mean(axis=1, keepdims=True))


def test_lpips_is_of_the_displayed_image_in_minus_one_to_one_over_the_mask(rng, monkeypatch):
    torch = types.SimpleNamespace(from_numpy=_FakeTensor, no_grad=contextlib.nullcontext)
    monkeypatch.setitem(sys.modules, "torch", torch)
    monkeypatch.setitem(sys.modules, "lpips", types.SimpleNamespace(LPIPS=_FakeLpips))
    scores._lpips_model.cache_clear()
    try:
        reference = rng.random((12, 16, 3)).astype(np.float32)
        image = np.clip(reference + rng.normal(0, 0.05, reference.shape), 0, 1).astype(np.float32)
        mask = np.zeros((12, 16), bool)
        mask[2:9, 3:12] = True
        got = image_scores(image, reference, mask, "linear")  # LPIPS is of the displayed image whatever the space
        x, y = _FakeLpips.seen[-2:]
        assert x.shape == (1, 3, 12, 16) and x.dtype == np.float32 and x.min() >= -1 and x.max() <= 1
        np.testing.assert_allclose(x[0].transpose(1, 2, 0), linear_to_srgb(image) * 2 - 1, atol=1e-6)
        expected = (np.abs(linear_to_srgb(image) - linear_to_srgb(reference)) * 2).mean(axis=-1)[mask].mean()
        assert got.lpips == pytest.approx(expected, rel=1e-5) and "LPIPS" in str(got)
    finally:
        scores._lpips_model.cache_clear()


def test_without_the_lpips_package_the_scores_leave_it_out(rng, monkeypatch):
    monkeypatch.setitem(sys.modules, "lpips", None)  # import lpips raises ImportError
    scores._lpips_model.cache_clear()
    image = rng.random((8, 8, 3)).astype(np.float32)
    got = image_scores(image, image)
    assert got.lpips is None and "LPIPS" not in str(got) and got.psnr == float("inf")
