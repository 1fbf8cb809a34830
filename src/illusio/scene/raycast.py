"""First hits of rays against a scene's visible triangles, on the CPU (NumPy, Möller–Trumbore):
for the few rays a tool needs (is this camera inside the room?), not for rendering."""

from __future__ import annotations

import numpy as np

from .scene import Scene
from .transforms import transform_points

__all__ = ["world_triangles", "first_hit"]


def world_triangles(scene: Scene) -> np.ndarray:
    """(n, 3, 3) float64: every visible node's triangles in world space (metres)."""
    parts = [
        transform_points(n.transform, np.asarray(n.mesh.vertices, np.float64))[np.asarray(n.mesh.faces)]
        for n in scene.nodes
        if n.visible and len(n.mesh.faces)
    ]
    return np.concatenate(parts) if parts else np.zeros((0, 3, 3))


def first_hit(triangles: np.ndarray, origin, direction) -> float:
    """Distance along the unit ``direction`` from ``origin`` to the nearest triangle it crosses,
    either side facing (inf when none)."""
    o, d = np.asarray(origin, np.float64), np.asarray(direction, np.float64)
    d = d / np.linalg.norm(d)
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = o - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    v = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
    return float(t[hit].min()) if hit.any() else float("inf")
