"""One display strategy per method behind one small interface: how a prepared session's texture
work is done and how an edit's image is drawn.

- ``baseline``: the photograph modulated by B/D (eq. 4.3); its photographed shadows stay when a
  lamp goes off (4.2.2).
- ``loscos``: the mesh refined along the photographed shadows (4.3.1), textures free of them
  (4.3.2), optionally a fresh solution over them (4.3.3); displayed as baseline is.
- ``per-pixel``: the texture work per pixel (the chapter's conclusion; relight.per_pixel); no edit of
  the geometry.

A session calls, in order: ``hierarchy`` (the refinement its first solution is built with),
``refine`` (before the photograph's textures reach the leaves), ``textures`` (the method's texture
work), ``finish`` (after the display factor is stored), ``prepare_edits`` (what makes edits fast),
then ``image`` for every edit."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..core.errors import InputError
from ..radiosity import HierarchyParams
from . import corners, loscos, per_pixel, prepare

__all__ = ["Display", "BaselineDisplay", "LoscosDisplay", "PerPixelDisplay", "display_for"]


class Display:
    """The baseline's strategy, and what every method shares."""

    method = "baseline"
    edits_geometry = True  # a virtual lamp or object can be added

    def hierarchy(self, params: HierarchyParams) -> HierarchyParams:
        return params

    def refine(self, s) -> None:
        pass

    def textures(self, s) -> None:
        pass

    def finish(self, s) -> None:
        pass

    def prepare_edits(self, s) -> None:
        # the lamps' basis: part of the preparation, so the first edit is as fast as the next
        s._geometry_key = corners.geometry_key(s)
        corners.corner_radiosity(s)

    def image(self, s) -> np.ndarray:
        """Eq. (4.3): the ratio B/D drawn from the corners the photograph's view shows, times the
        texture; a virtual object by its own radiance B/π. Photograph scale, (H, W, 3) float64."""
        sol = s.solution
        corners.inherit_display_factor(s)
        h = sol.hierarchy
        shown = corners.shown_elements(s)
        now = corners.corner_radiosity(s, shown)
        leaves = h.leaves()
        d = s.corner_d[leaves].reshape(-1, 3)
        virtual = np.isin(sol.polygons.group[h.polygon[leaves]], list(s.virtual_groups))
        ratio = np.where(d > 0, now.radiance / np.where(d > 0, d, 1), 0.0)
        # a virtual object is not in the photograph: its own radiance B/π, marked by a negative sign
        radiance = np.where(np.repeat(virtual, 4)[:, None], -now.radiance, ratio).astype(np.float32)
        now.radiance = radiance
        # only the shown leaves are drawn: a leaf no pixel saw at preparation wins no pixel now (the
        # camera is fixed; what moves is virtual, and shown), so the image is the same
        drawn = shown[now.face_element]
        now = dataclasses.replace(now, faces=now.faces[drawn], face_element=now.face_element[drawn])
        s.display.load(now)
        colour, _ = s.display(s.real.view, s.real.size, elements=False)
        out = s.ctx.readback_image(colour, 3, clip=False)
        s.ctx.release(colour)
        own = out[..., :1] < 0
        # eq. (4.3) with the ratio B/D already at the corners: the displayed ratio times the texture
        relit = s._lamp_rims(out.astype(np.float64) * s.texture)
        return np.where(own, -out, relit)


class BaselineDisplay(Display):
    pass


class LoscosDisplay(Display):
    method = "loscos"

    def hierarchy(self, params: HierarchyParams) -> HierarchyParams:
        # the lamps' links at the leaves: 4.3.2 reads each leaf's blocked light from them
        return dataclasses.replace(params, lights_to_leaves=True)

    def refine(self, s) -> None:
        if s.params.texture_refinement:
            prepare.texture_refinement(s)

    def textures(self, s) -> None:
        loscos.visibility_independent_textures(s)

    def finish(self, s) -> None:
        if s.params.fresh_solution:
            loscos.fresh_solution(s)


class PerPixelDisplay(Display):
    method = "per-pixel"
    edits_geometry = False

    def textures(self, s) -> None:
        per_pixel.prepare(s)

    def prepare_edits(self, s) -> None:
        pass

    def image(self, s) -> np.ndarray:
        s.solution.set_lamps(s.scales)
        return s._lamp_rims(per_pixel.image(s))


_DISPLAYS = {d.method: d for d in (BaselineDisplay(), LoscosDisplay(), PerPixelDisplay())}


def display_for(method: str) -> Display:
    """The strategy of ``method`` (RelightParams.method)."""
    if method not in _DISPLAYS:
        raise InputError(f"no relighting method {method!r}; choose one of {', '.join(_DISPLAYS)}")
    return _DISPLAYS[method]
