"""The autostereogram algorithms stated plainly, in NumPy and numba: the specification the GPU passes
are tested against (Dehos et al. 2014, sections 3.3–3.4; Thimbleby, Inglis & Witten 1994).

Conventions shared by every function here and by the shaders:

* ``depth`` D: float32 (H, W) in [0, 1], 0 = nearest, 1 = farthest (the paper's D).
* ``separation`` s: float32 (H, W), pixels between the two pixels that show a point; a pixel uses the
  rounded value ``floor(s + 0.5)``.
* ``pattern`` T: float32 (H_T, W_T, C), tiled: T[y mod H_T, x mod W_T], rows counted from the top.
* ``row_start``: int32 (H,), the column where each row's stereogram starts (0 for a whole image; the
  left edge of the host surface in a 3D scene). Each row's first strip is the ``first_strip`` columns
  from there: W_s + β in Algorithm 1. ``row_end``: int32 (H,), one past the host's last column in
  each row (the image width if not given): the first strip's pattern columns wrap inside
  [row_start, row_end), so a row shorter than a strip shows only the pattern on the host.
* Left-anchored algorithms (sequential, strip, chain; the fast GPU pass is the sequential one) make S[x] = S[x −
s(x)]: a pixel repeats the one
  s to its left. The symmetric algorithm links x − s/2 and x − s/2 + s for the point at x.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..scene.camera import Screen
from .physics import depth_range, separation_px

__all__ = [
    "separation",
    "rounded",
    "sequential",
    "strip",
    "chain",
    "symmetric",
    "occlusion_separation",
    "upsample_depth",
    "downsample",
    "strip_passes",
    "host_projection",
]


def upsample_depth(depth: np.ndarray, factor: int) -> np.ndarray:
    """Depth at ``factor`` times the width, interpolated linearly between pixel centres (clamped at
    the edges) — what the separation shader does when oversampling."""
    d = np.asarray(depth, np.float32)
    if factor == 1:
        return d
    h, w = d.shape
    pos = (np.arange(w * factor, dtype=np.float32) + np.float32(0.5)) / np.float32(factor) - np.float32(0.5)
    pos = np.clip(pos, 0, w - 1).astype(np.float32)
    i0 = np.floor(pos).astype(np.int64)
    i1 = np.minimum(i0 + 1, w - 1)
    t = (pos - i0).astype(np.float32)
    return (d[:, i0] * (np.float32(1) - t) + d[:, i1] * t).astype(np.float32)


def separation(
    depth: np.ndarray,
    strip_width: float,
    depth_factor: float,
    exact: bool = False,
    screen: Screen | None = None,
    invert: bool = False,
    oversample: int = 1,
) -> np.ndarray:
    """Depth → separation, pixels (at ``oversample`` times the width, separations scaled alike).

    Linear (the paper's approximation): s = W_s + β·D. Exact: D is linear in the simulated depth,
    f' = f'_min + D·(f'_max − f'_min) with [f'_min, f'_max] from equation (4) at W_s and W_s + β, and
    s = e'_p(f') by equation (3). Both give W_s at D = 0 and W_s + β at D = 1.
    """
    d = upsample_depth(np.asarray(depth, np.float32), oversample)
    if invert:
        d = np.float32(1) - d
    n = np.float32(oversample)
    if not exact:
        return ((np.float32(strip_width) + np.float32(depth_factor) * d) * n).astype(np.float32)
    screen = screen or Screen()
    near, far = depth_range(strip_width, depth_factor, screen)
    f_prime = np.float32(near) + d * np.float32(far - near)
    return (separation_px(f_prime, screen).astype(np.float32) * n).astype(np.float32)


def rounded(sep: np.ndarray) -> np.ndarray:
    """The whole-pixel separation a pixel uses: floor(s + 0.5)."""
    return np.floor(np.asarray(sep, np.float32) + np.float32(0.5)).astype(np.int32)


def _rows(row_start, height):
    if row_start is None:
        return np.zeros(height, np.int32)
    return np.asarray(row_start, np.int32)


def _ends(row_end, height, width):
    if row_end is None:
        return np.full(height, width, np.int32)
    return np.asarray(row_end, np.int32)


@njit(cache=True)
def _texel(pattern, x, y, shift, start, first_strip, end):
    """T[y mod H_T, (x − shift) mod W_T]; with a row start (start ≥ 0), a column left of it wraps
    into the first strip, and one at or past the row's ``end`` wraps back into [start, end) (the
    host's own projected pattern, never what lies off it)."""
    ht, wt = pattern.shape[0], pattern.shape[1]
    v = x - shift
    if start >= 0:
        if v < start:
            v += first_strip
        if v >= end:
            v = start + (v - start) % max(end - start, 1)
    return pattern[y % ht, v % wt]


