"""Dynamic updates (Drettakis & Sillion 1997, as Loscos 4.4.1 uses them): add a lamp, add, move or
remove an object, re-linking only what the change can affect.

A link j → i can change only if the change meets its shaft, the volume swept between the two
elements. The shaft is bounded by the boxes lerp(box_i, box_j, t), t ∈ [0, 1] (every segment from a
point of i to a point of j stays inside them); it meets an object's box when the six linear
conditions in t have a common solution in [0, 1] (:func:`shaft_meets_box`). Those links are taken
out and their pairs refined again against the changed scene (kept as they were, split where a new
shadow makes them partial). The moved, added or removed object's own links are rebuilt from its
roots; its subdivision is kept (a move casts the shafts' rays on a worker thread meanwhile, and
refines their pairs after the object's). A new lamp links straight to every leaf facing it (the chapter's
forced fine level), then refines like any link. The solution is then re-solved from the current B.

The refinement's criterion reads B: an added object's is a guess (its reflectance times the ambient
light), so its links are tested again against the solved B and the solution solved again, as a
build's second round does. A moved object's B is its solution's from where it was, and its links are
refined against that, once: as the hierarchical solver's refine/solve cycle (and Drettakis and
Sillion's interactive moves) take the last solution's B — the next move refines against this one's.
"""

from __future__ import annotations

import dataclasses
import time
from concurrent.futures import Future
from concurrent.futures import wait as futures_wait

import numba
import numpy as np

from ..core.errors import InputError
from .clusters import cluster_visibility
from .polygons import MAX_POLYGONS, Polygons, rectangle
from .refine import CHUNK, refine

__all__ = ["shaft_meets_box", "add_object", "add_lamp", "move_object", "remove_object"]


def element_boxes(h, elements) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (n, 3) of each element's corners, in world metres."""
    elements = np.asarray(elements, np.int64)
    lo, hi = np.empty((len(elements), 3)), np.empty((len(elements), 3))
    _corner_boxes(h.corners, elements, lo, hi)
    return lo, hi


@numba.njit(cache=True)
def _corner_boxes(corners, elements, lo, hi):
    """One pass (NumPy's gather of the corners and six comparisons took 0.7 ms of a drag's move)."""
    for p in range(len(elements)):
        e = elements[p]
        for a in range(3):
            lo[p, a] = min(min(corners[e, 0, a], corners[e, 1, a]), min(corners[e, 2, a], corners[e, 3, a]))
            hi[p, a] = max(max(corners[e, 0, a], corners[e, 1, a]), max(corners[e, 2, a], corners[e, 3, a]))


def _touching(sol, elements) -> np.ndarray:
    """Mask of the links received or sent by one of ``elements``."""
    mine = np.zeros(len(sol.hierarchy), bool)
    mine[elements] = True
    out = np.empty(len(sol.links), bool)
    _either_end(mine, sol.links.receiver, sol.links.source, out)
    return out


@numba.njit(cache=True)
def _either_end(mine, receiver, source, out):
    """out[k] = mine[receiver[k]] or mine[source[k]] (NumPy's two gathers took 1 ms of a drag's move)."""
    for k in range(len(receiver)):
        out[k] = mine[receiver[k]] or mine[source[k]]


def shaft_meets_box(lo_i, hi_i, lo_j, hi_j, box_lo, box_hi) -> np.ndarray:
    """For pairs of element boxes (n, 3) each, does the swept shaft between them meet the box?"""
    t0 = np.zeros(len(lo_i))
    t1 = np.ones(len(lo_i))
    ok = np.ones(len(lo_i), bool)
    for c0, dc, bound, upper in ((lo_i, lo_j - lo_i, box_hi, True), (hi_i, hi_j - hi_i, box_lo, False)):
        for a in range(3):
            # upper: c0 + dc·t ≤ bound;  lower: c0 + dc·t ≥ bound
            c, d = c0[:, a], dc[:, a]
            b = bound[a]
            sign = 1.0 if upper else -1.0
            c, d, b = sign * c, sign * d, sign * b  # now c + d·t ≤ b
            pos, neg, zero = d > 1e-15, d < -1e-15, np.abs(d) <= 1e-15
            with np.errstate(divide="ignore", invalid="ignore"):
                limit = (b - c) / d
            t1 = np.where(pos, np.minimum(t1, limit), t1)
            t0 = np.where(neg, np.maximum(t0, limit), t0)
            ok &= ~zero | (c <= b)
    return ok & (t0 <= t1)


