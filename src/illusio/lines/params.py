"""Every knob of a line drawing and of the curvature estimate it draws from, with units, ranges and
the report's symbols (Judd et al. 2007; Jardim & de Figueiredo's hybrid method as the report
describes it). The CLI, the gallery and the viewer read their defaults from here."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.params import check_ranges, param
from .reference import REPORT_THRESHOLD

__all__ = ["LINE_TYPES", "METHODS", "SILHOUETTE_SPACES", "LineParams", "CurvatureParams"]

LINE_TYPES = (
    "apparent-ridges",
    "silhouettes",
    "suggestive",
    "ridges",
    "valleys",
    "boundaries",
    "k-zero",
    "h-zero",
    "isophotes",
    "suggestive-highlights",
    "principal-highlights",
    "dwkr",
)
METHODS = ("hybrid", "object-space")
SILHOUETTE_SPACES = ("object", "image")

#: linear RGB per line type
DEFAULT_COLOURS = (
    ("apparent-ridges", (0.0, 0.0, 0.0)),
    ("silhouettes", (0.0, 0.0, 0.0)),
    ("suggestive", (0.05, 0.1, 0.45)),
    ("ridges", (0.55, 0.05, 0.05)),
    ("valleys", (0.05, 0.35, 0.1)),
    ("boundaries", (0.0, 0.0, 0.0)),
    ("k-zero", (0.45, 0.2, 0.0)),
    ("h-zero", (0.3, 0.0, 0.4)),
    ("isophotes", (0.4, 0.4, 0.4)),
    ("suggestive-highlights", (0.75, 0.45, 0.0)),
    ("principal-highlights", (0.85, 0.6, 0.1)),
    ("dwkr", (0.8, 0.1, 0.5)),
)
#: pixels per line type (object-space lines)
DEFAULT_WIDTHS = (
    ("apparent-ridges", 1.5),
    ("silhouettes", 2.0),
    ("suggestive", 1.5),
    ("ridges", 1.5),
    ("valleys", 1.5),
    ("boundaries", 2.0),
    ("k-zero", 1.5),
    ("h-zero", 1.5),
    ("isophotes", 1.0),
    ("suggestive-highlights", 2.0),
    ("principal-highlights", 2.0),
    ("dwkr", 1.0),
)


@dataclass(frozen=True)
class CurvatureParams:
    """How the per-vertex curvature is estimated (lines.curvature.estimate_curvature): a jet of
    ``degree`` on at least ``rings`` rings, then ``smoothing`` passes of tensor averaging; with
    ``adaptive``, lower degrees on up to ``extra_rings`` more rings join under the ICI rule at
    ``confidence``. Part of the line renderer's cache key: a change re-estimates."""

    PANEL: ClassVar[str] = "Curvature"  # its options' panel in --help

    rings: int = param(2, range=(1, 8), step=1, help="smallest neighbourhood, in edge rings")
    degree: int = param(4, choices=(2, 3, 4), help="jet degree")
    smoothing: int = param(3, range=(0, 8), step=1, help="passes of tensor averaging over the 1-ring")
    adaptive: bool = param(False, help="ICI choice among lower degrees and more rings")
    extra_rings: int = param(1, range=(0, 8), step=1, help="rings beyond the start for adaptive fits", group="advanced")
    confidence: float = param(2.0, range=(0.1, 10.0), help="ICI confidence factor", group="advanced")

    __post_init__ = check_ranges


