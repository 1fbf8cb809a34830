"""Stereogram videos: depth frames in (a depth video, a numbered image sequence, a folder of depth
images or ``.npy`` frames, or a mesh turning on a turntable), stereogram frames out, with the
pattern held still where the depth does not change.

Why holding needs more than a fixed seed: a left-anchored stereogram (sequential, strip, chain, fast:
one image) copies S[x] = S[x − s(x)], so every pixel repeats the colour of its chain's root in the
first strip. A depth change at x₀ re-routes the chains that pass through it, and every pixel to its
right on such a chain takes another root's colour: regenerated frames shimmer across the whole
width right of anything that moves.

The rule here: the pixels of one root form a tree, and a tree's colour is free (any colour keeps
S[x] = S[x − s(x)]). Each tree takes the colour of the previous frame's tree that most of its
unchanged pixels (the same rounded separation as before) belonged to — of the previous colours, the
one that changes the fewest of them, trees being disjoint; a tree with no unchanged pixel takes its
root's pattern colour, as a single stereogram would. Where depth changes, trees split and merge (two
pixels link to one wherever s(x + 1) = s(x) + 1), and a tree holds one colour: some unchanged pixels
must still change. Regenerating keeps only the pixels whose root did not move. Every frame is still an exact
stereogram of its depth; only the choice of colours carries over.
"""

from __future__ import annotations

import os
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba import njit

from ..core.errors import InputError
from . import reference
from .inputs import pixel_widths
from .params import StereogramParams

__all__ = [
    "VIDEO_SUFFIXES",
    "DepthFrames",
    "is_depth_sequence",
    "open_depth_frames",
    "turntable_depths",
    "StereogramSequence",
    "unchanged_change",
]

#: depth videos read through imageio's ffmpeg (8-bit luminance, white = near)
VIDEO_SUFFIXES = (".mp4", ".mov", ".avi", ".mkv", ".webm", ".gif")
#: depth frames a folder or a numbered sequence may hold (read as ``illusio sis`` reads one depth map)
FRAME_SUFFIXES = (".png", ".npy", ".tif", ".tiff", ".jpg", ".jpeg", ".exr")
#: frames a second when the input does not say
DEFAULT_FPS = 24.0
_NUMBERED = re.compile(r"%0?(\d*)d")


def is_depth_sequence(source: str) -> bool:
    """Whether ``source`` names depth frames rather than one depth map or a shape: a video file, a
    printf-numbered pattern (``depth_%04d.png``) or a folder."""
    p = Path(source)
    return p.suffix.lower() in VIDEO_SUFFIXES or bool(_NUMBERED.search(p.name)) or p.is_dir()


@dataclass
class DepthFrames:
    """Depth frames D (float32 (H, W), 0 = near), read one at a time: ``count`` of them, each
    ``size`` (W, H), meant to play at ``fps``."""

    source: str
    count: int
    size: tuple[int, int]
    fps: float
    _read: object  # () -> iterator of D

    def __iter__(self) -> Iterator[np.ndarray]:
        for k, depth in enumerate(self._read()):
            if (depth.shape[1], depth.shape[0]) != self.size:
                raise InputError(
                    f"{self.source}: frame {k} is {depth.shape[1]}×{depth.shape[0]}, "
                    f"the first {self.size[0]}×{self.size[1]}"
                )
            yield depth


def _natural_key(path: Path):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", path.name)]