@numba.njit(parallel=True, cache=True)
def _links_in_shafts(lo, hi, receiver, source, box_lo, box_hi, out):
    """out[k] |= the shaft of link k (receiver's box lo/hi to source's) meets one of the boxes
    (m, 3): :func:`shaft_meets_box` as one loop over the links, without its (n, 3) temporaries."""
    for k in numba.prange(len(receiver)):
        i, j = receiver[k], source[k]
        for b in range(box_lo.shape[0]):
            # the shaft lies inside the box around both ends' boxes: most links miss a small box there
            apart = False
            for a in range(3):
                if min(lo[i, a], lo[j, a]) > box_hi[b, a] or max(hi[i, a], hi[j, a]) < box_lo[b, a]:
                    apart = True
                    break
            if apart:
                continue
            t0, t1, ok = 0.0, 1.0, True
            for a in range(3):
                # lower faces: lo_i + (lo_j − lo_i)·t ≤ box_hi; upper: hi_i + (hi_j − hi_i)·t ≥ box_lo
                for c, d, bound in (
                    (lo[i, a], lo[j, a] - lo[i, a], box_hi[b, a]),
                    (-hi[i, a], hi[i, a] - hi[j, a], -box_lo[b, a]),
                ):
                    if d > 1e-15:
                        t1 = min(t1, (bound - c) / d)
                    elif d < -1e-15:
                        t0 = max(t0, (bound - c) / d)
                    elif c > bound:
                        ok = False
            if ok and t0 <= t1:
                out[k] = True
                break


def _object_elements(sol, group: int) -> np.ndarray:
    h = sol.hierarchy
    roots = h.roots[sol.polygons.group[h.polygon[h.roots]] == group]
    return h.descendants(roots)


def _object_box(sol, elements) -> tuple[np.ndarray, np.ndarray]:
    c = sol.hierarchy.corners[elements].reshape(-1, 3)
    margin = 2 * sol.visibility.offset
    return c.min(axis=0) - margin, c.max(axis=0) + margin


def _detach(sol, name: str):
    """(group, elements, box) of object ``name``, its links taken out."""
    group = sol.polygons.group_of(name)
    elements = _object_elements(sol, group)
    box = _object_box(sol, elements)
    sol.links.remove(_touching(sol, elements))
    if sol.tree is not None:
        # its roots leave their clusters (which stop counting their light) and are linked on their own
        sol.cluster_links.remove(sol.cluster_links.touching(elements, len(sol.hierarchy)))
        sol.tree.exclude(elements)
    return group, elements, box


def _relink_shafts(sol, boxes) -> int:
    """Take out the links whose shaft meets any of ``boxes`` and refine their pairs again. Returns
    how many were redone."""
    return _shafts_started(sol, boxes, background=False).finish()


@dataclasses.dataclass
class _Shafts:
    """The links taken out because their shaft meets a box, their V being cast again (a future
    of :meth:`Visibility.recast_in_background`, or None: cast in the refinement)."""

    sol: object
    gone: object
    boxes: list
    recast: Future | None
    clusters: int

    def wait(self) -> None:
        if self.recast is not None:
            futures_wait([self.recast])

    def finish(self) -> int:
        """Refine the pairs again with their new V. Returns how many links were redone."""
        sol, gone = self.sol, self.gone
        # their ends did not move: F stands, only V is cast again — the rays through the boxes (and
        # the pair split if it must be)
        refine(
            sol.hierarchy,
            sol.visibility,
            gone.receiver,
            gone.source,
            sol.threshold,
            sol.min_area,
            sol.params.criterion,
            links=sol.links,
            form_factor=gone.form_factor,
            rays=gone.rays,
            boxes=self.boxes,
            recast=None if self.recast is None else self.recast.result(),
        )
        return len(gone) + self.clusters


