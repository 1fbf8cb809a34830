"""The debug maps of a depth-of-field frame, as grey images: what ``illusio dof --debug`` writes and
the gallery shows.

- ``coc``: the circle of confusion of each pixel over ``max_coc`` (0 black: in focus; 1: the largest
  drawn);
- ``depth``: linear depth, near white, far dark, 0 where nothing is;
- ``planes``: the index of the blur plane each pixel takes (dof.reference.plane_index) over the
  number of planes less one.

A map is of the first eye. The planes exist only for the planes method, so ``planes`` renders with
it; the others need a blur method, so the accumulation is drawn with the gather instead."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..core.errors import InputError
from ..core.renderer import Frame
from .params import DofParams
from .reference import plane_index

__all__ = ["DEBUG_MAPS", "debug_params", "debug_map"]

DEBUG_MAPS = ("coc", "depth", "planes")


def debug_params(params: DofParams, kind: str) -> DofParams:
    """The params a ``kind`` map is drawn with: one eye, and a method that makes that map."""
    if kind not in DEBUG_MAPS:
        raise InputError(f"--debug must be one of {', '.join(DEBUG_MAPS)}, got {kind!r}")
    blur = params.method if params.method != "accumulation" else "gather"
    method = "planes" if kind == "planes" else blur
    return replace(params, method=method, stereo="none")


def debug_map(renderer, frame: Frame, params: DofParams, kind: str) -> np.ndarray:
    """The ``kind`` map (float32 (H, W), values in [0, 1]) of ``renderer``'s prepared scene in ``frame``."""
    params = debug_params(params, kind)
    renderer.render(frame, params)
    result = renderer.result()
    m = renderer.ctx.readback(renderer.maps()["coc" if kind == "coc" else "depth"])[..., 0]
    if kind == "coc":
        image = m / params.max_coc
    elif kind == "depth":
        image = np.where(m > 0, 1 - m / max(float(m.max()), 1e-9), 0.0)
    else:
        image = plane_index(m, result.planes) / max(len(result.planes) - 1, 1)
    return np.clip(image, 0.0, 1.0).astype(np.float32)
