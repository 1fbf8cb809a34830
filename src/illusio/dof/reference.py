"""Depth of field stated plainly in NumPy: the specification the GPU passes are tested against, one
function per pass and named after it (``coc`` for CocPass, ``gather`` for GatherPass,
``accumulate`` for the accumulation method's average). Arrays have row 0 at the top."""

from __future__ import annotations

import numpy as np

from .lens import coc_pixels

__all__ = [
    "coc",
    "gather",
    "coc_tiles",
    "gather_taps",
    "tile_size",
    "disk_spiral",
    "MAX_TAPS",
    "accumulate",
    "lens_samples",
    "mip_pyramid",
    "sample_lod",
    "mipmap",
    "planes",
    "plane_index",
    "DEPTH_SLACK",
]

#: relative depth within which a neighbour counts as level with a pixel (not behind it)
DEPTH_SLACK = 0.02


def tile_size(max_coc: float) -> int:
    """Pixels per side of the sampled gather's tiles: at least the largest covering radius, so a
    tile and its eight neighbours hold every pixel whose circle can cover one of its pixels."""
    return max(int(np.ceil(max_coc / 2)), 1)


#: the most points the sampled gather reads per pixel (the shader's uniform array)
MAX_TAPS = 128


def disk_spiral(taps: int) -> np.ndarray:
    """(taps, 2) points of the unit disk on Vogel's golden-angle spiral, radius √((k + ½)/taps),
    angle k·π(3 − √5), unturned: the sampled gather's pattern (the same for every pixel, so that
    its error is a fixed pattern, not noise)."""
    k = np.arange(taps, dtype=np.float64)
    angle = k * np.pi * (3 - np.sqrt(5))
    return np.sqrt((k + 0.5) / taps)[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=1)


def coc(depth: np.ndarray, focus_distance: float, aperture_m: float, fov_y: float, max_coc: float) -> np.ndarray:
    """CocPass: the circle of confusion in pixels of every pixel of a linear depth image (H, W),
    clamped to ``max_coc``; depth ≤ 0 is nothing there (infinitely far)."""
    d = np.asarray(depth, np.float64)
    return np.minimum(coc_pixels(d, focus_distance, aperture_m, fov_y, d.shape[0]), max_coc).astype(np.float32)


def gather(
    image: np.ndarray, coc_px: np.ndarray, depth: np.ndarray, radius: int, depth_slack: float = DEPTH_SLACK
) -> np.ndarray:
    """GatherPass: for each pixel p, the weighted mean of the pixels q within ``radius`` (a square of
    offsets, Euclidean distance) whose circle covers p (r_q = max(c_q/2, ½)), weight cover/(π r_q²)
    with cover = clamp(r_q + ½ − |q − p|, 0, 1) (the circle's edge smoothed over a pixel), leaving
    out a q behind p (z_q > z_p (1 + slack)) outside p's own circle. Depth ≤ 0 is infinitely far.
    (H, W, 3) float32."""
    img = np.asarray(image, np.float64)[..., :3]
    h, w = img.shape[:2]
    r = np.maximum(np.asarray(coc_px, np.float64) / 2, 0.5)
    z = np.where(np.asarray(depth) > 0, np.asarray(depth, np.float64), 1e30)
    total = np.zeros((h, w))
    acc = np.zeros((h, w, 3))
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            dist = float(np.hypot(dx, dy))
            # q = p + (dx, dy) in GL's rows (up) = p + (dx, −dy) in array rows (down)
            ys0, ys1 = max(0, dy), min(h, h + dy)  # p rows whose q row p_y − dy is inside
            xs0, xs1 = max(0, -dx), min(w, w - dx)
            if ys0 >= ys1 or xs0 >= xs1:
                continue
            p = (slice(ys0, ys1), slice(xs0, xs1))
            q = (slice(ys0 - dy, ys1 - dy), slice(xs0 + dx, xs1 + dx))
            rq = r[q]
            cover = np.clip(rq + 0.5 - dist, 0.0, 1.0)
            keep = (cover > 0) & ~((z[q] > z[p] * (1 + depth_slack)) & (dist > r[p]))
            weight = np.where(keep, cover / (np.pi * rq * rq), 0.0)
            acc[p] += weight[..., None] * img[q]
            total[p] += weight
    return (acc / total[..., None]).astype(np.float32)


