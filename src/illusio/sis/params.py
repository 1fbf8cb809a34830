"""Every knob of an autostereogram, with units, defaults and the paper's symbols (Dehos et al. 2014).

The CLI, the gallery and the viewer read their defaults from here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

from ..core.errors import InputError
from ..core.gl import MAX_SIZE
from ..core.params import check_ranges, param
from ..passes.settings import RenderSettings
from ..scene.camera import Screen
from .physics import depth_range, max_separation_px

__all__ = ["StereogramParams", "MultiSceneParams", "ALGORITHMS", "PATTERNS"]

#: sequential: S[x] ← S[x − s(x)] row by row (section 3.3); strip: Algorithm 1, one render pass per
#: strip of W_s columns; fast: every pixel follows its chain of links back to the first strip in one
#: pass; symmetric: Thimbleby, Inglis & Witten (1994), links centred on each point, hidden surfaces removed.
ALGORITHMS = ("sequential", "strip", "fast", "symmetric")
#: built-in patterns; any other value is a path to an image used as a tiled texture
PATTERNS = ("random-dot", "grey-dots", "colour-dots", "pink-noise", "snow")


_SCREEN_FIELDS = ("diagonal_cm", "aspect", "width_px", "viewing_distance_cm", "eye_separation_cm")
_SCREEN_ONLY_WHEN_EXACT = "the physical screen enters only with exact (equation 3) and the range checks"


@dataclass(frozen=True)
class StereogramParams:
    """How depth becomes a stereogram.

    algorithm: one of :data:`ALGORITHMS`.

    strip_width: W_s, pixels — the separation of the nearest depth (Algorithm 1's strip width).

    depth_factor: β, pixels — separations span [W_s, W_s + β] from near (D = 0) to far (D = 1).

    exact: map depth through equation (3) on ``screen`` (linear in the simulated depth f' between the
    f'_min, f'_max that W_s and W_s + β stand for) instead of the linear W_s + β·D.

    screen: the physical display (d, a, w_p, f, e of Table 1); gives e_p for the range checks and the
    hidden-surface test of the symmetric algorithm.

    pattern: one of :data:`PATTERNS` or an image path (tiled, its period scaled to W_s + β).

    dot_size: pixels per random dot.

    guides: draw two guide dots W_s + β apart near the top.

    cross_eyed: for viewing with crossed eyes (the depth is flipped so that near stays near).

    invert: flip the depth map (D → 1 − D) before anything else.

    oversample: compute at this many times the width and average back (smooths depth terracing).

    seed: for every random pattern.
    """

    PANEL: ClassVar[str] = "Stereogram"  # its options' panel in --help

    algorithm: str = param("fast", choices=ALGORITHMS, help="how the links are followed", group="method")
    strip_width: float = param(
        100.0, range=(2.0, 1000.0), unit="px", label="strip width W_s", help="separation of the nearest depth"
    )
    depth_factor: float = param(
        50.0, range=(0.0, 1000.0), unit="px", label="depth factor β", help="separations span [W_s, W_s + β]"
    )
    exact: bool = param(False, help="equation (3) of the physical screen (Dehos et al. 2014) instead of W_s + β·D")
    screen: Screen = param(default_factory=Screen, panel=False, cli=True)
    pattern: str = param(
        "random-dot", panel=False, cli=True, help=f"{', '.join(PATTERNS)}, or an image file", group="output"
    )
    dot_size: int = param(1, range=(1, 64), unit="px", step=1, help="pixels per random dot", group="output")
    guides: bool = param(False, help="two guide dots W_s + β apart", group="output")
    cross_eyed: bool = param(False, help="for crossed eyes (default: wall-eyed)", group="output")
    invert: bool = param(False, help="D becomes 1 − D (black = near)", group="output")
    oversample: int = param(1, range=(1, 8), step=1, help="compute at N times the width", group="advanced")
    seed: int = param(0, range=(0, 2**31 - 1), step=1, help="seed of every random pattern", group="advanced")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        f"screen.{name}": _SCREEN_ONLY_WHEN_EXACT for name in _SCREEN_FIELDS
    }

    def __post_init__(self):
        if self.algorithm not in ALGORITHMS:
            raise InputError(f"unknown algorithm {self.algorithm!r}; choose one of {', '.join(ALGORITHMS)}")
        depth_range(self.strip_width, self.depth_factor, self.screen)  # raises on W_s, β out of range
        if self.strip_width < 2:
            raise InputError(f"strip width W_s = {self.strip_width:g} px is too small (at least 2 px)")
        if not 1 <= int(self.oversample) <= 8 or int(self.oversample) != self.oversample:
            raise InputError(f"oversample must be an integer in 1..8, got {self.oversample}")
        if not 1 <= int(self.dot_size) <= 64:
            raise InputError(f"dot size must be in 1..64 pixels, got {self.dot_size}")
        check_ranges(self)

    def check_width(self, width: int) -> None:
        """InputError unless a stereogram ``width`` pixels wide holds one strip of the farthest
        separation (W_s + β) and its oversampled width fits a texture (refused before drawing)."""
        if width <= self.far_separation:
            raise InputError(
                f"a stereogram {width} px wide cannot hold one strip of W_s + β = {self.far_separation:g} px: "
                f"give a depth map at least {math.floor(self.far_separation) + 1} px wide, or narrower strips"
            )
        if width * self.oversample > MAX_SIZE:
            raise InputError(
                f"oversampling {self.oversample}× makes a {width} px wide stereogram {width * self.oversample} px "
                f"wide, past the {MAX_SIZE} px texture limit: lower the oversampling or the width"
            )

    @property
    def far_separation(self) -> float:
        """W_s + β: the separation of the farthest depth, pixels (also the guide-dot spacing)."""
        return self.strip_width + self.depth_factor

    @property
    def eye_separation_px(self) -> float:
        """e_p of the screen, pixels."""
        return max_separation_px(self.screen)

    @property
    def depth_range_cm(self) -> tuple[float, float]:
        """[f'_min, f'_max]: the depths behind the screen these separations simulate (equation 4)."""
        return depth_range(self.strip_width, self.depth_factor, self.screen)


#: how the hidden depth image is laid on the host (MultiSceneParams.host_layout)
HOST_LAYOUTS = ("uv", "viewer")


@dataclass(frozen=True)
class MultiSceneParams:
    """host: name or tag of the surface that shows the stereogram. stereogram: its parameters, with
    W_s and β given for a frame ``reference_width`` pixels wide (scaled to the frame actually drawn,
    so the physical separations hold at any size).
    hidden_size: pixels of the hidden depth image's longer side (its aspect is the host's).
    emission: how bright the host glows with its stereogram (a TV: > 0; a painted wall: 0).
    pattern_repeat: pattern tiles across the host (u, v). interactive: orient the hidden scene by
    where the viewer stands relative to the host (Figure 25). spin: degrees per frame the hidden
    scene turns (animated hidden scene). settings: lighting of the main scene (shadows off by
    default: hard shadows on a stereogram disturb it, section 6). reuse_static: while the main scene,
    the view and the settings stay the same from one frame to the next (a still camera on an animated
    TV), only the host is shaded again; the image is the same either way. host_layout: "uv" paints
    the hidden depth image on the host through its uvs (a host seen at an angle shows it
    foreshortened and keystoned); "viewer" lays it out, its aspect kept, across the host's bounding
    rectangle on the screen, so the viewer sees the hidden scene undistorted at any angle (issue 20,
    the paper's Figure 27)."""

    PANEL: ClassVar[str] = "Multi-scene"  # its options' panel in --help

    host: str = param("tv-screen", panel=False, cli=True, help="name or tag of the surface showing the stereogram")
    stereogram: StereogramParams = param(
        default_factory=lambda: StereogramParams(pattern="snow", strip_width=100, depth_factor=40)
    )
    reference_width: int = param(1920, range=(16, 8192), unit="px", panel=False)
    hidden_size: int = param(512, range=(16, 4096), unit="px", step=16, label="hidden depth size")
    emission: float = param(0.9, range=(0.0, 4.0), help="host glow (a TV); 0 for a lit wall", group="output")
    pattern_repeat: tuple[float, float] = param((1.0, 1.0), panel=False, group="output")
    interactive: bool = param(
        False, help="orient the hidden scene by where the viewer stands (Dehos et al. 2014, Figure 25)"
    )
    spin: float = param(0.0, range=(-30.0, 30.0), unit="°/frame", help="the hidden scene turns")
    settings: RenderSettings = param(default_factory=lambda: RenderSettings(shadows=False), group="advanced")
    host_shadows: bool = param(
        False, help="shadows fall on the host too (they break the stereogram's fusion)", group="advanced"
    )
    host_layout: str = param(
        "uv",
        choices=HOST_LAYOUTS,
        help="the hidden scene through the host's uvs, or laid out upright in the viewer's image of it",
        group="advanced",
    )
    reuse_static: bool = param(True, help="a still camera shades only the host again", group="advanced")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        **{f"stereogram.{path}": why for path, why in StereogramParams.NOT_VISIBLE_BY_DEFAULT.items()},
        "stereogram.guides": "a host's stereogram has no guide dots: only the full-frame stereogram (sis) draws them",
        "spin": "turns the hidden scene from one frame to the next: frame 0 is unturned",
        "settings.shadow_tile_size": "shadows are off by default (section 6: they disturb the stereogram)",
        "settings.forward": "the main scene is always lit forward, in the pass that colours the host",
        "host_shadows": "only with settings.shadows on",
        "reuse_static": "speed only: an unchanged view's static shading is kept, the image is the same",
    }

    __post_init__ = check_ranges

    def scaled_stereogram(self, width: int) -> StereogramParams:
        """The stereogram parameters for a frame ``width`` pixels wide."""
        k = width / self.reference_width
        return replace(
            self.stereogram,
            strip_width=self.stereogram.strip_width * k,
            depth_factor=self.stereogram.depth_factor * k,
            screen=replace(
                self.stereogram.screen, width_px=int(round(self.stereogram.screen.width_px * k)), height_px=None
            ),
        )