def _frame_files(source: str) -> list[Path]:
    p = Path(source)
    if p.is_dir():
        files = sorted((f for f in p.iterdir() if f.suffix.lower() in FRAME_SUFFIXES), key=_natural_key)
        kinds = {f.suffix.lower() for f in files}
        if not files:
            raise InputError(f"{source}: no depth frames ({', '.join(FRAME_SUFFIXES)}) in this folder")
        if len(kinds) > 1:
            raise InputError(f"{source}: frames of several kinds ({', '.join(sorted(kinds))}): keep one")
        return files
    folder = p.parent if str(p.parent) else Path(".")
    match = _NUMBERED.search(p.name)
    head, tail = p.name[: match.start()], p.name[match.end() :]
    digits = f"\\d{{{match.group(1)}}}" if match.group(1) else "\\d+"
    named = re.compile(re.escape(head) + f"({digits})" + re.escape(tail) + "$")
    if not folder.is_dir():
        raise InputError(f"{source}: no such folder {folder}")
    numbered = sorted((int(m.group(1)), f) for f in folder.iterdir() if (m := named.match(f.name)))
    if not numbered:
        raise InputError(f"{source}: no file matches the numbered pattern in {folder}")
    numbers = [n for n, _ in numbered]
    gaps = sorted(set(range(numbers[0], numbers[-1] + 1)) - set(numbers))
    if gaps:
        raise InputError(f"{source}: frame {gaps[0]} is missing (frames {numbers[0]}..{numbers[-1]})")
    return [f for _, f in numbered]


def _video_depths(path: Path) -> tuple[int, tuple[int, int], float, object]:
    import imageio.v2 as iio2

    def reader():
        return iio2.get_reader(str(path), format="FFMPEG" if path.suffix.lower() != ".gif" else None)

    try:
        first_reader = reader()
        try:
            meta = first_reader.get_meta_data()
            count = first_reader.count_frames() if hasattr(first_reader, "count_frames") else len(first_reader)
            first = np.asarray(first_reader.get_data(0))
        finally:
            first_reader.close()
    except (OSError, RuntimeError, ValueError, IndexError) as exc:
        said = str(exc).strip().splitlines()
        raise InputError(f"{path}: not a readable video ({said[0] if said else type(exc).__name__})") from None
    fps = float(meta.get("fps") or DEFAULT_FPS)

    def read():
        r = reader()
        try:
            for frame in r:
                yield _luminance_depth(np.asarray(frame))
        finally:
            r.close()

    return int(count), (first.shape[1], first.shape[0]), fps, read


def _luminance_depth(frame: np.ndarray) -> np.ndarray:
    """A video frame (uint8 grey or RGB, white = near) as D (0 = near)."""
    a = np.asarray(frame, np.float32) / 255.0
    if a.ndim == 3:
        a = a[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32) if a.shape[2] >= 3 else a[..., 0]
    return np.clip(1.0 - a, 0.0, 1.0).astype(np.float32)


def open_depth_frames(source: str | os.PathLike, fps: float | None = None) -> DepthFrames:
    """The depth frames ``source`` names (see :func:`is_depth_sequence`). Images and ``.npy`` files
    are read as :func:`illusio.sis.depth.read_depth` reads one depth map (white = near; an array in
    [0, 1], 0 = near, else rescaled); a video's frames by their luminance (white = near). ``fps``:
    the video's own rate unless given, else DEFAULT_FPS."""
    from .depth import read_depth

    source = str(source)
    p = Path(source)
    if p.suffix.lower() in VIDEO_SUFFIXES and not p.is_dir():
        if not p.is_file():
            raise InputError(f"{source}: no such video")
        count, size, own_fps, read = _video_depths(p)
        return DepthFrames(source, count, size, float(fps or own_fps), read)
    files = _frame_files(source)
    first = read_depth(files[0])

    def read():
        yield first
        for f in files[1:]:
            yield read_depth(f)

    return DepthFrames(source, len(files), (first.shape[1], first.shape[0]), float(fps or DEFAULT_FPS), read)


def turntable_depths(ctx, mesh, size: tuple[int, int], frames: int, elevation: float = 10.0) -> Iterator[np.ndarray]:
    """D of ``mesh`` seen as a stereogram's hidden scene (:func:`illusio.sis.depth.hidden_scene`)
    from a camera going once round it in ``frames`` steps (azimuth 360°·k/frames)."""
    from .depth import depth_from_scene, hidden_scene

    for k in range(frames):
        yield depth_from_scene(ctx, hidden_scene(mesh, azimuth=360.0 * k / frames, elevation=elevation), size)


@njit(cache=True)
def _roots(sep_px, first_strip):
    """Each pixel's root: itself in the first strip, else its left partner's root (S[x] = S[x − s])."""
    h, w = sep_px.shape
    roots = np.empty((h, w), np.int32)
    for y in range(h):
        for x in range(w):
            roots[y, x] = x if x < first_strip else roots[y, x - sep_px[y, x]]
    return roots


