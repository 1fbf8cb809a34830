"""What the shared passes take, importable without GL or numba (a technique's Params holds them):
the scene renderer's settings and the stereo composites' names."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.params import check_ranges, param

__all__ = ["RenderSettings", "COMPOSITES"]

#: stereo layouts, then anaglyph schemes (passes.stereo.StereoCompositePass)
COMPOSITES = (
    "side-by-side",
    "cross-eyed",
    "top-bottom",
    "anaglyph",
    "anaglyph-colour",
    "anaglyph-half-colour",
    "anaglyph-grey",
)


@dataclass(frozen=True)
class RenderSettings:
    """shadows: cube shadow maps on/off; shadow_tile_size: pixels per cube face;
    exposure: scale on the linear result; forward: light the surfaces in the pass that draws them
    instead of through the G-buffer (same image; faster where G-buffer bandwidth dominates, as on a
    CPU rasteriser at high resolution)."""

    PANEL: ClassVar[str] = "Render settings"  # its options' panel in --help

    shadows: bool = param(True, help="cube shadow maps of every light", group="advanced")
    shadow_tile_size: int = param(
        512,
        range=(64, 4096),
        unit="px",
        step=64,
        label="shadow map size",
        help="pixels per cube face",
        group="advanced",
    )
    exposure: float = param(1.0, range=(0.01, 16.0), log=True, help="scale on the linear radiance", group="output")
    forward: bool = param(
        False, label="forward shading", help="light in the pass that draws (same image)", group="advanced"
    )

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "forward": "the same image by design (forward and deferred lighting agree within 1/255); speed only",
    }

    __post_init__ = check_ranges
