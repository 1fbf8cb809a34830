"""The texture work of Loscos 4.3.2: textures that show the light of every lamp as if nothing blocked
it, so that switching a lamp off takes its photographed shadows with it.

Per leaf (every link from a lamp ends at a leaf, ``lights_to_leaves``):
- eq. (4.5): the blocked irradiance Ē_i = Σ_s F_is (1 − V_is) B_s over the lamps s;
- eq. (4.6): T_inter = (B_i + ρ_i Ē_i) / D_i^orig × T_orig, D_i^orig = B_i;
- the frontier: leaves lit by every lamp (all lamp links VISIBLE), seen by the camera, next to a
  leaf in shadow (a lamp link PARTIAL or INVISIBLE) of the same surface (input polygons joined by
  shared edges in one plane: a triangulated model's neighbourhoods cross its triangles);
- Figure 4.11: each shadowed leaf's reference is the nearest frontier leaf of the same object whose
  colour (its reflectance in CIE L*a*b*, eq. 4.4) is within ``colour_threshold``; without one, the
  nearest frontier leaf of the object (the chapter asks the user for a default element); without
  any, the leaf keeps T_inter;
- eq. (4.8): ρ_corr = ρ_r · U_i / U_r, U the unoccluded irradiance (Σ_s F_is B_s over the lamps,
  weighted by their radiosity so lamps of different power count as they light, plus the indirect
  light the texture also holds), ρ_inter each leaf's T_inter read as eq. 4.1 reads a texture; and
  eq. (4.9): T_final = (ρ_corr / ρ_inter)^w · T_inter, with w (``correction_weight``) the share of
  the leaf's direct light that is blocked. The chapter has w = 1: the reference replaces the leaf's
  own texture wherever a reference exists. Ours trusts the leaf's own photograph in proportion to the
  light it still holds: a penumbra leaf's T_inter adds little blocked light to a texture mostly lit
  and is near right, where the reference brings the error of its own estimate and of the U_i/U_r
  ratio; an umbra leaf's T_inter multiplies a dark texture by a large (E + Ē)/E, and there the
  reference's lit texture is the better guess (measured in benchmarks/RESULTS.md, issue 33).
The textures are kept as one factor per leaf on the photograph (T = factor × photograph), modulated
at the leaves' vertices as the chapter does: each surface's corner points take the mean factor of
the leaves meeting there and the display interpolates across each leaf (``RelightSession``), so no
leaf shows as a patch.
"""

from __future__ import annotations

import numpy as np

#: the least share of a leaf's unoccluded irradiance (lamps' direct + indirect) that its blocked
#: light Ē must be for the leaf to count as shadowed (below it the leaf counts as lit)
BLOCKED_SHARE = 0.05

__all__ = [
    "BLOCKED_SHARE",
    "correction_weight",
    "srgb_to_lab",
    "colour_distance",
    "lamp_transfer",
    "neighbours",
    "references",
]


def srgb_to_lab(rgb: np.ndarray) -> np.ndarray:
    """Linear RGB (sRGB primaries, D65) → CIE L*a*b* (n, 3)."""
    rgb = np.asarray(rgb, np.float64)
    m = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = rgb @ m.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]), 200 * (f[:, 1] - f[:, 2])], axis=1)


def colour_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Eq. (4.4): the Euclidean distance in CIE L*a*b* between linear RGB colours."""
    return np.linalg.norm(srgb_to_lab(a) - srgb_to_lab(b), axis=1)


def lamp_transfer(h, links, leaves: np.ndarray):
    """Per leaf: (occluded direct irradiance Σ F V B_s, blocked Ē = Σ F (1 − V) B_s, unoccluded
    Σ F B_s — each (n, 3) W/m² — and whether every lamp link is VISIBLE, whether any is not)."""
    n = len(h)
    from_lamp = h.exitance[links.source].max(axis=1) > 0
    r, s = links.receiver[from_lamp], links.source[from_lamp]
    f, v = links.form_factor[from_lamp], links.visibility[from_lamp]
    b = h.radiosity[s]

    def total(weight):
        return np.stack([np.bincount(r, weights=weight * b[:, c], minlength=n) for c in range(3)], axis=1)[leaves]

    lit, blocked, free = total(f * v), total(f * (1 - v)), total(f)
    shadowed = np.bincount(r, weights=(v < 1).astype(float), minlength=n)[leaves] > 0
    linked = np.bincount(r, minlength=n)[leaves] > 0
    return lit, blocked, free, linked & ~shadowed, shadowed


def correction_weight(blocked: np.ndarray, free: np.ndarray) -> np.ndarray:
    """w of eq. (4.9) per leaf (n,): the blocked share of its direct light, Σ_c Ē / Σ_c Σ_s F_is B_s,
    in [0, 1] (1 in a full shadow: the reference's texture; 0 in full light: the leaf's own)."""
    total = np.asarray(free, np.float64).sum(axis=1)
    share = np.asarray(blocked, np.float64).sum(axis=1) / np.where(total > 0, total, 1.0)
    return np.clip(np.where(total > 0, share, 1.0), 0.0, 1.0)


def neighbours(h, leaves: np.ndarray) -> list[np.ndarray]:
    """For each leaf, the rows of the leaves of the same surface (``Polygons.surfaces``: input
    polygons joined by shared edges in one plane, so a triangulated wall is one) that touch it (their
    boxes meet within 10⁻⁶ of the scene's extent): edge and corner neighbours, a small leaf beside a
    large one included (a T-junction shares no corner point)."""
    extent = max(float(np.ptp(h.corners[h.roots].reshape(-1, 3), axis=0).max()), 1e-9)
    tol = 1e-6 * extent
    c = h.corners[leaves]
    lo, hi = c.min(axis=1) - tol, c.max(axis=1) + tol
    polygon = h.polygons.surfaces()[h.polygon[leaves]]
    out: list[np.ndarray] = [np.zeros(0, np.int64)] * len(leaves)
    order = np.argsort(polygon, kind="stable")
    starts = np.flatnonzero(np.r_[True, polygon[order][1:] != polygon[order][:-1]])
    for rows in np.split(order, starts[1:]):
        touch = np.all((lo[rows, None] <= hi[None, rows]) & (lo[None, rows] <= hi[rows, None]), axis=2)
        np.fill_diagonal(touch, False)
        for k, row in enumerate(rows):
            out[row] = rows[touch[k]]
    return out


def references(h, leaves, shadow, frontier, group, reflectance, colour_threshold: float) -> np.ndarray:
    """Figure 4.11: for each leaf (row) in ``shadow``, the row of its reference among ``frontier``
    (−1 where there is none); see the module docstring."""
    out = np.full(len(leaves), -1)
    candidates = np.flatnonzero(frontier)
    if not len(candidates):
        return out
    centre = h.centre[leaves]
    for i in np.flatnonzero(shadow):
        same = candidates[group[candidates] == group[i]]
        if not len(same):
            continue
        distance = np.linalg.norm(centre[same] - centre[i], axis=1)
        similar = (
            colour_distance(reflectance[same], np.repeat(reflectance[i][None], len(same), axis=0)) < colour_threshold
        )
        pool = np.flatnonzero(similar) if similar.any() else np.arange(len(same))
        out[i] = same[pool[np.argmin(distance[pool])]]
    return out
