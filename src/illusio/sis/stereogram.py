"""Single-image stereograms from a depth map: the Renderer a window keeps, and a one-shot function."""

from __future__ import annotations

import moderngl
import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.renderer import Frame, Renderer
from . import reference
from .depth import check_depth
from .fast import ChainPass, FastPass
from .inputs import StereogramInputs, pixel_widths
from .params import StereogramParams
from .patterns import make_pattern
from .separation import SeparationPass
from .sequential import SequentialPass
from .snow import SnowPass
from .strip import StripPass
from .symmetric import SymmetricPass

__all__ = ["StereogramRenderer", "stereogram", "stereogram_cpu", "draw_guides", "quantise"]


def quantise(pattern: np.ndarray) -> np.ndarray:
    """The pattern as the GPU holds it (8 bits per channel), as float32 in [0, 1]."""
    return (np.round(np.clip(pattern, 0, 1) * 255) / 255).astype(np.float32)


def draw_guides(image: np.ndarray, spacing: float) -> np.ndarray:
    """Two guide dots ``spacing`` pixels apart (the far separation), centred near the top: when the
    eyes converge behind the screen correctly, the two dots in the middle of the four seen fuse."""
    img = np.array(image, np.float32, copy=True)
    h, w = img.shape[:2]
    r = max(2.0, min(h, w) / 90)
    cy = max(2 * r, 0.05 * h)
    ys, xs = np.mgrid[0:h, 0:w]
    for cx in (w / 2 - spacing / 2, w / 2 + spacing / 2):
        dist = np.hypot(xs + 0.5 - cx, ys + 0.5 - cy)
        img[dist <= r * 1.5] = 1.0
        img[dist <= r] = 0.0
    return img


class StereogramRenderer(Renderer):
    """The stereogram of a depth map, frame after frame (the Renderer protocol).

    Subject: D, float32 (H, W) in [0, 1], 0 = near. Params: :class:`StereogramParams`. A frame whose
    size differs from the depth map's gets the depth map resampled (bilinear) to it; ``frame.index``
    drives the snow pattern. ``render_texture`` returns the RGBA8 stereogram at ``oversample`` times
    the width; ``render`` averages that back and draws the guide dots. ``maps()``: "depth" (the
    uploaded D) and, for every algorithm but "fast", "separation" (pixels, R32F).

    :meth:`compute` and :meth:`stereogram_texture` are the GPU-in, GPU-out steps the multi-scene
    renderer composes."""

    Params = StereogramParams
    subject_name = "a depth map"

    def __init__(self, ctx: Context):
        super().__init__(ctx)
        self.separation_pass = SeparationPass(ctx)
        self._algorithms: dict[str, object] = {}
        self._snow: SnowPass | None = None
        self._pattern_key = None
        self._pattern_texture: moderngl.Texture | None = None
        self._depth: np.ndarray | None = None
        self._depth_texture: moderngl.Texture | None = None

    # -- the protocol -------------------------------------------------------------------------
    def _load(self, depth) -> None:
        self._depth = check_depth(depth)

    def _unload(self) -> None:
        super()._unload()
        self._drop_depth_texture()
        self._depth = None

    def _drop_depth_texture(self) -> None:
        if self._depth_texture is not None:
            self._forget_map(self._depth_texture)
            self.ctx.release(self._depth_texture)
            self._depth_texture = None

    @property
    def depth_size(self) -> tuple[int, int]:
        """(width, height) of the prepared depth map."""
        self._require_subject()
        return self._depth.shape[1], self._depth.shape[0]

    def depth_texture(self, size: tuple[int, int]) -> moderngl.Texture:
        """D on the GPU at ``size`` (uploaded once per subject and size; pooled)."""
        self._require_subject()
        if self._depth_texture is None or self._depth_texture.size != tuple(size):
            self._drop_depth_texture()
            d = self._depth
            if (d.shape[1], d.shape[0]) != tuple(size):
                d = resize_depth(d, size)
            self._depth_texture = self.ctx.acquire_upload(d)
        return self._depth_texture

    def render_texture(self, frame: Frame, params: StereogramParams | None = None) -> moderngl.Texture:
        """The stereogram, RGBA8 texture at ``oversample`` times the frame's width (pooled)."""
        params = self._params(params)
        depth = self.depth_texture(frame.size)
        params.check_width(frame.size[0])
        maps: dict[str, moderngl.Texture] = {"depth": depth}
        out = self.stereogram_texture(depth, params, frame.index, maps=maps)
        self._keep_maps(maps)
        return out

    def render(self, frame: Frame, params: StereogramParams | None = None) -> np.ndarray:
        """The stereogram, float32 (H, W, 3) in [0, 1], row 0 at the top (guide dots drawn)."""
        params = self._params(params)
        return finish(super().render(frame, params), params)

    def _unload_pattern(self) -> None:
        if self._pattern_texture is not None:
            self._pattern_texture.release()
            self._pattern_texture = None
            self._pattern_key = None

    def release(self) -> None:
        super().release()
        self._unload_pattern()

    # -- steps ---------------------------------------------------------------------------------
    def algorithm_pass(self, name: str):
        if name not in self._algorithms:
            cls = {
                "sequential": SequentialPass,
                "strip": StripPass,
                "fast": FastPass,
                "chain": ChainPass,
                "symmetric": SymmetricPass,
            }[name]
            self._algorithms[name] = cls(self.ctx)
        return self._algorithms[name]

    def pattern_texture(
        self, params: StereogramParams, size: tuple[int, int], frame: int = 0
    ) -> tuple[moderngl.Texture, bool]:
        """The pattern for a stereogram of ``size`` (logical pixels) and whether the caller must release
        it (GPU snow is made per frame; the others are uploaded once and kept while their parameters
        are the same)."""
        w, h = size
        n = params.oversample
        if params.pattern == "snow":
            if self._snow is None:
                self._snow = SnowPass(self.ctx)
            return self._snow((w * n, h), params.seed, frame, params.dot_size, n), True
        key = (params.pattern, w, h, params.seed, params.dot_size, n, params.far_separation)
        if key != self._pattern_key:
            self._unload_pattern()
            array = make_pattern(
                params.pattern, w, h, int(round(params.far_separation)), params.seed, params.dot_size, 0, n
            )
            self._pattern_texture = self.ctx.upload((quantise(array) * 255).round().astype(np.uint8), filter="nearest")
            self._pattern_key = key
        return self._pattern_texture, False

    def compute(
        self,
        separation: moderngl.Texture,
        pattern: moderngl.Texture,
        params: StereogramParams,
        row_starts: moderngl.Texture | None = None,
        max_row_start: int = 0,
        min_row_start: int = 0,
        algorithm: str | None = None,
    ) -> moderngl.Texture:
        """Separation map + pattern → the stereogram, RGBA8 texture (pooled: release it). ``algorithm``
        overrides ``params.algorithm``: any but "fast", which starts from depth (see
        stereogram_texture), plus "chain"."""
        algorithm = algorithm or params.algorithm
        strip_width, first_strip = pixel_widths(params)
        inputs = StereogramInputs(separation, pattern, strip_width, first_strip, row_starts)
        if algorithm == "fast":
            raise InputError("the fast pass starts from depth: use stereogram_texture")
        p = self.algorithm_pass(algorithm)
        if algorithm == "symmetric":
            n = params.oversample
            return p(inputs, params.strip_width * n, params.eye_separation_px * n)
        if algorithm == "strip":
            return p(inputs, max_row_start, min_row_start)
        return p(inputs)

    def stereogram_texture(
        self,
        depth: moderngl.Texture,
        params: StereogramParams,
        frame: int = 0,
        row_starts: moderngl.Texture | None = None,
        max_row_start: int = 0,
        min_row_start: int = 0,
        pattern: moderngl.Texture | None = None,
        end_column: int | None = None,
        maps: dict | None = None,
    ) -> moderngl.Texture:
        """D (R32F texture) → stereogram texture at ``oversample`` times the width (pooled).
        ``max_row_start``, ``min_row_start``: range of ``row_starts`` (strip algorithm only).
        ``end_column``: output columns from there on are not needed (fast algorithm only).
        ``pattern``: a texture to use instead of ``params.pattern`` (the multi-scene pipeline's
        screen-space pattern). ``maps``: receives the separation map (then the caller owns it)."""
        if pattern is not None:
            owned = False
        else:
            pattern, owned = self.pattern_texture(params, depth.size, frame)
        if params.algorithm == "fast":  # fused: no separation map
            out = self.algorithm_pass("fast")(depth, pattern, params, row_starts, end_column)
        else:
            sep = self.separation_pass(depth, params)
            out = self.compute(sep, pattern, params, row_starts, max_row_start, min_row_start)
            if maps is not None:
                maps["separation"] = sep
            else:
                self.ctx.release(sep)
        if owned:
            self.ctx.release(pattern)
        return out


