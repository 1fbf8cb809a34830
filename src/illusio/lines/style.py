"""How a finished drawing looks on the page: line width, one ink colour, a transparent background,
lines faded by their strength, and antialiasing — applied to the drawing's image (white paper, lines
in their colours), as a last step that draws nothing new.

- Ink: a pixel's coverage is c = 1 − min(R, G, B) (white paper 0, any pure ink 1) and its ink colour
  (image − (1 − c))/c, so the per-type colours survive unless ``colour`` replaces them.
- Width: coverage and ink are widened with a disk of diameter ``width`` (pixels of the output), the
  ink of the nearest line taken (a max filter of c·ink over a max filter of c).
- Antialiasing: the drawing is made at ``supersample`` times the size (its 1-pixel lines then span
  ``supersample`` pixels after widening) and box-filtered down, so edges get fractional coverage.
- Fade (the hybrid ridges, as rtsc fades lines by strength): a ridge pixel's coverage is scaled by
  min(1, |q| / q_ref), q the view-dependent curvature and q_ref the median |q| over the ridge pixels:
  weak ridges are drawn lighter.
- Output: on white paper (RGB), or with ``transparent`` the ink with alpha = coverage (RGBA).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.params import check_ranges, param

__all__ = ["LineStyle", "stylise", "coverage_and_ink", "parse_colour", "ridge_strength"]


@dataclass(frozen=True)
class LineStyle:
    """width: line width in output pixels. colour: one linear RGB ink for every line (None: each line
    type's own). transparent: RGBA output, alpha = coverage. fade: hybrid ridges lighter where weak.
    supersample: the factor the drawing was rendered at (it is reduced by it). svg_join, svg_smooth:
    how an SVG's strokes are chained and drawn (lines.svg)."""

    width: float = param(
        1.0, range=(0.5, 32.0), unit="px", flag="line-width", help="line width of the output", group="output"
    )
    colour: tuple | None = param(None, panel=False, group="output")
    transparent: bool = param(False, help="a PNG with the paper transparent (alpha = ink)", group="output")
    fade: bool = param(
        False, help="apparent ridges lighter where weak (|q| under the median ridge's), as rtsc does", group="output"
    )
    svg_join: float = param(
        1.5,
        range=(0.0, 8.0),
        unit="px",
        help="SVG: a line's ends this close to another's of its type join into one path (0: as traced)",
        group="output",
    )
    svg_smooth: bool = param(
        False, help="SVG: curves through each path's points (Catmull–Rom as cubic Béziers)", group="output"
    )
    # what the drawing was made at, set by whoever made it (the lines command's --antialias)
    supersample: int = param(1, range=(1, 4), step=1, cli=False, group="advanced")

    def __post_init__(self):
        check_ranges(self)
        if self.colour is not None:
            c = np.asarray(self.colour, np.float64)
            if c.shape != (3,) or not np.isfinite(c).all() or c.min() < 0 or c.max() > 1:
                raise InputError(f"line colour must be three numbers in [0, 1], got {self.colour!r}")


def parse_colour(text: str) -> tuple[float, float, float]:
    """``#rrggbb`` (sRGB) or ``R,G,B`` (linear, each in [0, 1]) → linear RGB."""
    from ..core.images import srgb_to_linear

    t = text.strip()
    try:
        if t.startswith("#") and len(t) == 7:
            srgb = np.array([int(t[k : k + 2], 16) for k in (1, 3, 5)], np.float32) / 255
            return tuple(float(v) for v in srgb_to_linear(srgb))
        values = tuple(float(v) for v in t.split(","))
    except ValueError:
        values = ()
    if len(values) != 3 or not all(0 <= v <= 1 for v in values):
        raise InputError(f"--colour takes #rrggbb or R,G,B in [0, 1], got {text!r}")
    return values


def coverage_and_ink(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(coverage (H, W) in [0, 1], ink (H, W, 3)) of a drawing on white paper (see the docstring)."""
    rgb = np.asarray(image, np.float64)[..., :3]
    cover = 1.0 - rgb.min(axis=-1)
    ink = np.where(cover[..., None] > 1e-6, (rgb - (1.0 - cover[..., None])) / np.maximum(cover[..., None], 1e-6), 0.0)
    return np.clip(cover, 0, 1), np.clip(ink, 0, 1)


def _disk(diameter: float) -> np.ndarray:
    """The pixels of a disk ``diameter`` pixels across (n × n, n the rounded diameter; an even n is
    centred between pixels)."""
    n = max(1, int(round(diameter)))
    c = np.arange(n) - (n - 1) / 2
    return c[None, :] ** 2 + c[:, None] ** 2 <= (n / 2) ** 2 + 1e-9


def stylise(image: np.ndarray, style: LineStyle = LineStyle(), strength: np.ndarray | None = None) -> np.ndarray:
    """The drawing ``image`` (float (H·s, W·s, 3) on white, s = style.supersample) in ``style``:
    float32 (H, W, 3), or (H, W, 4) with a transparent background. ``strength``: (H·s, W·s) weights
    in [0, 1] multiplying the coverage (the fade), or None."""
    from scipy import ndimage

    s = style.supersample
    cover, ink = coverage_and_ink(image)
    h, w = cover.shape
    if h % s or w % s:
        raise InputError(f"a drawing of {w}×{h} cannot be reduced by {s}")
    if strength is not None:
        cover = cover * np.clip(np.asarray(strength, np.float64), 0, 1)
    footprint = _disk(style.width * s)
    if footprint.size > 1:
        weighted = np.stack(
            [ndimage.maximum_filter(ink[..., c] * cover, footprint=footprint) for c in range(3)], axis=-1
        )
        cover = ndimage.maximum_filter(cover, footprint=footprint)
        ink = np.where(cover[..., None] > 1e-6, weighted / np.maximum(cover[..., None], 1e-6), 0.0)
    if style.colour is not None:
        ink = np.broadcast_to(np.asarray(style.colour, np.float64), ink.shape)
    premultiplied = ink * cover[..., None]
    if s > 1:
        cover = cover.reshape(h // s, s, w // s, s).mean(axis=(1, 3))
        premultiplied = premultiplied.reshape(h // s, s, w // s, s, 3).mean(axis=(1, 3))
    if style.transparent:
        colour = np.where(cover[..., None] > 1e-6, premultiplied / np.maximum(cover[..., None], 1e-6), 0.0)
        return np.dstack([colour, cover]).astype(np.float32)
    return (premultiplied + (1.0 - cover[..., None])).astype(np.float32)


def ridge_strength(q_t1: np.ndarray, ridge_mask: np.ndarray | None) -> np.ndarray | None:
    """The fade's weights: min(1, |q| / median |q| over the ridge pixels) on ridge pixels, 1 elsewhere
    (None without ridges)."""
    if ridge_mask is None or not ridge_mask.any():
        return None
    q = np.abs(np.asarray(q_t1)[..., 0])
    ref = float(np.median(q[ridge_mask]))
    out = np.ones(q.shape)
    out[ridge_mask] = np.clip(q[ridge_mask] / max(ref, 1e-12), 0, 1)
    return out
