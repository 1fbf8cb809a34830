"""An element's reflectance from the texture it covers: the mean of the surface's reflectance image
(material colour × texture) over the element's region of the image, given by the uvs at its corners.

Each element is sampled (a numba kernel) at ``SAMPLES``² points (``LARGE_SAMPLES``² for one over a
sixteenth of the image) spread evenly over it — a quad at the centres of an
``SAMPLES``×``SAMPLES`` grid of its bilinear parameters, a triangle at the centroids of its
``SAMPLES``²-triangle subdivision — in the level of a box-filtered mip pyramid where one sample's
share of the element covers about one texel, so a large element averages every texel it covers and
a small one is not aliased. Lookups are bilinear and wrap (uvs outside [0, 1] repeat, as the
renderer's textures do). The plain reference, :func:`reference_mean`, samples the full-resolution
image densely.

uvs follow the scene's convention: u to the right, v up, (0, 0) the bottom-left of the image.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["SAMPLES", "TextureReflectance", "element_points", "reference_mean", "MAX_TEXEL_REFLECTANCE"]

#: samples per side of an element (SAMPLES² in all)
SAMPLES = 8

#: an element covering more than this share of the image (uv area) takes LARGE_SAMPLES a side
LARGE_AREA = 1 / 16
LARGE_SAMPLES = 32

#: a texel's reflectance is capped here (radiosity needs ρ < 1: MGF's rd 1 is capped the same way)
MAX_TEXEL_REFLECTANCE = 0.98


def _weights(samples: int) -> tuple[np.ndarray, np.ndarray]:
    """(samples², 4) bilinear weights of a quad's corners at its grid's cell centres, and (samples², 4)
    barycentric weights (the fourth 0) of a triangle's corners at the centroids of its samples²-triangle
    subdivision: points evenly spread over each."""
    k = samples
    t = (np.arange(k) + 0.5) / k
    s, r = (a.reshape(-1) for a in np.meshgrid(t, t, indexing="ij"))
    quad = np.stack([(1 - s) * (1 - r), s * (1 - r), s * r, (1 - s) * r], axis=1)
    up = [((i + 1 / 3) / k, (j + 1 / 3) / k) for i in range(k) for j in range(k - i)]
    down = [((i + 2 / 3) / k, (j + 2 / 3) / k) for i in range(k - 1) for j in range(k - 1 - i)]
    a, b = np.asarray(up + down).T
    tri = np.stack([1 - a - b, a, b, np.zeros_like(a)], axis=1)
    return quad, tri


def element_points(uv: np.ndarray, triangle: np.ndarray, samples: int = SAMPLES) -> np.ndarray:
    """(n, samples², 2) points evenly spread over each element's uv region: ``uv`` (n, 4, 2) its
    corners (a triangle repeats corner 2), ``triangle`` (n,) bool."""
    quad, tri = _weights(samples)
    return np.where(
        np.asarray(triangle, bool)[:, None, None], np.einsum("pk,nkc->npc", tri, uv), np.einsum("pk,nkc->npc", quad, uv)
    )


@numba.njit(cache=True, parallel=True)
def _mean_kernel(image, uv, triangle, quad_weights, tri_weights, out):  # pragma: no cover - numba
    """out[i] = the mean of bilinear lookups (wrapping) of ``image`` at element i's sample points."""
    h, w = image.shape[0], image.shape[1]
    for i in numba.prange(uv.shape[0]):
        weights = tri_weights if triangle[i] else quad_weights
        acc0 = acc1 = acc2 = 0.0
        for p in range(weights.shape[0]):
            u = 0.0
            v = 0.0
            for k in range(4):
                u += weights[p, k] * uv[i, k, 0]
                v += weights[p, k] * uv[i, k, 1]
            x = u * w - 0.5
            y = (1.0 - v) * h - 0.5
            fx0 = np.floor(x)
            fy0 = np.floor(y)
            fx = x - fx0
            fy = y - fy0
            x0 = int(fx0) % w
            y0 = int(fy0) % h
            x1 = (x0 + 1) % w
            y1 = (y0 + 1) % h
            w00 = (1 - fx) * (1 - fy)
            w10 = fx * (1 - fy)
            w01 = (1 - fx) * fy
            w11 = fx * fy
            acc0 += w00 * image[y0, x0, 0] + w10 * image[y0, x1, 0] + w01 * image[y1, x0, 0] + w11 * image[y1, x1, 0]
            acc1 += w00 * image[y0, x0, 1] + w10 * image[y0, x1, 1] + w01 * image[y1, x0, 1] + w11 * image[y1, x1, 1]
            acc2 += w00 * image[y0, x0, 2] + w10 * image[y0, x1, 2] + w01 * image[y1, x0, 2] + w11 * image[y1, x1, 2]
        n = weights.shape[0]
        out[i, 0] = acc0 / n
        out[i, 1] = acc1 / n
        out[i, 2] = acc2 / n


