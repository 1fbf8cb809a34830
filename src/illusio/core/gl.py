"""Small GL helpers every pass uses: uniforms that may be optimised away, and the image-size check."""

from __future__ import annotations

import numpy as np

from .errors import InputError

__all__ = ["set_uniform", "check_size", "MAX_SIZE"]

#: the largest side of an image or render target, pixels (GL_MAX_TEXTURE_SIZE of the drivers we meet)
MAX_SIZE = 8192


def set_uniform(program, name: str, value) -> None:
    """Set a uniform if the program uses it (drivers drop unused ones). Matrices (4×4, 3×3 numpy
    arrays, row-major like the rest of illusio) are transposed to GL's column-major order; other
    arrays are written flat as they are."""
    u = program.get(name, None)
    if u is None:
        return
    if isinstance(value, np.ndarray):
        a = np.asarray(value, dtype=np.int32 if value.dtype.kind in "iu" else np.float32)
        if a.ndim == 2 and a.shape in ((4, 4), (3, 3)) and u.dimension in (9, 16):
            a = a.T
        u.write(np.ascontiguousarray(a).tobytes())
    else:
        u.value = value


def check_size(size) -> tuple[int, int]:
    """(width, height) as ints in 1..MAX_SIZE, or an InputError saying what was wrong."""
    try:
        w, h = (int(v) for v in size)
    except (TypeError, ValueError):
        raise InputError(f"image size must be (width, height), got {size!r}") from None
    if not (1 <= w <= MAX_SIZE and 1 <= h <= MAX_SIZE):
        raise InputError(f"image size {w}×{h} is out of range (1..{MAX_SIZE} per side)")
    return w, h
