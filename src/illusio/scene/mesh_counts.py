"""The element counts a mesh file declares, checked against what follows its header.

A truncated download or a cut copy of a PLY, OFF or binary STL still parses: the reader would draw
the part it got. These files say up front how many vertices and faces they hold, so a file holding
fewer is refused, naming both numbers. (OBJ declares nothing; a GLB's chunk lengths are checked by its
reader, its total length here.)
"""

from __future__ import annotations

import re
import struct
from pathlib import Path

from ..core.errors import InputError

__all__ = ["check_declared_counts", "length_error"]

_PLY_SIZES = {
    "char": 1,
    "int8": 1,
    "uchar": 1,
    "uint8": 1,
    "short": 2,
    "int16": 2,
    "ushort": 2,
    "uint16": 2,
    "int": 4,
    "int32": 4,
    "uint": 4,
    "uint32": 4,
    "float": 4,
    "float32": 4,
    "double": 8,
    "float64": 8,
}


def check_declared_counts(path: Path, data: bytes) -> None:
    """Raise InputError when ``data`` (the bytes of ``path``) holds fewer elements than its header
    declares; do nothing for formats without counts or headers this cannot parse (the reader will)."""
    suffix = path.suffix.lower()
    if suffix == ".ply" and data.startswith(b"ply"):
        _check_ply(path, data)
    elif suffix == ".off":
        _check_off(path, data)
    elif suffix == ".stl":
        _check_stl(path, data)
    elif suffix == ".glb" and data[:4] == b"glTF" and len(data) >= 12:
        (length,) = struct.unpack_from("<I", data, 8)
        if len(data) < length:
            raise _cut_short(path, f"a length of {length} bytes", f"{len(data)} bytes")


def length_error(path: Path, reason: str) -> InputError:
    """The error for a reader's own length check failing (binary PLY with list elements, GLB chunks):
    what the header declared, and the reader's words."""
    declared = "declares chunk lengths"
    if path.suffix.lower() == ".ply":
        try:
            header = _ply_header(path.read_bytes())
        except InputError:
            header = None
        if header:
            declared = "declares " + ", ".join(f"element {name} {count}" for name, count, _ in header[1])
    return InputError(
        f"{path}: the header {declared} but the file's length does not match ({reason}) — is it cut short?"
    )


def _cut_short(path: Path, declared: str, found: str) -> InputError:
    return InputError(f"{path}: the header declares {declared} but the file holds {found} — is it cut short?")


def _ply_header(data: bytes):
    end = data.find(b"end_header")
    if end < 0:
        return None
    newline = data.find(b"\n", end)
    body = len(data) if newline < 0 else newline + 1
    fmt, elements = "ascii", []
    for line in data[:end].decode("ascii", "replace").splitlines():
        parts = line.split()
        if parts[:1] == ["format"] and len(parts) > 1:
            fmt = parts[1]
        elif parts[:1] == ["element"] and len(parts) > 2:
            if not parts[2].isdigit():
                raise InputError(f"element {parts[1]!r} has count {parts[2]!r}, not a whole number")
            elements.append([parts[1], int(parts[2]), []])
        elif parts[:1] == ["property"] and elements:
            elements[-1][2].append(parts[1:])
    return fmt, elements, body


def _check_ply(path: Path, data: bytes) -> None:
    try:
        header = _ply_header(data)
    except InputError as exc:
        raise InputError(f"{path}: PLY header: {exc}") from None
    if header is None:
        raise InputError(f"{path}: PLY header has no end_header")
    fmt, elements, body = header
    declared = ", ".join(f"element {name} {count}" for name, count, _ in elements)
    if fmt == "ascii":
        # ascii PLY puts each element on its own line
        lines = sum(1 for line in data[body:].splitlines() if line.strip())
        wanted = sum(count for _, count, _ in elements)
        if lines < wanted:
            raise _cut_short(path, f"{declared} ({wanted} lines)", f"{lines} lines")
        return
    # the least the body can hold: lists counted as empty (the reader checks their lengths)
    least = 0
    for _, count, props in elements:
        sizes = [p[1] if p[0] == "list" and len(p) > 2 else p[0] for p in props if p]
        if any(size not in _PLY_SIZES for size in sizes):
            return
        least += count * sum(_PLY_SIZES[size] for size in sizes)
    if len(data) - body < least:
        raise _cut_short(path, f"{declared} (at least {least} bytes)", f"{len(data) - body} bytes")


def _check_off(path: Path, data: bytes) -> None:
    lines = [ln.split(b"#")[0].strip() for ln in data.splitlines()]
    lines = [ln for ln in lines if ln]
    if not lines:
        return
    head = lines[0].split()
    at = 1
    keyword = re.match(rb"^([A-Za-z]*OFF)(\d*)$", head[0]) if head else None
    if keyword:  # "OFF", "COFF"..., the counts on its line (even glued to it: "OFF8 6 12") or the next
        head = ([keyword.group(2)] if keyword.group(2) else []) + head[1:]
        if not head:
            head, at = (lines[1].split() if len(lines) > 1 else []), 2
    if len(head) < 2 or not all(t.isdigit() for t in head[:2]):
        raise InputError(
            f"{path}: OFF header must give the vertex and face counts, "
            f"got {b' '.join(head[:3]).decode(errors='replace')!r}"
        )
    vertices, faces = int(head[0]), int(head[1])
    found = len(lines) - at
    if found < vertices + faces:
        raise _cut_short(path, f"{vertices} vertices and {faces} faces ({vertices + faces} lines)", f"{found} lines")


def _check_stl(path: Path, data: bytes) -> None:
    if data[:5].lower() == b"solid":
        binary_size = len(data) >= 84 and len(data) == 84 + 50 * struct.unpack_from("<I", data, 80)[0]
        if b"endsolid" not in data[-1024:].lower() and not binary_size:  # some binary headers start "solid"
            raise InputError(f"{path}: ascii STL without its closing 'endsolid' line — is it cut short?")
        return
    if len(data) < 84:
        raise InputError(f"{path}: binary STL shorter than its 84-byte header ({len(data)} bytes)")
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) < 84 + 50 * count:
        raise _cut_short(path, f"{count} triangles ({84 + 50 * count} bytes)", f"{len(data)} bytes")