@njit(cache=True)
def _sequential(sep_px, pattern, strip_width, first_strip, row_start, row_end, wrap, out):
    h, w = sep_px.shape
    for y in range(h):
        for x in range(w):
            s = sep_px[y, x]
            if x - row_start[y] < first_strip:
                out[y, x] = _texel(
                    pattern, x, y, s - strip_width, row_start[y] if wrap else -1, first_strip, row_end[y]
                )
            else:
                out[y, x] = out[y, x - s]
    return out


def sequential(
    sep: np.ndarray,
    pattern: np.ndarray,
    strip_width: int,
    first_strip: int,
    row_start: np.ndarray | None = None,
    row_end: np.ndarray | None = None,
) -> np.ndarray:
    """Section 3.3, left to right along each row: the first strip (x − row_start < ``first_strip``)
    samples the pattern shifted by s − W_s (Algorithm 1's x − βD), every later pixel copies
    S[x − s(x)]. Returns float32 (H, W, C).

    Departure from the paper: its sequential algorithm (Figure 16) copies S[x − αD], separations in
    [0, α]; here the separation is the same s = W_s + βD (or equation (3)) as the strip algorithm's.
    With αD a point at D = 0 would copy itself (no separation, no depth), and the physical model of
    section 3.1 wants separations of at least W_s for a depth behind the screen; one mapping for all
    algorithms also makes their images comparable — sequential, strip and chain give the same one."""
    sep_px = rounded(sep)
    h, w = sep_px.shape
    pattern = np.ascontiguousarray(pattern, np.float32)
    out = np.zeros((h, w, pattern.shape[2]), np.float32)
    return _sequential(
        sep_px,
        pattern,
        int(strip_width),
        int(first_strip),
        _rows(row_start, h),
        _ends(row_end, h, w),
        row_start is not None,
        out,
    )


