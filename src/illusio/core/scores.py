"""Image scores as the literature states them.

The image-based-rendering and view-synthesis literature scores the *displayed* image: PSNR and SSIM
of the sRGB-encoded values in [0, 1] (IEC 61966-2-1, clipped), as floats, not of linear radiance.
:func:`image_scores` does that by default and says which space it used; ``space="linear"`` gives the
radiometric figure instead (a renderer's own error, as the radiosity and relighting goals state).
Where the ``lpips`` package is installed (``pip install illusio[perceptual]``, which brings PyTorch),
the scores add LPIPS (Zhang et al. 2018, AlexNet features) of the displayed image, as that
literature reports it beside PSNR and SSIM.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from functools import cache

import numpy as np

from .errors import InputError
from .images import linear_to_srgb

__all__ = ["ImageScores", "SPACES", "image_scores", "lpips_distance", "psnr"]

SPACES = ("srgb", "linear")


@dataclass(frozen=True)
class ImageScores:
    """psnr: dB (peak 1); ssim: mean SSIM (scikit-image, Gaussian-free 7×7 windows, per channel,
    averaged) over the mask; pixels: the share of the image scored; space: "srgb" (the displayed
    image, clipped to [0, 1]) or "linear"; lpips: LPIPS of the displayed image averaged over the mask
    (lower is closer; 0 the same image), None where the ``lpips`` package is not installed."""

    psnr: float
    ssim: float
    pixels: float
    space: str
    lpips: float | None = None

    def __str__(self) -> str:
        what = "sRGB, the displayed image" if self.space == "srgb" else "linear radiance"
        perceptual = "" if self.lpips is None else f", LPIPS {self.lpips:.3f}"
        return (
            f"PSNR {self.psnr:.2f} dB, SSIM {self.ssim:.3f}{perceptual} ({what}) over {self.pixels:.0%} of the pixels"
        )


def _encoded(image: np.ndarray, space: str) -> np.ndarray:
    if space not in SPACES:
        raise InputError(f"score space must be one of {', '.join(SPACES)}, got {space!r}")
    a = np.asarray(image, np.float32)[..., :3]
    return linear_to_srgb(a) if space == "srgb" else a


def _pair(image, reference, space: str) -> tuple[np.ndarray, np.ndarray]:
    a, b = _encoded(image, space), _encoded(reference, space)
    if a.shape != b.shape:
        raise InputError(f"cannot score a {a.shape[1]}×{a.shape[0]} image against a {b.shape[1]}×{b.shape[0]} one")
    return a, b


def psnr(image: np.ndarray, reference: np.ndarray, mask: np.ndarray | None = None, space: str = "srgb") -> float:
    """PSNR in dB (peak 1) of ``image`` against ``reference`` (float32 H×W×3, linear) over ``mask``
    (H×W bool; default every pixel), in ``space``; inf for equal images."""
    a, b = _pair(image, reference, space)
    diff = (a.astype(np.float64) - b) if mask is None else (a.astype(np.float64) - b)[np.asarray(mask, bool)]
    mse = float(np.mean(diff**2))
    return float("inf") if mse == 0 else float(10 * np.log10(1.0 / mse))


@cache
def _lpips_model():
    import lpips

    return lpips.LPIPS(net="alex", spatial=True, verbose=False).eval()


def lpips_distance(image: np.ndarray, reference: np.ndarray, mask: np.ndarray | None = None) -> float | None:
    """LPIPS (AlexNet) of the displayed images (linear float32 H×W×3 in, sRGB-encoded and mapped to
    [-1, 1] as the network was trained), its per-pixel map averaged over ``mask``; None where the
    ``lpips`` package (or the network's weights) is not at hand, said once as a warning."""
    try:
        import torch

        model = _lpips_model()
    except Exception as exc:  # not installed, or the weights cannot be fetched: scored without it
        if not isinstance(exc, ImportError):
            warnings.warn(f"LPIPS left out: {exc}", stacklevel=2)
        return None

    def tensor(x):
        chw = np.ascontiguousarray(_encoded(x, "srgb").transpose(2, 0, 1)[None] * 2 - 1, dtype=np.float32)
        return torch.from_numpy(chw)

    with torch.no_grad():
        distance = np.asarray(model(tensor(image), tensor(reference)).numpy(), np.float64)[0, 0]
    return float(distance.mean() if mask is None else distance[np.asarray(mask, bool)].mean())


def image_scores(image: np.ndarray, reference: np.ndarray, mask: np.ndarray | None = None, space: str = "srgb"):
    """PSNR and SSIM of ``image`` against ``reference`` (float32 H×W×3, linear, row 0 on top) over
    ``mask`` (H×W bool; default every pixel), in ``space`` (SPACES)."""
    from skimage.metrics import structural_similarity

    a, b = _pair(image, reference, space)
    mask = np.ones(a.shape[:2], bool) if mask is None else np.asarray(mask, bool)
    if not mask.any():
        return ImageScores(float("nan"), float("nan"), 0.0, space)
    _, ssim = structural_similarity(a, b, channel_axis=2, data_range=1.0, full=True)
    return ImageScores(
        psnr(image, reference, mask, space),
        float(ssim.mean(axis=-1)[mask].mean()),
        float(mask.mean()),
        space,
        lpips_distance(image, reference, mask),
    )
