"""The chapter's estimates from the photograph (Loscos 4.2.1), stated as functions.

Units: the photograph holds radiance (W/(m²·sr)) per pixel; a Lambertian surface of radiosity B shows
radiance B/π, so a mean pixel value B̂ is taken as radiosity π·B̂ where an exitance is derived from it.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "reflectance_from_photograph",
    "reestimated_reflectance",
    "lamp_exitance",
    "displayed",
    "reflectance_from_irradiance",
    "lamp_exitance_from_pixels",
]

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


def lamp_exitance(
    mean_reflectance, mean_scene_radiance, total_area: float, lamp_area: float, other_power=0.0
) -> np.ndarray:
    """Eq. (4.2) with every lamp of the same exitance: Σ_emitters E·A = (1 − ρ̂)·B̂_A·Σ_i A_i, so
    E = ((1 − ρ̂)·π·L̂_A·ΣA − P_other) / ΣA_lamps (W/m², RGB), L̂_A the photograph's mean radiance and
    P_other the power (W, RGB) of emitters whose exitance is already known (self-luminous surfaces),
    clipped at 0."""
    rho = np.asarray(mean_reflectance, np.float64)
    total = (1 - rho) * np.pi * np.asarray(mean_scene_radiance, np.float64) * total_area
    return np.maximum(total - np.asarray(other_power, np.float64), 0.0) / lamp_area


def reflectance_from_irradiance(mean_pixels, irradiance) -> np.ndarray:
    """The estimate the chapter's conclusion asks for ("des valeurs de réflectance mieux estimées"):
    each element's ρ explains its own photographed light, ρ_i = π·B̂_i / H_i, with B̂_i its mean pixel
    (radiance, (n, 3)) and H_i the irradiance the radiosity solution gathers there (W/m², direct and
    indirect, (n, 3)). Eq. (4.1) instead reads an element's brightness as its colour, so a shadowed
    floor comes out dark. Clipped to [0, MAX_REFLECTANCE]; 0 where H is 0. The session alternates it
    with a solve (H depends on the ρ of the elements that light i) until it settles."""
    h = np.asarray(irradiance, np.float64)
    rho = np.pi * np.asarray(mean_pixels, np.float64) / np.where(h > 0, h, 1.0)
    return np.clip(np.where(h > 0, rho, 0.0), 0.0, MAX_REFLECTANCE)


def lamp_exitance_from_pixels(lamp_pixels, saturation: float | None = None) -> np.ndarray | None:
    """A lamp's exitance read from its own pixels (radiance, (n, 3)): E = π × their mean (a
    Lambertian emitter of exitance E shows radiance E/π). None when fewer than 4 pixels, or when
    ``saturation`` is given (the level a low-dynamic-range photograph clips at) and a pixel reaches
    0.999 of it in every channel: a clipped lamp says only that it is brighter, and eq. (4.2) must
    estimate it."""
    px = np.asarray(lamp_pixels, np.float64).reshape(-1, 3)
    if len(px) < 4 or (saturation is not None and (px.min(axis=1) >= 0.999 * saturation).any()):
        return None
    return np.pi * px.mean(axis=0)


def displayed(radiosity, display_factor, texture) -> np.ndarray:
    """Eq. (4.3): (B_i / D_i)·T_i, elementwise (broadcast); 0 where D_i = 0."""
    b, d = np.asarray(radiosity, np.float64), np.asarray(display_factor, np.float64)
    return np.where(d > 0, b / np.where(d > 0, d, 1), 0.0) * texture
