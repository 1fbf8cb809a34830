"""PLY files whose faces are triangle strips (``element tristrips``, as in the Igea scan).

trimesh reads such a file as a point cloud; this reads the vertex positions and the strips
(``-1`` restarts a strip) and turns the strips into triangles with trimesh's own converter.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.errors import InputError

_PLY_TYPES = {
    "char": "i1",
    "int8": "i1",
    "uchar": "u1",
    "uint8": "u1",
    "short": "i2",
    "int16": "i2",
    "ushort": "u2",
    "uint16": "u2",
    "int": "i4",
    "int32": "i4",
    "uint": "u4",
    "uint32": "u4",
    "float": "f4",
    "float32": "f4",
    "double": "f8",
    "float64": "f8",
}


def has_tristrips(p: Path) -> bool:
    with open(p, "rb") as fh:
        head = fh.read(4096)
    return head.startswith(b"ply") and b"element tristrips" in head.split(b"end_header")[0]


def read_ply_tristrips(p: Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (N, 3) float64, faces (M, 3) int64) of a PLY with a ``tristrips`` element."""
    import trimesh

    data = p.read_bytes()
    end = data.find(b"end_header")
    if end < 0:
        raise InputError(f"{p}: PLY header has no end_header")
    body_start = data.index(b"\n", end) + 1
    lines = data[:end].decode("ascii", "replace").splitlines()
    fmt = next((ln.split()[1] for ln in lines if ln.startswith("format")), "ascii")
    elements: list[tuple[str, int, list[list[str]]]] = []
    for ln in lines:
        parts = ln.split()
        if parts[:1] == ["element"]:
            elements.append((parts[1], int(parts[2]), []))
        elif parts[:1] == ["property"] and elements:
            elements[-1][2].append(parts[1:])
    if [e[0] for e in elements[:1]] != ["vertex"]:
        raise InputError(f"{p}: tristrips PLY must start with the vertex element")
    name, count, props = elements[0]
    if any(pr[0] == "list" for pr in props):
        raise InputError(f"{p}: vertex element with list properties is not supported")
    names = [pr[1] for pr in props]
    if fmt == "ascii":
        tokens = data[body_start:].split()
        nv = len(props) * count
        vert = np.asarray(tokens[:nv], dtype=np.float64).reshape(count, len(props))
        strip_tokens = np.asarray(tokens[nv:], dtype=np.int64)
        if not len(strip_tokens) or len(strip_tokens) < 1 + strip_tokens[0] or strip_tokens[0] < 0:
            declared = int(strip_tokens[0]) if len(strip_tokens) else "a list of"
            raise InputError(
                f"{p}: the strip declares {declared} indices but "
                f"{max(len(strip_tokens) - 1, 0)} follow — is the file cut short?"
            )
        strips = strip_tokens[1 : 1 + strip_tokens[0]]
        xyz = vert[:, [names.index(c) for c in "xyz"]]
    else:
        endian = "<" if "little" in fmt else ">"
        dtype = np.dtype([(pr[1], endian + _PLY_TYPES[pr[0]]) for pr in props])
        vert = np.frombuffer(data, dtype=dtype, count=count, offset=body_start)
        xyz = np.stack([vert[c].astype(np.float64) for c in "xyz"], axis=1)
        strip_props = elements[1][2][0] if len(elements) > 1 else None
        if not strip_props or strip_props[0] != "list":
            raise InputError(f"{p}: tristrips element must be a list property")
        count_t, index_t = endian + _PLY_TYPES[strip_props[1]], endian + _PLY_TYPES[strip_props[2]]
        at = body_start + dtype.itemsize * count
        if len(data) < at + np.dtype(count_t).itemsize:
            raise InputError(
                f"{p}: the header declares {count} vertices and a strip, but the file ends at byte "
                f"{len(data)} — is it cut short?"
            )
        n = int(np.frombuffer(data, dtype=count_t, count=1, offset=at)[0])
        end = at + np.dtype(count_t).itemsize + n * np.dtype(index_t).itemsize
        if n < 0 or len(data) < end:
            raise InputError(
                f"{p}: the strip declares {n} indices ({end} bytes) but the file holds {len(data)} bytes — is "
                "it cut short?"
            )
        strips = np.frombuffer(data, dtype=index_t, count=n, offset=at + np.dtype(count_t).itemsize).astype(np.int64)
    breaks = np.flatnonzero(strips < 0)
    pieces = [s for s in np.split(strips, breaks) if len(s)]
    pieces = [s[1:] if s[0] < 0 else s for s in pieces]
    pieces = [s for s in pieces if len(s) >= 3]
    faces = trimesh.util.triangle_strips_to_faces(pieces) if pieces else np.zeros((0, 3), np.int64)
    return xyz, np.asarray(faces, dtype=np.int64)