def coc_tiles(coc_px: np.ndarray, max_coc: float) -> np.ndarray:
    """CocTilesPass: (ceil(H/T), ceil(W/T)) for tiles of T = tile_size(max_coc) pixels, row 0 the
    top tile (the image's top rows, as GL's bottom-up tiles read back): the largest covering radius
    max(c/2, ½) over each tile and its eight neighbours."""
    c = np.asarray(coc_px, np.float64)[::-1]  # GL rows from the bottom: tiles start at the bottom row
    h, w = c.shape
    tile = tile_size(max_coc)
    th, tw = -(-h // tile), -(-w // tile)
    padded = np.zeros((th * tile, tw * tile))
    padded[:h, :w] = c
    block = padded.reshape(th, tile, tw, tile).max(axis=(1, 3))
    around = np.pad(block, 1)
    near = np.max(
        [around[1 + dy : 1 + dy + th, 1 + dx : 1 + dx + tw] for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0
    )
    return np.maximum(near / 2, 0.5)[::-1].astype(np.float32)


def gather_taps(
    image: np.ndarray,
    coc_px: np.ndarray,
    depth: np.ndarray,
    max_coc: float,
    taps: int,
    depth_slack: float = DEPTH_SLACK,
) -> np.ndarray:
    """SampledGatherPass: the gather estimated from ``taps`` points per pixel. For a pixel p (GL
    coordinates, centre p + ½) of tile radius R (coc_tiles): the points q_k = p + ½ + R·s_k
    (s = disk_spiral(taps)), each of area a = πR²/taps and spacing s = √max(a, 1); a point inside
    the image adds the texel under it at mipmap level round(log2 s) (mip_pyramid, nearest; at most the last) with
    weight cover·a/(π r_q²), cover = clamp((r_q − |q_k − p − ½|)/s + ½, 0, 1), r_q, z_q those of
    the pixel under it, under gather's depth rule; p adds its own colour with weight 1/(π r_p²).
    Power-of-two sizes (the pyramid's). (H, W, 3) float32."""
    levels = [level[::-1] for level in mip_pyramid(np.asarray(image, np.float64)[..., :3])]  # GL rows
    h, w = levels[0].shape[:2]
    r = np.maximum(np.asarray(coc_px, np.float64)[::-1] / 2, 0.5)
    z = np.where(np.asarray(depth)[::-1] > 0, np.asarray(depth, np.float64)[::-1], 1e30)
    tile = tile_size(max_coc)
    ys, xs = np.mgrid[0:h, 0:w]
    radius = coc_tiles(coc_px, max_coc)[::-1].astype(np.float64)[ys // tile, xs // tile]
    area = np.pi * radius**2 / taps
    spacing = np.sqrt(np.maximum(area, 1.0))
    level = np.minimum(np.floor(np.log2(spacing) + 0.5).astype(int), len(levels) - 1)
    weight = 1.0 / (np.pi * r**2)
    acc = weight[..., None] * levels[0]
    total = weight.copy()
    for s in disk_spiral(taps):
        qx, qy = xs + 0.5 + radius * s[0], ys + 0.5 + radius * s[1]
        inside = (qx >= 0) & (qy >= 0) & (qx < w) & (qy < h)
        qi, qj = np.clip(qx, 0, w - 1).astype(int), np.clip(qy, 0, h - 1).astype(int)
        dist = radius * float(np.hypot(*s))
        rq = r[qj, qi]
        cover = np.clip((rq - dist) / spacing + 0.5, 0.0, 1.0)
        keep = inside & (cover > 0) & ~((z[qj, qi] > z * (1 + depth_slack)) & (dist > r))
        wq = np.where(keep, cover * area / (np.pi * rq**2), 0.0)
        colour = np.zeros((h, w, 3))
        for k in np.unique(level):
            at = level == k
            lv = levels[k]
            colour[at] = lv[np.minimum(qj[at] >> k, lv.shape[0] - 1), np.minimum(qi[at] >> k, lv.shape[1] - 1)]
        acc += wq[..., None] * colour
        total += wq
    return (acc / total[..., None])[::-1].astype(np.float32)


def accumulate(images) -> np.ndarray:
    """The accumulation method's image: the mean of the views through the lens samples."""
    return np.mean(np.stack([np.asarray(i, np.float64)[..., :3] for i in images]), axis=0).astype(np.float32)


def lens_samples(count: int, seed: int = 0) -> np.ndarray:
    """``count`` points (N, 2) spread evenly over the unit disk (Vogel's golden-angle spiral, the
    area-preserving radius √((i + ½)/N)), the whole pattern turned by an angle drawn from ``seed``."""
    i = np.arange(count, dtype=np.float64)
    radius = np.sqrt((i + 0.5) / count)
    turn = np.random.default_rng(seed).uniform(0, 2 * np.pi)
    angle = i * np.pi * (3 - np.sqrt(5)) + turn
    return np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)


def mip_pyramid(image: np.ndarray) -> list[np.ndarray]:
    """The mipmap levels of an (H, W, C) image, row 0 at the top: each level the 2×2 mean of the one
    before, down to 1×1 (the box filter GL uses for power-of-two sizes; other sizes are refused here,
    their filter being the driver's choice)."""
    level = np.asarray(image, np.float64)
    h, w = level.shape[:2]
    if h & (h - 1) or w & (w - 1):
        raise ValueError(f"the reference pyramid needs power-of-two sizes, got {w}×{h}")
    levels = [level]
    while level.shape[0] > 1 or level.shape[1] > 1:
        h, w = level.shape[:2]
        level = level.reshape(max(h // 2, 1), h // max(h // 2, 1), max(w // 2, 1), w // max(w // 2, 1), -1).mean(
            axis=(1, 3)
        )
        levels.append(level)
    return levels


def _bilinear(level: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """GL's bilinear lookup (clamp to edge) at texture coordinates u, v ((0, 0) bottom left)."""
    gl = level[::-1]  # GL rows from the bottom
    h, w = gl.shape[:2]
    x = np.clip(u * w - 0.5, 0, w - 1)
    y = np.clip(v * h - 0.5, 0, h - 1)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
    tx, ty = (x - x0)[..., None], (y - y0)[..., None]
    return (gl[y0, x0] * (1 - tx) + gl[y0, x1] * tx) * (1 - ty) + (gl[y1, x0] * (1 - tx) + gl[y1, x1] * tx) * ty


def sample_lod(levels: list[np.ndarray], lod: np.ndarray) -> np.ndarray:
    """textureLod with trilinear filtering at every pixel centre of level 0: bilinear on the levels
    floor(lod) and floor(lod) + 1, mixed by the fraction; lod clamped to the pyramid. Rows from the top."""
    h, w = levels[0].shape[:2]
    lod = np.clip(np.broadcast_to(np.asarray(lod, np.float64), (h, w)), 0, len(levels) - 1)
    ys, xs = np.mgrid[0:h, 0:w]
    u = (xs + 0.5) / w
    v = 1 - (ys + 0.5) / h
    base = np.floor(lod).astype(int)
    out = np.zeros((h, w, levels[0].shape[2]))
    for k in np.unique(base):
        at = base == k
        f = (lod - k)[at][:, None]
        lower = _bilinear(levels[k], u[at], v[at])
        upper = _bilinear(levels[min(k + 1, len(levels) - 1)], u[at], v[at])
        out[at] = lower * (1 - f) + upper * f
    return out


def mipmap(image: np.ndarray, coc_px: np.ndarray) -> np.ndarray:
    """MipmapPass: each pixel at the mipmap level of its circle, lod = log2(max(c, 1))."""
    levels = mip_pyramid(np.asarray(image, np.float64)[..., :3])
    return sample_lod(levels, np.log2(np.maximum(np.asarray(coc_px, np.float64), 1.0))).astype(np.float32)


def planes(image: np.ndarray, depth: np.ndarray, distances: np.ndarray, lods: np.ndarray) -> np.ndarray:
    """PlanesPass: each pixel takes the nearest plane behind its surface (the planes' depth test
    GREATER, drawn far to near); with nothing there (depth ≤ 0), the farthest plane. The plane's
    colour is the image's mipmap at the plane's level. ``distances`` far to near, as drawn."""
    levels = mip_pyramid(np.asarray(image, np.float64)[..., :3])
    index = plane_index(depth, distances)
    return sample_lod(levels, np.asarray(lods, np.float64)[index]).astype(np.float32)


def plane_index(depth: np.ndarray, distances: np.ndarray) -> np.ndarray:
    """(H, W) int: the plane each pixel takes (0 = the farthest, ``distances`` far to near): the
    nearest plane behind its surface, the farthest where nothing is there (depth ≤ 0)."""
    z = np.asarray(depth, np.float64)
    order = np.asarray(distances, np.float64)
    behind = order[None, None, :] > np.where(z > 0, z, np.inf)[..., None]
    return np.where(behind.any(axis=-1), order.size - 1 - np.argmax(behind[..., ::-1], axis=-1), 0)
