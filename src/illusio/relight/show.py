"""What ``RelightSession.show`` draws beside the relit image (``illusio relight --show``): the
textures, the mesh over the image, the display factor, the registration overlay."""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..radiosity import leaf_mesh
from . import corners
from .params import SHOW
from .registration import overlay


def show(s, what: str = "image", scale: int = 1) -> np.ndarray:
    """One of SHOW under the session's lamps, float32 (scale·H, scale·W, 3), × exposure: ``image``
    the relit photograph; ``textures`` the textures the method displays (the photograph for
    baseline and per-pixel, T_final of eq. 4.9 for loscos); ``mesh`` the relit image with the
    leaves' outlines (Figure 4.8b); ``display-factor`` D/π at the leaves' corners (Figure 4.13b).
    ``registration`` the photograph with the model's edges (red) over its own (cyan),
    relight.registration. ``scale``: the photograph's pixels repeated, the outlines and D drawn
    at that size."""
    if what not in SHOW:
        raise InputError(f"show must be one of {', '.join(SHOW)}, got {what!r}")
    if not 1 <= scale <= 8:
        raise InputError(f"show scale must be 1..8, got {scale}")

    def larger(image):
        return np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)

    if what in ("image", "textures"):
        return larger(s.image() if what == "image" else (s.texture * s.params.exposure).astype(np.float32))
    if what == "registration":
        return larger(overlay(s.real.photograph, s.registration()) * s.params.exposure)
    image = larger(s.image()) if what == "mesh" else None
    h = s.solution.hierarchy
    mesh = leaf_mesh(h, smooth=False)
    if what == "mesh":
        mesh.radiance = np.ones_like(mesh.radiance)
    else:
        corners.inherit_display_factor(s)
        mesh.radiance = s.corner_d[h.leaves()].reshape(-1, 3)
    s.display.load(mesh)
    w, h_pixels = s.real.size
    colour, element = s.display(s.real.view, (w * scale, h_pixels * scale), edges=what == "mesh")
    out = s.ctx.readback_image(colour, 3, clip=False)
    s.ctx.release(colour, element)
    if what == "mesh":
        return (image * out).astype(np.float32)
    return (out * s.params.exposure).astype(np.float32)
