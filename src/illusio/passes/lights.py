"""Scene lights flattened to point emitters, the form the shading pass and its reference take."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..scene.scene import AreaLight, PointLight

__all__ = ["Emitters", "emitters_from_lights"]


@dataclass
class Emitters:
    """K point emitters. position (K, 3) metres; normal (K, 3): emitting direction of an area-lamp
    sample, zero for isotropic point lights; weight (K, 3): I·colour for point lights, L·A/K·colour
    for area samples; shadow_row (K,): row of the light's shadow map in the atlas or −1;
    shadow_origin (K, 3): where that shadow map was rendered (the light's centre)."""

    position: np.ndarray
    normal: np.ndarray
    weight: np.ndarray
    shadow_row: np.ndarray
    shadow_origin: np.ndarray

    def __len__(self) -> int:
        return len(self.position)

    @property
    def shadow_positions(self) -> np.ndarray:
        """One origin per shadow row, in row order."""
        rows = self.shadow_row
        out = np.zeros((int(rows.max()) + 1 if len(rows) and rows.max() >= 0 else 0, 3), np.float32)
        for r, o in zip(rows, self.shadow_origin):
            if r >= 0:
                out[r] = o
        return out


def emitters_from_lights(lights: list[PointLight | AreaLight], shadows: bool = True, limit: int = 64) -> Emitters:
    pos, nor, wei, rows, origins = [], [], [], [], []
    row = 0
    for light in lights:
        p, n, w = light.sample_points()
        centre = np.asarray(getattr(light, "position", getattr(light, "centre", None)), np.float32)
        if isinstance(light, AreaLight):  # render its shadow map just in front of the lamp
            centre = centre + light.normal * 0.01
        r = row if (shadows and light.shadows) else -1
        row += r >= 0
        pos.append(p), nor.append(n), wei.append(w)
        rows.append(np.full(len(p), r, np.int32)), origins.append(np.repeat(centre[None], len(p), axis=0))
    if not pos:
        z = np.zeros((0, 3), np.float32)
        return Emitters(z, z, z, np.zeros(0, np.int32), z)
    e = Emitters(
        np.concatenate(pos), np.concatenate(nor), np.concatenate(wei), np.concatenate(rows), np.concatenate(origins)
    )
    if len(e) > limit:
        raise InputError(
            f"{len(e)} light samples exceed the shading limit of {limit}; use fewer lights or fewer area samples"
        )
    return e
