"""A relighting session: the real scene prepared once (estimates, hierarchy, display factor), then
edits that each return the new image.

Preparation (Loscos 4.2.1): the polygon under each pixel of the photograph gives B̂_i (mean pixel of
polygon i) and B̂_A (mean over every non-lamp pixel); eq. (4.1) with the user's ρ̂, ρ̂ re-estimated as
the area-weighted mean, eq. (4.1) again; polygons the photograph does not see get ρ̂. Eq. (4.2) gives
every lamp the same exitance. The hierarchy is built and solved; each leaf the photograph sees then
takes its own ρ from eq. (4.1) with its pixels (the chapter's update at subdivision), inner elements
the area-weighted mean of their children's, and the solution is solved again. The display factor D
is that B, kept at the leaves' corners. With the inverse estimate (``RelightParams.estimate``, the
default) each lamp the photograph shows unclipped and from the front takes π × its mean pixel
instead of eq. (4.2)'s share, and each seen leaf's ρ is then set to π·B̂/H, H the irradiance the
solution gathers there, alternated with the solve until it settles (``INVERSE_TOLERANCE``): the ρ that explains the
leaf's photographed light rather than its brightness.

Display, eq. (4.3): (B/D)·T per pixel, with B and D interpolated from the corners (smooth, as the
chapter does) and T the photograph itself (view-dependent textures: the model is seen from the
photograph's camera only). The ratio is drawn in a float framebuffer, so no multi-pass brightening
is needed where B > D (the chapter's annex A did that on 1999 hardware).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..radiosity import DisplayPass, Polygons, RadiosityParams, RadiosityRenderer, leaf_mesh
from ..radiosity.corner_cache import CornerGather
from ..radiosity.display import corner_average
from . import estimate, textures
from .params import INVERSE_MAX_ITERATIONS, INVERSE_TOLERANCE, SHOW, VIRTUAL_LAMP_SIZE, RelightParams
from .photograph import RealScene, polygon_ids
from .registration import overlay, registration
from .shadow_refine import refine_by_texture
from .state import load_session, save_session

__all__ = ["RelightSession"]


class RelightSession:
    def __init__(self, real: RealScene, params: RelightParams = RelightParams(), ctx: Context | None = None):
        self.real, self.params = real, params
        self.ctx = ctx or default_context()
        self.times: dict[str, float] = {}
        start = time.perf_counter()
        self.model, self.mean_reflectance = self._estimate()
        self.renderer = RadiosityRenderer(self.ctx)
        self.renderer.prepare(self.model)
        # the model's own polygons, uncut: the photograph's textures and pixels are keyed to them
        self.hierarchy_params = dataclasses.replace(params.hierarchy, sliver_piece=0.0)
        if params.method == "loscos":
            self.hierarchy_params = dataclasses.replace(self.hierarchy_params, lights_to_leaves=True)
        self.solution = self.renderer.solve(RadiosityParams(self.hierarchy_params))
        self.display = DisplayPass(self.ctx)
        self._gather = CornerGather()  # the corners' form factors, kept between edits
        if params.method == "loscos" and params.texture_refinement:
            self._refine_by_texture()
        self._textures_to_leaves()
        self.display_factor = leaf_mesh(
            self.solution.hierarchy, self.solution.links, self.solution.exitance(), gather=self._gather
        )
        self.texture_factor = np.ones((len(self.solution.hierarchy), 3))
        if params.method == "loscos":
            self._visibility_independent_textures()
        if params.method == "per-pixel":
            self._per_pixel_prepare()
        self.texture = (self.real.photograph * self._pixel_texture_factor()).astype(np.float32)
        self._store_display_factor()
        if params.method == "loscos" and params.fresh_solution:
            self._fresh_solution()
        self.virtual_groups: set[int] = set()
        self.scales: dict[str, float] = {}
        if params.method != "per-pixel":
            self._geometry_key = (len(self.solution.hierarchy), len(self.solution.links), tuple(self.lamp_names))
            self._corner_radiosity()  # the lamps' basis: part of the preparation
        self._prepare_rims()
        self.times["prepare"] = time.perf_counter() - start

    # --- preparation ---------------------------------------------------------------------------
    def _estimate(self) -> tuple[Polygons, np.ndarray]:
        p, photo = self.real.polygons, self.real.photograph.astype(np.float64)
        ids = polygon_ids(p, self.real.view, self.real.size)
        self.pixel_polygon = ids
        lamp = np.isin(p.group, p.lamps)
        # a surface the model gives an exitance but that is not a lamp (a monitor's screen) shines by
        # itself: not relit, its exitance taken from the photograph, its reflectance 0
        glowing = (p.exitance.max(axis=1) > 0) & ~lamp
        seen = ids >= 0
        surface = seen & ~lamp[np.maximum(ids, 0)]
        if not surface.any():
            raise InputError("the camera sees none of the scene's (non-lamp) geometry")
        mean_scene = photo[surface].mean(axis=0)  # B̂_A (radiance)
        count = np.bincount(ids[surface], minlength=len(p))
        total = np.stack(
            [np.bincount(ids[surface], weights=photo[surface][:, c], minlength=len(p)) for c in range(3)], axis=1
        )
        visible = (count > 0) & ~lamp & ~glowing
        from ..radiosity.polygons import polygon_areas

        areas = polygon_areas(p.corners, p.triangle)
        rho = np.zeros((len(p), 3))
        rho_visible, rho_hat = estimate.reestimated_reflectance(
            total[visible] / count[visible, None], mean_scene, self.params.mean_reflectance, areas[visible]
        )
        rho[visible] = rho_visible
        rho[~visible & ~lamp & ~glowing] = rho_hat
        exitance = np.zeros((len(p), 3))
        seen_glow = glowing & (count > 0)
        exitance[seen_glow] = np.pi * total[seen_glow] / count[seen_glow, None]
        exitance[glowing & ~seen_glow] = np.pi * mean_scene
        glow_power = (exitance[glowing] * areas[glowing, None]).sum(axis=0)
        exitance[lamp] = estimate.lamp_exitance(
            rho_hat, mean_scene, float(areas[~lamp].sum()), float(areas[lamp].sum()), other_power=glow_power
        )
        if self.params.estimate == "inverse":
            self._lamps_from_pixels(exitance)
        self.mean_scene = mean_scene
        return Polygons(p.corners, p.triangle, rho, exitance, p.group, list(p.names), list(p.lamps)), rho_hat

    def _lamps_from_pixels(self, exitance: np.ndarray) -> None:
        """The inverse estimate's lamps: each lamp group whose pixels (eroded by one, off its rim) the
        photograph holds unclipped takes E = π × their mean; the others keep eq. (4.2)'s."""
        from scipy import ndimage

        p, ids, photo = self.real.polygons, self.pixel_polygon, self.real.photograph
        # a photograph that never passes 1 is a low-dynamic-range one: its lamps clip there
        saturation = None if float(photo.max()) > 1.0 else 1.0
        eye = np.asarray(self.real.view.pose.position, np.float64)
        normals, centres = p.normals(), p.corners.mean(axis=1)
        self.lamps_read = []
        for g in p.lamps:
            rows = p.group == g
            if ((eye - centres[rows]) * normals[rows]).sum(axis=1).min() <= 0:
                continue  # seen from behind (or edge-on): its pixels are not its light
            own = ndimage.binary_erosion((ids >= 0) & (p.group[np.maximum(ids, 0)] == g))
            read = estimate.lamp_exitance_from_pixels(photo[own], saturation)
            if read is not None and read.max() > 0:
                exitance[rows] = read
                self.lamps_read.append(p.names[g])

    def _leaf_pixels(self, values: np.ndarray | None = None, element: np.ndarray | None = None):
        """(pixels seen per element (n,), the mean of ``values`` (H, W, 3; default the photograph's
        radiance) over them (n, 3)) for the non-emitting elements under ``element`` (default
        ``pixel_element``)."""
        h = self.solution.hierarchy
        element = self.pixel_element if element is None else element
        values = self.real.photograph.astype(np.float64) if values is None else values
        seen = (element >= 0) & (h.exitance[np.maximum(element, 0)].max(axis=-1) == 0)
        count = np.bincount(element[seen], minlength=len(h))
        total = np.stack(
            [np.bincount(element[seen], weights=values[seen][:, c], minlength=len(h)) for c in range(3)], axis=1
        )
        return count, total / np.maximum(count, 1)[:, None]

    def _textures_to_leaves(self) -> None:
        """Each seen leaf's ρ from its own pixels — eq. (4.1), or with the inverse estimate ρ = πB̂/H
        alternated with the solve — pulled up the tree, then solved again."""
        sol = self.solution
        h = sol.hierarchy
        self.pixel_element = self._pixel_leaf()
        count, mean_pixels = self._leaf_pixels()
        leaves = h.leaves()
        lit = leaves[count[leaves] > 0]
        h.reflectance[lit] = estimate.reflectance_from_photograph(
            mean_pixels[lit], self.mean_scene, self.mean_reflectance
        )
        self._pull_reflectance()
        sol.solve()
        if self.params.estimate == "inverse":
            self.inverse_iterations = 0
            while self.inverse_iterations < INVERSE_MAX_ITERATIONS:
                before = h.reflectance[lit].mean(axis=1)
                h.reflectance[lit] = estimate.reflectance_from_irradiance(
                    mean_pixels[lit], self._leaf_irradiance()[lit]
                )
                self._pull_reflectance()
                sol.solve()
                self.inverse_iterations += 1
                change = np.abs(h.reflectance[lit].mean(axis=1) - before) / np.maximum(before, 1e-6)
                if not len(lit) or np.median(change) < INVERSE_TOLERANCE:
                    break

    def _leaf_irradiance(self) -> np.ndarray:
        """H per element (n, 3): the irradiance gathered at it and at every ancestor (links may end
        above the leaves), W/m²."""
        h = self.solution.hierarchy
        total = h.irradiance.copy()
        for lv in h.by_level()[1:]:
            total[lv] += total[h.parent[lv]]
        return total

    def _pixel_leaf(self) -> np.ndarray:
        """The leaf seen through each pixel of the photograph (H, W) int, −1 where none."""
        self.display.load(leaf_mesh(self.solution.hierarchy, smooth=False))
        colour, element = self.display(self.real.view, self.real.size)
        out = self.ctx.readback_image(element, 1, clip=False)[..., 0].astype(np.int64)
        self.ctx.release(colour, element)
        return out

    def _refine_by_texture(self) -> None:
        """Loscos 4.3.1 (relight.shadow_refine), then the solution solved on the new leaves."""
        t = time.perf_counter()
        photo = self.real.photograph
        surface = self.pixel_polygon >= 0
        surface &= self.model.exitance[np.maximum(self.pixel_polygon, 0)].max(axis=-1) == 0
        luminance = photo[surface] @ np.array([0.2126, 0.7152, 0.0722]) if surface.any() else np.ones(1)
        white = float(np.percentile(luminance, 99))
        p = self.params
        self.refine_stats = refine_by_texture(
            self.solution, self._pixel_leaf, photo, white, p.colour_threshold, p.visibility_threshold, p.min_pixels
        )
        self.solution.solve()
        self.times["texture refinement"] = time.perf_counter() - t

    def _pull_reflectance(self) -> None:
        h = self.solution.hierarchy
        for lv in h.by_level()[-2::-1]:
            inner = lv[h.child[lv] >= 0]
            if len(inner):
                c = h.child[inner][:, None] + np.arange(4)
                h.reflectance[inner] = (h.area[c][..., None] * h.reflectance[c]).sum(axis=1) / h.area[inner][:, None]

    def _visibility_independent_textures(self) -> None:
        """Loscos 4.3.2 (relight.textures): per-leaf texture factors, the final reflectances, the new
        solution and its display factor D = B + ρĒ at the leaves' corners."""
        sol = self.solution
        h = sol.hierarchy
        leaves = h.leaves()
        rho = h.reflectance[leaves].copy()
        b_orig = h.radiosity[leaves]
        _, blocked, free, lit, shadowed = textures.lamp_transfer(h, sol.links, leaves)
        indirect = self._indirect()[leaves]
        # a leaf whose blocked light is a small share of what it would receive is in no shadow worth
        # the name (a monitor's light grazing the ceiling): its photograph is kept, and it may serve
        # as a reference
        significant = blocked.sum(axis=1) > textures.BLOCKED_SHARE * (free + indirect).sum(axis=1)
        lit = lit | (~significant & (free.sum(axis=1) > 0))
        shadowed &= significant
        shadowed &= h.exitance[leaves].max(axis=1) == 0  # a self-luminous leaf keeps its texture
        inter = np.where(b_orig > 0, (b_orig + rho * blocked) / np.where(b_orig > 0, b_orig, 1), 1.0)  # eq. 4.6
        count, mean_pixels = self._leaf_pixels()
        seen = count[leaves] > 0
        # ρ_inter: T_inter read as eq. 4.1 reads a texture (its brightness; the scale cancels in 4.9)
        rho_inter = mean_pixels[leaves] * inter / np.maximum(self.mean_scene, 1e-12) * self.mean_reflectance
        # the colour compared by Figure 4.11: the leaf's reflectance once unoccluded
        colour = np.clip(rho * inter if self.params.estimate == "brightness" else rho, 0, estimate.MAX_REFLECTANCE)
        near = textures.neighbours(h, leaves)
        frontier = lit & seen & np.array([bool(len(n)) and shadowed[n].any() for n in near])
        group = self.model.group[h.polygon[leaves]]
        ref = textures.references(h, leaves, shadowed, frontier, group, colour, self.params.colour_threshold)
        factor = inter.copy()
        fix = (ref >= 0) & seen & self.params.reference_correction
        r = ref[fix]
        # eq. 4.8 with the indirect irradiance I in both sums: the texture holds indirect light too, and
        # with the lamps' form factors alone a leaf nearer a lamp than its reference came out too bright
        unoccluded = free + indirect
        ratio = unoccluded[fix].sum(axis=1) / np.maximum(unoccluded[r].sum(axis=1), 1e-300)
        rho_corr = rho_inter[r] * ratio[:, None]  # eq. 4.8
        correction = rho_corr / np.maximum(rho_inter[fix], 1e-6)
        weight = (
            textures.correction_weight(blocked[fix], free[fix])
            if self.params.reference_weight == "blocked-share"
            else 1.0
        )
        factor[fix] = inter[fix] * correction ** np.reshape(weight, (-1, 1))  # eq. 4.9
        self.references = (leaves, ref)
        self.shadowed = shadowed
        # ρ_final: the brightness of T_final (4.1), or the inverse estimate's ρ times what 4.9 changed
        texture_change = factor if self.params.estimate == "brightness" else factor / inter
        h.reflectance[leaves] = np.clip(rho * texture_change, 0, estimate.MAX_REFLECTANCE)
        self._pull_reflectance()
        sol.solve()
        final = leaf_mesh(h, sol.links, sol.exitance(), gather=self._gather)
        _, blocked, _, _, _ = textures.lamp_transfer(h, sol.links, leaves)
        final.radiance = final.radiance + np.repeat(h.reflectance[leaves] * blocked / np.pi, 4, axis=0).astype(
            np.float32
        )
        self.display_factor = final
        self.texture_factor[leaves] = factor

    def _fresh_solution(self) -> None:
        """Loscos 4.3.3, the chapter's usual end: a new solution over the final textures. Pass one:
        mesh and links made with ``final_hierarchy`` and the lamps' links at the leaves, each leaf's ρ
        the mean over its pixels of the final ρ, D = B + ρĒ at the corners. Pass two: the links made
        again on that mesh where the criterion puts them, and solved: the B that is displayed. The
        textures (T_final) stay those of the 4.3 mesh."""
        t = time.perf_counter()
        old = self.solution.hierarchy
        rho_map = old.reflectance[np.maximum(self.pixel_element, 0)]
        model = dataclasses.replace(self.model, reflectance=old.reflectance[old.roots[: len(self.model)]].copy())
        from ..radiosity import Radiosity

        sol = Radiosity(
            model, dataclasses.replace(self.params.final_hierarchy, lights_to_leaves=True, sliver_piece=0.0)
        ).build()
        self.solution, self._gather = sol, CornerGather()
        h = sol.hierarchy
        element = self._pixel_leaf()
        count, mean_rho = self._leaf_pixels(rho_map, element)
        leaves = h.leaves()
        lit = leaves[count[leaves] > 0]
        h.reflectance[lit] = np.clip(mean_rho[lit], 0, estimate.MAX_REFLECTANCE)
        self._pull_reflectance()
        sol.solve()
        final = leaf_mesh(h, sol.links, sol.exitance(), gather=self._gather)
        _, blocked, _, _, _ = textures.lamp_transfer(h, sol.links, leaves)
        final.radiance = final.radiance + np.repeat(h.reflectance[leaves] * blocked / np.pi, 4, axis=0).astype(
            np.float32
        )
        self.display_factor, self.pixel_element = final, element
        self._store_display_factor()
        sol.relink()
        self.pixel_element = self._pixel_leaf()
        self.times["fresh solution"] = time.perf_counter() - t

    def _indirect(self) -> np.ndarray:
        """I per leaf (n_leaves, 3): the irradiance the solution gathers, less the lamps' direct part."""
        sol = self.solution
        h = sol.hierarchy
        lamp = sol.exitance()[sol.links.source].max(axis=1) > 0
        direct = np.zeros((len(h), 3))
        weight = sol.links.form_factor * sol.links.visibility
        b = h.radiosity[sol.links.source]
        for c in range(3):
            direct[:, c] = np.bincount(sol.links.receiver[lamp], weights=(weight * b[:, c])[lamp], minlength=len(h))
        lamps = direct
        for lv in h.by_level()[1:]:
            lamps[lv] += lamps[h.parent[lv]]
        return np.clip(self._leaf_irradiance() - lamps, 0, None)

    def _per_pixel_prepare(self) -> None:
        from .per_pixel import lamp_irradiance, surface_points

        m = self.model
        points, normals, polygon = surface_points(m, self.real.view, self.real.size)
        lamp_rows = np.flatnonzero(np.isin(m.group, m.lamps))
        emitting = m.exitance.max(axis=1) > 0  # lamps (scaled below) and self-luminous (kept)
        self.pixel_seen = (polygon >= 0) & ~emitting[np.maximum(polygon, 0)] & (self.pixel_element >= 0)
        self.lamp_rows = lamp_rows
        self.pixel_lamp = lamp_irradiance(
            m, lamp_rows, m.exitance[lamp_rows], points, normals, self.pixel_seen, seed=self.params.hierarchy.seed
        )
        self.pixel_indirect = self._pixel_indirect()

    def _corner_image(self, values: np.ndarray) -> np.ndarray:
        """Per-leaf ``values`` (n_leaves, 3) averaged at the corner points of each surface
        (radiosity.display.corner_average) and interpolated across the leaves by the display: (H, W,
        3) at the photograph's pixels, 0 off the geometry. No step at a leaf's edge."""
        h = self.solution.hierarchy
        mesh = leaf_mesh(h, smooth=False)
        mesh.radiance = corner_average(h, h.leaves(), values).reshape(-1, 3).astype(np.float32)
        self.display.load(mesh)
        colour, _ = self.display(self.real.view, self.real.size, elements=False)
        out = self.ctx.readback_image(colour, 3, clip=False)
        self.ctx.release(colour)
        return out.astype(np.float64)

    def _pixel_texture_factor(self) -> np.ndarray:
        """The texture factor at each pixel (H, W, 3): modulated at the leaves' vertices, as the
        chapter does (4.3.2), not flat over each leaf (which drew the leaves as patches); 1 off the
        geometry and on self-luminous leaves (their texture is the photograph)."""
        h = self.solution.hierarchy
        leaves = h.leaves()
        factor = self._corner_image(self.texture_factor[leaves])
        element = self.pixel_element
        keep = (element < 0) | (h.exitance[np.maximum(element, 0)].max(axis=-1) > 0)
        factor[keep] = 1.0
        return factor

    def _pixel_indirect(self) -> np.ndarray:
        """I at the pixels the per-pixel method relights (n, 3): each leaf's indirect irradiance
        averaged at the corner points of its surface and interpolated across the leaf by the display
        (a flat value per leaf drew the leaves' edges as seams across the ceiling)."""
        return self._corner_image(self._indirect()[self.solution.hierarchy.leaves()])[self.pixel_seen]

    def _per_pixel_image(self) -> np.ndarray:
        m = self.model
        scale = np.array([self.scales.get(m.names[m.group[r]], 1.0) for r in self.lamp_rows])
        before = self.pixel_lamp.sum(axis=1) + self.pixel_indirect
        after = (self.pixel_lamp * scale[None, :, None]).sum(axis=1) + self._pixel_indirect()
        image = self.real.photograph.astype(np.float64).copy()
        image[self.pixel_seen] *= np.where(before > 0, after / np.where(before > 0, before, 1), 0)
        lamps = (self.pixel_polygon >= 0) & np.isin(m.group[np.maximum(self.pixel_polygon, 0)], m.lamps)
        lamp_scale = {m.names[g]: self.scales.get(m.names[g], 1.0) for g in m.lamps}
        image[lamps] *= np.array([lamp_scale[m.names[m.group[r]]] for r in self.pixel_polygon[lamps]])[:, None]
        return image

    def _store_display_factor(self) -> None:
        """D at the corners of every element (n_elements, 4, 3): the leaves' from the display factor
        mesh, so that leaves made later (a virtual object's new shadows) inherit theirs."""
        h = self.solution.hierarchy
        leaves = h.leaves()
        self.corner_d = np.zeros((len(h), 4, 3), np.float32)
        self.corner_d[leaves] = self.display_factor.radiance.reshape(-1, 4, 3)
        self.has_d = np.zeros(len(h), bool)
        self.has_d[leaves] = True

    _CHILD_UV = np.array(
        [
            [(0, 0), (0.5, 0), (0.5, 0.5), (0, 0.5)],
            [(0.5, 0), (1, 0), (1, 0.5), (0.5, 0.5)],
            [(0.5, 0.5), (1, 0.5), (1, 1), (0.5, 1)],
            [(0, 0.5), (0.5, 0.5), (0.5, 1), (0, 1)],
        ]
    )
    _CHILD_BARY = np.array(
        [
            [(0, 0), (0.5, 0), (0, 0.5), (0, 0.5)],
            [(0.5, 0), (1, 0), (0.5, 0.5), (0.5, 0.5)],
            [(0, 0.5), (0.5, 0.5), (0, 1), (0, 1)],
            [(0.5, 0), (0.5, 0.5), (0, 0.5), (0, 0.5)],
        ]
    )

    def inherit_display_factor(self) -> None:
        """Elements made since preparation take D interpolated from their parent's corners (bilinear on
        quads, barycentric on triangles); a virtual object's elements have none (shown by B/π). Their
        texture factor is 1 (no texture work reached them), so every per-element array covers them."""
        h = self.solution.hierarchy
        n = len(h)
        if n > len(self.texture_factor):
            self.texture_factor = np.concatenate([self.texture_factor, np.ones((n - len(self.texture_factor), 3))])
        if n > len(self.corner_d):
            self.corner_d = np.concatenate([self.corner_d, np.zeros((n - len(self.corner_d), 4, 3), np.float32)])
            self.has_d = np.r_[self.has_d, np.zeros(n - len(self.has_d), bool)]
        for lv in h.by_level()[1:]:
            todo = lv[~self.has_d[lv] & self.has_d[h.parent[lv]]]
            if not len(todo):
                continue
            parent = h.parent[todo]
            k = todo - h.child[parent]  # which child
            d = self.corner_d[parent]  # (m, 4, 3)
            tri = h.triangle[todo]
            uv = np.where(tri[:, None, None], self._CHILD_BARY[k], self._CHILD_UV[k])  # (m, 4, 2)
            u, v = uv[..., :1], uv[..., 1:]
            quad = (
                (1 - u) * (1 - v) * d[:, None, 0]
                + u * (1 - v) * d[:, None, 1]
                + u * v * d[:, None, 2]
                + (1 - u) * v * d[:, None, 3]
            )
            bary = (1 - u - v) * d[:, None, 0] + u * d[:, None, 1] + v * d[:, None, 2]
            self.corner_d[todo] = np.where(tri[:, None, None], bary, quad)
            self.has_d[todo] = True

    def _element_method(self, what: str) -> None:
        if self.params.method == "per-pixel":
            raise InputError(f"{what} is not available with the per-pixel method yet; use baseline or loscos")

    def add_lamp(
        self, centre, size: float = VIRTUAL_LAMP_SIZE, exitance=(30.0, 30.0, 30.0), name: str = "virtual-lamp"
    ) -> np.ndarray:
        """A virtual rectangular lamp (size × size m, facing down, exitance W/m² RGB) linked at the
        leaves (Loscos 4.4.1); returns the new image."""
        self._element_method("a virtual lamp")
        start = time.perf_counter()
        self.solution.add_lamp(centre, (size, 0, 0), (0, 0, size), exitance, name)
        self.virtual_groups.add(self.solution.polygons.names.index(name))
        self.times["add lamp"] = time.perf_counter() - start
        return self.image()

    def add_object(self, mesh, name: str, at=(0.0, 0.0, 0.0), reflectance=(0.6, 0.6, 0.6)) -> np.ndarray:
        """A virtual object (a Mesh, its triangles paired into quads where they can be) placed at
        ``at`` (metres); it casts shadows and is shown by its own radiosity; returns the new image."""
        from ..radiosity.polygons import quads_from_triangles

        self._element_method("a virtual object")
        start = time.perf_counter()
        corners, triangle = quads_from_triangles(
            np.asarray(mesh.vertices, np.float64) + np.asarray(at, np.float64), mesh.faces
        )
        n = len(corners)
        polygons = Polygons(
            corners,
            triangle,
            np.repeat(np.asarray(reflectance, np.float64)[None], n, axis=0),
            np.zeros((n, 3)),
            np.zeros(n, int),
            [name],
        )
        self.solution.add_object(polygons, name)
        self.virtual_groups.add(self.solution.polygons.names.index(name))
        self.times["add object"] = time.perf_counter() - start
        return self.image()

    def move_object(self, name: str, offset) -> np.ndarray:
        """Move a virtual object by ``offset`` (metres); returns the new image."""
        self._element_method("moving an object")
        if (
            name not in self.solution.polygons.names
            or self.solution.polygons.names.index(name) not in self.virtual_groups
        ):
            raise InputError(f"no virtual object named {name!r}")
        start = time.perf_counter()
        move = np.eye(4)
        move[:3, 3] = offset
        self.solution.move_object(name, move)
        self.times["move object"] = time.perf_counter() - start
        return self.image()

    # --- edits -----------------------------------------------------------------------------------
    @property
    def lamp_names(self) -> list[str]:
        return self.solution.lamp_names

    def set_lamp(self, name: str, scale: float) -> np.ndarray:
        """Scale one real lamp's estimated exitance; returns the new image."""
        self.scales[name] = float(scale)
        return self.image()

    def image(self, scales: dict | None = None) -> np.ndarray:
        """The scene under ``scales`` (default: the session's), float32 (H, W, 3) radiance × exposure,
        unclipped: eq. (4.3) over the photograph."""
        if scales is not None:
            self.scales = dict(scales)
        start = time.perf_counter()
        sol = self.solution
        unknown = sorted(set(self.scales) - set(self.lamp_names))
        if unknown:
            raise InputError(f"no lamp named {unknown[0]!r}; lamps: {', '.join(self.lamp_names) or 'none'}")
        if self.params.method == "per-pixel":
            sol.set_lamps(self.scales)
            image = self._lamp_rims(self._per_pixel_image()) * self.params.exposure
            self.times["edit"] = time.perf_counter() - start
            return image.astype(np.float32)
        self.inherit_display_factor()
        h = sol.hierarchy
        shown = self._shown()
        now = self._corner_radiosity(shown)
        leaves = h.leaves()
        d = self.corner_d[leaves].reshape(-1, 3)
        virtual = np.isin(sol.polygons.group[h.polygon[leaves]], list(self.virtual_groups))
        ratio = np.where(d > 0, now.radiance / np.where(d > 0, d, 1), 0.0)
        # a virtual object is not in the photograph: its own radiance B/π, marked by a negative sign
        radiance = np.where(np.repeat(virtual, 4)[:, None], -now.radiance, ratio).astype(np.float32)
        now.radiance = radiance
        # only the shown leaves are drawn: a leaf no pixel saw at preparation wins no pixel now (the
        # camera is fixed; what moves is virtual, and shown), so the image is the same
        drawn = shown[now.face_element]
        now = dataclasses.replace(now, faces=now.faces[drawn], face_element=now.face_element[drawn])
        self.display.load(now)
        colour, _ = self.display(self.real.view, self.real.size, elements=False)
        out = self.ctx.readback_image(colour, 3, clip=False)
        self.ctx.release(colour)
        own = out[..., :1] < 0
        # eq. (4.3) with the ratio B/D already at the corners: the displayed ratio times the texture
        relit = self._lamp_rims(out.astype(np.float64) * self.texture)
        image = np.where(own, -out, relit) * self.params.exposure
        self.times["edit"] = time.perf_counter() - start
        return image.astype(np.float32)

    def _prepare_rims(self) -> None:
        from .lamp_rims import LampRims

        self._rims = LampRims.prepare(self.real.polygons, self.real.view, self.real.photograph, self.model.lamps)

    def registration(self):
        """How well the model lines up with the photograph (relight.registration), computed once."""
        if getattr(self, "_registration", None) is None:
            self._registration = registration(self.real.polygons, self.real.view, self.real.photograph)
        return self._registration

    def _lamp_rims(self, relit: np.ndarray) -> np.ndarray:
        """``relit`` (photograph scale) with the pixels on the real lamps' outlines recomposed
        (relight.lamp_rims): each lamp's share of such a pixel scaled as the lamp, the surface's as
        the surface."""
        m = self.model
        if getattr(self, "_rims", None) is None:
            self._prepare_rims()
        scales = np.array([self.scales.get(m.names[g], 1.0) for g in self._rims.groups])
        centre = (self.pixel_polygon >= 0) & np.isin(m.group[np.maximum(self.pixel_polygon, 0)], m.lamps)
        return self._rims.apply(relit, self.real.photograph, scales, centre)

    def show(self, what: str = "image", scale: int = 1) -> np.ndarray:
        """One of SHOW under the session's lamps, float32 (scale·H, scale·W, 3), × exposure: ``image``
        the relit photograph; ``textures`` the textures the method displays (the photograph for
        baseline and per-pixel, T_final of eq. 4.9 for loscos); ``mesh`` the relit image with the
        leaves' outlines (Figure 4.8b); ``display-factor`` D/π at the leaves' corners (Figure 4.13b).
        ``registration`` the photograph with the model's edges (red) over its own (cyan),
        relight.registration. ``scale``: the photograph's pixels repeated, the outlines and D drawn
        at that size."""
        if what not in SHOW:
            raise InputError(f"show must be one of {', '.join(SHOW)}, got {what!r}")
        if not 1 <= scale <= 8:
            raise InputError(f"show scale must be 1..8, got {scale}")

        def larger(image):
            return np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)

        if what in ("image", "textures"):
            return larger(self.image() if what == "image" else (self.texture * self.params.exposure).astype(np.float32))
        if what == "registration":
            return larger(overlay(self.real.photograph, self.registration()) * self.params.exposure)
        image = larger(self.image()) if what == "mesh" else None
        h = self.solution.hierarchy
        mesh = leaf_mesh(h, smooth=False)
        if what == "mesh":
            mesh.radiance = np.ones_like(mesh.radiance)
        else:
            self.inherit_display_factor()
            mesh.radiance = self.corner_d[h.leaves()].reshape(-1, 3)
        self.display.load(mesh)
        w, h_pixels = self.real.size
        colour, element = self.display(self.real.view, (w * scale, h_pixels * scale), edges=what == "mesh")
        out = self.ctx.readback_image(colour, 3, clip=False)
        self.ctx.release(colour, element)
        if what == "mesh":
            return (image * out).astype(np.float32)
        return (out * self.params.exposure).astype(np.float32)

    def _shown(self) -> np.ndarray:
        """Elements the photograph's view can show (mask): the leaves seen through its pixels at
        preparation, what they were split into since, the elements they were merged into, and every
        virtual object's (not in the photograph). The edits gather only at those leaves' corners."""
        h = self.solution.hierarchy
        seen = np.zeros(len(h), bool)
        seen[self.pixel_element[(self.pixel_element >= 0) & (self.pixel_element < len(h))]] = True
        shown = seen.copy()
        frontier = np.flatnonzero(seen)
        while len(frontier):  # up: a seen leaf merged into its parent
            frontier = h.parent[frontier]
            frontier = frontier[frontier >= 0]
            frontier = frontier[~shown[frontier]]
            shown[frontier] = True
        down = seen.copy()
        for lv in h.by_level()[1:]:  # down: a seen leaf split since
            down[lv] |= down[h.parent[lv]]
        shown = (shown & h.leaf) | down
        if self.virtual_groups:
            shown |= np.isin(self.solution.polygons.group[h.polygon], list(self.virtual_groups))
        return shown

    def _corner_radiosity(self, shown: np.ndarray | None = None):
        """The leaf mesh with B at the corners under ``self.scales``. With the links kept, B is linear in
        the lamps' exitances, so the corners' B are gathered once per lamp (and once with every lamp
        off, for the other emitters) and an edit is their weighted sum; after a change of geometry (a
        virtual object or lamp) the first edit gathers directly and the next makes the basis again."""
        sol = self.solution
        h = sol.hierarchy
        key = (len(h), len(sol.links), tuple(self.lamp_names))
        if getattr(self, "_basis_key", None) != key and getattr(self, "_geometry_key", None) != key:
            # the geometry just changed (a virtual object moved): one gather now; the basis waits for
            # a second edit of the same geometry, so dragging an object does not pay for it each step
            self._geometry_key = key
            if not np.array_equal(sol.lamp_scales(self.scales), sol.lamp_scale):
                sol.set_lamps(self.scales)  # (the edit solved under the session's lamps already)
            return leaf_mesh(
                h, sol.links, sol.exitance(), gather=self._gather, shown=self._shown() if shown is None else shown
            )
        if getattr(self, "_basis_key", None) != key:
            t = time.perf_counter()
            off = {n: 0.0 for n in self.lamp_names}
            sol.set_lamps(off)
            shown = self._shown() if shown is None else shown
            base = leaf_mesh(h, sol.links, sol.exitance(), gather=self._gather, shown=shown)
            basis = []
            for name in self.lamp_names:
                sol.set_lamps({**off, name: 1.0})
                basis.append(
                    leaf_mesh(h, sol.links, sol.exitance(), gather=self._gather, shown=shown).radiance - base.radiance
                )
            self._basis, self._basis_mesh, self._basis_key = basis, base, key
            self.times["lamp basis"] = time.perf_counter() - t
        sol.set_lamps(self.scales)  # the solution's state follows the edit (cheap: links kept)
        radiance = self._basis_mesh.radiance.copy()
        for name, response in zip(self.lamp_names, self._basis):
            radiance += float(self.scales.get(name, 1.0)) * response
        return dataclasses.replace(self._basis_mesh, radiance=radiance)

    def save(self, path) -> None:
        """Write the prepared session to ``path`` (.npz; relight.state): load it with :meth:`load`."""
        save_session(self, path)

    @classmethod
    def load(cls, path, ctx: Context | None = None) -> RelightSession:
        """A session saved by :meth:`save`, ready for edits."""
        fields = load_session(path)
        basis = fields.pop("basis")
        s = cls.__new__(cls)
        vars(s).update(fields)
        s.ctx, s.renderer = ctx or default_context(), None
        s.display = DisplayPass(s.ctx)
        s._gather = CornerGather()
        sol = s.solution
        s._geometry_key = (len(sol.hierarchy), len(sol.links), tuple(sol.lamp_names))
        if basis is not None:
            s._basis_key, s._basis, s._basis_mesh = basis
        s._prepare_rims()  # not saved: made again from the photograph and the model
        return s

    def lamp_basis(self):
        """(key, one corner-radiosity response per lamp and one with them off, their leaf mesh): what
        an edit weights by the lamps' scales, made now if it is not yet (saved by ``save``); None
        when the geometry has changed since and the basis waits for the next edit."""
        self._corner_radiosity()
        if getattr(self, "_basis_key", None) is None:
            return None
        return self._basis_key, self._basis, self._basis_mesh

    def release(self) -> None:
        self.display.release()
        if self.renderer is not None:
            self.renderer.release()
