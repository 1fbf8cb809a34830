"""The pixels a lamp's outline crosses. A photograph's pixel on a lamp's edge holds both the lamp's
glow and the surface behind it; every method relights a pixel by what its centre sees, so a lamp
switched off left a ring of its own light around a black panel (the "dotted bright rim" of issue
33), and a lamp turned up left a dark ring.

At preparation: each pixel's coverage by each lamp (4×4 rays a pixel, Embree), which says where the
rims are (the pixels partly covered, and their neighbours: the photograph's pixel filter spreads the
glow a pixel further), and each lamp's radiance L in the photograph (the median over the pixels it
covers wholly). At a rim pixel, with S the surface's radiance (the nearest pixel no lamp covers) and
L that of the lamp covering most of the pixel, the photograph is

    P = c·L + (1 − c)·S,     c = (P − S) / (L − S) in luminance, clipped to [0, 1]

(c read from the photograph: its filter spreads a lamp's glow otherwise than the geometric
coverage). Under the lamp's scale k the pixel is relit as k·G + (1 − c)·S·r, G = P − (1 − c)·S the
lamp's part (c·L, or all of P where it is brighter than L), written as the change
P + (k − 1)·G + (1 − c)·S·(r − 1), so that nothing changed gives the photograph back exactly; r is
the method's own relighting ratio of the surface: its output over its input at the pixel when the
centre saw the surface, else the nearest such pixel's. (Computed when first needed, not saved with
a session.)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LampRims"]

#: rays a pixel side for the coverage
SUPERSAMPLE = 4


@dataclass(eq=False)
class LampRims:
    """coverage (H, W, L) of the lamp groups ``groups`` (L,); radiance (L, 3) of each in the
    photograph; rim (H, W): the pixels partly covered by some lamp."""

    groups: np.ndarray
    coverage: np.ndarray
    radiance: np.ndarray

    @property
    def rim(self) -> np.ndarray:
        """The pixels a lamp's outline crosses, and their neighbours (the photograph's pixel filter
        spreads the glow a pixel further)."""
        from scipy import ndimage

        total = self.coverage.sum(axis=-1)
        whole = total >= 1
        return ndimage.binary_dilation(total > 0) & ~whole

    @classmethod
    def prepare(cls, polygons, view, photograph: np.ndarray, groups) -> LampRims:
        from .photograph import polygon_ids

        h, w = photograph.shape[:2]
        k = SUPERSAMPLE
        ids = polygon_ids(polygons, view, (w * k, h * k))
        group = np.where(ids >= 0, polygons.group[np.maximum(ids, 0)], -1)
        groups = np.asarray(sorted(groups), np.int64)
        coverage = (
            np.stack([(group == g).reshape(h, k, w, k).mean(axis=(1, 3)) for g in groups], axis=-1)
            if len(groups)
            else np.zeros((h, w, 0))
        )
        radiance = np.zeros((len(groups), 3))
        for s in range(len(groups)):
            whole = coverage[..., s] >= 1.0
            pick = whole if whole.any() else coverage[..., s] >= coverage[..., s].max() - 1e-9
            if coverage[..., s].max() > 0:
                radiance[s] = np.median(photograph[pick][..., :3], axis=0)
        return cls(groups, coverage, radiance)

    def _rim_pixels(self) -> np.ndarray:
        if getattr(self, "_rim", None) is None:
            self._rim = self.rim
        return self._rim

    def _nearest(self, centre_on_lamp: np.ndarray):
        """(rows, cols) of the nearest lamp-free pixel, and of the nearest pixel whose centre sees no
        lamp, for every pixel (distance transforms, kept: the camera and the lamps do not move)."""
        from scipy import ndimage

        key = centre_on_lamp.tobytes()
        if getattr(self, "_nearest_key", None) != key:
            _, free = ndimage.distance_transform_edt(self.coverage.sum(axis=-1) > 0, return_indices=True)
            if (~centre_on_lamp).any():
                _, surface = ndimage.distance_transform_edt(centre_on_lamp, return_indices=True)
            else:
                surface = np.indices(centre_on_lamp.shape)
            self._nearest_key, self._nearest_indices = key, (tuple(free), tuple(surface))
        return self._nearest_indices

    def apply(
        self, relit: np.ndarray, photograph: np.ndarray, scales: np.ndarray, centre_on_lamp: np.ndarray
    ) -> np.ndarray:
        """The relit image with its rim pixels recomposed (the module docstring). ``relit`` and
        ``photograph`` (H, W, 3) at the same exposure; ``scales`` (L,) the lamps' k_s;
        ``centre_on_lamp`` (H, W): the pixels whose centre sees a lamp."""
        rim = self._rim_pixels()
        if not rim.any():
            return relit
        (sy, sx), (iy, ix) = self._nearest(centre_on_lamp)
        ry, rx = np.nonzero(rim)  # only the rim pixels are worked on
        photograph = photograph[..., :3]
        photo = photograph[ry, rx].astype(np.float64)
        surface = photograph[sy[ry, rx], sx[ry, rx]].astype(np.float64)  # S: the nearest pixel no lamp covers
        # the surface's own ratio where the centre saw it, else the nearest such pixel's
        at = (iy[ry, rx], ix[ry, rx])
        seen, now = photograph[at].astype(np.float64), relit[..., :3][at].astype(np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(seen > 0, now / np.where(seen > 0, seen, 1), 1.0)
        # the lamp's share c of each rim pixel read from the photograph itself, P = c·L + (1 − c)·S in
        # luminance, with L the lamp covering most of it: the geometric coverage says where the
        # rims are, but the photograph's filter spreads a lamp's glow differently
        lamp = np.argmax(self.coverage[ry, rx], axis=-1)
        glow = self.radiance[lamp]
        lum = lambda a: a.mean(axis=-1)  # noqa: E731
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.clip((lum(photo) - lum(surface)) / (lum(glow) - lum(surface)), 0, 1)
        share = np.where(np.isfinite(share), share, 0.0)
        k = np.asarray(scales, np.float64)[lamp]
        # the lamp's part of P is what the surface's is not (all of P where c reached 1: a pixel
        # brighter than the lamp's median is lamp through and through)
        own = np.clip(photo - (1 - share)[:, None] * surface, 0, None)
        out = relit.astype(np.float64).copy()
        # written as a change of the photograph, so that nothing changed gives it back exactly
        out[ry, rx] = photo + (k - 1)[:, None] * own + (1 - share)[:, None] * surface * (ratio - 1)
        return out