def _held_colours(image, roots, sep_px, previous) -> np.ndarray:
    """``image`` (the fresh stereogram, (H, W, C) at the oversampled width) with each tree recoloured
    by the previous frame's tree most of its unchanged pixels belonged to (module docstring)."""
    prev_image, prev_roots, prev_sep = previous
    h, w = roots.shape
    ys, xs = np.nonzero(sep_px == prev_sep)
    if len(ys) == 0:
        return image
    tree = ys.astype(np.int64) * w + roots[ys, xs]
    vote = tree * w + prev_roots[ys, xs]
    keys, counts = np.unique(vote, return_counts=True)
    trees, before = keys // w, keys % w
    order = np.lexsort((-counts, trees))  # per tree, its most voted previous tree first
    trees, before = trees[order], before[order]
    first = np.r_[True, trees[1:] != trees[:-1]]
    chosen = np.full(h * w, -1, np.int64)
    chosen[trees[first]] = before[first]
    previous_tree = chosen.reshape(h, w)[np.arange(h)[:, None], roots]  # per pixel, via its root
    held = previous_tree >= 0
    out = image.copy()
    rows = np.broadcast_to(np.arange(h)[:, None], (h, w))
    out[held] = prev_image[rows[held], previous_tree[held]]
    return out


class StereogramSequence:
    """Stereogram frames of successive depth maps, computed by the reference's left-anchored
    algorithm (sequential, strip, chain and fast give one image) on the CPU. With ``hold`` each
    frame keeps the previous frame's colours where its chains allow (module docstring); without,
    every frame is made afresh with the same pattern (what a loop over :func:`stereogram` gives)."""

    def __init__(self, params: StereogramParams = StereogramParams(), hold: bool = True):
        if params.algorithm == "symmetric":
            raise InputError(
                "a stereogram video holds its pattern with a left-anchored algorithm (sequential, strip, fast):"
                " the symmetric algorithm links pixel pairs, not chains"
            )
        self.params, self.hold = params, bool(hold)
        self._previous = None
        self._pattern = None
        self._said: set[str] = set()

    def frame(self, depth: np.ndarray) -> np.ndarray:
        """The next frame: float32 (H, W, 3) (as :func:`illusio.sis.stereogram.stereogram` gives)."""
        from .depth import check_depth
        from .patterns import make_pattern
        from .stereogram import finish, quantise

        p = self.params
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            d = check_depth(depth)
        for w in said:  # a warning about the depth (a flat frame) is said once a video, not each frame
            if str(w.message) not in self._said:
                self._said.add(str(w.message))
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        h, w = d.shape
        p.check_width(w)
        n = p.oversample
        sep = reference.separation(d, p.strip_width, p.depth_factor, p.exact, p.screen, p.invert != p.cross_eyed, n)
        if self._pattern is None or self._pattern[0] != (h, w):
            far = int(round(p.far_separation))
            self._pattern = ((h, w), quantise(make_pattern(p.pattern, w, h, far, p.seed, p.dot_size, 0, n)))
        strip_width, first_strip = pixel_widths(p)
        image = reference.sequential(sep, self._pattern[1], strip_width, first_strip)
        if self.hold:
            sep_px = reference.rounded(sep)
            roots = _roots(sep_px, first_strip)
            if self._previous is not None and self._previous[0].shape == image.shape:
                image = _held_colours(image, roots, sep_px, self._previous)
            self._previous = (image, roots, sep_px)
        return finish(image, p)


def unchanged_change(frames: list[np.ndarray], depths: list[np.ndarray]) -> float:
    """The mean absolute frame-to-frame change of ``frames`` (H, W, C) over the pixels whose depth is
    the same in both frames (D equal), over every consecutive pair: 0 for a pattern held still."""
    total, count = 0.0, 0
    for k in range(1, len(frames)):
        same = depths[k] == depths[k - 1]
        if same.any():
            total += float(np.abs(frames[k] - frames[k - 1])[same].sum())
            count += int(same.sum()) * frames[k].shape[2]
    return total / count if count else 0.0
