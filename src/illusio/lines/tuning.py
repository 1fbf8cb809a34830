"""The τ × λ parameter grid (report Figure 4.2) and the automatic choice of τ, λ and the ridge
filter's threshold that best matches a target edge image (the report's main open problem: no (τ, λ)
suits every mesh), scored by F1 of line pixels."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from PIL import Image, ImageDraw

from ..core.errors import InputError
from ..core.renderer import Frame
from .compare import Scores, image_edges, line_mask, phong_render, score
from .drawing import LineRenderer
from .params import LineParams

__all__ = ["parameter_grid", "auto_parameters", "edge_target", "AutoResult", "AUTO_GRID", "TAUS", "LAMBDAS"]

TAUS = (-3.0, -2.0, -1.0, 0.0)
LAMBDAS = (0.0, 0.5, 1.0, 2.0)


def _hybrid(params: LineParams) -> LineParams:
    return replace(params, lines=("apparent-ridges",), method="hybrid")


def parameter_grid(
    renderer: LineRenderer, view, size, taus=TAUS, lambdas=LAMBDAS, params: LineParams = LineParams()
) -> np.ndarray:
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


#: the values the automatic choice tries for each parameter (τ and the threshold relative to the
#: mesh's curvature scale, as the defaults are)
AUTO_GRID = (
    ("tau", (-4.0, -3.0, -2.0, -1.0, 0.0, 1.0)),
    ("lam", (0.0, 0.5, 1.0, 2.0, 4.0, 8.0)),
    ("threshold", (0.05, 0.1, 0.2, 0.4, 0.8)),
)


@dataclass(frozen=True)
class AutoResult:
    """params: the chosen parameters (the start's, with τ, λ and the threshold changed); scores: their
    drawing against the target; start: the starting parameters' scores; drawings: how many were
    drawn; converged: the last round changed nothing (a local best on the grid: no single parameter
    moved to another of its values scores higher)."""

    params: LineParams
    scores: Scores
    start: Scores
    drawings: int
    converged: bool

    def __str__(self) -> str:
        p = self.params
        return (
            f"tau {p.tau:g}, lambda {p.lam:g}, threshold {p.threshold:g}: F1 {self.scores.f1:.3f} "
            f"(from {self.start.f1:.3f}, {self.drawings} drawings)"
        )


def edge_target(renderer: LineRenderer, mesh, view, size, method: str = "canny") -> np.ndarray:
    """The edges (``method``: sobel, laplace, canny) of the shaded render the report compares with."""
    return image_edges(phong_render(renderer.ctx, mesh, view, size), method)


def auto_parameters(
    renderer: LineRenderer,
    view,
    size,
    target: np.ndarray,
    params: LineParams = LineParams(),
    tolerance: float = 2.0,
    grid=AUTO_GRID,
    rounds: int = 4,
) -> AutoResult:
    """τ, λ and the ridge filter's threshold of the hybrid apparent ridges that make the drawing of
    the prepared mesh (every line type of ``params``) best match the ``target`` line mask (F1 of
    line pixels within ``tolerance`` px): coordinate ascent from ``params`` over ``grid``, each
    parameter in turn set to its best value with the others held, until a round changes nothing.
    Never worse than the start; deterministic."""
    if params.method != "hybrid":
        raise InputError("the automatic choice tunes the hybrid method's τ, λ and threshold; use --method hybrid")
    if "apparent-ridges" not in params.lines:
        raise InputError("the automatic choice tunes apparent ridges: add them to the line types")
    scored: dict[tuple, Scores] = {}

    def f1(p: LineParams) -> float:
        key = (p.tau, p.lam, p.threshold)
        if key not in scored:
            scored[key] = score(line_mask(renderer.render(Frame(view, size), p)), target, tolerance)
        return scored[key].f1

    best, converged = params, False
    for _ in range(rounds):
        changed = False
        for name, values in grid:
            for value in values:
                candidate = replace(best, **{name: value})
                if f1(candidate) > f1(best) + 1e-9:
                    best, changed = candidate, True
        if not changed:
            converged = True
            break
    return AutoResult(
        best,
        scored[(best.tau, best.lam, best.threshold)],
        scored[(params.tau, params.lam, params.threshold)],
        len(scored),
        converged,
    )
