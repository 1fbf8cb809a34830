"""The chapter's estimates from the photograph (Loscos 4.2.1), stated as functions.

Units: the photograph holds radiance (W/(m²·sr)) per pixel; a Lambertian surface of radiosity B shows
radiance B/π, so a mean pixel value B̂ is taken as radiosity π·B̂ where an exitance is derived from it.
"""

from __future__ import annotations

import numpy as np

__all__ = ["reflectance_from_photograph", "reestimated_reflectance", "lamp_exitance", "displayed"]

#: the largest reflectance the estimate gives (a texture brighter than the mean by 1/ρ̂ would reach 1)
MAX_REFLECTANCE = 0.95


def reflectance_from_photograph(mean_pixels: np.ndarray, mean_scene: np.ndarray, mean_reflectance) -> np.ndarray:
    """Eq. (4.1): ρ_i = B̂_i / B̂_A × ρ̂ per channel. mean_pixels: B̂_i (n, 3), the mean of the pixels
    of each polygon or element; mean_scene: B̂_A (3,), the mean over the whole photograph;
    mean_reflectance: ρ̂ (scalar or (3,)). Clipped to [0, MAX_REFLECTANCE]."""
    rho = np.asarray(mean_pixels, np.float64) / np.maximum(np.asarray(mean_scene, np.float64), 1e-12) * mean_reflectance
    return np.clip(rho, 0.0, MAX_REFLECTANCE)


def reestimated_reflectance(mean_pixels, mean_scene, mean_reflectance, areas) -> tuple[np.ndarray, np.ndarray]:
    """The two steps of 4.2.1: ρ from eq. (4.1) with the user's ρ̂; ρ̂ re-estimated as the (area-
    weighted) mean of those ρ; ρ again from eq. (4.1) with it. Returns (ρ (n, 3), ρ̂ (3,))."""
    first = reflectance_from_photograph(mean_pixels, mean_scene, mean_reflectance)
    areas = np.asarray(areas, np.float64)
    rho_hat = (first * areas[:, None]).sum(axis=0) / max(areas.sum(), 1e-300)
    return reflectance_from_photograph(mean_pixels, mean_scene, rho_hat), rho_hat


def lamp_exitance(mean_reflectance, mean_scene_radiance, total_area: float, lamp_area: float,
                  other_power=0.0) -> np.ndarray:
    """Eq. (4.2) with every lamp of the same exitance: Σ_emitters E·A = (1 − ρ̂)·B̂_A·Σ_i A_i, so
    E = ((1 − ρ̂)·π·L̂_A·ΣA − P_other) / ΣA_lamps (W/m², RGB), L̂_A the photograph's mean radiance and
    P_other the power (W, RGB) of emitters whose exitance is already known (self-luminous surfaces),
    clipped at 0."""
    rho = np.asarray(mean_reflectance, np.float64)
    total = (1 - rho) * np.pi * np.asarray(mean_scene_radiance, np.float64) * total_area
    return np.maximum(total - np.asarray(other_power, np.float64), 0.0) / lamp_area


def displayed(radiosity, display_factor, texture) -> np.ndarray:
    """Eq. (4.3): (B_i / D_i)·T_i, elementwise (broadcast); 0 where D_i = 0."""
    b, d = np.asarray(radiosity, np.float64), np.asarray(display_factor, np.float64)
    return np.where(d > 0, b / np.where(d > 0, d, 1), 0.0) * texture