def _shafts_started(sol, boxes, background: bool) -> _Shafts:
    """Take out the links whose shaft meets any of ``boxes`` (and cast the cluster links' V again);
    with ``background``, start casting their V on the worker thread (:class:`_Shafts` refines them
    when asked)."""
    h, L = sol.hierarchy, sol.links
    lo, hi = element_boxes(h, np.arange(len(h)))  # once per element, then per link end
    hit = np.zeros(len(L), bool)
    _links_in_shafts(
        lo,
        hi,
        L.receiver,
        L.source,
        np.array([b[0] for b in boxes], np.float64),
        np.array([b[1] for b in boxes], np.float64),
        hit,
    )
    gone = L.remove(hit)
    clusters = _recast_cluster_links(sol, boxes, lo, hi)
    recast = None
    if background and len(gone):
        recast = sol.visibility.recast_in_background(gone.receiver, gone.source, gone.rays, boxes, CHUNK)
    return _Shafts(sol, gone, list(boxes), recast, clusters)


def _recast_cluster_links(sol, boxes, lo, hi) -> int:
    """V cast again (fresh rays) for the cluster links whose shaft meets a box; their kernel stands
    (a cluster's box is where it was built: conservative once a member left)."""
    C, tree = sol.cluster_links, sol.tree
    if tree is None or not len(C):
        return 0
    n = len(lo)
    lo, hi = np.r_[lo, tree.lo], np.r_[hi, tree.hi]

    def index(node):
        return np.where(node >= 0, node, n - 1 - node)  # cluster c after the elements

    hit = np.zeros(len(C), bool)
    _links_in_shafts(
        lo,
        hi,
        index(C.receiver),
        index(C.source),
        np.array([b[0] for b in boxes], np.float64),
        np.array([b[1] for b in boxes], np.float64),
        hit,
    )
    if hit.any():
        C.visibility[hit] = cluster_visibility(sol.hierarchy, tree, sol.visibility, C.receiver[hit], C.source[hit])
    return int(hit.sum())


def _link_object(sol, roots: np.ndarray) -> None:
    """Refine every pair between ``roots`` and the active roots (both directions, and among
    themselves); with clusters, between ``roots`` and the tree's top (refined down through it) and
    among themselves."""
    h = sol.hierarchy
    if sol.tree is not None:
        roots = np.sort(roots)
        top = np.full(len(roots), sol.tree.top)
        among_r, among_s = np.repeat(roots, len(roots)), np.tile(roots, len(roots))
        sol._refine_nodes(np.r_[roots, top, among_r], np.r_[top, roots, among_s])
        return
    recv, src = _pairs_with(np.sort(h.roots[h.active[h.roots]]), np.sort(roots))
    refine(h, sol.visibility, recv, src, sol.threshold, sol.min_area, sol.params.criterion, links=sol.links)


