"""``RelightRenderer``: the Renderer protocol over a relighting session. The subject is a RealScene;
the session is prepared on the first frame for the params' method, ρ̂ and hierarchy and kept —
a frame whose params change only the lamp scales is an edit (``session.image``). The image is the
photograph's own size and camera (the model is seen from there only); the frame's view is ignored.
Maps: none."""

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
        self.session: RelightSession | None = None
        self._key = None

    def _load(self, subject) -> None:
        from ..core.errors import InputError

        if not isinstance(subject, RealScene):
            raise InputError(f"RelightRenderer takes a RealScene, got {type(subject).__name__}")
        self.real = subject

    def _unload(self) -> None:
        super()._unload()
        if self.session is not None:
            self.session.release()
        self.session, self._key = None, None

    def session_for(self, params: RelightParams | None = None) -> RelightSession:
        """The session prepared for ``params`` (made again when anything but the lamp scales and the
        exposure changed: virtual lamps and objects added to the old one are gone)."""
        params = self._params(params)
        self._require_subject()
        key = dataclasses.replace(params, lamp_scales=(), exposure=1.0)
        if self.session is None or self._key != key:
            if self.session is not None:
                self.session.release()
            self.session = RelightSession(self.real, key, self.ctx)
            self._key = key
        return self.session

    def render_texture(self, frame: Frame, params: RelightParams | None = None) -> moderngl.Texture:
        params = self._params(params)
        self.session_for(params)
        image = self.session.image(dict(params.lamp_scales)) * params.exposure
        rgba = np.dstack([np.clip(image, 0, None), np.ones(image.shape[:2], np.float32)]).astype(np.float32)
        return self.ctx.acquire_upload(rgba, filter="linear")