def strip_passes(width: int, strip_width: int, first_strip: int) -> int:
    """How many passes Algorithm 1 takes for rows of ``width`` pixels: the first strip, then one per
    W_s columns — 19 for Full HD with W_s = 100, β = 50 (a first strip of W_s + β = 150 px, then 18
    of 100). The paper's "20 passes" (section 2) counts 1920 / 100."""
    return 1 + max(0, -(-(width - first_strip) // strip_width))


def _pattern_at(pattern, ys, xs, shift, row_start, first_strip, row_end):
    """Vectorised _texel (``row_end``: as _ends gives it)."""
    ht, wt = pattern.shape[:2]
    v = xs - shift
    if row_start is not None:
        start = np.asarray(row_start, np.int64)[ys]
        end = np.asarray(row_end, np.int64)[ys]
        v = np.where(v < start, v + first_strip, v)
        v = np.where(v >= end, start + (v - start) % np.maximum(end - start, 1), v)
    return pattern[ys % ht, v % wt]


def strip(
    sep: np.ndarray,
    pattern: np.ndarray,
    strip_width: int,
    first_strip: int,
    row_start: np.ndarray | None = None,
    row_end: np.ndarray | None = None,
) -> np.ndarray:
    """Algorithm 1: the first strip from the pattern, then strips of W_s columns, each computed all at
    once from the strips before it (every pixel of a strip reads at least W_s to its left)."""
    sep_px = rounded(sep)
    h, w = sep_px.shape
    rows = _rows(row_start, h)
    ys, xs = np.mgrid[0:h, 0:w]
    out = _pattern_at(
        np.asarray(pattern, np.float32), ys, xs, sep_px - strip_width, row_start, first_strip, _ends(row_end, h, w)
    ).astype(np.float32)
    rel = xs - rows[:, None]
    for k in range(1, strip_passes(w + int(rows.max(initial=0)), strip_width, first_strip)):
        lo = first_strip + (k - 1) * strip_width
        band = (rel >= lo) & (rel < lo + strip_width)
        out[band] = out[ys[band], xs[band] - sep_px[band]]
    return out


def chain(
    sep: np.ndarray,
    pattern: np.ndarray,
    strip_width: int,
    first_strip: int,
    row_start: np.ndarray | None = None,
    row_end: np.ndarray | None = None,
) -> np.ndarray:
    """Every pixel independently follows its chain x → x − s(x) → … until it lands in the first strip,
    and takes the pattern value there: the same image as :func:`sequential`, with no order between
    pixels."""
    sep_px = rounded(sep)
    h, w = sep_px.shape
    rows = _rows(row_start, h)
    ys, xs = np.mgrid[0:h, 0:w]
    at = xs.copy()
    while True:
        moving = at - rows[:, None] >= first_strip
        if not moving.any():
            break
        at[moving] -= sep_px[ys[moving], at[moving]]
    return _pattern_at(
        np.asarray(pattern, np.float32),
        ys,
        at,
        sep_px[ys, at] - strip_width,
        row_start,
        first_strip,
        _ends(row_end, h, w),
    )


def occlusion_separation(sep: float, offset: float, eye_separation: float) -> float:
    """The separation a point of the sight line from a point of separation ``sep`` to one eye has,
    ``offset`` pixels to the side: σ(t) = e_p − e_p (e_p − s) / (e_p − 2t).

    Derived from equations (3)–(4) with the eyes centred on the point: σ(0) = s, and σ reaches 0 (the
    screen) at t = s/2. A surface at that column with a smaller separation (nearer) hides the point.
    """
    return eye_separation - eye_separation * (eye_separation - sep) / (eye_separation - 2.0 * offset)


@njit(cache=True)
def _symmetric(sep, pattern, near_separation, eye_separation, row_start, row_end, wrap, first_strip, out, same):
    h, w = sep.shape
    e = np.float32(eye_separation)
    for y in range(h):
        for x in range(w):
            same[x] = x
        r0 = row_start[y]
        for x in range(r0, w):
            sf = sep[y, x]
            s = np.int32(np.floor(sf + np.float32(0.5)))
            left = x - s // 2
            right = left + s
            if left < r0 or right >= w:
                continue
            visible = True
            t = 1
            while True:
                sigma = e - e * (e - sf) / (e - np.float32(2 * t))
                if sigma <= near_separation:
                    break  # nothing can be nearer than the near plane
                if (x - t >= r0 and sep[y, x - t] < sigma) or (x + t < w and sep[y, x + t] < sigma):
                    visible = False
                    break
                t += 1
            if not visible:
                continue
            # record left ≡ right, keeping each chain of same[] sorted left to right
            k = same[left]
            while k != left and k != right:
                if k < right:
                    left = k
                else:
                    left, right = right, k
                k = same[left]
            same[left] = right
        for x in range(w - 1, -1, -1):
            if same[x] == x:
                out[y, x] = _texel(pattern, x, y, 0, r0 if wrap else -1, first_strip, row_end[y])
            else:
                out[y, x] = out[y, same[x]]
    return out


def symmetric(
    sep: np.ndarray,
    pattern: np.ndarray,
    near_separation: float,
    eye_separation: float,
    row_start: np.ndarray | None = None,
    first_strip: int = 0,
    row_end: np.ndarray | None = None,
) -> np.ndarray:
    """Thimbleby, Inglis & Witten (1994): for each point x, the pixels x − ⌊s/2⌋ and x − ⌊s/2⌋ + s must
    match, unless the point is hidden from one eye (hidden-surface removal with
    :func:`occlusion_separation`; ``near_separation`` is W_s, nothing is nearer). Constraints are
    recorded as links to the right; pixels at the right end of a chain take the pattern, and colours
    run right to left. No left-to-right bias. ``first_strip`` only matters with ``row_start`` (the
    pattern wrap of :func:`_texel`)."""
    sep = np.ascontiguousarray(sep, np.float32)
    h, w = sep.shape
    pattern = np.ascontiguousarray(pattern, np.float32)
    out = np.zeros((h, w, pattern.shape[2]), np.float32)
    same = np.zeros(w, np.int32)
    return _symmetric(
        sep,
        pattern,
        np.float32(near_separation),
        np.float32(eye_separation),
        _rows(row_start, h),
        _ends(row_end, h, w),
        row_start is not None,
        int(first_strip),
        out,
        same,
    )


def downsample(image: np.ndarray, factor: int) -> np.ndarray:
    """Average each run of ``factor`` columns (undoes the oversampled width)."""
    if factor == 1:
        return image
    h, w, c = image.shape
    return image[:, : w - w % factor].reshape(h, w // factor, factor, c).mean(axis=2, dtype=np.float32)


def host_projection(
    corners: np.ndarray,
    uvs: np.ndarray,
    view_projection: np.ndarray,
    size: tuple[int, int],
    hidden_depth: np.ndarray,
    pattern: np.ndarray,
    pattern_repeat=(1.0, 1.0),
    depth_box=None,
) -> tuple[np.ndarray, np.ndarray]:
    """Steps (2) and (4) of Figure 22 for a planar parallelogram host, by casting each pixel centre's
    ray onto its plane: (D in screen space, −1 off the host; the pattern in screen space, RGB, 0 off
    the host). ``corners``: (3, 3) world points p0, p1, p2 with the fourth at p1 + p2 − p0; ``uvs``:
    their (3, 2) texture coordinates (affine across the parallelogram). D is sampled bilinearly with
    texel centres at (i + ½)/W and clamped edges, the pattern at the nearest texel, repeated — the
    GL conventions of the pass (row 0 of the arrays at the top, uv (0, 0) at the bottom left).
    ``depth_box`` (x0, y0, x1, y1 pixels, row 0 at the top): the "viewer" layout, D read across that
    screen rectangle at each pixel centre (1 outside it) instead of through the uvs."""
    w, h = size
    inv = np.linalg.inv(np.asarray(view_projection, np.float64))
    xs = (np.arange(w) + 0.5) / w * 2 - 1
    ys = 1 - (np.arange(h) + 0.5) / h * 2  # row 0 at the top
    ndc_x, ndc_y = np.meshgrid(xs, ys)

    def unproject(z):
        p = np.stack([ndc_x, ndc_y, np.full_like(ndc_x, z), np.ones_like(ndc_x)], -1) @ inv.T
        return p[..., :3] / p[..., 3:]

    near, far = unproject(-1.0), unproject(1.0)
    direction = far - near
    p0, p1, p2 = (np.asarray(c, np.float64) for c in corners)
    e1, e2 = p1 - p0, p2 - p0
    normal = np.cross(e1, e2)
    t = ((p0 - near) @ normal) / (direction @ normal)
    hit = near + t[..., None] * direction
    # hit = p0 + a e1 + b e2: solve the 2×2 system in the plane
    gram = np.array([[e1 @ e1, e1 @ e2], [e1 @ e2, e2 @ e2]])
    rel = hit - p0
    a, b = np.linalg.solve(gram, np.stack([rel @ e1, rel @ e2], -1)[..., None])[..., 0].transpose(2, 0, 1)
    on = (t > 0) & (a >= 0) & (a <= 1) & (b >= 0) & (b <= 1)
    uv0, uv1, uv2 = (np.asarray(u, np.float64) for u in uvs)
    uv = uv0 + a[..., None] * (uv1 - uv0) + b[..., None] * (uv2 - uv0)
    corners_uv = np.stack([uv0, uv1, uv2, uv1 + uv2 - uv0])
    lo, hi = corners_uv.min(axis=0), corners_uv.max(axis=0)
    st = (uv - lo) / np.maximum(hi - lo, 1e-6)
    at = st
    if depth_box is not None:  # pixel centres across the box, in GL rows (bottom up)
        x0, y0, x1, y1 = (float(v) for v in depth_box)
        gl_x, gl_y = np.meshgrid(np.arange(w) + 0.5, h - 0.5 - np.arange(h))
        at = np.stack([(gl_x - x0) / max(x1 - x0, 1e-6), (gl_y - (h - y1)) / max(y1 - y0, 1e-6)], -1)
    # D, bilinear, clamped; array row r holds GL row H-1-r
    dh, dw = hidden_depth.shape
    fx = np.clip(at[..., 0] * dw - 0.5, 0, dw - 1)
    fy = np.clip(at[..., 1] * dh - 0.5, 0, dh - 1)
    x0, y0 = np.floor(fx).astype(int), np.floor(fy).astype(int)
    x1, y1 = np.minimum(x0 + 1, dw - 1), np.minimum(y0 + 1, dh - 1)
    tx, ty = fx - x0, fy - y0
    gl_rows = np.asarray(hidden_depth, np.float64)[::-1]
    depth = (gl_rows[y0, x0] * (1 - tx) + gl_rows[y0, x1] * tx) * (1 - ty) + (
        gl_rows[y1, x0] * (1 - tx) + gl_rows[y1, x1] * tx
    ) * ty
    if depth_box is not None:
        depth = np.where(((at >= 0) & (at <= 1)).all(axis=-1), depth, 1.0)
    ph, pw = pattern.shape[:2]
    rep = st * np.asarray(pattern_repeat, np.float64)
    px = np.floor(rep[..., 0] * pw).astype(int) % pw
    py = np.floor(rep[..., 1] * ph).astype(int) % ph
    colour = np.asarray(pattern, np.float32)[::-1][py, px][..., :3]
    return (np.where(on, depth, -1.0).astype(np.float32), np.where(on[..., None], colour, 0.0).astype(np.float32))
