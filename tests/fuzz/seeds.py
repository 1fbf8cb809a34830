"""Valid seed files the fuzzers mutate, made here from code (no fetched data)."""

from __future__ import annotations

import io
from functools import cache

import numpy as np


@cache
def mesh_seeds() -> dict[str, bytes]:
    """A small icosphere in every mesh format illusio reads (name → file bytes; the name's suffix
    is the format)."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=1)
    seeds = {
        "sphere.obj": sphere.export(file_type="obj").encode(),
        "sphere-ascii.ply": sphere.export(file_type="ply", encoding="ascii"),
        "sphere-binary.ply": sphere.export(file_type="ply", encoding="binary"),
        "sphere.off": sphere.export(file_type="off").encode(),
        "sphere-ascii.stl": sphere.export(file_type="stl_ascii").encode(),
        "sphere-binary.stl": sphere.export(file_type="stl"),
        "sphere.glb": sphere.export(file_type="glb"),
        "strips-ascii.ply": tristrip_ply(sphere.vertices, binary=False),
        "strips-binary.ply": tristrip_ply(sphere.vertices, binary=True),
    }
    return seeds


def tristrip_ply(vertices: np.ndarray, binary: bool) -> bytes:
    """A PLY whose faces are one triangle strip (``element tristrips``), as the Igea scan stores."""
    strip = np.array([0, 1, 2, 3, -1, 4, 5, 6, 7, 8], np.int32)
    head = (
        f"ply\nformat {'binary_little_endian' if binary else 'ascii'} 1.0\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
    ).encode()
    if binary:
        body = np.asarray(vertices, "<f4").tobytes() + np.int32(len(strip)).tobytes() + strip.astype("<i4").tobytes()
    else:
        rows = "\n".join(" ".join(f"{c:.6f}" for c in v) for v in vertices)
        body = (rows + "\n" + " ".join(str(i) for i in [len(strip), *strip]) + "\n").encode()
    return head + body


def png_bytes(array: np.ndarray, mode: str | None = None) -> bytes:
    from PIL import Image

    out = io.BytesIO()
    Image.fromarray(array, mode).save(out, format="PNG")
    return out.getvalue()


@cache
def image_seeds() -> dict[str, bytes]:
    """A grey depth ramp (8 and 16-bit PNG), a colour pattern (PNG, JPEG), and .npy arrays."""
    from PIL import Image

    rng = np.random.default_rng(0)
    ramp = np.tile(np.linspace(0, 255, 64).astype(np.uint8), (24, 1))
    ramp16 = ramp.astype(np.uint16) * 257
    colour = rng.integers(0, 256, (16, 20, 3), dtype=np.uint8)
    jpeg = io.BytesIO()
    Image.fromarray(colour).save(jpeg, format="JPEG")
    npy, npy3 = io.BytesIO(), io.BytesIO()
    np.save(npy, ramp.astype(np.float32) / 255)
    np.save(npy3, colour.astype(np.float32) / 255)
    return {
        "ramp.png": png_bytes(ramp),
        "ramp16.png": png_bytes(ramp16),
        "pattern.png": png_bytes(colour),
        "pattern.jpg": jpeg.getvalue(),
        "ramp.npy": npy.getvalue(),
        "pattern.npy": npy3.getvalue(),
    }