def _pairs_with(others: np.ndarray, roots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every pair (receiver, source) with one end in ``roots`` and the other in ``others`` (both
    sorted, roots among others), each once, ordered by receiver then source (as np.unique of the
    pairs would give them, at a fraction of its cost): a root receives from every other, any other
    from the roots."""
    is_root = np.isin(others, roots)
    count = np.where(is_root, len(others), len(roots))
    first = np.cumsum(count) - count
    src = np.empty(int(count.sum()), np.int64)
    src[(first[~is_root, None] + np.arange(len(roots))).ravel()] = np.tile(roots, int((~is_root).sum()))
    src[(first[is_root, None] + np.arange(len(others))).ravel()] = np.tile(others, int(is_root.sum()))
    return np.repeat(others, count), src


def _finish(sol, started: float, phase: str, tolerance: float, max_iterations: int, elements=None):
    """Solve; then, when the object's links were made from estimated B (``elements``), re-test them
    against the solved B and solve again if any had to be refined (as a build's second round does)."""
    sol.links_changed()
    result = sol.solve(tolerance, max_iterations)
    if elements is not None and sol.rerefine(_touching(sol, elements)):
        result = sol.solve(tolerance, max_iterations)
    sol.stats.add_time(phase, time.perf_counter() - started)
    return result


def add_object(
    sol, polygons: Polygons, name: str, tolerance: float = 1e-4, max_iterations: int = 200, lamp: bool = False
):
    """Add ``polygons`` as a new object ``name``: its links, and the links whose shafts it enters."""
    t = time.perf_counter()
    first = len(sol.polygons)
    if first + len(polygons) > MAX_POLYGONS and sol.tree is None:
        raise InputError(
            f"{name!r} has {len(polygons)} polygons: with the scene's {first} that is past the "
            f"{MAX_POLYGONS} radiosity takes without clusters; use a coarser mesh"
        )
    sol.polygons = sol.polygons.extended(polygons, name, lamp)
    sol.hierarchy.polygons = sol.polygons
    sol.lamp_scale = np.r_[sol.lamp_scale, 1.0]
    roots = sol.hierarchy.add_roots(polygons, first)
    # what its light will be, until solved (B = E alone would let every link from it stay coarse)
    sol.hierarchy.radiosity[roots] = polygons.exitance + polygons.reflectance * sol.ambient_irradiance()
    sol.visibility.rebuild()
    box = _object_box(sol, roots)
    _relink_shafts(sol, [box])
    if lamp:
        _link_lamp(sol, roots)
    else:
        _link_object(sol, roots)
    return _finish(sol, t, "add", tolerance, max_iterations, sol.hierarchy.descendants(roots))


def _link_lamp(sol, roots) -> None:
    """Links from the lamp's polygons to every active leaf (those facing it keep a link), then the
    lamp as a receiver of nothing (ρ = 0) and a source refined like any other."""
    h = sol.hierarchy
    leaves = h.leaves()
    leaves = leaves[h.reflectance[leaves].max(axis=1) > 0]
    recv = np.repeat(leaves, len(roots))
    src = np.tile(roots, len(leaves))
    refine(h, sol.visibility, recv, src, sol.threshold, sol.min_area, sol.params.criterion, links=sol.links)


def add_lamp(sol, centre, edge_u, edge_v, exitance, name: str, tolerance: float = 1e-4, max_iterations: int = 200):
    """A rectangular lamp (one-sided along edge_u × edge_v, exitance E W/m² RGB) linked at the leaves."""
    corners = rectangle(centre, edge_u, edge_v)[None]
    lamp = Polygons(corners, [False], np.zeros((1, 3)), np.asarray(exitance, np.float64).reshape(1, 3), [0], [name])
    return add_object(sol, lamp, name, tolerance, max_iterations, lamp=True)


def remove_object(sol, name: str, tolerance: float = 1e-4, max_iterations: int = 200):
    """Remove object ``name``: its elements go inactive, its links go, the shafts it blocked are redone."""
    t = time.perf_counter()
    h = sol.hierarchy
    _, elements, box = _detach(sol, name)
    h.active[elements] = False
    h.radiosity[elements] = 0
    h.irradiance[elements] = 0
    sol.visibility.rebuild(moved=[box])
    _relink_shafts(sol, [box])
    return _finish(sol, t, "remove", tolerance, max_iterations)


def move_object(sol, name: str, matrix: np.ndarray, tolerance: float = 1e-4, max_iterations: int = 200):
    """Move object ``name`` by the 4×4 world ``matrix`` (applied to where it is now)."""
    t = time.perf_counter()
    h = sol.hierarchy
    group, elements, old_box = _detach(sol, name)
    h.transform(elements, matrix)
    sol.polygons = sol.polygons.moved(group, matrix)  # never edit the caller's
    sol.hierarchy.polygons = sol.polygons
    new_box = _object_box(sol, elements)
    sol.visibility.rebuild(moved=[old_box, new_box])
    # the links whose shafts it crosses are cast again on the worker thread while its own are made
    # here (nothing moves meanwhile: both only add elements and links); theirs are added after its
    shafts = _shafts_started(sol, [old_box, new_box], background=True)
    roots = h.roots[sol.polygons.group[h.polygon[h.roots]] == group]
    try:
        _link_object(sol, roots)
    finally:
        shafts.wait()
    shafts.finish()
    # refined against the B it had where it was (the module docstring): no second round
    return _finish(sol, t, "move", tolerance, max_iterations)
