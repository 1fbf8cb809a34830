"""Patterns an autostereogram repeats: random dots (black/white, grey, colour), 1/f (pink) noise, TV
"snow" that changes every frame, and any texture image tiled with its period matched to the far
separation. All return float32 (H, W, 3) in [0, 1], row 0 on top; every random one takes a seed.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.images import read_image

__all__ = ["random_dots", "pink_noise", "snow", "hash32", "texture_tile", "make_pattern"]


def _blocks(values: np.ndarray, height: int, width: int, dot_size: int) -> np.ndarray:
    return np.repeat(np.repeat(values, dot_size, axis=0), dot_size, axis=1)[:height, :width]


def random_dots(width: int, height: int, seed: int = 0, kind: str = "bw", dot_size: int = 1) -> np.ndarray:
    """Random dots of ``dot_size`` pixels. kind: "bw" (black or white, half each), "grey" (uniform
    grey levels) or "colour" (uniform RGB)."""
    rng = np.random.default_rng(seed)
    shape = (-(-height // dot_size), -(-width // dot_size))
    if kind == "bw":
        v = (rng.random(shape) < 0.5).astype(np.float32)[..., None].repeat(3, axis=2)
    elif kind == "grey":
        v = rng.random(shape, dtype=np.float32)[..., None].repeat(3, axis=2)
    elif kind == "colour":
        v = rng.random(shape + (3,), dtype=np.float32)
    else:
        raise InputError(f"unknown dot kind {kind!r} (bw, grey or colour)")
    return np.ascontiguousarray(_blocks(v, height, width, dot_size), np.float32)


def pink_noise(width: int, height: int, seed: int = 0, exponent: float = 1.0) -> np.ndarray:
    """1/f noise: white noise whose spectrum amplitude is scaled by 1/|f|^exponent, stretched to
    [0, 1] between its 1st and 99th percentiles. Its large blobs give the eye more to lock onto than
    dots do, and the fine grain keeps the matches unambiguous."""
    rng = np.random.default_rng(seed)
    spectrum = np.fft.rfft2(rng.standard_normal((height, width)))
    fy = np.fft.fftfreq(height)[:, None]
    fx = np.fft.rfftfreq(width)[None, :]
    f = np.sqrt(fx**2 + fy**2)
    f[0, 0] = 1.0
    field = np.fft.irfft2(spectrum / f**exponent, s=(height, width))
    lo, hi = np.percentile(field, (1, 99))
    v = np.clip((field - lo) / max(hi - lo, 1e-12), 0, 1).astype(np.float32)
    return np.ascontiguousarray(v[..., None].repeat(3, axis=2))


def hash32(values: np.ndarray) -> np.ndarray:
    """A 32-bit integer mixer (Wellons' "lowbias32"), the same in ``shaders/snow.glsl``."""
    x = np.asarray(values, np.uint32).copy()
    x ^= x >> np.uint32(16)
    x *= np.uint32(0x7FEB352D)
    x ^= x >> np.uint32(15)
    x *= np.uint32(0x846CA68B)
    x ^= x >> np.uint32(16)
    return x


def snow(width: int, height: int, seed: int = 0, frame: int = 0, dot_size: int = 1) -> np.ndarray:
    """TV "snow": grey random dots drawn from a hash of (x, y, frame, seed), so every frame differs and
    any frame can be made again, on the CPU here and on the GPU by ``shaders/snow.glsl``."""
    ys, xs = np.mgrid[0:height, 0:width]
    key = hash32(xs // dot_size)
    key = hash32(key ^ np.uint32(ys // dot_size))
    key = hash32(key ^ np.uint32(frame & 0xFFFFFFFF))
    key = hash32(key ^ np.uint32(seed & 0xFFFFFFFF))
    v = (key >> np.uint32(8)).astype(np.float32) / np.float32(16777216.0)
    return np.ascontiguousarray(v[..., None].repeat(3, axis=2))


def texture_tile(image: np.ndarray, period: int) -> np.ndarray:
    """Scale a texture so that its width is ``period`` pixels (the far separation W_s + β, so the far
    plane shows the texture undistorted), keeping its aspect ratio."""
    from PIL import Image

    img = np.asarray(image, np.float32)
    if img.ndim == 2:
        img = img[..., None]
    if img.shape[2] == 1:
        img = img.repeat(3, axis=2)
    img = img[..., :3]
    h, w = img.shape[:2]
    new_h = max(1, int(round(h * period / w)))
    channels = [
        np.asarray(Image.fromarray(img[..., c]).resize((int(period), new_h), Image.Resampling.LANCZOS))
        for c in range(3)
    ]
    return np.clip(np.stack(channels, axis=2), 0, 1).astype(np.float32)


def make_pattern(
    name: str,
    width: int,
    height: int,
    period: int,
    seed: int = 0,
    dot_size: int = 1,
    frame: int = 0,
    oversample: int = 1,
) -> np.ndarray:
    """The pattern a stereogram of ``width`` × ``height`` needs, by name (random-dot, grey-dots,
    colour-dots, pink-noise, snow) or image path; at ``oversample`` times the width."""
    if name == "random-dot":
        p = random_dots(width, height, seed, "bw", dot_size)
    elif name == "grey-dots":
        p = random_dots(width, height, seed, "grey", dot_size)
    elif name == "colour-dots":
        p = random_dots(width, height, seed, "colour", dot_size)
    elif name == "pink-noise":
        p = pink_noise(width, height, seed)
    elif name == "snow":
        p = snow(width, height, seed, frame, dot_size)
    else:
        path = Path(name)
        if not path.exists():
            raise InputError(
                f"pattern {name!r} is neither a built-in pattern (random-dot, grey-dots, colour-dots, "
                f"pink-noise, snow) nor an existing image file"
            )
        return texture_tile(read_image(path), period * oversample)
    return np.repeat(p, oversample, axis=1) if oversample > 1 else p
