"""The demo's path-traced images, each rendered once a run: a section that needs a render another
section made (the office photographed for relighting is radiosity's reference of the office, same
polygons, camera, size and seed) gets that one. Few paths a pixel, denoised by Open Image Denoise
when pyoidn is there (both come with the photo extra), so the demo stays within minutes on 2 cores."""

from __future__ import annotations

import numpy as np

from ..core.renderer import fingerprint
from ..passes.denoise import denoiser_available
from ..radiosity.polygons import Polygons
from ..scene.camera import View

__all__ = ["DEMO_SAMPLES", "path_traced", "clear", "renders_made"]

#: paths a pixel of the demo's renders (denoised: about what 128 noisy paths give, see tests/passes/test_denoise.py)
DEMO_SAMPLES = 16

_renders: dict[bytes, np.ndarray] = {}
_made = 0


def path_traced(
    polygons: Polygons, view: View, size: tuple[int, int], samples: int = DEMO_SAMPLES, seed: int = 0
) -> np.ndarray:
    """Mitsuba's radiance (H, W, 3) of ``polygons`` from ``view`` (radiosity.mitsuba.render_mitsuba),
    denoised when pyoidn is installed; the same arguments by value give the same (read-only) array."""
    global _made
    key = fingerprint((polygons, view, tuple(size), int(samples), int(seed)))
    if key not in _renders:
        from ..radiosity.mitsuba import render_mitsuba

        image = render_mitsuba(polygons, view, size, samples, seed, denoise=denoiser_available())
        image.setflags(write=False)
        _renders[key] = image
        _made += 1
    return _renders[key]


def renders_made() -> int:
    """How many renders this process made (not counting those shared)."""
    return _made


def clear() -> None:
    """Forget the renders (the demo calls it at the end of a run)."""
    _renders.clear()
