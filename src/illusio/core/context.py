"""Context: one moderngl context with its program cache, texture pool and full-screen triangle.

It is passed explicitly to every pass and renderer, never kept in a module global. ``Context()``
creates a headless EGL context (OpenGL 4.3 core or newer); ``Context.wrap(gl)`` adopts the context
of a window (the viewer). ``ILLUSIO_GL_BACKEND`` overrides the backend (e.g. ``x11``).
"""

from __future__ import annotations

import os
from typing import Any

import moderngl
import numpy as np

from .errors import APT_HINT, GLUnavailable
from .fullscreen import FullscreenTriangle
from .gl import set_uniform
from .programs import ProgramCache
from .textures import TexturePool, TextureSpec, readback, upload, write_texture

__all__ = ["Context", "REQUIRED_GL", "current_context", "default_context", "live_contexts", "release_current"]

REQUIRED_GL = 430
_CURRENT: list[Context | None] = [None]  # the Context whose GL context was made current last (one GL thread)


class Context:
    """The GPU side of illusio.

    Attributes: ``gl`` (moderngl.Context), ``programs`` (ProgramCache), ``textures`` (TexturePool),
    ``fullscreen`` (FullscreenTriangle).
    """

    def __init__(
        self, gl: moderngl.Context | None = None, *, backend: str | None = None, activate=None, deactivate=None
    ):
        # how to make this context current and to leave it: moderngl's enter/exit for a headless
        # context; the window toolkit's calls for a window's (see wrap)
        self._activate = activate or (lambda: self.gl.__enter__())
        self._deactivate = deactivate or (lambda: self.gl.__exit__(None, None, None))
        if gl is None:
            release_current()
            gl = _create_headless(backend)
        if gl.version_code < REQUIRED_GL:
            raise GLUnavailable(
                f"OpenGL {gl.version_code // 100}.{gl.version_code // 10 % 10} found "
                f"({gl.info.get('GL_RENDERER', '?')}); illusio needs OpenGL 4.3 core. "
                f"Install Mesa ({APT_HINT}) or a newer GPU driver"
            )
        self.gl = gl
        self.programs = ProgramCache(gl)
        self.textures = TexturePool(gl)
        self.fullscreen = FullscreenTriangle(gl)
        self._framebuffers: dict[tuple, moderngl.Framebuffer] = {}
        self._default_framebuffer: moderngl.Framebuffer | None = None  # 0: where a released one leaves the binding
        self._kept: dict[type, Any] = {}
        _CURRENT[0] = self  # creating a context makes it current

    def make_current(self) -> None:
        """Make this context the current one if another Context was used since (a second
        Context in one process, e.g. a CLI call inside a script, would otherwise receive this one's
        GL calls). Called by every entry point below; passes call it before direct ``gl`` work."""
        if _CURRENT[0] is not self:
            release_current()
            self._activate()
            _CURRENT[0] = self

    @classmethod
    def wrap(cls, gl: moderngl.Context, activate=None, deactivate=None) -> Context:
        """Adopt an existing context (a window's); ``activate`` and ``deactivate`` make it current
        and leave it through the window toolkit (e.g. glfw.make_context_current)."""
        return cls(gl, activate=activate, deactivate=deactivate)

    def kept(self, renderer_class):
        """One renderer of ``renderer_class`` kept on this context for the one-shot functions
        (``stereogram(depth)``): compiled passes and patterns are paid for once per process."""
        renderer = self._kept.get(renderer_class)
        if renderer is None:
            renderer = self._kept[renderer_class] = renderer_class(self)
        return renderer

    # -- small conveniences every pass uses -------------------------------------------------
    def program(self, path: str, varyings: tuple[str, ...] = (), **defines: Any):
        self.make_current()
        return self.programs.get(path, varyings, **defines)

    def acquire(self, size: tuple[int, int], components: int = 4, dtype: str = "f4", **kw) -> moderngl.Texture:
        self.make_current()
        return self.textures.acquire(TextureSpec((int(size[0]), int(size[1])), components, dtype, **kw))

    def release(self, *textures: moderngl.Texture) -> None:
        self.textures.release(*textures)

    def upload(self, array: np.ndarray, **kw) -> moderngl.Texture:
        self.make_current()
        return upload(self.gl, array, **kw)

    def readback(self, texture: moderngl.Texture, components: int | None = None) -> np.ndarray:
        self.make_current()
        return readback(texture, components)

    def upload_into(self, texture: moderngl.Texture, array: np.ndarray) -> moderngl.Texture:
        """Write an (H, W[, C]) array with row 0 at the top into ``texture`` (same size, channels and
        dtype class), e.g. one acquired from the pool, instead of creating a texture per upload."""
        self.make_current()
        return write_texture(texture, array)

    def acquire_upload(self, array: np.ndarray, filter: str = "nearest") -> moderngl.Texture:
        """A pooled texture holding ``array`` (float32, or uint8 as normalised values); release it."""
        a = np.asarray(array)
        c = 1 if a.ndim == 2 else a.shape[2]
        dtype = "f1" if a.dtype == np.uint8 else "f4"
        tex = self.acquire((a.shape[1], a.shape[0]), c, dtype, filter=filter)
        return self.upload_into(tex, a)

    def readback_image(self, texture: moderngl.Texture, components: int = 3, clip: bool = True) -> np.ndarray:
        """The first ``components`` channels of a colour texture as float32 (H, W, C), row 0 at the
        top, clipped to [0, 1] unless ``clip`` is False: GL drops the extra channels, and the flip,
        the conversion and the clip are one NumPy pass (the array path of every Renderer)."""
        fbo = self.framebuffer([texture])
        w, h = texture.size
        out = np.empty((h, w, components), np.float32)
        if texture.dtype == "f1":
            raw = np.frombuffer(fbo.read(components=components, dtype="f1", alignment=1), np.uint8)
            np.divide(raw.reshape(h, w, components)[::-1], np.float32(255), out=out)
            return out
        raw = np.frombuffer(fbo.read(components=components, dtype="f4", alignment=1), np.float32)
        flipped = raw.reshape(h, w, components)[::-1]
        if clip:
            np.clip(flipped, 0.0, 1.0, out=out)
        else:
            out[...] = flipped
        return out

    def readback_u8(self, texture: moderngl.Texture, components: int = 1) -> np.ndarray:
        """The first ``components`` channels as uint8 (H, W, C), row 0 at the top, converted by GL
        (values clamped to [0, 1] × 255): a quarter of a float readback's bytes, for masks."""
        return self._read_channels(texture, components, "f1")

    def readback_red(self, texture: moderngl.Texture) -> np.ndarray:
        """The first channel of a colour texture as float32 (H, W), row 0 at the top, read through a
        framebuffer (one channel of a float texture: 1 ms at 1024², where reading all four is 6 and
        a conversion to bytes 6)."""
        return self._read_channels(texture, 1, "f4")[..., 0]

    def _read_channels(self, texture: moderngl.Texture, components: int, dtype: str) -> np.ndarray:
        """The first ``components`` channels through a framebuffer, converted by GL to ``dtype``
        ("f1" uint8, "f4" float32), (H, W, C) with row 0 at the top."""
        raw = self.framebuffer([texture]).read(components=components, dtype=dtype, alignment=1)
        w, h = texture.size
        return np.frombuffer(raw, np.uint8 if dtype == "f1" else np.float32).reshape(h, w, components)[::-1].copy()

    def framebuffer(
        self, colour: list[moderngl.Texture], depth: bool | moderngl.Texture = False
    ) -> moderngl.Framebuffer:
        """A framebuffer over ``colour`` textures (cached by their GL names), with an optional depth
        attachment (``True``: a depth renderbuffer of the same size, kept with the framebuffer)."""
        self.make_current()
        key = (tuple(t.glo for t in colour), depth.glo if isinstance(depth, moderngl.Texture) else bool(depth))
        fbo = self._framebuffers.get(key)
        stale = fbo is not None and (
            any(a is not t for a, t in zip(fbo.color_attachments, colour))
            or (isinstance(depth, moderngl.Texture) and fbo.depth_attachment is not depth)
        )
        if stale:
            self.release_framebuffer(fbo)  # a GL name was reused by a new texture: the cached one is stale
            fbo = None
        if fbo is None:
            size = colour[0].size if colour else depth.size
            depth_attachment = (
                depth if isinstance(depth, moderngl.Texture) else (self.gl.depth_renderbuffer(size) if depth else None)
            )
            fbo = self.gl.framebuffer(color_attachments=colour, depth_attachment=depth_attachment)
            self._framebuffers[key] = fbo
        return fbo

    def release_framebuffer(self, fbo: moderngl.Framebuffer) -> None:
        """Release ``fbo``, first binding framebuffer 0 if it is the bound one: moderngl keeps the
        bound framebuffer and binds it back after making the next one, and binding a deleted name
        raises GL_INVALID_OPERATION (seen: every dof planes frame raised it until this)."""
        self.make_current()
        if self.gl.fbo is fbo:
            if self._default_framebuffer is None:
                self._default_framebuffer = self.gl.detect_framebuffer(0)
            self._default_framebuffer.use()
        fbo.release()

    def draw_fullscreen(
        self,
        program: moderngl.Program,
        size: tuple[int, int],
        components: int = 4,
        dtype: str = "f4",
        textures: dict[str, moderngl.Texture] | None = None,
        **uniforms: Any,
    ) -> moderngl.Texture:
        """One full-screen pass into a new pooled texture of ``size`` (release it): ``textures``
        bound to units 0, 1, ... under their sampler names, ``uniforms`` set, no depth test."""
        out = self.acquire(size, components, dtype)
        fbo = self.framebuffer([out])
        fbo.use()
        fbo.viewport = (0, 0, *size)
        for unit, (name, texture) in enumerate((textures or {}).items()):
            texture.use(unit)
            set_uniform(program, name, unit)
        for name, value in uniforms.items():
            set_uniform(program, name, value)
        self.gl.disable(moderngl.DEPTH_TEST)
        self.fullscreen.draw(program)
        return out

    def info(self) -> dict[str, str]:
        """Renderer, vendor and version strings of the driver."""
        i = self.gl.info
        return {
            "renderer": i.get("GL_RENDERER", "?"),
            "vendor": i.get("GL_VENDOR", "?"),
            "version": i.get("GL_VERSION", "?"),
            "version_code": str(self.gl.version_code),
            "max_texture_size": str(i.get("GL_MAX_TEXTURE_SIZE", "?")),
        }

    def gl_error(self) -> str | None:
        """The GL error flag raised since it was last read (``"GL_INVALID_OPERATION"``, ...), or None
        when clean; reading clears it. Tests read it after each test (tests/conftest.py)."""
        self.make_current()
        error = self.gl.error
        return None if error == "GL_NO_ERROR" else error

    def finish(self) -> None:
        """Block until the GPU has done all queued work (for timing)."""
        self.make_current()
        self.gl.finish()

    def release_all(self) -> None:
        self.make_current()
        for renderer in self._kept.values():
            renderer.release()
        self._kept.clear()
        for fbo in self._framebuffers.values():
            self.release_framebuffer(fbo)
        self._framebuffers.clear()
        self.textures.clear()
        self.gl.release()
        self.gl = None
        _CURRENT[0] = None
        if _DEFAULT[0] is self:
            _DEFAULT[0] = None


