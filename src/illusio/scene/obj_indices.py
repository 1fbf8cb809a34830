"""OBJ's relative indices made absolute before trimesh reads the file.

An OBJ face may index vertices, texture coordinates and normals relative to where it stands
(``f -8/-14/-6 ...``: the 8th position, 14th uv, 6th normal *before this line*). trimesh resolves them
against the end of the whole file (and fails with ``maintain_order``), so a file that interleaves
``v`` and ``f`` lines reads wrong. :func:`absolute_indices` rewrites such faces with the absolute
indices the OBJ specification gives them; a file without relative indices is left to trimesh as is.
"""

from __future__ import annotations

import re

__all__ = ["absolute_indices"]

_RELATIVE = re.compile(rb"^\s*(f|l|p)\s.*(^|\s|/)-\d", re.M)
_KINDS = {b"v": 0, b"vt": 1, b"vn": 2}


def absolute_indices(data: bytes) -> bytes | None:
    """``data`` (an OBJ file) with every relative index of its f, l and p lines made absolute, or
    None when it has none."""
    if not _RELATIVE.search(data):
        return None
    counts = [0, 0, 0]
    out = []
    for line in data.splitlines():
        words = line.split()
        head = words[0] if words else b""
        if head in _KINDS:
            counts[_KINDS[head]] += 1
        elif head in (b"f", b"l", b"p") and b"-" in line:
            line = b" ".join([head] + [_absolute(word, counts) for word in words[1:]])
        out.append(line)
    return b"\n".join(out) + b"\n"


def _absolute(word: bytes, counts: list[int]) -> bytes:
    parts = word.split(b"/")
    for k, part in enumerate(parts[:3]):
        if part.startswith(b"-") and part[1:].isdigit():
            parts[k] = str(counts[k] + 1 + int(part)).encode()
    return b"/".join(parts)
