"""The engine's state: a hierarchy, its links and its solution, kept across edits.

``Radiosity(polygons, params).build()`` refines and solves; afterwards ``set_lamps`` re-solves with the
links kept (interactive relighting, Loscos 4.4.2) and ``illusio.radiosity.dynamic`` adds lamps and
adds, moves or removes objects, re-linking only what the change touches (Drettakis & Sillion 1997).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError, did_you_mean
from ..core.kernels import compile_note
from ..core.memory import release_free_heap
from ..core.progress import phase
from .clusters import ClusteredGather, ClusterLinks, ClusterTree, refine_nodes, transfer_bound
from .contacts import cut_at_contacts
from .display import corner_average
from .dynamic import add_lamp, add_object, move_object, remove_object
from .hierarchy import Hierarchy
from .links import Links
from .params import HierarchyParams
from .polygons import MAX_POLYGONS, Polygons, polygon_areas
from .refine import channel_max, needs_refinement, refine, transfer_estimate
from .solve import SolveResult, form_factor_scale, push_pull, reflecting_sums, solve
from .visibility import Visibility

#: the first compilation of radiosity's kernels after an install, measured on 2 cores
#: (`NUMBA_CACHE_DIR=EMPTY illusio radiosity cornell-box --size 64x64`: its phase 5.7 s, the run
#: 10.2 s against 2.4 s once compiled)
COMPILE_SECONDS = 10


def _compile_note() -> str:
    from . import formfactor, solve, visibility

    # kernels every build calls (a cluster kernel is not called where no link joins clusters)
    kernels = (solve._push_pull, formfactor._point_polygon, visibility._fraction_and_masks)
    return compile_note("the radiosity kernels", COMPILE_SECONDS, *kernels)


__all__ = ["Radiosity", "Stats", "AUTO_MIN_AREA", "MAX_POLYGONS"]

#: the automatic minimum element area, as a fraction of the scene's total surface area
AUTO_MIN_AREA = 3e-5


@dataclass
class Stats:
    """Sizes and seconds per phase (the CLI's ``--stats``)."""

    elements: int = 0
    leaves: int = 0
    links: int = 0
    #: of the links, those with a cluster at one end or both
    cluster_links: int = 0
    clusters: int = 0
    rays: int = 0
    iterations: int = 0
    #: the last iteration's largest change of B relative to the reflected light (below the tolerance
    #: when the solve converged)
    residual: float = 0.0
    seconds: dict = field(default_factory=dict)

    def add_time(self, phase: str, seconds: float) -> None:
        self.seconds[phase] = self.seconds.get(phase, 0.0) + seconds

    def lines(self) -> list[str]:
        times = ", ".join(f"{k} {v * 1000:.0f} ms" for k, v in self.seconds.items())
        return [
            f"elements {self.elements} ({self.leaves} leaves), links {self.links} ({self.cluster_links} through "
            f"{self.clusters} clusters), rays {self.rays}, "
            f"iterations {self.iterations} (residual {self.residual:.2g})",
            f"time: {times}",
        ]


#: how many times the ratio reach / sums is averaged over the leaves' corners
REACH_SMOOTHING = 2
#: a leaf's links must sum to this much of its hemisphere for it to be scaled to its reach
REACH_MIN_SUM = 0.05
#: the largest factor (and its inverse the smallest) the reach may put on a leaf's links
REACH_MAX_RATIO = 10.0


def smoothed_reach(h: Hierarchy, reach: np.ndarray, sums: np.ndarray) -> np.ndarray:
    """The reach the solve scales each leaf to (n,; NaN where not measured or where the leaf's links
    reach almost nothing): the measured reach averaged REACH_SMOOTHING times over the leaf's corners
    (display.corner_average: the leaves of its surface meeting there), the rays' noise shared out
    (32 rays leave a leaf's reach ±7 %, which scaled each leaf to its own made the Cornell box
    worse); the misses that matter (a ceiling over a lamp at three times its reach, a small leaf
    lit through clusters at a third) span neighbours and survive the mean. The factor on a leaf,
    reach / sums, stays within REACH_MAX_RATIO either way."""
    leaves = h.leaves()
    known = np.isfinite(reach[leaves])
    mean = np.where(known, reach[leaves], 0.0)
    weight = known.astype(np.float64)
    for _ in range(REACH_SMOOTHING):
        mean = corner_average(h, leaves, np.repeat((mean * weight)[:, None], 3, axis=1))[..., 0].mean(axis=1)
        weight = corner_average(h, leaves, np.repeat(weight[:, None], 3, axis=1))[..., 0].mean(axis=1)
        mean = np.where(weight > 0, mean / np.maximum(weight, 1e-300), 0.0)
    # a leaf whose links reach almost nothing is left as it is: a ratio over a near-zero sum (the
    # cluster push's order-2 cosine dips below 0 by up to 4 %) would spread without bound
    total = sums[leaves]
    scaled = known & (total > REACH_MIN_SUM)
    ratio = np.clip(mean / np.where(scaled, total, 1.0), 1 / REACH_MAX_RATIO, REACH_MAX_RATIO)
    out = np.full(len(h), np.nan)
    out[leaves[scaled]] = (total * ratio)[scaled]
    return out


class Radiosity:
    """Hierarchical radiosity over ``polygons`` with ``params`` (HierarchyParams)."""

    def __init__(self, polygons: Polygons, params: HierarchyParams = HierarchyParams()):
        self.params = params
        self._auto_min_area = AUTO_MIN_AREA * float(polygon_areas(polygons.corners, polygons.triangle).sum())
        if params.contact_cuts:  # self.polygons are then the cut ones: h.polygon indexes them
            # at the automatic A_ε whatever min_area is: a finer mesh cuts the same room shell (at
            # RenderPark's 6·10⁻⁴ m² the Graz office's furniture made 19k more roots and 35 % more time)
            polygons = cut_at_contacts(polygons, self._auto_min_area)
        if params.sliver_piece > 0:
            polygons = polygons.split_slivers(params.sliver_piece * np.sqrt(self.min_area))
        if len(polygons) > MAX_POLYGONS and not params.clusters:
            counts = np.bincount(polygons.group, minlength=len(polygons.names))
            worst = int(counts.argmax())
            raise InputError(
                f"without clusters radiosity takes at most {MAX_POLYGONS} input polygons; this scene has "
                f"{len(polygons)}, {counts[worst]} of them in {polygons.names[worst]!r}: link through "
                "clusters (--clusters) or use coarser meshes"
            )
        self.polygons = polygons
        self.hierarchy = Hierarchy(polygons)
        self.visibility = Visibility(self.hierarchy, params.visibility_samples, params.seed)
        self.links = Links()
        self.links.budget = self.params.max_links
        #: the clusters over the input polygons (None without ``params.clusters``) and their links
        self.tree = ClusterTree.build(self.hierarchy) if params.clusters else None
        self.cluster_links = ClusterLinks()
        self.lamp_scale = np.ones(len(polygons.names))  # per group
        self.stats = Stats()
        self.result: SolveResult | None = None
        self._matrix = None
        self.built = False

    @classmethod
    def from_state(
        cls, polygons: Polygons, params: HierarchyParams, hierarchy: Hierarchy, links: Links, lamp_scale: np.ndarray
    ) -> Radiosity:
        """A built solution from its saved parts (the ray-casting scene is made again; its jitter
        starts over from ``params.seed``). Only solutions without clusters are saved."""
        if params.clusters:
            raise InputError("a saved solution holds no cluster links: it must have been built with clusters=False")
        sol = cls.__new__(cls)
        sol.polygons, sol.params, sol.hierarchy, sol.links = polygons, params, hierarchy, links
        sol.visibility = Visibility(hierarchy, params.visibility_samples, params.seed)
        sol.lamp_scale = np.asarray(lamp_scale, np.float64)
        sol.tree, sol.cluster_links = None, ClusterLinks()
        sol.stats, sol.result, sol._matrix, sol.built = Stats(), None, None, True
        sol._update_stats()
        return sol

    # --- what the criterion measures against
    @property
    def power(self) -> float:
        """Φ = Σ E_i·A_i over the roots at full lamp scale (W, max over RGB): ε's unit."""
        h = self.hierarchy
        roots = h.roots[h.active[h.roots]]
        return float((h.exitance[roots] * h.area[roots, None]).sum(axis=0).max())

    @property
    def min_area(self) -> float:
        """A_ε in m² (params.min_area, or 3·10⁻⁵ of the total area of the input when that is 0)."""
        if self.params.min_area > 0:
            return self.params.min_area
        if not hasattr(self, "_auto_min_area"):
            h = self.hierarchy
            self._auto_min_area = AUTO_MIN_AREA * float(h.area[h.roots].sum())
        return self._auto_min_area

    @property
    def threshold(self) -> float:
        return self.params.epsilon * max(self.power, 1e-300)

    def exitance(self) -> np.ndarray:
        """E per element with the lamp scales applied (n, 3)."""
        h = self.hierarchy
        return h.exitance * self.lamp_scale[self.polygons.group[h.polygon]][:, None]

    def ambient_irradiance(self) -> np.ndarray:
        """The ambient irradiance of a closed room of the same power, Φ / (ΣA·(1 − ρ̄)) (RGB, W/m²;
        the estimate of Loscos eq. 4.2): what the criterion assumes of light not yet solved for."""
        h = self.hierarchy
        roots = h.roots[h.active[h.roots]]
        area = h.area[roots]
        rho = (h.reflectance[roots] * area[:, None]).sum(axis=0) / area.sum()
        power = (h.exitance[roots] * area[:, None]).sum(axis=0)
        return power / (area.sum() * np.maximum(1 - rho, 1e-3))

    def _ambient_estimate(self) -> np.ndarray:
        """A first B for the criterion before any solve: E + ρ·(ambient irradiance)."""
        h = self.hierarchy
        return h.exitance + h.reflectance * self.ambient_irradiance()

    # --- building
    def build(self, tolerance: float = 1e-4, max_iterations: int = 200) -> Radiosity:
        """Refine every pair of roots, solve, and re-refine with the solved B (``params.refinements``
        rounds); then, with ``lights_to_leaves``, push the lamps' links down to the leaves."""
        self._link_from_roots(tolerance, max_iterations)
        if self.params.lights_to_leaves:
            self.lights_to_leaves()
            self.solve(tolerance, max_iterations)
        self.built = True
        return self

    def _link_from_roots(self, tolerance: float, max_iterations: int) -> None:
        h = self.hierarchy
        rounds = self.params.refinements
        with phase("radiosity" + _compile_note(), total=rounds) as next_round:
            t = time.perf_counter()
            h.radiosity[:] = self._ambient_estimate()  # children inherit it as they are made
            with phase(f"radiosity: refine, round 1 of {rounds}"):
                if self.tree is not None:
                    self._refine_nodes([self.tree.top], [self.tree.top])
                else:
                    roots = h.roots[h.active[h.roots]]
                    recv, src = np.repeat(roots, len(roots)), np.tile(roots, len(roots))
                    refine(
                        h,
                        self.visibility,
                        recv,
                        src,
                        self.threshold,
                        self.min_area,
                        self.params.criterion,
                        links=self.links,
                    )
            self.stats.add_time("refine", time.perf_counter() - t)
            # refinement's freed batches back to the system before the solve's working set (and the
            # solve's before the next round's refinement): the glibc heap keeps them otherwise
            release_free_heap()
            with phase(f"radiosity: solve, round 1 of {rounds}"):
                self.solve(tolerance, max_iterations)
            release_free_heap()
            next_round()
            for k in range(2, rounds + 1):
                with phase(f"radiosity: refine, round {k} of {rounds}"):
                    refined = self.rerefine()
                release_free_heap()
                if not refined:
                    break
                with phase(f"radiosity: solve, round {k} of {rounds}"):
                    self.solve(tolerance, max_iterations)
                release_free_heap()
                next_round()

    def relink(self, tolerance: float = 1e-4, max_iterations: int = 200) -> None:
        """Drop every link and refine again from the roots over the mesh as it is (its elements are
        reused, new ones made where the criterion asks), then solve: the second pass of Loscos
        4.3.3, links where the criterion puts them instead of at the leaves."""
        self.links = Links()
        self.links.budget = self.params.max_links
        self.cluster_links = ClusterLinks()
        self._matrix = None
        self._link_from_roots(tolerance, max_iterations)

    def rerefine(self, links: np.ndarray | None = None) -> int:
        """Re-test existing links (all, or those where the mask ``links``) against the criterion with
        the current B; refine those that fail. Returns how many were refined."""
        t = time.perf_counter()
        redone = self._rerefine_elements(links)  # its working arrays gone before the clusters' turn
        if links is None and len(self.cluster_links):
            redone += self._rerefine_clusters()
        self.stats.add_time("refine", time.perf_counter() - t)
        return redone

    def _rerefine_elements(self, links: np.ndarray | None) -> int:
        h, L = self.hierarchy, self.links
        tested = np.arange(len(L)) if links is None else np.flatnonzero(links)  # (a drag tests a few)
        r, s = L.receiver[tested], L.source[tested]
        transfer = transfer_estimate(h, r, s, L.form_factor[tested])
        fail = needs_refinement(transfer, L.visibility[tested], self.threshold, self.params.criterion)
        fail &= (h.area[r] / 4 >= self.min_area) | (h.area[s] / 4 >= self.min_area)
        mask = np.zeros(len(L), bool)
        mask[tested[fail]] = True
        del tested, r, s, transfer, fail
        gone = L.remove(mask)
        if len(gone):
            self._drop_gather()
            # the pairs re-enter refinement one level down, so an accepted pair is not re-accepted as is
            self._split_and_refine(gone.receiver, gone.source)
        return len(gone)

    def _drop_gather(self) -> None:
        """The links change: the gather operator and the scale kept with it go before refinement
        (its F·V of every link, 30 MB at RenderPark's element count, and the link buffers it views,
        which the store's growth would otherwise keep, under its working set)."""
        self._matrix = self._scale_kept = None

    def _refine_nodes(self, receivers, sources) -> None:
        refine_nodes(
            self.hierarchy,
            self.tree,
            self.visibility,
            np.asarray(receivers, np.int64),
            np.asarray(sources, np.int64),
            self.threshold,
            self.min_area,
            self.params.criterion,
            self.links,
            self.cluster_links,
        )
        self._matrix = None

    def _rerefine_clusters(self) -> int:
        """Cluster links whose bound fails with the current B go back to refinement (which splits
        them, their bound being above the threshold)."""
        h, tree, C = self.hierarchy, self.tree, self.cluster_links
        b = channel_max(h.radiosity)
        member_max = tree.member_max(b) if len(tree) else b[:0]
        gone = C.remove(transfer_bound(h, tree, C.receiver, C.source, b, member_max, above=self.threshold))
        # refinement holds only the pairs: the removed links' kernels and V go first
        count, receivers, sources = len(gone), gone.receiver, gone.source
        del gone
        if count:
            self._drop_gather()
            self._refine_nodes(receivers, sources)
        return count

    def _split_and_refine(self, recv, src) -> None:
        h = self.hierarchy
        split_src = (h.area[src] >= h.area[recv]) & (h.area[src] / 4 >= self.min_area)
        split_src |= h.area[recv] / 4 < self.min_area
        first_s = h.subdivide(src[split_src])
        first_r = h.subdivide(recv[~split_src])
        quad = np.arange(4)
        r = np.r_[np.repeat(recv[split_src], 4), (first_r[:, None] + quad).reshape(-1)]
        s = np.r_[(first_s[:, None] + quad).reshape(-1), np.repeat(src[~split_src], 4)]
        refine(h, self.visibility, r, s, self.threshold, self.min_area, self.params.criterion, links=self.links)

    def lights_to_leaves(self) -> None:
        """Replace every link from an emitter by links from the same source to each leaf under its
        receiver (F and V computed per leaf)."""
        t = time.perf_counter()
        h, L = self.hierarchy, self.links
        from_lamp = (h.exitance.max(axis=1)[L.source] > 0) & (h.child[L.receiver] >= 0)
        gone = L.remove(from_lamp)
        recv, src = [], []
        for r, s in zip(gone.receiver, gone.source):
            leaves = h.leaves(np.array([r]))
            recv.append(leaves)
            src.append(np.full(len(leaves), s))
        if recv:
            recv, src = np.concatenate(recv), np.concatenate(src)
            self.add_links(recv, src)
        self.stats.add_time("lights to leaves", time.perf_counter() - t)

    def add_links(self, recv: np.ndarray, src: np.ndarray) -> None:
        """Links for these pairs as they are (no refinement): F and V computed."""
        self.links.extend(recv, src, *self.visibility(recv, src))
        self._matrix = None

    # --- solving
    def matrix(self):
        """The gather operator K (``K @ B``: :meth:`Links.gather_operator`, with the cluster links'
        :class:`clusters.ClusteredGather` around it), kept until the links change."""
        if self._matrix is None:
            self._matrix = self.links.gather_operator(len(self.hierarchy))
            if len(self.cluster_links):
                self._matrix = ClusteredGather(self._matrix, self.cluster_links, self.tree, self.hierarchy)
        return self._matrix

    def display_exitance(self) -> np.ndarray:
        """What the smooth display's corner gather adds to the element links' light (n, 3), W/m²:
        E (lamp scales applied) plus ρ times the irradiance the cluster links bring, pushed down to
        every element below its receiver (uniform below a root, as the solve has it), the reflected
        part of it times the solve's scale (:meth:`display_scale`)."""
        exitance = self.exitance()
        if not len(self.cluster_links):
            return exitance
        h = self.hierarchy
        scale = self.display_scale()
        if scale is None:
            return exitance + h.reflectance * self._cluster_light(h.radiosity)
        lamp = self.lamp_radiosity()
        from_lamps = self._cluster_light(lamp)
        reflected = self._cluster_light(h.radiosity - lamp)
        return exitance + h.reflectance * (from_lamps + scale[:, None] * reflected)

    def _cluster_light(self, b: np.ndarray) -> np.ndarray:
        """The irradiance the cluster links bring from radiosities ``b`` (n, 3), pushed down."""
        h = self.hierarchy
        element, moments = self.matrix().cluster_irradiance(b)
        self.tree.push(moments, h.normal, element)
        for level in h.by_level()[1:]:
            element[level] += element[h.parent[level]]
        return element

    def display_scale(self) -> np.ndarray | None:
        """(n,) the solve's factor on each element's reflected light (solve.form_factor_scale: the
        gain cap, and the reach where measured), which the display applies too, so the image shows
        the solve's light; None before a solve or where it is 1 everywhere."""
        scale = None if self.result is None else self.result.scale
        if scale is None or len(scale) != len(self.hierarchy) or np.all(scale == 1.0):
            return None
        return scale

    def lamp_radiosity(self) -> np.ndarray:
        """The lamps' exitance as a radiosity (n, 3), lamp scales applied, pulled up the hierarchy:
        what the display gathers as the lamps' own light."""
        h = self.hierarchy
        return push_pull(h, np.zeros((len(h), 3)), self.exitance(), h.by_level())

    def reach(self) -> np.ndarray | None:
        """Each leaf's reach as the solve takes it (Visibility.reach, then :func:`smoothed_reach`;
        NaN off the leaves), None with ``reach_rays`` 0. Measured once per leaf: after an edit only
        the leaves it made or moved are measured again (moving a reflecting object leaves a room's
        hemispheres much as they were, and measuring every leaf again cost a moved chair seat 0.12
        of a rebuild where the goal is 0.1)."""
        rays = self.params.reach_rays
        if not rays:
            return None
        h = self.hierarchy
        leaves = h.leaves()
        cached = getattr(self, "_reach", None)
        raw = np.full(len(h), np.nan)
        fresh = leaves
        if cached is not None:
            old_raw, old_measured, old_corners = cached
            keep = min(len(old_raw), len(h))
            same = np.zeros(len(h), bool)
            same[:keep] = np.all(h.corners[:keep] == old_corners[:keep], axis=(1, 2)) & old_measured[:keep]
            raw[:keep] = np.where(same[:keep], old_raw[:keep], np.nan)
            fresh = leaves[~same[leaves]]
        matrix = self.matrix()
        smoothed = getattr(self, "_smoothed_reach", None)
        if not len(fresh) and smoothed is not None and smoothed[0] is matrix and len(smoothed[1]) == len(h):
            return smoothed[1]  # a lamp change: nothing it depends on moved
        if len(fresh):
            t = time.perf_counter()
            raw[fresh] = self.visibility.reach(fresh, rays)
            self.stats.add_time("reach", time.perf_counter() - t)
        on_leaves = np.full(len(h), np.nan)
        on_leaves[leaves] = raw[leaves]
        measured = np.zeros(len(h), bool)
        measured[leaves] = True  # NaN too: a leaf with no exposed point stays so until it moves
        self._reach = (on_leaves, measured, h.corners.copy())
        out = smoothed_reach(h, on_leaves, reflecting_sums(h, matrix, h.by_level()))
        self._smoothed_reach = (matrix, out)
        return out

    def solve(self, tolerance: float = 1e-4, max_iterations: int = 200) -> SolveResult:
        t = time.perf_counter()
        matrix, reach = self.matrix(), self.reach()
        self.result = solve(
            self.hierarchy,
            matrix,
            self.exitance(),
            tolerance,
            max_iterations,
            reach=reach,
            scale=self._gather_scale(matrix, reach),
        )
        self.stats.add_time("solve", time.perf_counter() - t)
        self._update_stats()
        if self.result.dark:
            warnings.warn(
                "radiosity: no light reaches any surface (the reflected light is under 1e-9 of the "
                "lamps' exitance): do the lamps face the scene? (a lamp shines to its front)",
                stacklevel=2,
            )
        if not self.result.converged:  # an image made from it would be wrong without a word
            warnings.warn(
                f"radiosity: the solve stopped at its cap of {max_iterations} iterations, the last change "
                f"of B {self.result.change:.2g} of the reflected light (tolerance {tolerance:g}); raise "
                "--max-iterations, or check that the lamps face the scene",
                stacklevel=2,
            )
        return self.result

    def _gather_scale(self, matrix, reach) -> np.ndarray:
        """solve.form_factor_scale, kept while the gather operator and the reflectances are the same
        (a lamp change re-solves with both: the scale's product was 1.2 ms of the office's 15 ms)."""
        h = self.hierarchy
        kept = getattr(self, "_scale_kept", None)
        if (
            kept is not None
            and kept[0] is matrix
            and reach is None
            and kept[1] is None
            and np.array_equal(kept[2], h.reflectance)
        ):
            return kept[3]
        scale = form_factor_scale(h, matrix, h.by_level(), reach)
        self._scale_kept = (matrix, reach, h.reflectance.copy(), scale)
        return scale

    def set_lamps(
        self, scales: dict[str, float] | tuple = (), tolerance: float = 1e-4, max_iterations: int = 200
    ) -> SolveResult:
        """Lamp exitances scaled by name (others back to 1), then re-solved with the links kept."""
        self.lamp_scale = self.lamp_scales(scales)
        return self.solve(tolerance, max_iterations)

    def lamp_scales(self, scales: dict[str, float] | tuple = ()) -> np.ndarray:
        """The per-group scale vector of ``scales`` (by lamp name, others 1), as set_lamps sets it."""
        scales = dict(scales)
        unknown = sorted(set(scales) - set(self.lamp_names))
        if unknown:
            raise InputError(
                f"no lamp named {unknown[0]!r}{did_you_mean(unknown[0], self.lamp_names)}; "
                f"lamps: {', '.join(self.lamp_names) or 'none'}"
            )
        new = np.ones(len(self.polygons.names))
        for name, value in scales.items():
            if not 0 <= float(value) < float("inf"):
                raise InputError(f"lamp {name!r}: a scale must be finite and ≥ 0, got {value!r}")
            new[self.polygons.names.index(name)] = float(value)
        return new

    def links_changed(self) -> None:
        """Forget what was made from the links (the gather operator): for whoever edits the hierarchy
        or the links in place (dynamic updates, relight's shadow refinement)."""
        self._matrix = None

    # --- dynamic updates (illusio.radiosity.dynamic)
    def add_lamp(self, centre, edge_u, edge_v, exitance, name: str, **solve) -> SolveResult:
        """A new rectangular lamp (exitance W/m², RGB), linked at the leaves (Loscos 4.4.1)."""
        return add_lamp(self, centre, edge_u, edge_v, exitance, name, **solve)

    def add_object(self, polygons: Polygons, name: str, **solve) -> SolveResult:
        return add_object(self, polygons, name, **solve)

    def move_object(self, name: str, matrix, **solve) -> SolveResult:
        return move_object(self, name, matrix, **solve)

    def remove_object(self, name: str, **solve) -> SolveResult:
        return remove_object(self, name, **solve)

    @property
    def lamp_names(self) -> list[str]:
        return [self.polygons.names[g] for g in self.polygons.lamps]

    def _update_stats(self) -> None:
        h = self.hierarchy
        self.stats.elements = int(h.active.sum())
        self.stats.leaves = int((h.leaf & h.active).sum())
        self.stats.links = len(self.links) + len(self.cluster_links)
        self.stats.cluster_links = len(self.cluster_links)
        self.stats.clusters = len(self.tree) if self.tree is not None else 0
        self.stats.rays = self.visibility.rays
        self.stats.iterations = self.result.iterations if self.result else 0
        self.stats.residual = self.result.change if self.result else 0.0
