"""Image scores as the literature states them.

The image-based-rendering and view-synthesis literature scores the *displayed* image: PSNR and SSIM
of the sRGB-encoded values in [0, 1] (IEC 61966-2-1, clipped), as floats, not of linear radiance.
:func:`image_scores` does that by default and says which space it used; ``space="linear"`` gives the
radiometric figure instead (a renderer's own error, as the radiosity and depth-of-field goals state).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .images import linear_to_srgb

__all__ = ["ImageScores", "SPACES", "image_scores"]

SPACES = ("srgb", "linear")


@dataclass(frozen=True)
class ImageScores:
    """psnr: dB (peak 1); ssim: mean SSIM (scikit-image, Gaussian-free 7×7 windows, per channel,
    averaged) over the mask; pixels: the share of the image scored; space: "srgb" (the displayed
    image, clipped to [0, 1]) or "linear"."""

    psnr: float
    ssim: float
    pixels: float
    space: str

    def __str__(self) -> str:
        what = "sRGB, the displayed image" if self.space == "srgb" else "linear radiance"
        return f"PSNR {self.psnr:.2f} dB, SSIM {self.ssim:.3f} ({what}) over {self.pixels:.0%} of the pixels"


def image_scores(image: np.ndarray, reference: np.ndarray, mask: np.ndarray | None = None, space: str = "srgb"):
    """PSNR and SSIM of ``image`` against ``reference`` (float32 H×W×3, linear, row 0 on top) over
    ``mask`` (H×W bool; default every pixel), in ``space`` (SPACES)."""
    from skimage.metrics import structural_similarity

    if space not in SPACES:
        raise InputError(f"score space must be one of {', '.join(SPACES)}, got {space!r}")
    a, b = (np.asarray(x, np.float32)[..., :3] for x in (image, reference))
    if a.shape != b.shape:
        raise InputError(f"cannot score a {a.shape[1]}×{a.shape[0]} image against a {b.shape[1]}×{b.shape[0]} one")
    if space == "srgb":
        a, b = linear_to_srgb(a), linear_to_srgb(b)
    mask = np.ones(a.shape[:2], bool) if mask is None else np.asarray(mask, bool)
    if not mask.any():
        return ImageScores(float("nan"), float("nan"), 0.0, space)
    diff = (a - b)[mask]
    psnr = 10 * np.log10(1.0 / max(float(np.mean(diff**2)), 1e-12))
    _, ssim = structural_similarity(a, b, channel_axis=2, data_range=1.0, full=True)
    return ImageScores(float(psnr), float(ssim.mean(axis=-1)[mask].mean()), float(mask.mean()), space)
