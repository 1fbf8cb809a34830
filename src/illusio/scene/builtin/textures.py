"""Procedural texture images for the built-in scenes: float32 (H, W, 3), linear, row 0 on top.
Every random choice takes a seed."""

from __future__ import annotations

import numpy as np

__all__ = ["value_noise", "checker", "planks", "tiles", "fabric", "wallpaper"]


def value_noise(size: int, cells: int, seed: int = 0, octaves: int = 4) -> np.ndarray:
    """Tileable fractal value noise in [0, 1], shape (size, size)."""
    rng = np.random.default_rng(seed)
    out = np.zeros((size, size))
    amp, total = 1.0, 0.0
    for o in range(octaves):
        n = cells * 2**o
        grid = rng.random((n, n))
        x = np.arange(size) * n / size
        i0 = np.floor(x).astype(int)
        f = x - i0
        f = f * f * (3 - 2 * f)
        i1 = (i0 + 1) % n
        rows = grid[i0][:, i0] * (1 - f)[None, :] + grid[i0][:, i1] * f[None, :]
        rows1 = grid[i1][:, i0] * (1 - f)[None, :] + grid[i1][:, i1] * f[None, :]
        out += amp * (rows * (1 - f)[:, None] + rows1 * f[:, None])
        total += amp
        amp *= 0.5
    return (out / total).astype(np.float32)


def _mix(a, b, t):
    return (np.asarray(a, np.float32) * (1 - t[..., None]) + np.asarray(b, np.float32) * t[..., None]).astype(
        np.float32
    )


def checker(size: int = 256, squares: int = 8, a=(0.8, 0.8, 0.78), b=(0.1, 0.1, 0.1)) -> np.ndarray:
    i = np.arange(size) * squares // size
    t = ((i[:, None] + i[None, :]) % 2).astype(np.float32)
    return _mix(a, b, t)


def planks(size: int = 512, boards: int = 4, seed: int = 1) -> np.ndarray:
    """Wooden floor boards running along u: grain noise, per-board tint, dark joints."""
    rng = np.random.default_rng(seed)
    y = np.arange(size) * boards / size
    board = np.floor(y).astype(int)
    grain = value_noise(size, 4, seed, 3)
    streaks = 0.5 + 0.5 * np.sin(np.arange(size)[:, None] * 0.9 + 6 * grain)
    tint = rng.uniform(0.75, 1.15, boards)[board][:, None]
    base = _mix((0.30, 0.16, 0.07), (0.52, 0.32, 0.16), 0.6 * streaks + 0.4 * grain)
    img = base * tint[..., None]
    joint = (y % 1.0) < 0.02
    img[joint] *= 0.35
    offsets = rng.integers(0, size, boards)  # staggered board ends
    for b in range(boards):
        rows = board == b
        img[rows, offsets[b] % size] *= 0.35
    return np.clip(img, 0, 1).astype(np.float32)


def tiles(size: int = 256, count: int = 4, seed: int = 2, colour=(0.62, 0.58, 0.52)) -> np.ndarray:
    """Stone floor tiles with grout lines and a little mottling."""
    n = value_noise(size, 8, seed, 4)
    img = np.asarray(colour, np.float32) * (0.8 + 0.35 * n)[..., None]
    x = (np.arange(size) * count / size) % 1.0
    grout = (x[:, None] < 0.03) | (x[None, :] < 0.03)
    img[grout] = (0.25, 0.24, 0.22)
    return np.clip(img, 0, 1).astype(np.float32)


def fabric(size: int = 128, colour=(0.15, 0.25, 0.45), seed: int = 3) -> np.ndarray:
    """Woven cloth: a fine crossed weave over slight noise."""
    x = np.arange(size)
    weave = 0.5 + 0.25 * (np.sin(x * np.pi / 2)[:, None] + np.sin(x * np.pi / 2)[None, :])
    n = value_noise(size, 4, seed, 2)
    return np.clip(np.asarray(colour, np.float32) * (0.75 + 0.3 * weave + 0.2 * n)[..., None], 0, 1).astype(np.float32)


def wallpaper(size: int = 256, a=(0.78, 0.74, 0.64), b=(0.68, 0.62, 0.52), stripes: int = 8) -> np.ndarray:
    """Vertical stripes, as on a living-room wall."""
    t = (np.sin(np.arange(size) * 2 * np.pi * stripes / size) > 0.6).astype(np.float32)
    return np.broadcast_to(_mix(a, b, t)[None, :, :], (size, size, 3)).copy()
