"""The gamma/tone step for comparing a relit image with a photograph (Loscos 4.5, Figure 4.21: "un
simple gamma suffit pour rendre l'image photographiée et l'image simulée similaires").

The relit image I and the photograph P are related by P ≈ a·I^γ per pixel and channel; a and γ
are fitted by least squares on log P = log a + γ·log I over the channels of the pixels of a mask. Fitting only a (γ =
1) is the exposure match."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError

__all__ = ["Tone", "fit_tone"]


@dataclass(frozen=True)
class Tone:
    """gain: a; gamma: γ, in P ≈ a·I^γ (I, P in the same linear units)."""

    gain: float = 1.0
    gamma: float = 1.0

    def apply(self, image: np.ndarray) -> np.ndarray:
        """a·I^γ per channel, float32 (negative values clipped to 0 first)."""
        return (self.gain * np.power(np.maximum(np.asarray(image, np.float64), 0.0), self.gamma)).astype(np.float32)


def fit_tone(image: np.ndarray, photograph: np.ndarray, mask: np.ndarray | None = None, fit_gamma: bool = True) -> Tone:
    """The Tone that maps ``image`` onto ``photograph`` (both (H, W, 3) linear) over ``mask`` (H, W)
    (default: every pixel), values ≤ 0 in either image left out."""
    image, photograph = np.asarray(image, np.float64), np.asarray(photograph, np.float64)
    if image.shape != photograph.shape or image.ndim != 3 or image.shape[2] < 3:
        raise InputError(f"tone fit needs two H×W×3 images of one size, got {image.shape} and {photograph.shape}")
    i, p = image[..., :3], photograph[..., :3]
    use = (i > 0) & (p > 0) & np.isfinite(i) & np.isfinite(p)
    if mask is not None:
        use &= np.asarray(mask, bool)[..., None]
    if use.sum() < 2:
        raise InputError("tone fit needs at least two pixels lit in both images")
    x, y = np.log(i[use]), np.log(p[use])
    if not fit_gamma or np.ptp(x) == 0:
        return Tone(float(np.exp(np.mean(y - x))), 1.0)
    gamma, log_gain = np.polyfit(x, y, 1)
    return Tone(float(np.exp(log_gain)), float(gamma))
