"""The physical model of an autostereogram (Dehos et al. 2014, section 3.1, equations 1–4).

A viewer at distance f from a screen fuses two pixels a distance e' apart as one point P at depth f'
behind the screen. Units: centimetres for lengths, pixels where the name says ``_px``. Every function
works on floats or NumPy arrays alike.

Note on the paper's numbers: with Table 1 (d = 53 cm, a = 16/9, w_p = 1920, f = 100, e = 6.5) the limit
e_p is 270 px; the paper's "≈ 277 px" is the 16/10 value. Its example "e'_p ∈ [100, 150] ↔ f' ∈ [74,
175] cm" holds for neither aspect: it matches w = 53 cm, the diagonal used as the width (e_p ≈ 235 px).
``tests/sis/test_physics.py`` checks all three.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from ..scene.camera import Screen

__all__ = [
    "separation_cm",
    "screen_width_cm",
    "separation_px",
    "depth_from_separation",
    "max_separation_px",
    "depth_range",
    "linear_depth_error",
    "Screen",
]


def separation_cm(depth_cm, viewing_distance_cm: float = 100.0, eye_separation_cm: float = 6.5):
    """Equation (1): e' = f'·e / (f + f'), the on-screen distance between the two pixels that show a
    point at depth f' (``depth_cm``) behind the screen."""
    f_prime = np.asarray(depth_cm, dtype=np.float64)
    return f_prime * eye_separation_cm / (viewing_distance_cm + f_prime)


def screen_width_cm(diagonal_cm: float, aspect: float) -> float:
    """Equation (2): w = a·d / √(1 + a²). (``Screen.width_cm`` is the same formula.)"""
    return Screen(diagonal_cm=diagonal_cm, aspect=aspect).width_cm


def separation_px(depth_cm, screen: Screen = Screen(), width_cm: float | None = None):
    """Equation (3): e'_p = f'·w_p·e / ((f + f')·w), in pixels. ``width_cm`` overrides w."""
    w = screen.width_cm if width_cm is None else width_cm
    return separation_cm(depth_cm, screen.viewing_distance_cm, screen.eye_separation_cm) * screen.width_px / w


def depth_from_separation(separation, screen: Screen = Screen(), width_cm: float | None = None):
    """Equation (4): f' = e'_p·w·f / (w_p·e − e'_p·w), in cm; +inf at and beyond e_p."""
    w = screen.width_cm if width_cm is None else width_cm
    s = np.asarray(separation, dtype=np.float64)
    denominator = screen.width_px * screen.eye_separation_cm - s * w
    with np.errstate(divide="ignore"):
        return np.where(
            denominator > 0, s * w * screen.viewing_distance_cm / np.where(denominator > 0, denominator, 1.0), np.inf
        )


def max_separation_px(screen: Screen = Screen(), width_cm: float | None = None) -> float:
    """e_p: the limit of equation (3) as f' → ∞, i.e. the eye separation in pixels, w_p·e / w."""
    w = screen.width_cm if width_cm is None else width_cm
    return screen.width_px * screen.eye_separation_cm / w


def depth_range(
    strip_width: float, depth_factor: float, screen: Screen = Screen(), width_cm: float | None = None
) -> tuple[float, float]:
    """[f'_min, f'_max] in cm simulated by separations in [W_s, W_s + β] (equation 4 at both ends)."""
    e_p = max_separation_px(screen, width_cm)
    if not 0 < strip_width < e_p:
        raise InputError(f"strip width W_s = {strip_width:g} px must lie in ]0, e_p[ = ]0, {e_p:.1f}[ for this screen")
    if not 0 < depth_factor < e_p - strip_width:
        raise InputError(
            f"depth factor β = {depth_factor:g} px must lie in ]0, e_p − W_s[ = ]0, {e_p - strip_width:.1f}[ "
            "for this screen"
        )
    near, far = depth_from_separation([strip_width, strip_width + depth_factor], screen, width_cm)
    return float(near), float(far)


def linear_depth_error(strip_width: float, depth_factor: float, screen: Screen = Screen(), samples: int = 101):
    """The error of the paper's linear approximation (section 3.4), in cm: (D, f'_linear − f'_exact).

    Exact mode puts D linearly in the simulated depth, f'_exact = f'_min + D·(f'_max − f'_min); the
    linear mode puts it linearly in the separation, W_s + β·D, which the viewer sees at
    f'_linear = equation (4) of that separation. Both agree at D = 0 and D = 1; f' is convex in the
    separation, so between them the linear mode shows every point nearer (the error is ≤ 0)."""
    near, far = depth_range(strip_width, depth_factor, screen)
    d = np.linspace(0.0, 1.0, samples)
    exact = near + d * (far - near)
    linear = depth_from_separation(strip_width + depth_factor * d, screen)
    return d, linear - exact
