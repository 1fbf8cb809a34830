"""Every knob of relighting a real scene (Loscos 1999, ch. 4), with units and ranges."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.errors import InputError
from ..core.params import check_ranges, param
from ..radiosity import HierarchyParams

__all__ = [
    "RelightParams",
    "METHODS",
    "ESTIMATES",
    "REFERENCE_WEIGHTS",
    "SHOW",
    "INITIAL_HIERARCHY",
    "DEFAULT_SIZE",
    "DEFAULT_PATHS",
]

#: the built-in photograph's size (pixels) and paths a pixel unless asked otherwise: the CLI's
#: defaults, and what the relight benchmark's table is made at
DEFAULT_SIZE, DEFAULT_PATHS = (320, 240), 64

#: what RelightSession.show draws (``illusio relight --show``)
SHOW = ("image", "textures", "mesh", "display-factor", "registration")

#: baseline: the system as initialised in 4.2.1 (textures of the photograph modulated by B/D, eq. 4.3):
#: a lamp switched off leaves its photographed shadows (the limitation of 4.2.2). loscos: the mesh
#: refined along the photographed shadows (4.3.1, relight.shadow_refine), then the textures of 4.3.2
#: (blocked energy added, shadowed elements corrected from a lit reference), shown with D = B + ρĒ.
#: per-pixel: the photograph scaled at each pixel by the change of its irradiance, lamp by lamp with
#: per-pixel visibility (the chapter's conclusion; relight.per_pixel). loscos is the default: at the
#: CLI's defaults it has the least error of the three over the whole image (mean over the edits of
#: Figure 4.17 and a virtual lamp 0.088, baseline 0.094) and in the photographed shadows (0.104,
#: baseline 0.144; benchmarks/RESULTS.md, issue 33).
METHODS = ("baseline", "loscos", "per-pixel")

#: brightness: the chapter's estimates of 4.2.1 — each element's ρ from its brightness (eq. 4.1), every
#: lamp the same exitance from the energy balance (eq. 4.2). inverse: each seen leaf's ρ explains its
#: own photographed light, ρ = π·B̂/H, alternated with the solve until it settles (relight.estimate.
#: reflectance_from_irradiance); each lamp's exitance from its own pixels where the photograph holds
#: them unclipped (a high-dynamic-range photograph), eq. (4.2) for the others. The chapter's conclusion
#: asks for it; with eq. 4.1's ρ the texture work of 4.3 cannot beat the baseline in the shadows
#: (benchmarks/RESULTS.md, issue 33: an oracle with the true ρ and E shows that estimate is what
#: holds the shadow error up).
ESTIMATES = ("brightness", "inverse")
#: w of eq. (4.9), T_final = (ρ_corr/ρ_inter)^w · T_inter: blocked-share, the share of the leaf's
#: direct light that is blocked (relight.textures.correction_weight); full, w = 1 as the chapter has it
REFERENCE_WEIGHTS = ("blocked-share", "full")
#: ρ = π·B̂/H alternates with the solve until the median relative change of the seen leaves' ρ is
#: under INVERSE_TOLERANCE, at most INVERSE_MAX_ITERATIONS times (the office at the CLI's defaults:
#: 14 times for loscos, 17 for the baseline, each change about 0.8× the last; the baseline's B is
#: then within 1 % of π·B̂ at the median leaf, 27 % after eq. 4.1)
INVERSE_TOLERANCE, INVERSE_MAX_ITERATIONS = 0.01, 40

#: the initial solution of 4.2.1: "la subdivision initiale, obtenue avec un critère de raffinement BF,
#: est grossière" (Figure 4.6a) — BF, at a coarser ε than a radiosity frame's default
INITIAL_HIERARCHY = HierarchyParams(criterion="bf", epsilon=3e-3, clusters=False)
#: the fresh solution of 4.3.3 is the chapter's BFV one ("un critère de raffinement BFV": coarser in
#: the shadows, fewer links). Relighting reads element links (a lamp's shadow masks, the frontier,
#: the corner gather): its solutions link every pair of polygons, without clusters
FINAL_HIERARCHY = HierarchyParams(criterion="bfv", clusters=False)


#: metres on a side of a virtual lamp added by the CLI, the viewer or ``RelightSession.add_lamp``
VIRTUAL_LAMP_SIZE = 0.4


@dataclass(frozen=True)
class RelightParams:
    """method: one of METHODS. mean_reflectance: ρ̂ of eq. (4.1), the user's first guess of the scene's
    mean reflectance (re-estimated from the photograph afterwards). colour_threshold: the largest
    CIE L*a*b* distance (eq. 4.4) between two colours called similar — neighbours in Figure 4.7, a
    shadowed element and its reference in Figure 4.11. visibility_threshold: the largest difference of
    a lamp's visibility V between two elements called similar (Figure 4.7; the types must match too).
    estimate: one of ESTIMATES, how ρ and the lamps' exitances are read from the photograph (every
    method). texture_refinement: loscos runs 4.3.1 (off: the initial mesh is kept, for comparison).
    reference_correction: loscos corrects each shadowed leaf by its reference (eqs. 4.8/4.9; off:
    T_inter of eq. 4.6 alone, for comparison). reference_weight: one of REFERENCE_WEIGHTS. min_pixels:
    4.3.1 splits only elements covering at least this many photograph pixels. hierarchy: the initial
    radiosity solution (default: BF at ε 3e-3, the chapter's coarse start, Figure 4.6a; with loscos the
    lamps' links are pushed to the leaves). fresh_solution: loscos ends as the chapter mostly does
    (4.3.3): the mesh and links made again with ``final_hierarchy`` (default: BFV, as the
    chapter has it) over the final textures, D computed with the lamps' links at the leaves, then B with
    the links where the criterion puts them. Both keep the model's own polygons (their sliver_piece is
    taken as 0 and contact_cuts as off: the photograph's textures and pixels are keyed to the input
    polygons) and their links' own form-factor sums (reach_rays taken as 0: the estimates were
    measured with them). lamp_scales: (lamp name, factor on its estimated exitance) pairs. exposure:
    factor on the displayed radiance."""

    PANEL: ClassVar[str] = "Relighting"  # its options' panel in --help

    method: str = param("loscos", choices=METHODS, group="method")
    estimate: str = param(
        "inverse",
        choices=ESTIMATES,
        help="brightness: Loscos eqs. 4.1/4.2 as the chapter; inverse: ρ = π·(pixel radiance)/H, "
        "lamps from their own pixels",
        group="method",
    )
    mean_reflectance: float = param(0.5, range=(0.01, 0.95), label="mean reflectance (first guess, Loscos eq. 4.1)")
    colour_threshold: float = param(20.0, range=(0.0, 200.0), label="colour similarity ε (CIE L*a*b*, Fig. 4.7, 4.11)")
    visibility_threshold: float = param(0.3, range=(0.0, 1.0), label="visibility similarity (Fig. 4.7)")
    texture_refinement: bool = param(True, help="loscos: split leaves along the photographed shadows (4.3.1)")
    reference_correction: bool = param(
        True,
        help="loscos: correct each shadowed leaf's texture by its reference "
        "leaf's (eqs. 4.8, 4.9); off: the blocked light added alone (4.6)",
    )
    reference_weight: str = param(
        "blocked-share",
        choices=REFERENCE_WEIGHTS,
        help="loscos: how much of Loscos eq. 4.9's correction a shadowed leaf takes — "
        "in proportion to the share of its direct light blocked, or in full (the chapter)",
    )
    min_pixels: int = param(
        4, range=(1, 10000), step=1, help="4.3.1 splits only leaves covering this many pixels", group="advanced"
    )
    hierarchy: HierarchyParams = param(
        default_factory=lambda: INITIAL_HIERARCHY, help="the initial radiosity solution (BF at a coarse ε)"
    )
    fresh_solution: bool = param(
        False, help="loscos: end with a fresh BFV solution over the final textures (4.3.3)", group="advanced"
    )
    final_hierarchy: HierarchyParams = param(default_factory=lambda: FINAL_HIERARCHY, panel=False, group="advanced")
    lamp_scales: tuple = param((), panel=False)
    exposure: float = param(1.0, range=(1e-6, 1e6), log=True, help="factor on the displayed radiance", group="output")

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "hierarchy.lights_to_leaves": "loscos, the default method, pushes the lamps' links to the leaves (4.3.2)",
        "hierarchy.clusters": "refused: relighting reads element links, its solutions take clusters=False",
        "hierarchy.sliver_piece": "relighting keeps the model's own polygons (taken as 0)",
        "hierarchy.contact_cuts": "relighting keeps the model's own polygons (taken as off)",
        "hierarchy.reach_rays": "relighting keeps its links' own form-factor sums, which its photograph "
        "estimates were measured with (taken as 0)",
        "hierarchy.max_links": "a budget: the default scene stays far below it (at its low end, refused)",
    }

    def __post_init__(self):
        check_ranges(self)
        if self.hierarchy.clusters or self.final_hierarchy.clusters:
            raise InputError(
                "relighting reads element links (shadow masks, frontier): its solutions take "
                "clusters=False (--no-clusters)"
            )
        for pair in self.lamp_scales:
            if len(pair) != 2 or not isinstance(pair[0], str) or not 0 <= float(pair[1]) < float("inf"):
                raise InputError(f"lamp_scales takes (name, finite factor ≥ 0) pairs, got {pair!r}")
        if self.fresh_solution and self.method != "loscos":
            raise InputError(f"the fresh solution of 4.3.3 follows the loscos textures; method is {self.method!r}")
