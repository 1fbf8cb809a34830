"""The one protocol every technique's Renderer follows (docs/architecture.md, "A Renderer").

::

    renderer = SomeRenderer(ctx)
    renderer.prepare(subject)                     # the scene / mesh / depth map it draws
    tex = renderer.render_texture(frame, params)  # a pooled texture: the caller releases it
    img = renderer.render(frame, params)          # float32 (H, W, C) array, row 0 at the top
    renderer.maps()                               # {"depth": Texture, ...} of the last frame
    renderer.release()

``prepare`` compares the subject by value (:func:`fingerprint`) with the one it holds and rebuilds
only when it differs; ``render_texture`` compares params by value (they are frozen dataclasses) with
the last frame's. A renderer never keys a cache by object identity.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import moderngl
import numpy as np

from .errors import InputError
from .gl import check_size

if TYPE_CHECKING:  # core does not import scene at run time
    from ..scene.camera import View
    from .context import Context

__all__ = ["Frame", "Renderer", "fingerprint", "DEFAULT_SIZE"]

#: the size a Frame gets when none is given, for every renderer (width, height) in pixels
DEFAULT_SIZE = (1280, 720)


@dataclass(frozen=True)
class Frame:
    """What changes from one frame to the next.

    view: the camera (``scene.camera.View``); None lets the renderer use its subject's own default
    (a scene's main camera, a view framing a mesh; a depth map has no view). size: (width, height) in
    pixels. time: seconds since the start (animation). index: the frame number (per-frame noise).
    """

    view: View | None = None
    size: tuple[int, int] = DEFAULT_SIZE
    time: float = 0.0
    index: int = 0

    def __post_init__(self):
        object.__setattr__(self, "size", check_size(self.size))
        if not np.isfinite(self.time):
            raise InputError(f"frame time must be finite, got {self.time}")

    @property
    def aspect(self) -> float:
        return self.size[0] / self.size[1]


def fingerprint(obj: Any) -> bytes:
    """A digest of ``obj``'s value: arrays by their bytes, dataclasses and plain objects by their
    fields, containers by their items. Two subjects with equal fingerprints draw the same."""
    h = hashlib.sha1(usedforsecurity=False)  # a content key, not a secret; ~3× faster than blake2b here
    _feed(h, obj, 0)
    return h.digest()


def _feed(h, obj: Any, depth: int) -> None:
    if depth > 32:
        raise InputError("subject is nested too deeply to compare by value")
    if obj is None or isinstance(obj, (bool, int, float, complex, str, bytes)):
        h.update(repr((type(obj).__name__, obj)).encode())
    elif isinstance(obj, os.PathLike):  # a file named, by its name (what it holds is read elsewhere)
        h.update(repr(("path", os.fspath(obj))).encode())
    elif isinstance(obj, np.ndarray):
        a = np.ascontiguousarray(obj)
        h.update(repr(("ndarray", a.shape, a.dtype.str)).encode())
        h.update(a.data if a.size else b"")
    elif isinstance(obj, np.generic):
        h.update(repr(("np", obj.dtype.str, obj.item())).encode())
    elif isinstance(obj, (tuple, list)):
        h.update(f"{type(obj).__name__}[{len(obj)}]".encode())
        for item in obj:
            _feed(h, item, depth + 1)
    elif isinstance(obj, dict):
        h.update(f"dict[{len(obj)}]".encode())
        for key in sorted(obj, key=repr):
            _feed(h, key, depth + 1)
            _feed(h, obj[key], depth + 1)
    elif dataclasses.is_dataclass(obj):
        h.update(type(obj).__qualname__.encode())
        for f in dataclasses.fields(obj):
            _feed(h, getattr(obj, f.name), depth + 1)
    elif hasattr(obj, "__dict__"):
        h.update(type(obj).__qualname__.encode())
        for key in sorted(vars(obj)):
            if not key.startswith("_"):
                _feed(h, key, depth + 1)
                _feed(h, vars(obj)[key], depth + 1)
    else:
        raise InputError(f"cannot compare a {type(obj).__name__} by value")


class Renderer:
    """Base of every technique's renderer. A subclass sets ``Params`` (its frozen params class) and
    ``channels``, and implements :meth:`_load` (take a new subject) and :meth:`render_texture`.

    The textures in :meth:`maps` belong to the renderer: they stay valid until the next frame or
    :meth:`release`, and the caller must not release them.
    """

    Params: ClassVar[type]
    channels: ClassVar[int] = 3
    #: what prepare() takes, for error messages ("a scene", "a depth map"...)
    subject_name: ClassVar[str] = "a subject"

    def __init__(self, ctx: Context):
        self.ctx = ctx
        self._subject_key: bytes | None = None
        self._maps: dict[str, moderngl.Texture] = {}
        self._result: Any = None

    # -- the protocol -------------------------------------------------------------------------
    def prepare(self, subject: Any) -> bool:
        """Hold ``subject`` for the frames to come; returns True when it differed from the one held
        (and was loaded), False when it was the same by value (nothing is done)."""
        subject = self._subject(subject)
        key = fingerprint(subject)
        if key == self._subject_key:
            return False
        self._unload()
        self._subject_key = None  # a subject that fails to load leaves none held
        self._load(subject)
        self._subject_key = key
        return True

    def render_texture(self, frame: Frame, params=None) -> moderngl.Texture:
        """The frame as a pooled texture (linear colour; the caller releases it)."""
        raise NotImplementedError

    def render(self, frame: Frame, params=None) -> np.ndarray:
        """The frame as float32 (H, W, ``channels``), row 0 at the top, linear values in [0, 1]."""
        tex = self.render_texture(frame, params)
        try:
            return self.ctx.readback_image(tex, self.channels)
        finally:
            self.ctx.release(tex)

    def maps(self) -> dict[str, moderngl.Texture]:
        """The named intermediate images of the last frame (depth, separation, q1, CoC…)."""
        return dict(self._maps)

    def result(self) -> Any:
        """What the last frame made beside its image, as the technique's documented object (dof:
        ``DofResult``; radiosity: the ``Radiosity`` solution; relight: the ``RelightSession``; lines:
        the ``Drawing``), or None before a frame and for techniques with nothing more to say. Valid
        until the next frame or :meth:`prepare` of another subject."""
        return self._result

    def release(self) -> None:
        """Free the subject's GPU copy and every kept texture; the renderer stays usable after a
        new :meth:`prepare`."""
        self.release_subject()

    def release_subject(self) -> None:
        """Forget the subject (and the maps) but keep what does not depend on it (compiled
        passes, pattern textures): what a one-shot call does after its frame."""
        self._unload()
        self._subject_key = None

    # -- for subclasses ----------------------------------------------------------------------
    def _subject(self, subject: Any) -> Any:
        """``subject`` in the form this renderer holds (a subclass converts what users hand it, such
        as a trimesh mesh, before it is compared or loaded); the subject itself by default."""
        return subject

    def _load(self, subject: Any) -> None:
        raise NotImplementedError

    def _unload(self) -> None:
        """Drop what :meth:`_load` made (subclasses extend this and call it)."""
        self._keep_maps({})

    def _keep_maps(self, maps: dict[str, moderngl.Texture]) -> None:
        """Replace the kept maps (the previous frame's go back to the pool)."""
        old = [t for name, t in self._maps.items() if t is not None and all(t is not n for n in maps.values())]
        self.ctx.release(*old)
        self._maps = {k: v for k, v in maps.items() if v is not None}

    def _forget_map(self, texture: moderngl.Texture | None) -> None:
        """Drop ``texture`` from the kept maps without releasing it: for a texture the renderer frees
        itself (a replaced subject upload), which must not be released again at the next frame."""
        self._maps = {k: v for k, v in self._maps.items() if v is not texture}

    def _require_subject(self) -> None:
        if self._subject_key is None:
            raise InputError(f"{type(self).__name__}: call prepare() with {self.subject_name} first")

    def _params(self, params):
        """``params`` or the Params defaults, checked to be of the right class."""
        if params is None:
            return self.Params()
        if not isinstance(params, self.Params):
            raise InputError(f"{type(self).__name__} takes {self.Params.__name__}, got {type(params).__name__}")
        return params