def resize_depth(depth: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """D resampled to ``size`` (width, height), bilinear."""
    from PIL import Image

    return np.asarray(
        Image.fromarray(np.asarray(depth, np.float32)).resize(tuple(size), Image.Resampling.BILINEAR), np.float32
    )


def finish(image: np.ndarray, params: StereogramParams) -> np.ndarray:
    """Average the oversampled width back and draw the guide dots."""
    image = reference.downsample(image, params.oversample)
    return draw_guides(image, params.far_separation) if params.guides else image


def stereogram_cpu(depth: np.ndarray, params: StereogramParams = StereogramParams(), frame: int = 0) -> np.ndarray:
    """The same image as :func:`stereogram`, computed by the NumPy/numba reference."""
    d = check_depth(depth)
    h, w = d.shape
    params.check_width(w)
    n = params.oversample
    sep = reference.separation(
        d, params.strip_width, params.depth_factor, params.exact, params.screen, params.invert != params.cross_eyed, n
    )
    pattern = quantise(
        make_pattern(params.pattern, w, h, int(round(params.far_separation)), params.seed, params.dot_size, frame, n)
    )
    strip_width, first_strip = pixel_widths(params)
    if params.algorithm == "symmetric":
        image = reference.symmetric(sep, pattern, params.strip_width * n, params.eye_separation_px * n)
    else:
        run = reference.sequential if params.algorithm == "fast" else getattr(reference, params.algorithm)
        image = run(sep, pattern, strip_width, first_strip)
    return finish(image, params)


def stereogram(
    depth: np.ndarray,
    params: StereogramParams = StereogramParams(),
    ctx: Context | None = None,
    cpu: bool = False,
    frame: int = 0,
) -> np.ndarray:
    """One stereogram from D (float32 (H, W) in [0, 1], 0 = near): float32 (H, W, 3), row 0 on top.
    ``cpu``: use the reference instead of the GPU (same image). Without ``ctx``, the process's default
    headless context is used; either way the context keeps one renderer for these calls, so a
    script calling this in a loop pays for the GL set-up and the pattern once."""
    if cpu:
        return stereogram_cpu(depth, params, frame)
    renderer = (ctx or default_context()).kept(StereogramRenderer)
    renderer.prepare(depth)  # checks D once, when it is new
    return renderer.render(Frame(None, renderer.depth_size, index=frame), params)
