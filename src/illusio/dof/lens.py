"""The thin lens of section 2.2.1: where a point focuses (equation 1), the circle of confusion it makes
on the image plane (equation 2), and that circle in pixels of an image with a given field of view.

Units: distances along the view axis in metres, lens quantities in the same unit as each other
(millimetres in the Params). The image plane sits where the focus distance is sharp, and its height
is the one the camera's vertical field of view gives there, so a pixel's circle of confusion is

    c_px = A · |1/d − 1/d_f| · H / (2 tan(fov_y / 2))

with A the aperture (lens diameter) in metres: the focal length cancels out (a longer lens at the
same field of view is a bigger image plane). The same formula is the blur of the accumulation
method, whose eye moves over a disk of diameter A with the focal plane held fixed.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.errors import InputError

__all__ = ["image_distance", "coc_diameter", "coc_pixels", "fov_for_focal_length", "SENSOR_HEIGHT_MM"]

#: the image height a focal length is quoted for (a 24 × 36 mm frame), for --focal-length
SENSOR_HEIGHT_MM = 24.0


def image_distance(focal_length: float, distance):
    """Equation (1), 1/F = 1/d + 1/d_s, solved for d_s: where a point at ``distance`` focuses behind a
    lens of focal length F (same units). Needs distance > F (a real image)."""
    d = np.asarray(distance, np.float64)
    if focal_length <= 0 or (d <= focal_length).any():
        raise InputError(f"a thin lens of focal length {focal_length:g} images only points farther than it")
    return 1.0 / (1.0 / focal_length - 1.0 / d)


def coc_diameter(distance, focus_distance: float, aperture: float, focal_length: float):
    """Equation (2): the diameter C of the circle of confusion on the image plane placed where
    ``focus_distance`` is sharp, for a point at ``distance``: by similar triangles,
    C = A · abs(d_s(d) − d_s(d_f)) / d_s(d) (same units as the aperture A)."""
    d_s = image_distance(focal_length, distance)
    plane = image_distance(focal_length, focus_distance)
    return aperture * np.abs(d_s - plane) / d_s


def coc_pixels(depth: np.ndarray, focus_distance: float, aperture_m: float, fov_y: float, height: int) -> np.ndarray:
    """Circle-of-confusion diameter in pixels for linear view depths (metres; ≤ 0 or inf: nothing
    there, taken as infinitely far). ``aperture_m``: lens diameter in metres; ``fov_y`` degrees;
    ``height``: image height in pixels."""
    if not focus_distance > 0:
        raise InputError(f"focus distance must be positive, got {focus_distance}")
    d = np.asarray(depth, np.float64)
    inverse = np.where(np.isfinite(d) & (d > 0), 1.0 / np.where(d > 0, d, 1.0), 0.0)
    scale = height / (2.0 * math.tan(math.radians(fov_y) / 2))
    return (aperture_m * np.abs(inverse - 1.0 / focus_distance) * scale).astype(np.float32)


def fov_for_focal_length(focal_length_mm: float, sensor_height_mm: float = SENSOR_HEIGHT_MM) -> float:
    """The vertical field of view (degrees) of a lens of ``focal_length_mm`` on a frame
    ``sensor_height_mm`` high."""
    if not focal_length_mm > 0:
        raise InputError(f"focal length must be positive, got {focal_length_mm}")
    return math.degrees(2 * math.atan(sensor_height_mm / (2 * focal_length_mm)))
