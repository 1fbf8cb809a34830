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

import numba
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
    order = rng.permutation(side * side)[:samples]
    shift = rng.integers(0, side * side, (n, 1))
    return _grid_points(order, shift[:, 0], rng.random((n, samples, 2)), side)


@numba.njit(cache=True)
def _grid_points(order, shift, jitter, side):
    """(n, samples, 2): sample s of row p in cell (order[s] + shift[p]) mod side², jittered."""
    n, samples = jitter.shape[0], jitter.shape[1]
    out = np.empty((n, samples, 2))
    for p in range(n):
        for s in range(samples):
            cell = (order[s] + shift[p]) % (side * side)
            out[p, s, 0] = (cell % side + jitter[p, s, 0]) / side
            out[p, s, 1] = (cell // side + jitter[p, s, 1]) / side
    return out


@numba.njit(cache=True)
def _segments(a, b, receiver_normal, source_normal, offset):
    """The rays of the (n, k) surface samples a → b, both lifted by ``offset`` along their normals,
    as embree takes them (float32): origins, unit directions, lengths short of b by ``offset``, and
    the probes' directions (the receiver's normal)."""
    n, k = a.shape[0], a.shape[1]
    origins = np.empty((n * k, 3), np.float32)
    directions = np.empty((n * k, 3), np.float32)
    dists = np.empty(n * k, np.float32)
    up = np.empty((n * k, 3), np.float32)
    for p in range(n):
        for s in range(k):
            i = p * k + s
            a0 = a[p, s, 0] + offset * receiver_normal[p, 0]
            a1 = a[p, s, 1] + offset * receiver_normal[p, 1]
            a2 = a[p, s, 2] + offset * receiver_normal[p, 2]
            d0 = b[p, s, 0] + offset * source_normal[p, 0] - a0
            d1 = b[p, s, 1] + offset * source_normal[p, 1] - a1
            d2 = b[p, s, 2] + offset * source_normal[p, 2] - a2
            length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            norm = max(length, 1e-300)
            directions[i, 0], directions[i, 1], directions[i, 2] = d0 / norm, d1 / norm, d2 / norm
            dists[i] = max(length - offset, 0.0)
            origins[i, 0], origins[i, 1], origins[i, 2] = a0, a1, a2
            for c in range(3):
                up[i, c] = receiver_normal[p, c]
    return origins, directions, dists, up


@numba.njit(cache=True)
def _exposed_clear_fraction(hit, probe_prim, probe_distance, probe_normal, up, contact, k):
    """V per pair: among its k samples whose probe met nothing within ``contact`` nor the back of a
    face (exposed), the fraction whose ray was clear (hit < 0); 0 when none is exposed."""
    n = len(hit) // k
    out = np.zeros(n)
    for p in range(n):
        exposed = clear = 0
        for s in range(k):
            i = p * k + s
            if probe_prim[i] >= 0:
                back = probe_normal[i, 0] * up[i, 0] + probe_normal[i, 1] * up[i, 1] + probe_normal[i, 2] * up[i, 2] > 0
                if probe_distance[i] < contact or back:
                    continue
            exposed += 1
            if hit[i] < 0:
                clear += 1
        if exposed > 0:
            out[p] = clear / exposed
    return out


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

    def __call__(self, receivers: np.ndarray, sources: np.ndarray,
                 form_factor: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(F_ij, V_ij) for each (receiver, source) pair, (n,) float64 each; ``form_factor`` given (a
        pair already estimated, whose ends have not moved): only V is computed (the same draws)."""
        n = len(receivers)
        if n == 0:
            return np.zeros(0), np.zeros(0)
        h = self.hierarchy
        k = self.samples
        a = h.sample_points(receivers, jittered_grid(n, k, self.rng))
        b = h.sample_points(sources, jittered_grid(n, k, self.rng))
        q = min(k, self.form_factor_points)
        receiver_normal = h.normal[receivers]
        if form_factor is None:
            form_factor = point_polygon(a[:, :q], receiver_normal, h.corners[sources], h.triangle[sources])
        if self.empty:
            return form_factor, np.ones(n)
        origins, directions, dists, up = _segments(a, b, receiver_normal, h.normal[sources], self.offset)
        hit = self.scene.run(origins, directions, dists=dists, query="OCCLUDED")
        # a sample point with something right above it (under a board on a wall, behind a door in
        # contact) is not part of the surface anyone sees: a probe along the normal finds it
        # contact, or inside a closed object (the probe meets the back of a face: under a door that
        # stands on the wall, the points are inside the door)
        probe = self.scene.run(origins, up, output=1)
        self.rays += 2 * n * k
        visibility = _exposed_clear_fraction(np.asarray(hit), np.asarray(probe["primID"]), np.asarray(probe["tfar"]),
                                             np.asarray(probe["Ng"]), up, self.contact, k)
        return form_factor, visibility