_DEFAULT: list[Context | None] = [None]


def current_context() -> Context | None:
    """The Context made current last (None when none is, or it was released)."""
    ctx = _CURRENT[0]
    return ctx if ctx is not None and ctx.gl is not None else None


def live_contexts() -> list[Context]:
    """The contexts of this process that are still open: the current one and the default one."""
    seen = []
    for ctx in (_CURRENT[0], _DEFAULT[0]):
        if ctx is not None and ctx.gl is not None and ctx not in seen:
            seen.append(ctx)
    return seen


def release_current() -> None:
    """Leave no illusio Context current on this thread. A headless EGL context and a window's GLX
    context cannot both be current (X answers BadAccess to glXMakeCurrent): the viewer's window calls
    this before it makes its own, and every switch between Contexts goes through it."""
    ctx = _CURRENT[0]
    # a context its owner released (moderngl leaves an InvalidObject behind) has nothing to leave
    if ctx is not None and ctx.gl is not None and type(getattr(ctx.gl, "mglo", None)).__name__ != "InvalidObject":
        ctx._deactivate()
    _CURRENT[0] = None


def default_context() -> Context:
    """The process's headless context for one-shot functions (``stereogram(depth)``), made on first
    use and kept: a new GL context per call costs more than the work. Renderers, passes, the CLI and
    the viewer take a Context explicitly; this is only the one-shot functions' default."""
    if _DEFAULT[0] is None or _DEFAULT[0].gl is None:
        _DEFAULT[0] = Context()
    return _DEFAULT[0]


def _create_headless(backend: str | None) -> moderngl.Context:
    backend = backend or os.environ.get("ILLUSIO_GL_BACKEND", "egl")
    kwargs = {"standalone": True, "require": REQUIRED_GL}
    if backend and backend != "default":
        kwargs["backend"] = backend
    if backend == "egl" and os.environ.get("ILLUSIO_EGL_DEVICE"):
        kwargs["device_index"] = int(os.environ["ILLUSIO_EGL_DEVICE"])  # a batch worker's GPU
    try:
        return moderngl.create_context(**kwargs)
    except Exception as exc:  # glcontext raises plain Exception/OSError on missing libraries
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise GLUnavailable(
            f"cannot create a headless OpenGL 4.3 context through {backend} ({reason}); on Debian/Ubuntu: {APT_HINT}"
        ) from None
