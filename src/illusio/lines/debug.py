"""Debug views of a line drawing: the maps of the hybrid method's first pass, and the curvature as
seen from the view. Used by ``illusio lines --debug`` and the viewer's lines mode."""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..scene.mesh import Mesh
from .curvature import Curvature
from .drawing import Drawing

__all__ = ["DEBUG_VIEWS", "debug_view"]

DEBUG_VIEWS = ("q1", "t1", "curvature")


def _direction_colour(angle: np.ndarray) -> np.ndarray:
    """t1's colour: its angle doubled (t1 and −t1 are one direction) around the hue circle."""
    return 0.5 + 0.5 * np.stack([np.cos(2 * angle), np.cos(2 * angle - 2.094), np.cos(2 * angle + 2.094)], -1)


def _curvature_colour(mean: np.ndarray) -> np.ndarray:
    """Mean curvature (in units of the mesh's curvature scale) → blue (concave) … grey … red (convex)."""
    return np.clip(np.stack([0.5 + mean, 0.5 - np.abs(mean) * 0.5, 0.5 - mean], -1), 0, 1)


#: per view: (values along the legend, their colours, the labels at its left, middle and right end)
def _legend_of(kind: str):
    t = np.linspace(0.0, 1.0, 256)
    if kind == "q1":
        return np.repeat(t[:, None], 3, axis=1), ("q1 0", "0.5", ">= 1")
    if kind == "t1":
        return _direction_colour(t * np.pi), ("t1 at 0 deg", "90 deg", "180 deg")
    # ASCII only: PIL's built-in bitmap font has no minus sign or multiplication sign
    return _curvature_colour(t - 0.5), ("-0.5 concave", "0  (mean curvature / scale)", "+0.5 convex")


def with_legend(image: np.ndarray, colours: np.ndarray, labels: tuple[str, str, str]) -> np.ndarray:
    """``image`` with its bottom band (a tenth of the height, at least 20 px) replaced by a colour bar
    of ``colours`` (n, 3) left to right and three labels under it."""
    from PIL import Image, ImageDraw

    from ..core.images import linear_to_srgb, srgb_to_linear

    h, w = image.shape[:2]
    band = min(h, max(20, h // 10))
    bar = max(band // 2, 1)
    strip = np.ones((band, w, 3), np.float32)
    columns = np.linspace(0, len(colours) - 1, w).round().astype(int)
    strip[:bar] = np.asarray(colours, np.float32)[columns][None]
    pil = Image.fromarray((linear_to_srgb(strip) * 255).round().astype(np.uint8))
    draw = ImageDraw.Draw(pil)
    for text, x, anchor in ((labels[0], 2, "la"), (labels[1], w // 2, "ma"), (labels[2], w - 2, "ra")):
        draw.text((x, bar + 1), text, fill=(0, 0, 0), anchor=anchor)
    out = np.array(image, np.float32, copy=True)
    out[h - band :] = srgb_to_linear(np.asarray(pil, np.float32) / 255)
    return out


def debug_view(kind: str, drawing: Drawing, mesh: Mesh, curvature: Curvature, legend: bool = True) -> np.ndarray:
    """A debug image of ``drawing`` (float32 (H, W, 3) linear): "q1" map (grey), "t1" direction field
    (hue), or "curvature": the mean curvature seen from the view (blue concave, red convex); with
    ``legend``, a colour bar with its values along the bottom."""
    if kind not in DEBUG_VIEWS:
        raise InputError(f"debug view must be one of {', '.join(DEBUG_VIEWS)}, got {kind!r}")
    image = _debug_image(kind, drawing, mesh, curvature)
    return with_legend(image, *_legend_of(kind)) if legend else image


def _debug_image(kind: str, drawing: Drawing, mesh: Mesh, curvature: Curvature) -> np.ndarray:
    maps = drawing.q_t1
    covered = maps[..., 3] > 0
    if kind == "q1":
        return np.repeat(np.where(covered, maps[..., 0], 1.0)[..., None], 3, axis=-1).astype(np.float32)
    if kind == "t1":
        rgb = _direction_colour(np.arctan2(maps[..., 2], maps[..., 1]))
        return np.where(covered[..., None], rgb, 1.0).astype(np.float32)
    curv = curvature
    mean = (curv.k_min + curv.k_max) / 2 / max(curv.scale(), 1e-12)
    colour = _curvature_colour(mean)
    # shade each visible pixel by the nearest projected vertex's colour
    px, depth = drawing.view.project(mesh.vertices, drawing.size)
    w, h = drawing.size
    image = np.ones((h, w, 3), np.float32)
    xi, yi = px[:, 0].astype(int), px[:, 1].astype(int)
    ok = (xi >= 0) & (xi < w) & (yi >= 0) & (yi < h) & (depth > 0)
    order = np.argsort(-depth[ok])  # far first, near last wins
    image[yi[ok][order], xi[ok][order]] = colour[ok][order]
    known = np.zeros((h, w), bool)
    known[yi[ok], xi[ok]] = True
    return np.where(covered[..., None], _fill(image, known), 1.0).astype(np.float32)


def _fill(image: np.ndarray, known: np.ndarray) -> np.ndarray:
    """Every pixel takes the colour of the nearest known one."""
    from scipy import ndimage

    _, (iy, ix) = ndimage.distance_transform_edt(~known, return_indices=True)
    return image[iy, ix]
