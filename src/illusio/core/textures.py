"""Textures: a pool of reusable render targets, and upload/readback with the one row flip.

OpenGL stores row 0 at the bottom; arrays have row 0 at the top. :func:`upload` and
:func:`readback` are the only places that flip, so every other piece of code can think in
one convention per side: shaders in GL's (uv (0, 0) at the bottom left), Python in arrays'.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from .errors import InputError

__all__ = ["TextureSpec", "TexturePool", "upload", "write_texture", "readback", "GL_DTYPES"]

# numpy dtype -> moderngl dtype string
GL_DTYPES = {
    np.dtype(np.float32): "f4",
    np.dtype(np.float16): "f2",
    np.dtype(np.uint8): "f1",
    np.dtype(np.int32): "i4",
    np.dtype(np.uint32): "u4",
}
_NP_DTYPES = {"f4": np.float32, "f2": np.float16, "f1": np.uint8, "i4": np.int32, "u4": np.uint32}


@dataclass(frozen=True)
class TextureSpec:
    """What a pooled texture is: size (width, height) in pixels, channels 1-4, moderngl dtype."""

    size: tuple[int, int]
    components: int = 4
    dtype: str = "f4"
    filter: str = "nearest"  # or "linear"
    mipmaps: bool = False


class TexturePool:
    """Hands out textures by :class:`TextureSpec` and takes them back for reuse.

    A pass acquires its outputs here; whoever consumes them releases them when done. Nothing is
    freed until :meth:`clear`, so a renderer called every frame allocates nothing after the first.
    """

    def __init__(self, gl: moderngl.Context):
        self.gl = gl
        self._free: dict[TextureSpec, list[moderngl.Texture]] = {}
        self._spec_of: dict[int, TextureSpec] = {}
        self._in_use: set[int] = set()

    def acquire(self, spec: TextureSpec) -> moderngl.Texture:
        free = self._free.get(spec)
        if free:
            tex = free.pop()
        else:
            w, h = spec.size
            if w <= 0 or h <= 0:
                raise InputError(f"texture size must be positive, got {w}×{h}")
            tex = self.gl.texture((w, h), spec.components, dtype=spec.dtype)
            if spec.mipmaps:
                tex.build_mipmaps()
            f = moderngl.LINEAR if spec.filter == "linear" else moderngl.NEAREST
            fmin = moderngl.LINEAR_MIPMAP_LINEAR if spec.mipmaps else f
            tex.filter = (fmin, f)
            tex.repeat_x = tex.repeat_y = False
            self._spec_of[tex.glo] = spec
        self._in_use.add(tex.glo)
        return tex

    def release(self, *textures: moderngl.Texture) -> None:
        for tex in textures:
            if tex is None or tex.glo not in self._in_use:
                continue
            self._in_use.discard(tex.glo)
            self._free.setdefault(self._spec_of[tex.glo], []).append(tex)

    @property
    def in_use(self) -> int:
        return len(self._in_use)

    def clear(self) -> None:
        """Free every pooled texture not in use."""
        for textures in self._free.values():
            for tex in textures:
                self._spec_of.pop(tex.glo, None)
                tex.release()
        self._free.clear()


def upload(
    gl: moderngl.Context, array: np.ndarray, *, filter: str = "linear", mipmaps: bool = False, repeat: bool = False
) -> moderngl.Texture:
    """Make a texture from an (H, W) or (H, W, C) array with row 0 at the top.

    float32/float16 arrays keep their values; uint8 becomes normalised [0, 1]; int32/uint32 stay
    integers. The array is flipped so that uv (0, 0) samples the bottom-left pixel of the image.
    """
    a = np.asarray(array)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or not 1 <= a.shape[2] <= 4 or a.shape[0] == 0 or a.shape[1] == 0:
        raise InputError(f"cannot upload an array of shape {np.shape(array)} as a texture")
    if a.dtype == np.float64:
        a = a.astype(np.float32)
    if a.dtype not in GL_DTYPES:
        raise InputError(f"cannot upload dtype {a.dtype} as a texture")
    h, w, c = a.shape
    data = np.ascontiguousarray(a[::-1])
    tex = gl.texture((w, h), c, data.tobytes(), dtype=GL_DTYPES[a.dtype], alignment=1)
    if mipmaps:
        tex.build_mipmaps()
    f = moderngl.LINEAR if filter == "linear" and a.dtype.kind == "f" else moderngl.NEAREST
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR if mipmaps else f, f)
    tex.repeat_x = tex.repeat_y = repeat
    return tex


def write_texture(texture: moderngl.Texture, array: np.ndarray) -> moderngl.Texture:
    """Write an (H, W) or (H, W, C) array, row 0 at the top, into an existing texture of the same
    size and channels (float arrays into float textures, uint8 into 'f1'). Returns the texture."""
    a = np.asarray(array)
    if a.ndim == 2:
        a = a[:, :, None]
    w, h = texture.size
    if a.shape != (h, w, texture.components):
        raise InputError(
            f"cannot write an array of shape {np.shape(array)} into a {w}×{h}×{texture.components} texture"
        )
    want = _NP_DTYPES[texture.dtype]
    if a.dtype != want:
        if texture.dtype == "f1" or a.dtype.kind not in "fiu":
            raise InputError(f"cannot write dtype {a.dtype} into a {texture.dtype} texture")
        a = a.astype(want)
    texture.write(np.ascontiguousarray(a[::-1]), alignment=1)
    return texture


def readback(texture: moderngl.Texture, components: int | None = None, level: int = 0) -> np.ndarray:
    """Read a texture (or mip ``level``) as an (H, W, C) array with row 0 at the top.

    float textures read as float32 (f2 too), 'f1' as float32 in [0, 1], integer ones as int32/uint32.
    """
    c = components or texture.components
    w, h = max(1, texture.width >> level), max(1, texture.height >> level)
    raw = texture.read(level=level, alignment=1)
    arr = np.frombuffer(raw, dtype=_NP_DTYPES[texture.dtype]).reshape(h, w, texture.components)
    if texture.dtype == "f1":
        arr = arr.astype(np.float32) / 255.0
    elif texture.dtype == "f2":
        arr = arr.astype(np.float32)
    return np.ascontiguousarray(arr[::-1, :, :c])
