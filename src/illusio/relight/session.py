"""A relighting session: the real scene prepared once (estimates, hierarchy, display factor), then
edits that each return the new image.

The parts, each a module: ``prepare`` (the estimates and the first hierarchy, Loscos 4.2.1),
``display`` (one strategy per method: baseline, loscos, per-pixel), ``loscos`` and ``per_pixel``
(their texture work), ``corners`` (the display factor and the relit B at the elements' corners),
``edits`` (virtual lamps and objects, 4.4.1), ``show`` (the views beside the image) and ``state``
(a prepared session saved and loaded).

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
from ..core.progress import phase
from ..radiosity import DisplayPass, RadiosityParams, RadiosityRenderer, leaf_mesh
from . import corners, edits, prepare, show
from .display import display_for
from .params import VIRTUAL_LAMP_SIZE, RelightParams
from .photograph import RealScene
from .registration import registration
from .state import SavedSession, load_session, save_session

__all__ = ["RelightSession"]


class RelightSession:
    def __init__(self, real: RealScene, params: RelightParams = RelightParams(), ctx: Context | None = None):
        self.real, self.params = real, params
        self.ctx = ctx or default_context()
        self.strategy = display_for(params.method)
        self.times: dict[str, float] = {}
        with phase(f"relight: prepare ({params.method})"):
            self._prepare(real, params)

    def _prepare(self, real: RealScene, params: RelightParams) -> None:
        start = time.perf_counter()
        self.model, self.mean_reflectance = prepare.estimate_model(self)
        self.renderer = RadiosityRenderer(self.ctx)
        self.renderer.prepare(self.model)
        # the model's own polygons, uncut: the photograph's textures and pixels are keyed to them
        self.hierarchy_params = self.strategy.hierarchy(
            dataclasses.replace(params.hierarchy, sliver_piece=0.0, contact_cuts=False, reach_rays=0)
        )
        self.solution = self.renderer.solve(RadiosityParams(self.hierarchy_params))
        self.display = DisplayPass(self.ctx)
        self._gather = corners.corner_gather()
        self.strategy.refine(self)
        prepare.textures_to_leaves(self)
        self.display_factor = leaf_mesh(
            self.solution.hierarchy, self.solution.links, self.solution.exitance(), gather=self._gather
        )
        self.texture_factor = np.ones((len(self.solution.hierarchy), 3))
        self.strategy.textures(self)
        self.texture = (self.real.photograph * corners.pixel_texture_factor(self)).astype(np.float32)
        corners.store_display_factor(self)
        self.strategy.finish(self)
        self.virtual_groups: set[int] = set()
        self.scales: dict[str, float] = {}
        self.strategy.prepare_edits(self)
        self._prepare_rims()
        self.times["prepare"] = time.perf_counter() - start

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
        unknown = sorted(set(self.scales) - set(self.lamp_names))
        if unknown:
            raise InputError(f"no lamp named {unknown[0]!r}; lamps: {', '.join(self.lamp_names) or 'none'}")
        image = self.strategy.image(self) * self.params.exposure
        self.times["edit"] = time.perf_counter() - start
        return image.astype(np.float32)

    def add_lamp(
        self, centre, size: float = VIRTUAL_LAMP_SIZE, exitance=(30.0, 30.0, 30.0), name: str = "virtual-lamp"
    ) -> np.ndarray:
        """A virtual rectangular lamp (size × size m, facing down, exitance W/m² RGB) linked at the
        leaves (Loscos 4.4.1); returns the new image."""
        with phase(f"relight: add the lamp {name}"):
            return edits.add_lamp(self, centre, size, exitance, name)

    def add_object(self, mesh, name: str, at=(0.0, 0.0, 0.0), reflectance=(0.6, 0.6, 0.6)) -> np.ndarray:
        """A virtual object (a Mesh, its triangles paired into quads where they can be) placed at
        ``at`` (metres); it casts shadows and is shown by its own radiosity; returns the new image."""
        with phase(f"relight: add the object {name}"):
            return edits.add_object(self, mesh, name, at, reflectance)

    def move_object(self, name: str, offset) -> np.ndarray:
        """Move a virtual object by ``offset`` (metres); returns the new image."""
        with phase(f"relight: move the object {name}"):
            return edits.move_object(self, name, offset)

    def show(self, what: str = "image", scale: int = 1) -> np.ndarray:
        """One of SHOW under the session's lamps (relight.show.show)."""
        return show.show(self, what, scale)

    def inherit_display_factor(self) -> None:
        """Elements made since preparation take D from their parent's corners (relight.corners)."""
        corners.inherit_display_factor(self)

    def _shown(self) -> np.ndarray:
        return corners.shown_elements(self)

    def _leaf_pixels(self, values: np.ndarray | None = None, element: np.ndarray | None = None):
        return prepare.leaf_pixels(self, values, element)

    # --- the photograph's lamps and registration ----------------------------------------------------
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

    # --- saved sessions ----------------------------------------------------------------------------
    def save(self, path) -> None:
        """Write the prepared session to ``path`` (.npz; relight.state): load it with :meth:`load`."""
        basis = self.lamp_basis()  # saved so edits start at once
        corners.inherit_display_factor(self)  # per-element arrays cover elements made by edits
        save_session(SavedSession.of(self, basis), path)

    @classmethod
    def load(cls, path, ctx: Context | None = None) -> RelightSession:
        """A session saved by :meth:`save`, ready for edits."""
        saved = load_session(path)
        s = cls.__new__(cls)
        vars(s).update(saved.fields())
        s.ctx, s.renderer = ctx or default_context(), None
        s.strategy = display_for(s.params.method)
        s.display = DisplayPass(s.ctx)
        s._gather = corners.corner_gather()
        s._geometry_key = corners.geometry_key(s)
        if saved.basis is not None:
            s._basis_key, s._basis, s._basis_mesh = saved.basis
        s._prepare_rims()  # not saved: made again from the photograph and the model
        s.times["load"] = saved.load_seconds
        return s

    def lamp_basis(self):
        """(key, one corner-radiosity response per lamp and one with them off, their leaf mesh): what
        an edit weights by the lamps' scales, made now if it is not yet (saved by ``save``); None
        when the geometry has changed since and the basis waits for the next edit."""
        corners.corner_radiosity(self)
        if getattr(self, "_basis_key", None) is None:
            return None
        return self._basis_key, self._basis, self._basis_mesh

    def release(self) -> None:
        self.display.release()
        if self.renderer is not None:
            self.renderer.release()
