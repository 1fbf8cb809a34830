"""The τ × λ parameter grid (report Figure 4.2) and the automatic choice of (τ, λ) that best matches
a target edge image (the report's own perspective), scored by F1 of line pixels."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from PIL import Image, ImageDraw

from .compare import Scores, line_mask, score
from ..core.renderer import Frame
from .drawing import LineRenderer
from .params import LineParams

__all__ = ["parameter_grid", "best_parameters", "TAUS", "LAMBDAS"]

TAUS = (-3.0, -2.0, -1.0, 0.0)
LAMBDAS = (0.0, 0.5, 1.0, 2.0)


def _hybrid(params: LineParams) -> LineParams:
    return replace(params, lines=("apparent-ridges",), method="hybrid")


def parameter_grid(renderer: LineRenderer, view, size, taus=TAUS, lambdas=LAMBDAS,
                   params: LineParams = LineParams()) -> np.ndarray:
    """One hybrid apparent-ridge drawing of the prepared mesh per (τ, λ): rows τ, columns λ, labelled.
    (H, W, 3) linear."""
    w, h = size
    gap = 4
    sheet = Image.new("RGB", (len(lambdas) * (w + gap) - gap, len(taus) * (h + gap) - gap), (160, 160, 160))
    draw = ImageDraw.Draw(sheet)
    for r, tau in enumerate(taus):
        for c, lam in enumerate(lambdas):
            img = renderer.render(Frame(view, size), replace(_hybrid(params), tau=tau, lam=lam))
            tile = Image.fromarray((np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8))
            x, y = c * (w + gap), r * (h + gap)
            sheet.paste(tile, (x, y))
            draw.text((x + 6, y + 4), f"tau {tau:g}  lambda {lam:g}", fill=(200, 0, 0))
    return np.asarray(sheet, np.float32) / 255.0


def best_parameters(renderer: LineRenderer, view, size, target: np.ndarray, taus=TAUS, lambdas=LAMBDAS,
                    params: LineParams = LineParams(), tolerance: float = 2.0) -> tuple[float, float, Scores]:
    """The (τ, λ) on the grid whose hybrid drawing of the prepared mesh has the best F1 against the
    ``target`` line mask."""
    best = None
    for tau in taus:
        for lam in lambdas:
            img = renderer.render(Frame(view, size), replace(_hybrid(params), tau=tau, lam=lam))
            s = score(line_mask(img), target, tolerance)
            if best is None or s.f1 > best[2].f1:
                best = (tau, lam, s)
    return best
