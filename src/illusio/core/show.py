"""Images in a notebook: :func:`show` wraps the float images illusio returns (linear, row 0 on top)
in a :class:`Picture` that Jupyter and IPython draw inline through ``_repr_png_`` (sRGB-encoded
8-bit PNG), several side by side."""

from __future__ import annotations

import io
import os

import numpy as np

from .errors import InputError
from .images import as_image, linear_to_srgb, write_image

__all__ = ["Picture", "show"]


class Picture:
    """A linear float image (H, W, C) shown inline in a notebook (``_repr_png_``); ``image`` is the
    array, :meth:`save` writes it as :func:`illusio.core.images.write_image` does."""

    def __init__(self, image: np.ndarray):
        self.image = as_image(image, "picture")

    def _repr_png_(self) -> bytes:
        from PIL import Image

        a = self.image
        if a.shape[2] == 1:
            a = np.repeat(a, 3, axis=2)
        elif a.shape[2] == 2:  # grey and alpha
            a = np.dstack([np.repeat(a[..., :1], 3, axis=2), a[..., 1:]])
        rgb = linear_to_srgb(np.clip(a[..., :3], 0, 1))
        pixels = np.dstack([rgb, np.clip(a[..., 3:], 0, 1)]) if a.shape[2] == 4 else rgb
        buffer = io.BytesIO()
        Image.fromarray((pixels * 255 + 0.5).astype(np.uint8)).save(buffer, format="PNG")
        return buffer.getvalue()

    def save(self, path: str | os.PathLike):
        return write_image(path, self.image)

    def __repr__(self) -> str:
        h, w, c = self.image.shape
        return f"<Picture {w}×{h}, {c} channels>"


def show(*images: np.ndarray, gap: int = 8) -> Picture:
    """A :class:`Picture` of ``images`` (linear float, row 0 on top) side by side on white, ``gap``
    px apart, each padded to the tallest: the last expression of a notebook cell draws it."""
    if not images:
        raise InputError("show() needs at least one image")
    arrays = [as_image(a, f"image {k}") for k, a in enumerate(images)]
    arrays = [np.repeat(a[..., :1], 3, axis=2) if a.shape[2] < 3 else a[..., :3] for a in arrays]
    height = max(a.shape[0] for a in arrays)
    width = sum(a.shape[1] for a in arrays) + gap * (len(arrays) - 1)
    strip = np.ones((height, width, 3), np.float32)
    x = 0
    for a in arrays:
        strip[: a.shape[0], x : x + a.shape[1]] = a
        x += a.shape[1] + gap
    return Picture(strip if len(arrays) > 1 else arrays[0])
