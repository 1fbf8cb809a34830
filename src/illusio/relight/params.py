"""Every knob of relighting a real scene (Loscos 1999, ch. 4), with units and ranges."""

from __future__ import annotations

from dataclasses import dataclass

from ..core.params import check_ranges, param
from ..radiosity.params import HierarchyParams

__all__ = ["RelightParams", "METHODS"]

#: baseline: the system as initialised in 4.2.1 (textures of the photograph modulated by B/D, eq. 4.3):
#: a lamp switched off leaves its photographed shadows (the limitation of 4.2.2). loscos: the
#: textures of 4.3.2 (blocked energy added, shadowed elements corrected from a lit reference), shown
#: with D = B + ρĒ; without the texture-driven refinement of 4.3.1 yet (the BFV mesh with the lamps'
#: links at the leaves is used).
#: per-pixel: the photograph scaled at each pixel by the change of its irradiance, lamp by lamp with
#: per-pixel visibility (the chapter's conclusion; relight.per_pixel).
METHODS = ("baseline", "loscos", "per-pixel")


@dataclass(frozen=True)
class RelightParams:
    """method: one of METHODS. mean_reflectance: ρ̂ of eq. (4.1), the user's first guess of the scene's
    mean reflectance (re-estimated from the photograph afterwards). hierarchy: the radiosity solution's
    refinement (with loscos, the lamps' links are pushed to the leaves). colour_threshold: ε of Figure
    4.11, the largest L*a*b* distance between a shadowed element and its reference. lamp_scales: (lamp name, factor on its estimated exitance) pairs. exposure: factor on
    the displayed radiance."""

    method: str = param("baseline", choices=METHODS)
    mean_reflectance: float = param(0.5, range=(0.01, 0.95), label="mean reflectance ρ̂ (first guess)")
    colour_threshold: float = param(20.0, range=(0.0, 200.0), label="colour similarity ε (CIE L*a*b*, Fig. 4.11)")
    hierarchy: HierarchyParams = param(default_factory=HierarchyParams)
    lamp_scales: tuple = param((), panel=False)
    exposure: float = param(1.0, range=(1e-6, 1e6), log=True)

    __post_init__ = check_ranges