def _bilinear(image: np.ndarray, points: np.ndarray) -> np.ndarray:
    """``image`` (H, W, 3) at uv ``points`` (..., 2), wrapping; texel centres at ((i + ½)/W, …)."""
    h, w = image.shape[:2]
    x = points[..., 0] * w - 0.5
    y = (1.0 - points[..., 1]) * h - 0.5  # v up, row 0 on top
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    x0, y0 = x0.astype(np.int64), y0.astype(np.int64)
    x1, y1 = (x0 + 1) % w, (y0 + 1) % h
    x0, y0 = x0 % w, y0 % h
    return (
        image[y0, x0] * (1 - fx) * (1 - fy)
        + image[y0, x1] * fx * (1 - fy)
        + image[y1, x0] * (1 - fx) * fy
        + image[y1, x1] * fx * fy
    )


def _pyramid(image: np.ndarray) -> list[np.ndarray]:
    """Box-filtered levels of the image, each half the last: level 0 is the image resampled
    (bilinear, wrapping) to the next powers of two when its sides are not, so every level covers
    the uv square texel for texel."""
    image = np.asarray(image, np.float64)
    h, w = image.shape[:2]
    ph, pw = (1 << int(np.ceil(np.log2(max(n, 1)))) for n in (h, w))
    a = image
    if (ph, pw) != (h, w):
        v, u = np.meshgrid(1 - (np.arange(ph) + 0.5) / ph, (np.arange(pw) + 0.5) / pw, indexing="ij")
        a = _bilinear(image, np.stack([u, v], axis=-1))
    levels = [a]
    while min(a.shape[:2]) > 1:
        hh, ww = a.shape[:2]
        a = a.reshape(hh // 2, 2, ww // 2, 2, 3).mean(axis=(1, 3))
        levels.append(a)
    return levels


def _uv_areas(uv: np.ndarray, triangle: np.ndarray) -> np.ndarray:
    d1, d2 = uv[:, 2] - uv[:, 0], uv[:, 3] - uv[:, 1]
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    quad = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    tri = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    return np.where(triangle, tri, quad)


class TextureReflectance:
    """The mean reflectance elements cover, for polygons whose group has a reflectance image.

    ``images``: group → (H, W, 3) reflectance image (colour × texture, each texel < 1)."""

    def __init__(self, images: dict[int, np.ndarray]):
        self.images = {int(g): np.asarray(a, np.float64) for g, a in images.items()}
        self._levels: dict[int, list[np.ndarray]] = {}

    def levels(self, group: int) -> list[np.ndarray]:
        if group not in self._levels:
            self._levels[group] = _pyramid(self.images[group])
        return self._levels[group]

    def __call__(self, group: np.ndarray, uv: np.ndarray, triangle: np.ndarray) -> np.ndarray:
        """(n, 3) mean reflectance of elements of ``group`` (n,) over their uv corners (n, 4, 2); rows
        of a group without an image, or with a non-finite uv, are NaN."""
        group = np.asarray(group, np.int64)
        uv = np.asarray(uv, np.float64)
        triangle = np.asarray(triangle, bool)
        out = np.full((len(group), 3), np.nan)
        ok = np.isfinite(uv).all(axis=(1, 2))
        for g in np.unique(group[ok]):
            if int(g) not in self.images:
                continue
            rows = np.flatnonzero(ok & (group == g))
            levels = self.levels(int(g))
            h, w = levels[0].shape[:2]
            area = _uv_areas(uv[rows], triangle[rows])
            # elements over a sixteenth of the image (roots, mostly) take LARGE_SAMPLES a side
            samples = np.where(area > LARGE_AREA, LARGE_SAMPLES, SAMPLES)
            # the level where a sample's share of the element is about one texel; below that, the
            # image itself
            footprint = np.sqrt(np.maximum(area * h * w, 1e-300)) / samples
            level = np.clip(np.floor(np.log2(np.maximum(footprint, 1.0))), 0, len(levels) - 1).astype(np.int64)
            for n in np.unique(samples):
                quad_weights, tri_weights = _weights(int(n))
                for k in np.unique(level[samples == n]):
                    at = rows[(level == k) & (samples == n)]
                    mean = np.empty((len(at), 3))
                    image = np.ascontiguousarray(levels[k] if k else self.images[int(g)])
                    _mean_kernel(image, np.ascontiguousarray(uv[at]), triangle[at], quad_weights, tri_weights, mean)
                    out[at] = mean
        return out


def reference_mean(image: np.ndarray, uv: np.ndarray, triangle: bool, samples: int = 64) -> np.ndarray:
    """The plain reference: (3,) mean of ``image`` over one element's uv corners (4, 2), sampled at
    ``samples``² evenly spread points in the full-resolution image."""
    points = element_points(np.asarray(uv, np.float64)[None], np.array([triangle]), samples)
    return _bilinear(np.asarray(image, np.float64), points[0]).mean(axis=0)
