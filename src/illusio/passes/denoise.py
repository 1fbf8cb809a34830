"""Denoising of path-traced images: Intel Open Image Denoise through pyoidn (the `photo` extra),
guided by the first hit's albedo and normal. Used where a few paths a pixel must look like many
(the demo's path-traced photographs and truths); scores of accuracy keep their own sample counts."""

from __future__ import annotations

import importlib.util

import numpy as np

from ..core.errors import InputError

__all__ = ["denoiser_available", "denoise"]


def denoiser_available() -> bool:
    return importlib.util.find_spec("pyoidn") is not None


def denoise(color: np.ndarray, albedo: np.ndarray | None = None, normal: np.ndarray | None = None) -> np.ndarray:
    """``color`` (H, W, 3) float32 radiance (linear, ≥ 0, any range: OIDN's HDR mode) denoised.

    ``albedo`` (H, W, 3) in [0, 1] and ``normal`` (H, W, 3) in [−1, 1] are the first hit's, each
    as noisy as the colour (OIDN prefilters them); both or neither. Returns a new float32 array."""
    try:
        import pyoidn
    except ImportError:
        raise InputError("denoising needs the pyoidn package: pip install 'illusio[photo]'") from None
    color = np.asarray(color, np.float32)
    if color.ndim != 3 or color.shape[2] != 3:
        raise InputError(f"denoise: colour must be (H, W, 3), got shape {color.shape}")
    if (albedo is None) != (normal is None):
        raise InputError("denoise: give both albedo and normal, or neither")
    aux = {}
    if albedo is not None:
        for name, image in (("albedo", albedo), ("normal", normal)):
            if np.shape(image) != color.shape:
                raise InputError(f"denoise: {name} must be {color.shape}, got {np.shape(image)}")
        aux = {
            "albedo": np.clip(np.asarray(albedo, np.float32), 0, 1),
            "normal": np.clip(np.asarray(normal, np.float32), -1, 1),
        }
    if not np.isfinite(color).all():
        raise InputError("denoise: the colour holds NaN or infinite values")
    out = pyoidn.denoise(np.ascontiguousarray(np.maximum(color, 0)), **aux, hdr=True)
    return np.maximum(np.asarray(out, np.float32), 0)
