"""Form factor and visibility of a link, from one set of sample points.

Sample s of a link joins a point x_s of a jittered grid on the receiver i to a point y_s of a
differently ordered jittered grid on the source j (both lifted off their surfaces by ``offset`` so a
ray does not hit its own ends); the rays are cast with Embree (embreex).

- F_ij: the exact point-to-polygon form factor (:func:`formfactor.point_polygon`) averaged over the
  first ``form_factor_points`` of the x_s: quadrature over the receiver, exact over the source;
- V_ij: the fraction of the rays x_s → y_s no polygon blocks, among the rays whose start x_s is
  exposed: a probe ray along the normal meets nothing within ``contact`` = 0.2 % of the scene's
  extent and does not meet the back of a face (the point is then inside a closed object). The part of
  an element under a board or behind a door in contact with it is not part of the surface anyone
  sees, and counting it would darken the whole element. Its type (VISIBLE, PARTIAL, INVISIBLE): all counted rays clear,
  some, none.
"""

from __future__ import annotations

import numpy as np

from ..core.errors import InputError
from .formfactor import point_polygon
from .hierarchy import Hierarchy

__all__ = ["Visibility", "VISIBLE", "PARTIAL", "INVISIBLE", "link_type"]

#: link types of Loscos 4.3.1
VISIBLE, PARTIAL, INVISIBLE = 0, 1, 2


def link_type(visibility: np.ndarray) -> np.ndarray:
    """VISIBLE where V = 1, INVISIBLE where V = 0, PARTIAL between."""
    return np.where(visibility >= 1.0, VISIBLE, np.where(visibility <= 0.0, INVISIBLE, PARTIAL)).astype(np.int8)


def jittered_grid(n: int, samples: int, rng: np.random.Generator) -> np.ndarray:
    """(n, samples, 2) points in [0, 1)²: a ⌈√samples⌉² grid, one jittered point per cell, the
    first ``samples`` cells in a random order per row (one random permutation of the cells, cycled
    by a random shift per row: cheaper than one permutation per row and as well spread)."""
    side = int(np.ceil(np.sqrt(samples)))
    cells = (rng.permutation(side * side)[None, :samples] + rng.integers(0, side * side, (n, 1))) % (side * side)
    cu, cv = cells % side, cells // side
    jitter = rng.random((n, samples, 2))
    return np.stack([(cu + jitter[..., 0]) / side, (cv + jitter[..., 1]) / side], axis=2)


class Visibility:
    """Ray casting against the polygons of a hierarchy (rebuilt with :meth:`rebuild` when they move)."""

    def __init__(self, hierarchy: Hierarchy, samples: int = 16, seed: int = 0, form_factor_points: int = 16):
        self.hierarchy = hierarchy
        self.samples = int(samples)
        self.form_factor_points = int(form_factor_points)
        self.rng = np.random.default_rng(seed)
        self.rays = 0
        self.rebuild()

    def rebuild(self, exclude: np.ndarray | None = None) -> None:
        """Rebuild the ray-casting scene from the active roots (``exclude``: root polygons left out)."""
        try:
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh
        except ImportError:  # pragma: no cover - a dependency
            raise InputError("radiosity visibility needs embreex: pip install embreex") from None
        h = self.hierarchy
        roots = h.roots[h.active[h.roots]]
        if exclude is not None:
            roots = np.setdiff1d(roots, exclude)
        c = h.corners[roots]
        tri = h.triangle[roots]
        tris = np.concatenate([c[:, [0, 1, 2]], c[~tri][:, [0, 2, 3]]])
        extent = np.ptp(h.corners[h.roots].reshape(-1, 3), axis=0).max() if len(h.roots) else 1.0
        self.offset = 1e-5 * max(float(extent), 1e-6)
        self.contact = 2e-3 * max(float(extent), 1e-6)
        self.scene = rtcore_scene.EmbreeScene()
        if len(tris):
            TriangleMesh(self.scene, tris.astype(np.float32))
        self.empty = len(tris) == 0

    def __call__(self, receivers: np.ndarray, sources: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F_ij, V_ij) for each (receiver, source) pair, (n,) float64 each."""
        n = len(receivers)
        if n == 0:
            return np.zeros(0), np.zeros(0)
        h = self.hierarchy
        k = self.samples
        a = h.sample_points(receivers, jittered_grid(n, k, self.rng)) + self.offset * h.normal[receivers][:, None]
        b = h.sample_points(sources, jittered_grid(n, k, self.rng)) + self.offset * h.normal[sources][:, None]
        q = min(k, self.form_factor_points)
        form_factor = point_polygon(a[:, :q] - self.offset * h.normal[receivers][:, None], h.normal[receivers],
                                    h.corners[sources], h.triangle[sources])
        if self.empty:
            return form_factor, np.ones(n)
        d = (b - a).reshape(-1, 3)
        length = np.linalg.norm(d, axis=1)
        direction = d / np.maximum(length, 1e-300)[:, None]
        origins = a.reshape(-1, 3).astype(np.float32)
        hit = self.scene.run(origins, direction.astype(np.float32),
                             dists=np.maximum(length - self.offset, 0).astype(np.float32), query="OCCLUDED")
        # a sample point with something right above it (under a board on a wall, behind a door in
        # contact) is not part of the surface anyone sees: a probe along the normal finds it
        # contact, or inside a closed object (the probe meets the back of a face: under a door that
        # stands on the wall, the points are inside the door)
        up = np.repeat(h.normal[receivers], k, axis=0).astype(np.float32)
        probe = self.scene.run(origins, up, output=1)
        met = np.asarray(probe["primID"]) >= 0
        back = (np.asarray(probe["Ng"]) * up).sum(axis=1) > 0
        covered = (met & ((np.asarray(probe["tfar"]) < self.contact) | back)).reshape(n, k)
        self.rays += 2 * n * k
        clear = np.asarray(hit).reshape(n, k) < 0
        exposed = ~covered
        count = exposed.sum(axis=1)
        visibility = np.where(count > 0, (clear & exposed).sum(axis=1) / np.maximum(count, 1), 0.0)
        return form_factor, visibility
