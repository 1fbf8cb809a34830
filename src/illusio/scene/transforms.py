"""4×4 float32 transforms for column vectors (p' = M @ p), right-handed, y up, metres, degrees."""

from __future__ import annotations

import numpy as np

__all__ = [
    "identity",
    "translate",
    "scale",
    "rotate",
    "rotate_euler",
    "compose",
    "transform_points",
    "transform_normals",
    "look_at",
    "frustum",
]


def identity() -> np.ndarray:
    return np.eye(4, dtype=np.float32)


def translate(offset) -> np.ndarray:
    m = identity()
    m[:3, 3] = np.asarray(offset, dtype=np.float32)
    return m


def scale(factor) -> np.ndarray:
    f = np.broadcast_to(np.asarray(factor, dtype=np.float32), (3,))
    return np.diag([f[0], f[1], f[2], 1.0]).astype(np.float32)


def rotate(axis, degrees: float) -> np.ndarray:
    """Rotation by ``degrees`` about ``axis`` (right-hand rule)."""
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    t = np.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    r = np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * (k @ k)
    m = identity()
    m[:3, :3] = r
    return m


def rotate_euler(degrees) -> np.ndarray:
    """Rotation by (x, y, z) degrees applied in that order (x first)."""
    rx, ry, rz = (float(v) for v in degrees)
    return rotate((0, 0, 1), rz) @ rotate((0, 1, 0), ry) @ rotate((1, 0, 0), rx)


def compose(*matrices) -> np.ndarray:
    """Product of matrices, leftmost applied last: compose(T, R, S) = T @ R @ S."""
    m = identity()
    for x in matrices:
        m = m @ np.asarray(x, dtype=np.float32)
    return m.astype(np.float32)


def transform_points(matrix: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply an affine or projective 4×4 to (N, 3) points (with perspective divide)."""
    p = np.asarray(points, dtype=np.float64)
    h = p @ np.asarray(matrix, dtype=np.float64)[:3, :3].T + np.asarray(matrix, dtype=np.float64)[:3, 3]
    w = p @ np.asarray(matrix, dtype=np.float64)[3, :3] + matrix[3, 3]
    return (h / w[:, None]).astype(np.float32) if not np.allclose(w, 1) else h.astype(np.float32)


def transform_normals(matrix: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Apply the inverse transpose of the 3×3 part to (N, 3) normals and renormalise."""
    n = np.asarray(normals, dtype=np.float64) @ np.linalg.inv(np.asarray(matrix, dtype=np.float64)[:3, :3])
    return (n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)).astype(np.float32)


def _cross(a, b) -> np.ndarray:
    """a × b of two 3-vectors (np.cross's axis handling costs ~25 µs a call: a camera's matrix is
    made several times a frame)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def look_at(eye, target, up=(0.0, 1.0, 0.0)) -> np.ndarray:
    """World -> camera matrix: camera at ``eye`` looking at ``target`` down its −z axis."""
    eye = np.asarray(eye, dtype=np.float64)
    f = np.asarray(target, dtype=np.float64) - eye
    f /= np.sqrt(f @ f)
    s = _cross(f, np.asarray(up, dtype=np.float64))
    if np.sqrt(s @ s) < 1e-9:  # looking along up: pick any perpendicular
        s = _cross(f, [1.0, 0.0, 0.0] if abs(f[0]) < 0.9 else [0.0, 0.0, 1.0])
    s /= np.sqrt(s @ s)
    u = _cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m.astype(np.float32)


def frustum(left: float, right: float, bottom: float, top: float, near: float, far: float) -> np.ndarray:
    """OpenGL perspective projection of the window [left, right]×[bottom, top] at distance ``near``."""
    m = np.zeros((4, 4), dtype=np.float64)
    m[0, 0] = 2 * near / (right - left)
    m[1, 1] = 2 * near / (top - bottom)
    m[0, 2] = (right + left) / (right - left)
    m[1, 2] = (top + bottom) / (top - bottom)
    m[2, 2] = -(far + near) / (far - near)
    m[2, 3] = -2 * far * near / (far - near)
    m[3, 2] = -1.0
    return m.astype(np.float32)