@dataclass(frozen=True)
class LineParams:
    """lines: which line types to draw (LINE_TYPES). method: apparent ridges by the hybrid GPU method
    or Judd's object-space method. tau: τ, q = 2^τ q1 (/ curvature scale when relative).
    lam: λ of the adaptive Laplacian. threshold: the ridge filter's response threshold (0.2 in the
    report). object_threshold: q1 / scale above which object-space apparent ridges are kept.
    ridge_threshold: abs(k) / scale for ridges and valleys. suggestive_threshold: D_w κ_r / scale² (and
    the level of the DwKr lines). highlight_threshold: the strength of suggestive highlights
    (−D_w κ_r / scale²) and principal highlights ((k_max² − k_min²)·n·v / scale²) kept.
    silhouette_space: "object" (zero crossings of n·v) or "image" (depth discontinuities).
    depth_jump: an image silhouette where a neighbour is farther by more than this share of depth.
    min_ridge_pixels: hybrid ridge fragments of fewer pixels (8-connected; counted at 1024 px and
    scaled with the image's longer side) are dropped — a scan's small bumps otherwise hatch the
    surface, as Judd's length threshold prunes short object-space ridges; 0 keeps every fragment.
    colours (linear RGB) and widths (pixels, object-space lines): (line type, value) pairs.
    curvature: how the curvature is estimated (:class:`CurvatureParams`)."""

    PANEL: ClassVar[str] = "Line drawing"  # its options' panel in --help

    lines: tuple[str, ...] = param(
        ("apparent-ridges", "silhouettes"), choices=LINE_TYPES, multiple=True, label="line types", group="method"
    )
    method: str = param("hybrid", choices=METHODS, help="apparent ridges: hybrid GPU or object space", group="method")
    tau: float = param(-2.0, range=(-12.0, 12.0), label="τ", help="q = 2^τ q1")
    lam: float = param(
        0.5, range=(0.0, 16.0), label="λ", help="direction weight of the adaptive Laplacian", flag="lambda"
    )
    threshold: float = param(REPORT_THRESHOLD, range=(0.0, 100.0), help="ridge filter response threshold")
    relative: bool = param(
        True,
        help="thresholds relative to the mesh's curvature scale (raw: the report's τ, q1 in 1/mesh units)",
        flag="relative/raw",
    )
    object_threshold: float = param(0.2, range=(0.0, 100.0), help="object-space apparent ridges: q1 / scale")
    ridge_threshold: float = param(1.0, range=(0.0, 100.0), help="ridges and valleys: |k| / scale")
    suggestive_threshold: float = param(0.05, range=(0.0, 100.0), help="suggestive contours: D_w κ_r / scale²")
    isophote_level: float = param(0.5, range=(0.0, 1.0), help="isophotes: the n·l they follow (headlight)")
    highlight_threshold: float = param(
        0.05,
        range=(0.0, 100.0),
        help="suggestive highlights: −D_w κ_r / scale²; principal: (k_max² − k_min²) n·v / scale²",
    )
    silhouette_space: str = param(
        "object",
        choices=SILHOUETTE_SPACES,
        flag="silhouettes",
        help="object: n·v = 0 zero crossings; image: depth edges",
        group="advanced",
    )
    depth_jump: float = param(0.05, range=(0.0, 10.0), help="image silhouettes: relative depth jump", group="advanced")
    min_ridge_pixels: int = param(
        24, range=(0, 100000), step=1, unit="px", help="drop shorter ridge fragments", group="advanced"
    )
    colours: tuple = param(DEFAULT_COLOURS, panel=False, group="output")
    widths: tuple = param(DEFAULT_WIDTHS, panel=False, group="output")
    curvature: CurvatureParams = param(default_factory=CurvatureParams, group="advanced")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "object_threshold": "only with method object-space",
        "ridge_threshold": "only where ridges or valleys are drawn",
        "suggestive_threshold": "only where suggestive contours or DwKr lines are drawn",
        "isophote_level": "only where isophotes are drawn",
        "highlight_threshold": "only where suggestive or principal highlights are drawn",
        "depth_jump": "only with the image-space silhouettes",
        "curvature.confidence": "only with adaptive fits (curvature.adaptive)",
    }

    def __post_init__(self):
        object.__setattr__(self, "lines", tuple(self.lines))
        check_ranges(self)

    def colour(self, kind: str) -> tuple[float, float, float]:
        """The linear RGB colour of a line type."""
        return dict(self.colours)[kind]

    def width(self, kind: str) -> float:
        """The width in pixels of a line type."""
        return dict(self.widths)[kind]
