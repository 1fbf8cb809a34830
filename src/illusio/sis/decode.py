"""Self-check: recover the separation map of a stereogram by window matching, and score it against the
separation expected from its depth map.

For every pixel x and every candidate separation s in [s_min, s_max], the cost is the sum of squared
differences between a window around x and the same window around x − s; the decoded separation is the
cheapest s. Left-anchored algorithms (sequential, strip, fast) put the match at x − s(x); the symmetric
one at the point's centre, handled by :func:`expected_separation`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from .reference import rounded

__all__ = ["decode_separation", "expected_separation", "DecodeReport", "check", "separation_to_depth"]


#: a rival separation whose mean squared difference is within this of the best one makes a pixel
#: ambiguous (for black-and-white dots and the 7×3 window: fewer than ~2 of 21 dots decide)
AMBIGUITY_MARGIN = 0.1


def _box_sum(a: np.ndarray, radius_x: int, radius_y: int) -> np.ndarray:
    """Sum over a (2·radius_y + 1) × (2·radius_x + 1) window, zero outside the image."""
    c = np.pad(a, ((radius_y + 1, radius_y), (radius_x + 1, radius_x))).cumsum(0).cumsum(1)
    h, w = a.shape
    ky, kx = 2 * radius_y + 1, 2 * radius_x + 1
    return c[ky : ky + h, kx : kx + w] - c[:h, kx : kx + w] - c[ky : ky + h, :w] + c[:h, :w]


def _costs(img, lo, hi, rx, ry):
    """Yield (s, cost) for every candidate separation: windowed sum of squared differences between
    the pixels at x and x − s (inf where x − s falls outside the image)."""
    h, w, _ = img.shape
    for s in range(lo, hi + 1):
        diff = np.zeros((h, w), np.float32)
        diff[:, s:] = ((img[:, s:] - img[:, :-s]) ** 2).sum(axis=2)
        cost = _box_sum(diff, rx, ry)
        cost[:, : s + rx] = np.inf
        yield s, cost


def decode_separation(
    image: np.ndarray,
    min_separation: int,
    max_separation: int,
    window: tuple[int, int] = (7, 3),
    ambiguity: bool = False,
):
    """Per-pixel separation (int32, 0 where no partner fits in the image) and its matching cost
    (mean squared difference per pixel and channel; lower is surer).

    image: float32 (H, W, C). window: (width, height) of the matching window, odd numbers.
    ambiguity: also return a bool map of pixels where a separation more than 1 px away from the best
    matches (almost, :data:`AMBIGUITY_MARGIN`) as well (the doubled images at occlusion edges of left-anchored
    stereograms: where a chain
    forks, two separations repeat the same dots).
    """
    img = np.asarray(image, np.float32)
    if img.ndim == 2:
        img = img[:, :, None]
    h, w, _ = img.shape
    lo, hi = int(min_separation), int(max_separation)
    if not 1 <= lo <= hi < w:
        raise InputError(f"separation search range [{lo}, {hi}] does not fit an image {w} pixels wide")
    rx, ry = window[0] // 2, window[1] // 2
    best = np.full((h, w), np.inf, np.float32)
    best_s = np.zeros((h, w), np.int32)
    for s, cost in _costs(img, lo, hi, rx, ry):
        better = cost < best
        best[better] = cost[better]
        best_s[better] = s
    norm = (2 * rx + 1) * (2 * ry + 1) * img.shape[2]
    if not ambiguity:
        return best_s, best / norm
    rival = np.full((h, w), np.inf, np.float32)
    for s, cost in _costs(img, lo, hi, rx, ry):
        far = np.abs(best_s - s) > 1
        rival[far] = np.minimum(rival[far], cost[far])
    with np.errstate(invalid="ignore"):  # inf − inf where no partner fits: not ambiguous
        return best_s, best / norm, (rival - best) / norm <= AMBIGUITY_MARGIN


def expected_separation(sep: np.ndarray, anchor: str = "left") -> np.ndarray:
    """The separation a decoder should find at each right-hand pixel (int32; -1 where none).

    anchor "left": pixel x repeats x − s(x), so the answer is s(x) itself. "centre": the point at x
    links x − ⌊s/2⌋ to x − ⌊s/2⌋ + s, so the right pixel of each point gets that point's s.
    """
    s = rounded(sep)
    if anchor == "left":
        return s
    if anchor != "centre":
        raise InputError(f"anchor must be 'left' or 'centre', got {anchor!r}")
    h, w = s.shape
    out = np.full((h, w), -1, np.int32)
    ys, xs = np.mgrid[0:h, 0:w]
    right = xs - s // 2 + s
    ok = right < w
    out[ys[ok], right[ok]] = s[ok]
    return out


@dataclass(frozen=True)
class DecodeReport:
    """matched: fraction of checked pixels whose decoded separation is within ``tolerance`` px of the
    expected one; checked: how many pixels were checked (those with a partner in the stereogram and a
    window of one depth, not ambiguous); ambiguous: pixels left out because two separations match
    equally well (doubled images where a chain forks at an occlusion edge); mean_error: mean
    abs(decoded − expected) over the checked pixels."""

    matched: float
    checked: int
    mean_error: float
    tolerance: int
    ambiguous: int = 0

    def __str__(self) -> str:
        return (
            f"{self.matched:.2%} of {self.checked:,} checked pixels within {self.tolerance} px "
            f"(mean error {self.mean_error:.3f} px; {self.ambiguous:,} ambiguous pixels left out)"
        )


def check(
    image: np.ndarray,
    sep: np.ndarray,
    first_strip: int,
    anchor: str = "left",
    tolerance: int = 1,
    window: tuple[int, int] = (7, 3),
    row_start: np.ndarray | None = None,
    columns: tuple[int, int] | None = None,
) -> DecodeReport:
    """Decode ``image`` and compare with the separation ``sep`` it was made from.

    Checked pixels: past each row's first strip, with one expected separation (±1) over the matching
    window at both ends of the link (pixels at depth edges are where occlusion lives), and not
    ambiguous (see :func:`decode_separation`; their number is reported). ``columns``: (first, end)
    — only right-hand pixels in these columns are checked (the left or right half, say).
    """
    expected = expected_separation(sep, anchor)
    known = expected[expected > 0]
    if known.size == 0:
        raise InputError("no pixel has a partner: the image is narrower than one separation")
    lo, hi = int(known.min()) - 2, int(known.max()) + 2
    lo = max(lo, 1)
    decoded, _, ambiguous = decode_separation(image, lo, hi, window, ambiguity=True)
    h, w = expected.shape
    rx, ry = window[0] // 2, window[1] // 2
    e = np.where(expected > 0, expected, 0).astype(np.float32)
    big = np.pad(e, ((ry, ry), (rx, rx)), mode="edge")
    lo_win = np.full((h, w), np.inf, np.float32)
    hi_win = np.full((h, w), -np.inf, np.float32)
    for dy in range(2 * ry + 1):
        for dx in range(2 * rx + 1):
            v = big[dy : dy + h, dx : dx + w]
            lo_win = np.minimum(lo_win, v)
            hi_win = np.maximum(hi_win, v)
    flat = (hi_win - lo_win) <= 1
    ys, xs = np.mgrid[0:h, 0:w]
    partner = xs - np.maximum(expected, 0)
    rows = np.zeros(h, np.int32) if row_start is None else np.asarray(row_start, np.int32)
    mask = (expected > 0) & flat & (xs - rows[:, None] >= first_strip + rx) & (partner >= rx) & (xs < w - rx)
    mask &= flat[ys, np.clip(partner, 0, w - 1)]
    if columns is not None:
        mask &= (xs >= columns[0]) & (xs < columns[1])
    left_out = int((mask & ambiguous).sum())
    mask &= ~ambiguous
    n = int(mask.sum())
    if n == 0:
        raise InputError("no pixel can be checked: the image is too small for its separations")
    err = np.abs(decoded[mask] - expected[mask])
    return DecodeReport(float((err <= tolerance).mean()), n, float(err.mean()), tolerance, left_out)


def separation_to_depth(sep: np.ndarray, strip_width: float, depth_factor: float) -> np.ndarray:
    """Invert the linear map s = W_s + β·D: D = (s − W_s)/β clipped to [0, 1] (float32, 0 = near)."""
    return np.clip((np.asarray(sep, np.float32) - strip_width) / depth_factor, 0, 1).astype(np.float32)
