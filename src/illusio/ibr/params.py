"""Every knob of image-based rendering from reference views (Porquet 2005, section 4.2)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.params import check_ranges, param
from ..passes.settings import RenderSettings

__all__ = ["IbrParams", "DISTANCES", "SELECTIONS"]

#: how the point a reference sees is compared with the point to draw: "2d", in pixels on the new
#: camera's image plane (the text's choice, for the depth buffer's precision); "3d", in metres
DISTANCES = ("2d", "3d")
#: how the second pass chooses: "single-pass", one draw comparing every reference (the default: the
#: same choice, 1.1–1.2× faster on llvmpipe, benchmarks/RESULTS.md); "multi-pass", a draw per
#: reference with the depth test keeping the nearest (the text's any-number-of-views mode; texture
#: arrays give the single pass any number too, up to 16)
SELECTIONS = ("single-pass", "multi-pass")


@dataclass(frozen=True)
class IbrParams:
    """distance: DISTANCES. selection: SELECTIONS (the same choice either way). bilinear_depth: read a reference's
    depth by bilinear interpolation of the
    four texels around the back-projected point (the text's fix for border artefacts, Figure 4.4)
    rather than the nearest texel. max_distance: a point whose best reference misses it by more is
    a hole (pixels for "2d", metres for "3d"). mesh_step: reference pixels between the vertices of the
    depth-reconstruction mesh. grazing: a mesh triangle seen from its reference at more than this
    angle from its normal is left out (it would bridge an occlusion edge). fill_radius: holes of the
    reconstructed depth up to this many pixels wide take the farthest depth around them (where a cut
    triangle let the surface behind show). fill_disocclusions: pixels the new view sees and no
    reference does, up to this many pixels from a seen one, take the farthest seen point of the
    nearest ring around them (off in the sources view, which shows them as holes). show_sources: colour each pixel by
    the
    reference it came from (Figure 4.5), holes in magenta. relight: shade from the stored albedo and
    normals with the set's lights; off: show the chosen reference's recorded colour (a path-traced
    "photograph" keeps its indirect light). light_x, light_y, light_z: every light of
    the set moved by this many metres (the new view is lit again from the stored normals; the
    viewer's panel drags them live). settings: exposure."""

    PANEL: ClassVar[str] = "Image-based rendering"  # its options' panel in --help

    distance: str = param("2d", choices=DISTANCES, group="method")
    selection: str = param("single-pass", choices=SELECTIONS, group="method")
    bilinear_depth: bool = param(
        True,
        label="bilinear depth",
        flag="bilinear-depth/nearest-depth",
        help="bilinear reference depth, or the nearest texel's",
        group="method",
    )
    max_distance: float = param(3.0, range=(0.01, 1000.0), log=True, help="beyond it a pixel is a hole")
    mesh_step: int = param(2, range=(1, 16), step=1, unit="px", label="reconstruction mesh step", group="advanced")
    grazing: float = param(
        85.0, range=(1.0, 90.0), unit="°", help="mesh triangles seen more obliquely are cut", group="advanced"
    )
    fill_radius: int = param(
        4,
        range=(0, 64),
        step=1,
        unit="px",
        help="holes of the reconstructed depth this wide are filled",
        group="advanced",
    )
    fill_disocclusions: int = param(
        16,
        range=(0, 256),
        step=1,
        unit="px",
        help="disocclusions no reference sees are filled this far",
        group="advanced",
    )
    show_sources: bool = param(
        False, label="show source views", help="colour by source view, holes magenta", group="output"
    )
    relight: bool = param(
        True,
        help="light from the stored normals; photographic: the references' recorded colour",
        flag="relight/photographic",
    )
    light_x: float = param(0.0, range=(-10.0, 10.0), unit="m", label="move lights x")
    light_y: float = param(0.0, range=(-10.0, 10.0), unit="m", label="move lights y")
    light_z: float = param(0.0, range=(-10.0, 10.0), unit="m", label="move lights z")

    settings: RenderSettings = param(default_factory=lambda: RenderSettings(shadows=False), group="advanced")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "selection": "the same choice in one pass or several: speed only",
        "bilinear_depth": "the default references are as sharp as the output: under 2/255",
        "max_distance": "the default capture leaves no point farther than this from its best reference",
        "grazing": "the default capture's proxy mesh has few triangles seen that obliquely: under 2/255",
        "fill_radius": "fills holes: the default view between the references has none",
        "fill_disocclusions": "fills disocclusions: the default view between the references has none",
        "relight": "the default view is the middle reference's, its lamps the ones relighting shades with: "
        "relit and captured colours agree within rounding (under 2/255)",
        "settings.shadows": "the image comes from the references, their shadows in them",
        "settings.shadow_tile_size": "the image comes from the references, their shadows in them",
        "settings.forward": "the same image by design; speed only",
    }

    @property
    def light_offset(self) -> tuple[float, float, float]:
        """Metres every light of the set moves."""
        return (self.light_x, self.light_y, self.light_z)

    __post_init__ = check_ranges
