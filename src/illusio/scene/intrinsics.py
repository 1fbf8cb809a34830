"""A pinhole camera in pixels with OpenCV's lens distortion: what a calibration, a depth camera or a
photogrammetry pipeline says of a camera, and the undoing of its distortion. Shared by image-based
rendering's captures and relighting's photographs."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from .camera import Camera

__all__ = ["Intrinsics", "undistort_image", "distort_image"]


@dataclass(frozen=True)
class Intrinsics:
    """A pinhole in pixels, OpenCV's convention (the top-left pixel's centre at (0, 0)). model and
    distortion: "PINHOLE" (none), or "OPENCV" with (k1, k2, p1, p2)."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    model: str = "PINHOLE"
    distortion: tuple[float, ...] = ()

    def __post_init__(self):
        values = (self.width, self.height, self.fx, self.fy, self.cx, self.cy) + tuple(self.distortion)
        if not all(math.isfinite(v) for v in values) or min(self.width, self.height, self.fx, self.fy) <= 0:
            raise InputError(f"intrinsics must be finite with positive size and focal lengths, got {self}")
        if self.model not in ("PINHOLE", "OPENCV") or (self.model == "OPENCV") != (len(self.distortion) == 4):
            raise InputError(
                f"intrinsics: model PINHOLE without distortion or OPENCV with (k1, k2, p1, p2), got "
                f"{self.model} with {len(self.distortion)} coefficients"
            )

    def camera(self, near: float = 0.05, far: float = 100.0) -> Camera:
        return Camera.from_intrinsics(self.width, self.height, self.fx, self.fy, self.cx, self.cy, near, far)

    @property
    def distorted(self) -> bool:
        return self.model == "OPENCV" and any(self.distortion)

    @property
    def pinhole(self) -> Intrinsics:
        """The same camera without its distortion (what :func:`undistort_image` gives)."""
        return Intrinsics(self.width, self.height, self.fx, self.fy, self.cx, self.cy)


def _pixel_rays(i: Intrinsics) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) (H, W): each pixel's normalised image coordinates, (u − c_x)/f_x and (v − c_y)/f_y."""
    v, u = np.mgrid[0 : i.height, 0 : i.width].astype(np.float64)
    return (u - i.cx) / i.fx, (v - i.cy) / i.fy


def _distort(i: Intrinsics, x, y):
    """OpenCV's model: (x, y) of a pinhole → where the lens records them (normalised)."""
    k1, k2, p1, p2 = i.distortion
    r2 = x * x + y * y
    radial = 1 + k1 * r2 + k2 * r2 * r2
    return x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x), y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y


def _sample(image, i: Intrinsics, x, y, order: int, cval: float | None) -> np.ndarray:
    """``image`` sampled at the normalised coordinates (x, y), per channel."""
    from scipy import ndimage

    coords = np.stack([y * i.fy + i.cy, x * i.fx + i.cx])
    a = np.asarray(image)
    mode = dict(mode="nearest") if cval is None else dict(mode="constant", cval=cval)
    if a.ndim == 2:
        return ndimage.map_coordinates(a, coords, order=order, **mode).astype(a.dtype)
    return np.stack(
        [ndimage.map_coordinates(a[..., c], coords, order=order, **mode) for c in range(a.shape[2])], axis=-1
    ).astype(a.dtype)


def undistort_image(image: np.ndarray, intrinsics: Intrinsics, order: int = 1, cval: float | None = None) -> np.ndarray:
    """``image`` (H, W) or (H, W, C) as the pinhole of ``intrinsics`` would have seen it: OPENCV's
    radial (k1, k2) and tangential (p1, p2) distortion undone by sampling the recorded image where
    each undistorted ray landed — ``order`` 1 bilinear (colour), 0 nearest (a depth is not blended
    across an edge); outside the recorded image the nearest edge pixel, or ``cval`` when given."""
    if not intrinsics.distorted:
        return np.asarray(image)
    return _sample(image, intrinsics, *_distort(intrinsics, *_pixel_rays(intrinsics)), order, cval)


def distort_image(image: np.ndarray, intrinsics: Intrinsics, iterations: int = 20) -> np.ndarray:
    """The inverse of :func:`undistort_image`: what the distorted lens of ``intrinsics`` records of
    a scene whose pinhole image is ``image`` (H, W, C) — each recorded pixel looks up, bilinearly,
    the pinhole pixel its undistorted ray hits (the distortion inverted by fixed-point iteration,
    x ← x − (distort(x) − x_d), exact to 10⁻⁶ pixel for the modest lenses of photographs). Used to
    make test photographs."""
    if not intrinsics.distorted:
        return np.asarray(image)
    xd, yd = _pixel_rays(intrinsics)
    x, y = xd.copy(), yd.copy()
    for _ in range(iterations):
        fx, fy = _distort(intrinsics, x, y)
        x, y = x - (fx - xd), y - (fy - yd)
    return _sample(image, intrinsics, x, y, 1, None)
