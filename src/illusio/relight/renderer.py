"""``RelightRenderer``: the Renderer protocol over a relighting session. The subject is a RealScene;
the session is prepared on the first frame for the params' method, ρ̂ and hierarchy and kept —
a frame whose params change only the lamp scales is an edit (``session.image``). The image is seen
from the photograph's camera only (the model is known from there): a frame's view must be None or
that camera (else InputError); it is resampled (bilinear) to the frame's size when that differs
from the photograph's. Maps: none."""

from __future__ import annotations

import dataclasses

import moderngl
import numpy as np

from ..core.renderer import Frame, Renderer
from .params import RelightParams
from .photograph import RealScene
from .session import RelightSession

__all__ = ["RelightRenderer"]


class RelightRenderer(Renderer):
    Params = RelightParams
    channels = 3
    subject_name = "a RealScene"

    def __init__(self, ctx):
        super().__init__(ctx)
        self.real: RealScene | None = None
        self._session: RelightSession | None = None
        self._key = None

    def _load(self, subject) -> None:
        from ..core.errors import InputError

        if not isinstance(subject, RealScene):
            raise InputError(f"RelightRenderer takes a RealScene, got {type(subject).__name__}")
        self.real = subject

    def _unload(self) -> None:
        super()._unload()
        if self._session is not None:
            self._session.release()
        self._session, self._key = None, None

    def result(self) -> RelightSession | None:
        """The session the last frame was drawn by (its solution, textures, lamps, times), or None."""
        return self._session

    def session_for(self, params: RelightParams | None = None) -> RelightSession:
        """The session prepared for ``params`` (made again when anything but the lamp scales and the
        exposure changed: virtual lamps and objects added to the old one are gone)."""
        params = self._params(params)
        self._require_subject()
        key = dataclasses.replace(params, lamp_scales=(), exposure=1.0)
        if self._session is None or self._key != key:
            if self._session is not None:
                self._session.release()
            self._session = RelightSession(self.real, key, self.ctx)
            self._key = key
        return self._session

    def render_texture(self, frame: Frame, params: RelightParams | None = None) -> moderngl.Texture:
        from ..core.errors import InputError

        params = self._params(params)
        self.session_for(params)
        if frame.view is not None and frame.view != self.real.view:
            raise InputError(
                "relighting shows the photograph's own camera only: give the frame no view (or that camera)"
            )
        image = self._session.image(dict(params.lamp_scales)) * params.exposure
        rgba = np.dstack([np.clip(image, 0, None), np.ones(image.shape[:2], np.float32)]).astype(np.float32)
        h, w = rgba.shape[:2]
        if frame.size != (w, h):
            rgba = resample_bilinear(rgba, frame.size)
        return self.ctx.acquire_upload(rgba, filter="linear")


def resample_bilinear(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """``image`` (H, W, C) resampled to ``size`` (w, h) by bilinear interpolation at the pixel
    centres (edges clamped): the new pixel (x + ½)·W/w − ½ of the old grid."""
    h0, w0 = image.shape[:2]
    w, h = size
    x = np.clip((np.arange(w) + 0.5) * w0 / w - 0.5, 0, w0 - 1)
    y = np.clip((np.arange(h) + 0.5) * h0 / h - 0.5, 0, h0 - 1)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, w0 - 1), np.minimum(y0 + 1, h0 - 1)
    fx, fy = (x - x0)[None, :, None], (y - y0)[:, None, None]
    top = image[y0][:, x0] * (1 - fx) + image[y0][:, x1] * fx
    bottom = image[y1][:, x0] * (1 - fx) + image[y1][:, x1] * fx
    return (top * (1 - fy) + bottom * fy).astype(np.float32)
