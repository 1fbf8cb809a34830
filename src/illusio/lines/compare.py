"""Comparing drawings (report, chapter 4, plus the objective score it lacked): image edges (Sobel,
Laplace, Canny from scikit-image) of a shaded render, line masks from drawings, precision/recall of
line pixels within a tolerance, the symmetric chamfer distance, overlays, the τ × λ grid and the
automatic choice of (τ, λ) that best matches a target edge image."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core.errors import InputError

__all__ = [
    "Scores",
    "score",
    "registered_score",
    "shift_mask",
    "line_mask",
    "image_edges",
    "overlay",
    "phong_render",
    "EDGE_METHODS",
]

EDGE_METHODS = ("sobel", "laplace", "canny")


@dataclass(frozen=True)
class Scores:
    """precision: fraction of predicted line pixels within ``tolerance`` px of a target line pixel;
    recall: the converse; f1: their harmonic mean; chamfer: mean of both directions' mean distance
    (pixels) from a line pixel to the nearest line pixel of the other drawing."""

    precision: float
    recall: float
    f1: float
    chamfer: float
    tolerance: float

    def __str__(self) -> str:
        return (
            f"precision {self.precision:.3f}, recall {self.recall:.3f}, F1 {self.f1:.3f}, "
            f"chamfer {self.chamfer:.2f} px (tolerance {self.tolerance:g} px)"
        )


def line_mask(image: np.ndarray, level: float = 0.5) -> np.ndarray:
    """Line pixels of a drawing (dark lines on white paper): luminance below ``level``."""
    a = np.asarray(image, np.float32)
    lum = a if a.ndim == 2 else a[..., :3].mean(axis=2)
    return lum < level


def score(predicted: np.ndarray, target: np.ndarray, tolerance: float = 2.0) -> Scores:
    """Compare two boolean line masks of the same size, as they lie (:func:`registered_score` with
    no shift)."""
    return registered_score(predicted, target, tolerance, max_shift=0)[0]


def shift_mask(mask: np.ndarray, dx: int, dy: int) -> np.ndarray:
    """``mask`` moved by (dx right, dy down) pixels, the uncovered border False."""
    out = np.zeros_like(mask)
    h, w = mask.shape
    out[max(dy, 0) : h + min(dy, 0), max(dx, 0) : w + min(dx, 0)] = mask[
        max(-dy, 0) : h - max(dy, 0), max(-dx, 0) : w - max(dx, 0)
    ]
    return out


def registered_score(
    predicted: np.ndarray, target: np.ndarray, tolerance: float = 2.0, max_shift: int = 4
) -> tuple[Scores, tuple[int, int]]:
    """The best :func:`score` of ``predicted`` moved by any whole-pixel shift up to ``max_shift`` in x
    and y against ``target`` (a photograph never sits exactly where the drawing's camera was), and
    that shift (dx right, dy down): the misregistration it found (of the shifts with the best F1, the
    one with the smallest chamfer distance). Precision and recall at each shift
    read the two distance transforms at shifted pixels (each computed once)."""
    p = np.asarray(predicted, bool)
    t = np.asarray(target, bool)
    if p.shape != t.shape:
        raise InputError(f"drawings to compare must have the same size, got {p.shape[::-1]} and {t.shape[::-1]}")
    if not p.any() or not t.any():
        return Scores(0.0, 0.0, 0.0, float("inf"), tolerance), (0, 0)
    h, w = t.shape
    to_target = ndimage.distance_transform_edt(~t)
    to_pred = ndimage.distance_transform_edt(~p)
    py, px = np.nonzero(p)
    ty, tx = np.nonzero(t)
    best = None
    for dy in range(-max_shift, max_shift + 1):
        for dx in range(-max_shift, max_shift + 1):
            # predicted pixels moved by (dx, dy) that stay inside, and target pixels seen from them
            inside_p = (px + dx >= 0) & (px + dx < w) & (py + dy >= 0) & (py + dy < h)
            inside_t = (tx - dx >= 0) & (tx - dx < w) & (ty - dy >= 0) & (ty - dy < h)
            if not inside_p.any() or not inside_t.any():
                continue
            near_p = to_target[py[inside_p] + dy, px[inside_p] + dx]
            near_t = to_pred[ty[inside_t] - dy, tx[inside_t] - dx]
            precision, recall = float((near_p <= tolerance).mean()), float((near_t <= tolerance).mean())
            f1 = 0.0 if precision + recall == 0 else 2 * precision * recall / (precision + recall)
            chamfer = float((near_p.mean() + near_t.mean()) / 2)
            # ties of F1 (a shift within the tolerance scores alike) go to the nearer lines
            if best is None or (f1, -chamfer) > (best[0].f1, -best[0].chamfer):
                best = (Scores(precision, recall, f1, chamfer, tolerance), (dx, dy))
    return best


def phong_render(ctx, mesh, view, size) -> np.ndarray:
    """The shaded image the edge detectors see (report, chapter 4): the mesh in grey Lambert + Phong,
    lit by a lamp at the eye and one above it, on a white background. (H, W, 3) linear."""
    from ..passes.scene_renderer import RenderSettings, render_scene
    from ..scene.scene import Material, Node, PointLight, Scene

    eye = np.asarray(view.pose.position, np.float64)
    lo, hi = mesh.bounds
    reach = float(np.linalg.norm(eye - (np.asarray(lo) + hi) / 2))
    right, up, _ = view.pose.axes()
    scene = Scene(
        name="phong",
        nodes=[Node("mesh", mesh, material=Material((0.75, 0.75, 0.75), specular=0.3, shininess=40.0))],
        lights=[
            PointLight(tuple(eye), intensity=reach**2 * 2.2, shadows=False),
            PointLight(tuple(eye + (up + right * 0.5) * reach), intensity=reach**2 * 1.2, shadows=False),
        ],
        ambient=(0.05, 0.05, 0.05),
        background=(1.0, 1.0, 1.0),
    )
    return render_scene(scene, view, size, ctx, RenderSettings(shadows=False))


def image_edges(image: np.ndarray, method: str = "canny", sigma: float = 1.5, fraction: float = 0.08) -> np.ndarray:
    """Edge mask of a grey or RGB image. sobel/laplace: the magnitude's top ``fraction`` of pixels;
    canny: scikit-image's Canny with ``sigma`` and quantile thresholds."""
    from skimage import feature, filters

    a = np.asarray(image, np.float32)
    grey = a if a.ndim == 2 else a[..., :3].mean(axis=2)
    if method == "canny":
        return feature.canny(grey, sigma=sigma, low_threshold=0.85, high_threshold=0.95, use_quantiles=True)
    if method == "sobel":
        magnitude = filters.sobel(grey)
    elif method == "laplace":
        magnitude = np.abs(filters.laplace(ndimage.gaussian_filter(grey, sigma / 2)))
    else:
        raise InputError(f"edge method must be one of {', '.join(EDGE_METHODS)}, got {method!r}")
    return magnitude > np.quantile(magnitude, 1 - fraction)


def overlay(ours: np.ndarray, theirs: np.ndarray) -> np.ndarray:
    """RGB overlay on white: ours only red, theirs only blue, both black."""
    out = np.ones(ours.shape + (3,), np.float32)
    out[ours & ~theirs] = (0.85, 0.1, 0.1)
    out[theirs & ~ours] = (0.1, 0.3, 0.9)
    out[ours & theirs] = (0.0, 0.0, 0.0)
    return out
