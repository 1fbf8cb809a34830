"""Every knob of hierarchical radiosity (Hanrahan, Salzman & Aupperle 1991, as Loscos' chapter 4 uses
it), with units and ranges. The CLI, the viewer and the benchmarks read their defaults from here."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from ..core.errors import InputError
from ..core.params import check_ranges, param

__all__ = ["HierarchyParams", "RadiosityParams", "CRITERIA", "SHOW"]

#: bf: refine a link when B_j·F_ij·A_i > ε (the chapter's BF: as fine in the shadows as in the light);
#: bfv: when B_j·F_ij·V_ij·A_i > ε (BFV: a shadowed link counts by its visible part, coarser in shadows)
CRITERIA = ("bf", "bfv")
#: radiosity: B/π of the final gather at each pixel (gather_rays > 0) or interpolated from the leaves'
#: corners (Gouraud); mesh: each leaf flat with its edges drawn;
#: links: the radiosity with the links the chosen element receives drawn to their sources
SHOW = ("radiosity", "mesh", "links")


@dataclass(frozen=True)
class HierarchyParams:
    """What builds the hierarchy and its links.

    epsilon: ε of the refinement criterion, as a fraction of the scene's total emitted power
    Φ = Σ E_i·A_i (W): a link from j to i is refined while B_j·F_ij·A_i > ε·Φ (max over RGB), so one
    value suits any scene's scale. min_area: A_ε, elements are not split below this area (m²); 0 takes
    3·10⁻⁵ of the scene's total area (the office: 0.006 m², the Cornell box: 6·10⁻⁵ m²).
    criterion: one of CRITERIA; bf by default: a link partly in shadow is refined as if it were
    lit, so the shadow's edge is placed in the mesh, not averaged over a large element (the living
    room 5.4 → 4.7 % from Mitsuba over 4×4 blocks for 5 % more links; bfv is the chapter's coarser
    final solution, fewer links in shadows). visibility_samples: rays per link for V_ij (a jittered grid of
    that many points on each element, paired). lights_to_leaves: push every link from a light source
    down to the receivers' leaves after refinement (Loscos Figure 4.6b). refinements: refine → solve
    rounds (the first round estimates B from the emitters' power). seed: the ray jitter.
    clusters: link through a hierarchy of clusters above the input polygons (radiosity.clusters:
    the first links are not every pair of polygons, so a scene of 10⁵ polygons solves); off: every
    pair of input polygons is refined from the start (exact form factors everywhere, quadratic in
    the polygon count, at most MAX_POLYGONS). sliver_piece: a quad longer than max(4 × its width,
    sliver_piece·√A_ε) is cut along its length into pieces that long (Polygons.split_slivers; 0: never),
    since an element narrower than √A_ε is never split however the light varies along it.
    contact_cuts: quads of at least 4× the automatic A_ε cut along the lines where other polygons
    touch or cross them (radiosity.contacts: a ceiling that runs on under a wall is cut at the wall's
    face, so no element averages its lit part with the part inside the wall; the Graz office 11.2 →
    8.4 % against Mitsuba). max_links:
    the refinement's budget: past it the refinement stops with an error naming it (a scene whose links
    run away would grow until memory runs out). reach_rays: cosine-weighted rays per leaf measuring
    its reach (Visibility.reach: the share of its hemisphere that meets a reflecting surface), to
    which the solve scales the links' Σ F·V of each leaf's reflected light, the reach averaged over
    neighbouring leaves (engine.smoothed_reach); 0, the default, leaves the sums as the links have
    them. The links miss it where one element stands for many points that see differently: a
    ceiling 8 cm over a lamp, a ceiling's strip inside a wall, a small leaf lit through clusters.
    Measured against Mitsuba over 4×4 blocks at 32 rays: RenderPark's Graz office 15.9 → 10.2 %,
    office3 4.8 → 3.8 %, office2 7.8 → 6.8 %; but the built-in scenes at the radiosity benchmark's
    settings go the other way (the Cornell box 3.0 → 3.9 %, the office 2.7 → 2.9 %, the living room
    4.7 → 5.3 %, past its 5 % goal, the bunny's scan room 3.7 → 3.9 %): where the links' sums were
    right the rays only add their noise, so it is not on by default."""

    PANEL: ClassVar[str] = "Hierarchy"  # its options' panel in --help

    epsilon: float = param(6e-5, range=(1e-9, 1.0), log=True, label="refinement ε (× total power)")
    min_area: float = param(0.0, range=(0.0, 100.0), unit="m²", label="minimum element area A_ε (0: automatic)")
    criterion: str = param("bf", choices=CRITERIA, group="method")
    visibility_samples: int = param(16, range=(1, 256), step=1, help="rays per link for the visibility V_ij")
    lights_to_leaves: bool = param(
        False, help="links from lamps pushed to the receivers' leaves (Loscos 1999, Figure 4.6b)", group="advanced"
    )
    refinements: int = param(2, range=(1, 8), step=1, help="refine, then solve: rounds", group="advanced")
    seed: int = param(
        0, range=(0, 2**31 - 1), step=1, help="visibility rays (and the path tracer of a reference)", group="advanced"
    )
    clusters: bool = param(
        True, help="link through clusters of polygons (off: every pair of input polygons)", group="advanced"
    )
    max_links: int = param(
        50_000_000,
        range=(1_000, 2**31 - 1),
        step=1_000,
        label="link budget",
        help="refinement stops with an error past this many links (memory: about 100 bytes a link)",
        group="advanced",
    )
    sliver_piece: float = param(
        1.0,
        range=(0.0, 100.0),
        label="sliver pieces (× √A_ε, 0: uncut)",
        help="quads longer than 4× their width are cut into pieces this long (× √A_ε)",
        group="advanced",
    )
    contact_cuts: bool = param(
        True,
        label="cut at contacts",
        help="quads cut along the lines where other polygons meet them (a floor under its walls), so no "
        "element averages a part under a wall with a part in the room",
        group="advanced",
    )
    reach_rays: int = param(
        0,
        range=(0, 1024),
        step=1,
        label="reach rays",
        help="cosine-weighted rays per leaf measuring the share of its hemisphere that meets a reflecting "
        "surface; each leaf's reflected light is scaled to it (0: off; only a gain over 0.98 is cut)",
        group="advanced",
    )

    __post_init__ = check_ranges


@dataclass(frozen=True)
class RadiosityParams:
    """A radiosity frame: the hierarchy's params, the solver's stopping rule, the lamps and the display.

    tolerance: stop gather + push-pull when the largest change of B is below tolerance × the largest
    B. max_iterations: at most this many. lamp_scales: (lamp name, factor on its exitance) pairs, the
    sliders of interactive relighting (links kept, only the solve reruns). show: one of SHOW.
    exposure: the displayed value is exposure × B/π (radiance, W/(m²·sr)) before sRGB encoding.
    element: the element whose links ``show="links"`` draws (−1: the brightest receiver's largest).
    textures: each textured element solved with the mean of the texture it covers
    (radiosity.texture_reflectance) and the displayed solution modulated by the textures
    (radiosity.texture_modulation); off, each polygon is solved and drawn with its own mean.
    gather_rays: with show="radiosity", each pixel's light gathered at its own point from the
    solution (radiosity.final_gather: the lamps through exact form factors and ``shadow_rays``
    shadow rays, the reflected light through this many cosine-weighted rays to the solved leaves);
    0 draws the corner gather interpolated across each leaf (Gouraud), as fast as the GPU draws it.
    Against Mitsuba over 4×4 blocks, the corner gather / 64 rays: RenderPark's Graz office 8.4 / 4.0 %,
    office2 6.1 / 4.5 %, the cube 1.6 / 0.7 %."""

    PANEL: ClassVar[str] = "Radiosity"  # its options' panel in --help

    hierarchy: HierarchyParams = param(default_factory=HierarchyParams)
    tolerance: float = param(1e-4, range=(1e-9, 0.5), log=True, group="advanced")
    max_iterations: int = param(200, range=(1, 10000), step=1, group="advanced")
    lamp_scales: tuple = param((), panel=False)
    show: str = param("radiosity", choices=SHOW, group="output")
    exposure: float = param(
        1.0, range=(1e-6, 1e6), log=True, help="scale on the radiance B/π before encoding", group="output"
    )
    textures: bool = param(
        True,
        help="solve each element with the texture it covers and draw the textures (off: each polygon at "
        "its mean reflectance, as a path tracer of untextured polygons sees it)",
        group="output",
    )
    gather_rays: int = param(
        64,
        range=(0, 4096),
        step=1,
        label="final gather rays",
        help="rays a pixel sample gathers the reflected light with, from the solved elements (0: the "
        "elements' corners interpolated, the fast display the viewer walks with)",
        group="output",
    )
    shadow_rays: int = param(
        16,
        range=(1, 1024),
        step=1,
        label="shadow rays",
        help="with the final gather: rays a pixel sample casts to the lamps (drawn by how much each lights it)",
        group="output",
    )
    element: int = param(
        -1,
        range=(-1, 2**31 - 1),
        step=1,
        panel=False,
        cli=True,
        help="show links: the receiving element (-1: the most linked)",
        group="output",
    )

    #: fields that leave the default view's image unchanged, and why (tests/core/test_technique_contract.py)
    NOT_VISIBLE_BY_DEFAULT: ClassVar[dict[str, str]] = {
        "element": "only with show links",
        "hierarchy.criterion": "the final gather draws each pixel's light from the solution, so the mesh's "
        "refinement barely shows (bfv: 0.9/255); with gather_rays 0 it does",
        "hierarchy.refinements": "as hierarchy.criterion: 0.04/255 at 8 rounds through the final gather",
        "hierarchy.max_links": "a budget: the default scene stays far below it (at its low end, refused)",
        "tolerance": "a solve starts from the last solution, which the default view's build leaves within "
        "2/255 of its fixed point at any tolerance up to 0.5 (a fresh build at 0.5 refines on a looser B: "
        "2.7/255)",
        "max_iterations": "a solve starts from the last solution; a fresh build stopped at 1 iteration "
        "differs by 4.3/255",
    }

    def __post_init__(self):
        check_ranges(self)
        for pair in self.lamp_scales:
            if len(pair) != 2 or not isinstance(pair[0], str) or not 0 <= float(pair[1]) < float("inf"):
                raise InputError(f"lamp_scales takes (name, finite factor ≥ 0) pairs, got {pair!r}")

    def scale_of(self, name: str) -> float:
        return float(dict(self.lamp_scales).get(name, 1.0))
