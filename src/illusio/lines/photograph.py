"""A stand-in for photographs of a mesh (the report's comparison with photographs, chapter 4):
the mesh path-traced by Mitsuba 3 with a painted albedo (a smooth random colour field: texture
edges that are not shape), a large rectangular lamp (soft shadows, on the mesh and on a floor under
it), a dim sky, the path tracer's own noise, and optionally a camera slightly off the drawing's
(misregistration, as a photograph taken by hand would be). Mitsuba is an optional dependency
(``pip install mitsuba``); the scene is written as a binary PLY with float vertex colours, which
Mitsuba reads as the ``vertex_color`` attribute."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from ..passes.mitsuba import load_mitsuba, load_scene, render, rgb, sensor
from ..scene.camera import Pose, View
from ..scene.mesh import Mesh

__all__ = ["painted_albedo", "photograph", "shifted_view", "exposed"]


def painted_albedo(vertices: np.ndarray, seed: int = 0, waves: int = 6, contrast: float = 0.5) -> np.ndarray:
    """(N, 3) albedo in [0.2, 0.9]: a sum of ``waves`` random plane waves over the positions (a few
    blotches across the mesh), one colour ramp per channel; deterministic in ``seed``."""
    rng = np.random.default_rng(seed)
    v = np.asarray(vertices, np.float64)
    extent = max(float(np.ptp(v, axis=0).max()), 1e-12)
    field = np.zeros((len(v), 3))
    for _ in range(waves):
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        frequency = rng.uniform(1.5, 4.0) * 2 * np.pi / extent
        field += np.sin(v @ direction * frequency + rng.uniform(0, 2 * np.pi))[:, None] * rng.uniform(-1, 1, 3)
    field /= max(float(np.abs(field).max()), 1e-12)
    return np.clip(0.55 + contrast * 0.7 * field, 0.2, 0.9)


def shifted_view(view: View, size, pixels: tuple[float, float]) -> View:
    """``view`` turned so that the scene moves by about ``pixels`` (dx right, dy down) in an image of
    ``size``: the target moved across the view at its distance."""
    w, h = size
    right, up, _ = view.pose.axes()
    eye, target = np.asarray(view.pose.position, np.float64), np.asarray(view.pose.target, np.float64)
    per_pixel = 2 * np.linalg.norm(target - eye) * np.tan(np.radians(view.camera.fov_y) / 2) / h
    # the camera turns towards −dx to move the scene by +dx on screen
    moved = target - (pixels[0] * right - pixels[1] * up) * per_pixel
    return View(Pose(tuple(eye), tuple(moved), view.pose.up), view.camera)


def _write_ply(path: Path, vertices: np.ndarray, faces: np.ndarray, colours: np.ndarray) -> None:
    head = (
        f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
        + "".join(f"property float {c}\n" for c in "xyzrgb")
        + f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    face = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face["n"], face["i"] = 3, faces
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(np.c_[vertices, colours].astype("<f4").tobytes())
        f.write(face.tobytes())


def photograph(
    mesh: Mesh,
    view: View,
    size: tuple[int, int],
    samples: int = 32,
    seed: int = 0,
    misregistration: tuple[float, float] = (0.0, 0.0),
) -> np.ndarray:
    """The "photograph" of ``mesh`` from ``view`` (turned by ``misregistration`` pixels), float32
    (H, W, 3) linear radiance, row 0 on top: painted albedo (``seed``), a lamp above and to the left
    of the camera, a floor under the mesh, a dim sky; ``samples`` paths a pixel (the noise)."""
    mi = load_mitsuba()
    v = np.asarray(mesh.vertices, np.float64)
    f = np.asarray(mesh.faces, np.int64)
    lo, hi = v.min(axis=0), v.max(axis=0)
    centre, radius = (lo + hi) / 2, float(np.linalg.norm(hi - lo)) / 2
    right, up, forward = view.pose.axes()
    lamp_at = centre + (up * 1.2 - right * 0.8 - forward * 0.6) * 2.5 * radius
    to_lamp = lamp_at - centre
    normal = -to_lamp / np.linalg.norm(to_lamp)
    u = np.cross(normal, up)
    u /= np.linalg.norm(u)
    lamp = np.eye(4)
    lamp[:3, 0], lamp[:3, 1], lamp[:3, 2], lamp[:3, 3] = u * radius, np.cross(normal, u) * radius, normal, lamp_at
    # the floor: a square under the mesh, at its lowest point along the view's up
    floor = np.eye(4)
    down = float(np.min((v - centre) @ up))
    floor_at = centre + up * (down - 1e-3 * radius)
    side = np.cross(up, right)
    floor[:3, 0], floor[:3, 1], floor[:3, 2], floor[:3, 3] = right * 4 * radius, side * 4 * radius, up, floor_at
    seen = shifted_view(view, size, misregistration) if any(misregistration) else view
    with tempfile.TemporaryDirectory(prefix="illusio-photo-") as tmp:
        path = Path(tmp) / "mesh.ply"
        _write_ply(path, v, f, painted_albedo(v, seed))
        scene = {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 4},
            "sensor": sensor(mi, seen, size, samples, seed),
            "mesh": {
                "type": "ply",
                "filename": str(path),
                "bsdf": {"type": "diffuse", "reflectance": {"type": "mesh_attribute", "name": "vertex_color"}},
            },
            "floor": {
                "type": "rectangle",
                "to_world": mi.ScalarTransform4f(floor.tolist()),
                "bsdf": {"type": "diffuse", "reflectance": rgb((0.8, 0.8, 0.8))},
            },
            "lamp": {
                "type": "rectangle",
                "to_world": mi.ScalarTransform4f(lamp.tolist()),
                "emitter": {"type": "area", "radiance": rgb((6.0, 6.0, 6.0))},
            },
            "sky": {"type": "constant", "radiance": rgb((0.25, 0.25, 0.25))},
        }
        image = np.asarray(render(mi, load_scene(mi, scene)), np.float32)
    return np.ascontiguousarray(image[..., :3])


def exposed(photo: np.ndarray, percentile: float = 99.5) -> np.ndarray:
    """The photograph as one would print it: scaled so its ``percentile`` is white, clipped to [0, 1]
    (what its edges are found on and what is shown)."""
    return np.clip(photo / max(float(np.percentile(photo, percentile)), 1e-6), 0, 1).astype(np.float32)
