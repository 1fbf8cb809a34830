import numpy as np

from illusio.core.renderer import Frame, Renderer

from .params import ToyParams


def toy_subject(source: str, size, ctx) -> float:
    return float(source)


def reference(size, offset: float, brightness: float) -> np.ndarray:
    """The plain statement: a left-to-right gradient from ``offset``, times ``brightness``."""
    w, h = size
    ramp = np.clip(offset + np.linspace(0.0, 1.0 - offset, w, dtype=np.float32), 0, 1) * brightness
    return np.repeat(np.broadcast_to(ramp, (h, w))[..., None], 3, axis=2).astype(np.float32)


class ToyRenderer(Renderer):
    Params = ToyParams
    channels = 3
    subject_name = "a number in [0, 1]"

    def _load(self, subject) -> None:
        self.offset = float(subject)

    def render_texture(self, frame: Frame, params=None):
        self._require_subject()
        params = self._params(params)
        tex = self.ctx.acquire_upload(reference(frame.size, self.offset, params.brightness))
        self._keep_maps({})
        return tex


class ToyMode:
    name = "toy"
