"""Clusters above the input polygons (Smits, Arvo & Greenberg 1994; Sillion 1995), so that the first
links are not every pair of polygons.

The tree: a binary hierarchy over the roots (the input polygons), built by sorting their centres
along a Morton curve and halving the sorted run until one root is left: cluster c covers the roots
``order[start[c]:end[c]]``. Its children are clusters or roots. A *node* is an element (index ≥ 0)
or a cluster (encoded −1 − c); links with a cluster at either end are :class:`ClusterLinks`.

What a cluster carries (the isotropic-cluster model of Sillion 1995, with the mean normal of
Smits et al.): its area A (the members' total), box, centre, and the area-weighted mean normal
N̄ = Σ A_k n_k / A (|N̄| = 1 for a flat cluster, 0 for a closed object). Toward a unit direction d a
source node's mean cosine is taken as

    c(d) = max(N̄·d, 0) + (1 − |N̄|)/4

exact for a flat cluster (and for an element, c = max(n·d, 0)) and for a sphere (1/4, the mean of
max(cos, 0) over all directions). A source cluster is read as two parts, each with its own mean
normal and power: its *fronts* (one-sided faces and the fronts of two-sided surfaces) and its
*twins* (the reversed twins of two-sided surfaces, Polygons.side 2). Read as one, a two-sided wall
and its twin would have N̄ = 0 and send half of the lit side's light out of its back; read as two,
the wall is exact (c = max(n·d, 0) for each side, with its own side's power). A link from node j to
node i with centres r apart, d the unit vector from i toward j, carries the irradiance normal to d

    E_ij = V_ij · (G_ij P_j + G'_ij P'_j),   G_ij = c_j(−d) / (π r² + A_j),   P_j = Σ_{k ∈ fronts of j} A_k B_k

and G', P' the same over its twins (W/m²; each part radiating c/π per unit area and solid angle:
the point-to-disk factor of formfactor.point_to_disk with A_j·cos θ_j replaced by A_j·c_j; an
element source is one part, P_j = A_j B_j; the two powers are sums of B, so B stays linear in the
lamps' exitances). An element receiver gains
max(n_i·d, 0)·E_ij (folded into its G). A cluster receiver keeps, per channel, the moments of what
arrives — Σ E, Σ E·d, Σ E·d dᵀ — and each member k gains Σ E_l·f(n_k·d_l) over the links of every
cluster above it, f(x) = 3/32 + x/2 + 15/32·x² the clamped cosine to order 2 (exact for light from
one hemisphere or from all around, linear in the light: :func:`member_irradiance`). A source
cluster's power is pulled from its members' B at every gather, so a member taken out of its
cluster (an object moved or removed) stops counting at once. V_ij is the visible share of the
light the link carries, estimated from rays between random points x of the receiver and y of the
source (area-weighted over a cluster's members): each ray counts with the weight
ρ(x)·o(x)·cos θ_x·cos θ_y·B(y)·o(y) (ρ and B the largest channel of the member it starts or ends
on, B the radiosity estimate the link is made with, o a cluster member's openness,
:meth:`Visibility.openness`: 0 for the inner faces of a closed two-sided object, which the exposure
probe cannot tell from outer ones), only rays that leave the front of one surface and reach
the front of the other, from a receiving point that is exposed (Visibility.exposed: not in contact
with another face, not inside an object); where every weight is 0 (no estimate of B yet), the plain
clear fraction. Unweighted, a cluster's V was its members' mean visibility: a roller blind's tube
counted its inner faces (two-sided, lit from nowhere) and its black window glass, and its lit front
received half the light it sees; a luminaire's cluster, its dark fixture as much as its lamp.

Refinement (:func:`refine_nodes`), with the conservative bound on what a link can carry,

    T_ij = B_max,j · A_i · min(A_j / (π d²), 1)

(B_max,j the largest B among j's members, d the distance between the two boxes, both cosines and V
taken as 1): a pair is linked where T_ij ≤ ε·Φ, else the larger node (box diagonal) is split — a
cluster into its two children, an element into its four while above A_ε — and a pair of two
elements goes to :func:`illusio.radiosity.refine.refine`, the hierarchy's own criterion with exact
form factors. Pairs whose element end has the other node's whole box behind its plane carry nothing
and are dropped, as are accepted pairs none of whose sampled rays leaves a front toward a front. The bound makes a
cluster link's error at most ε·Φ, the same as an element link's.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np

from ..core.memory import release_free_heap
from ..core.rays import cast
from .hierarchy import Hierarchy, point_on
from .refine import CHUNK, channel_max, refine
from .visibility import element_uv, stream_uniform

__all__ = ["ClusterTree", "ClusterLinks", "ClusteredGather", "refine_nodes", "is_cluster", "cluster_node"]


def cluster_node(c):
    """The node id of cluster ``c`` (−1 − c)."""
    return -1 - np.asarray(c, np.int64)


def is_cluster(node) -> np.ndarray:
    return np.asarray(node) < 0


def _morton(points: np.ndarray) -> np.ndarray:
    """30-bit Morton codes of points (n, 3) in their bounding box (10 bits per axis)."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    q = ((points - lo) / np.maximum(hi - lo, 1e-12) * 1023).astype(np.uint64)
    code = np.zeros(len(points), np.uint64)
    for bit in range(10):
        for axis in range(3):
            code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return code


@numba.njit(cache=True)
def _halve(n, left, right, start, end):
    """Fill the tree over n sorted roots: cluster 0 covers [0, n); each cluster splits its run at
    the middle; a run of one root is that root (its position, ≥ 0), a longer one a new cluster
    (−1 − c). Children come after their parents. Returns the number of clusters (n − 1)."""
    count = 1
    start[0], end[0] = 0, n
    for c in range(n - 1):
        s, e = start[c], end[c]
        mid = (s + e) // 2
        for side in range(2):
            a, b = (s, mid) if side == 0 else (mid, e)
            if b - a == 1:
                node = a  # a position in the order, mapped to its root later
            else:
                start[count], end[count] = a, b
                node = -1 - count
                count += 1
            if side == 0:
                left[c] = node
            else:
                right[c] = node
    return count


@dataclass(eq=False)
class ClusterTree:
    """The clusters over a hierarchy's roots (the module docstring). Per cluster c: ``start[c]``,
    ``end[c]`` (its run of ``order``), ``left[c]``, ``right[c]`` (child nodes), ``lo``/``hi`` (box,
    m), ``centre`` (m), ``area`` (m²), ``normal`` (N̄). ``included``: per position of ``order``,
    whether that root still counts as a member (False once its object moved or went). ``twin``: per
    position, whether the root is a two-sided surface's reversed twin; ``front_normal`` and
    ``twin_normal`` (C, 3): N̄ over the cluster's fronts and over its twins (0 where it has none);
    ``twin_area`` (C,): its twins' area."""

    order: np.ndarray
    start: np.ndarray
    end: np.ndarray
    left: np.ndarray
    right: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    centre: np.ndarray
    area: np.ndarray
    normal: np.ndarray
    included: np.ndarray
    twin: np.ndarray | None = None
    front_normal: np.ndarray | None = None
    twin_normal: np.ndarray | None = None
    twin_area: np.ndarray | None = None
    #: the included members' cumulative area along ``order`` (node_members' draw; the roots' areas
    #: are fixed for the tree's life), made on first use and dropped by exclude
    _cumulative_area: np.ndarray | None = field(default=None, repr=False)

    @classmethod
    def build(cls, h: Hierarchy, roots: np.ndarray | None = None) -> ClusterTree:
        roots = h.roots[h.active[h.roots]] if roots is None else np.asarray(roots, np.int64)
        n = len(roots)
        order = roots[np.argsort(_morton(h.centre[roots]), kind="stable")] if n else roots
        clusters = max(n - 1, 0)
        left, right = np.empty(clusters, np.int64), np.empty(clusters, np.int64)
        start, end = np.empty(clusters, np.int64), np.empty(clusters, np.int64)
        if clusters:
            _halve(n, left, right, start, end)
            for child in (left, right):
                leaf = child >= 0
                child[leaf] = order[child[leaf]]
        tree = cls(
            order,
            start,
            end,
            left,
            right,
            np.zeros((clusters, 3)),
            np.zeros((clusters, 3)),
            np.zeros((clusters, 3)),
            np.zeros(clusters),
            np.zeros((clusters, 3)),
            np.ones(n, bool),
            twins(h)[order],
        )
        tree._summarise(h)
        return tree

    def __len__(self) -> int:
        return len(self.start)

    @property
    def top(self) -> int:
        """The node covering every root: cluster 0, or the one root of a one-polygon scene."""
        return int(cluster_node(0)) if len(self) else int(self.order[0])

    def _summarise(self, h: Hierarchy) -> None:
        """Boxes, areas and mean normals, children before parents (clusters are made after theirs)."""
        c = h.corners[self.order]
        root_lo, root_hi = c.min(axis=1), c.max(axis=1)
        area = h.area[self.order]
        weighted = h.normal[self.order] * area[:, None]
        position = np.full(len(h), -1)
        position[self.order] = np.arange(len(self.order))
        for k in range(len(self) - 1, -1, -1):
            kids = (self.left[k], self.right[k])
            los, his, areas, normals = [], [], [], []
            for node in kids:
                if node >= 0:
                    p = position[node]
                    los.append(root_lo[p]), his.append(root_hi[p]), areas.append(area[p]), normals.append(weighted[p])
                else:
                    q = -1 - node
                    los.append(self.lo[q]), his.append(self.hi[q]), areas.append(self.area[q])
                    normals.append(self.normal[q] * self.area[q])
            self.lo[k], self.hi[k] = np.minimum(*los), np.maximum(*his)
            self.area[k] = areas[0] + areas[1]
            self.normal[k] = (normals[0] + normals[1]) / max(self.area[k], 1e-300)
        self.centre[:] = (self.lo + self.hi) / 2
        twin = np.zeros(len(self.order), bool) if self.twin is None else self.twin
        self.front_normal, _ = _mean_over(self, np.where(twin[:, None], 0.0, weighted), np.where(twin, 0.0, area))
        self.twin_normal, self.twin_area = _mean_over(
            self, np.where(twin[:, None], weighted, 0.0), np.where(twin, area, 0.0)
        )

    def powers(self, area_b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(P over the fronts, P' over the twins) per cluster (C, 3) from A·B per element (n, 3)."""
        total = self.member_sums(area_b)
        if self.twin is None or not self.twin.any():
            return total, np.zeros_like(total)
        twin = self.member_sums(area_b * _per_element(self, len(area_b))[:, None])
        return total - twin, twin

    def exclude(self, roots: np.ndarray) -> None:
        """``roots`` stop counting as members of their clusters (their object moved or went)."""
        self.included[np.isin(self.order, roots)] = False
        self._cumulative_area = None

    def member_sums(self, per_root: np.ndarray) -> np.ndarray:
        """Σ over each cluster's included members of ``per_root`` (indexed by element; (n,) or (n, k))."""
        values = np.asarray(per_root)[self.order] * self._mask(per_root)
        cum = np.concatenate([np.zeros((1,) + values.shape[1:]), np.cumsum(values, axis=0)])
        return cum[self.end] - cum[self.start]

    def _mask(self, per_root):
        return self.included.reshape((-1,) + (1,) * (np.ndim(per_root) - 1))

    def member_max(self, per_root: np.ndarray) -> np.ndarray:
        """max over each cluster's included members of ``per_root`` (n,), 0 where none is included."""
        values = np.where(self.included, np.asarray(per_root, np.float64)[self.order], 0.0)
        return _range_max(values, self.start, self.end)

    def push(self, moments: np.ndarray, normal: np.ndarray, out: np.ndarray) -> None:
        """Add to every included member root's row of ``out`` the irradiance its clusters' incident
        ``moments`` (C, 3, 10) give it, by its ``normal`` (per element): the moments of all the
        clusters above a root are summed, then turned into irradiance (member_irradiance)."""
        _push(
            self.order,
            self.start,
            self.end,
            self.included,
            np.ascontiguousarray(moments, np.float64),
            np.ascontiguousarray(normal, np.float64),
            out,
        )

    def members(self, cluster: int) -> np.ndarray:
        """The included member roots of cluster ``cluster``."""
        run = slice(self.start[cluster], self.end[cluster])
        return self.order[run][self.included[run]]

    def node_members(self, h: Hierarchy, nodes: np.ndarray, k: int, seed: np.uint64, slot: int) -> np.ndarray:
        """(n, k) elements for k samples on each of ``nodes``: an element itself; a cluster's member
        roots drawn in proportion to their area (included ones; −1 where the draw meets an
        excluded one or the cluster has none), sample s of row p from the uniform
        ``stream_uniform(seed, (p·k + s)·DRAWS_PER_SAMPLE + slot)``."""
        if self._cumulative_area is None:  # a cluster link batch asks it twice (0.2 ms at 44k roots)
            self._cumulative_area = np.r_[0.0, np.cumsum(np.where(self.included, h.area[self.order], 0.0))]
        out = np.empty((len(nodes), k), np.int64)
        _draw_members(
            self._cumulative_area,
            self.order,
            self.included,
            self.start,
            self.end,
            np.asarray(nodes, np.int64),
            np.uint64(seed),
            slot,
            out,
        )
        return out


#: the uniforms a sample of a cluster link draws from the stream: its receiving member, which of
#: that member's own points (element_uv), its sending member, the point's (u, v) there (slots 0–5;
#: slot 2 unused)
DRAWS_PER_SAMPLE = 8
RECEIVER_SLOT, SOURCE_SLOT = 0, 3


@numba.njit(parallel=True, cache=True)
def _draw_members(cum, order, included, start, end, nodes, seed, slot, out):
    """out[p, s]: nodes[p] where it is an element; for a cluster c = −1 − nodes[p], the member root
    whose run of the cumulative area ``cum`` holds lo + u·(hi − lo), lo and hi the cluster's ends
    in it and u the stream's uniform of (p, s, slot) (a binary search over its run); −1 where that
    member is excluded or the cluster has no area."""
    k = out.shape[1]
    for p in numba.prange(len(nodes)):
        if nodes[p] >= 0:
            for s in range(k):
                out[p, s] = nodes[p]
            continue
        c = -1 - nodes[p]
        first, last = start[c], end[c]
        lo, hi = cum[first], cum[last]
        for s in range(k):
            counter = np.uint64((p * k + s) * DRAWS_PER_SAMPLE + slot)
            u = lo + stream_uniform(seed, counter) * (hi - lo)
            a, b = first, last + 1  # the first index of the run with cum > u
            while a < b:
                m = (a + b) // 2
                if cum[m] <= u:
                    a = m + 1
                else:
                    b = m
            pos = min(max(a - 1, first), last - 1)
            out[p, s] = order[pos] if included[pos] and hi > lo else -1


def twins(h: Hierarchy) -> np.ndarray:
    """Per element: is it (on) the reversed twin of a two-sided surface (Polygons.side 2)?"""
    side = h.polygons.side
    return np.zeros(len(h), bool) if side is None else side[h.polygon] == 2


def _per_element(tree: ClusterTree, n: int) -> np.ndarray:
    """The tree's per-position twin flags as a per-element array of length ``n``."""
    out = np.zeros(n, bool)
    out[tree.order] = tree.twin
    return out


def _mean_over(tree: ClusterTree, weighted: np.ndarray, area: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(Σ weighted / Σ area, Σ area) over each cluster's run of positions (all members; 0 where
    the area is)."""
    cum_w = np.concatenate([np.zeros((1, 3)), np.cumsum(weighted, axis=0)])
    cum_a = np.r_[0.0, np.cumsum(area)]
    total = cum_a[tree.end] - cum_a[tree.start]
    return (cum_w[tree.end] - cum_w[tree.start]) / np.maximum(total, 1e-300)[:, None], total


@numba.njit(cache=True)
def _push(order, start, end, included, moments, normal, out):
    """A running sum over the positions of the moments the runs start and end with gives each
    position the sum over the clusters holding it."""
    delta = np.zeros((len(order) + 1, 3, 10))
    for c in range(len(start)):
        delta[start[c]] += moments[c]
        delta[end[c]] -= moments[c]
    running = np.zeros((3, 10))
    for p in range(len(order)):
        running += delta[p]
        if included[p]:
            e = order[p]
            for q in range(3):
                out[e, q] += member_irradiance(running[q], normal[e, 0], normal[e, 1], normal[e, 2])


@numba.njit(cache=True)
def _range_max(values, start, end):
    """max of ``values`` (per position of the order) over each cluster's run (each position lies in
    O(log n) runs)."""
    out = np.zeros(len(start))
    for c in range(len(start) - 1, -1, -1):
        m = 0.0
        for p in range(start[c], end[c]):
            if values[p] > m:
                m = values[p]
        out[c] = m
    return out


class ClusterLinks:
    """Links with a cluster at one end or both: ``receiver`` and ``source`` nodes, ``kernel`` (n, 2)
    G_ij and G'_ij (1/m², the module docstring: what the source's fronts and its twins send;
    G' = 0 for an element source) and ``visibility`` V_ij. The direction a receiving cluster's push
    orients by, the unit vector from the receiver's centre toward the source's, is not stored: the
    gather takes it from the two nodes' centres (12 bytes a link less).
    The fields are views of buffers with room to grow (read them again after an edit): refinement
    extends them a chunk of pairs at a time, and a copy of the whole store per chunk made the Graz
    office's build quadratic. Stored in 32 bits (20 bytes a link; the gather sums in float64): the
    Graz office at RenderPark's element count holds 7.9M of them, 64-bit fields and a stored direction
    made them 0.9 GB."""

    _FIELDS = ("receiver", "source", "kernel", "visibility")
    _SHAPES = {"receiver": ((), np.int32), "source": ((), np.int32), "kernel": ((2,), np.float32),
               "visibility": ((), np.float32)}  # fmt: skip

    def __init__(self, receiver=(), source=(), kernel=(), visibility=()):
        receiver = np.asarray(receiver, np.int64).reshape(-1)
        values = (receiver, source, kernel, visibility)
        self._buffers = {
            name: np.array(value, dtype).reshape((-1,) + shape)
            for (name, (shape, dtype)), value in zip(self._SHAPES.items(), values)
        }
        self._n = len(receiver)

    receiver = property(lambda self: self._buffers["receiver"][: self._n])
    source = property(lambda self: self._buffers["source"][: self._n])
    kernel = property(lambda self: self._buffers["kernel"][: self._n])
    visibility = property(lambda self: self._buffers["visibility"][: self._n])

    def __len__(self) -> int:
        return self._n

    def extend(self, receiver, source, kernel, visibility) -> None:
        k = len(receiver)
        if self._n + k > len(self._buffers["receiver"]):
            capacity = max(self._n + k, int(len(self._buffers["receiver"]) * 1.5) + 16)
            # the copy's pages come on top of what is in use, not also of the refinement batches'
            # freed pages the heap keeps (a build's peak is at a growth of this store)
            release_free_heap()
            for name, old in self._buffers.items():
                grown = np.empty((capacity,) + old.shape[1:], old.dtype)
                grown[: self._n] = old[: self._n]
                self._buffers[name] = grown
        for name, value in zip(self._FIELDS, (receiver, source, kernel, visibility)):
            self._buffers[name][self._n : self._n + k] = value
        self._n += k

    def remove(self, drop: np.ndarray) -> ClusterLinks:
        """Remove the links where ``drop`` and return them (both in link order). The kept ones move
        forward in place: an index of the kept and a masked copy of each field, 16 bytes a link, were
        the top of the Graz office's peak at RenderPark's element count."""
        drop = np.asarray(drop, np.bool_)
        gone = ClusterLinks.__new__(ClusterLinks)
        gone._buffers = {name: _compact_rows(drop, getattr(self, name)) for name in self._FIELDS}
        gone._n = len(gone._buffers["receiver"])
        self._n -= gone._n
        return gone

    def touching(self, elements: np.ndarray, size: int) -> np.ndarray:
        """Mask of the links with an end among ``elements`` (element nodes only)."""
        mine = np.zeros(size, bool)
        mine[elements] = True
        return ((self.receiver >= 0) & mine[np.maximum(self.receiver, 0)]) | (
            (self.source >= 0) & mine[np.maximum(self.source, 0)]
        )


@numba.njit(cache=True)
def _compact_rows(drop, values):
    """Move the rows of ``values`` where not ``drop`` to its front, in order, in place; return the
    rows where ``drop`` (a fresh array, in order)."""
    count = 0
    for k in range(len(drop)):
        count += drop[k]
    gone = np.empty_like(values[:count])
    a = b = 0
    for k in range(len(drop)):
        if drop[k]:
            gone[b] = values[k]
            b += 1
        else:
            values[a] = values[k]
            a += 1
    return gone


class ClusteredGather:
    """The gather H = K·B of the element links plus what the cluster links bring (``@``, as
    :class:`links.LinkGather`): each cluster's power pulled from its members' B, each link's
    G·V·P_j added to its receiver — an element's row, or every member root of a receiving cluster
    (push_pull then pushes a root's irradiance down its quadtree)."""

    def __init__(self, element_gather, links: ClusterLinks, tree: ClusterTree, h: Hierarchy):
        self.element_gather, self.links, self.tree = element_gather, links, tree
        self.area = h.area.copy()
        self.normal = h.normal.copy()
        # each node's centre, elements' then clusters' (node −1 − c at row n + c): the links' directions
        self.centre = np.concatenate([h.centre, tree.centre]).astype(np.float64)
        self.shape = (len(self.area), len(self.area))

    def cluster_irradiance(self, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(element rows (n, 3), cluster moments (C, 3, 10)) of what the cluster links bring: an
        element's irradiance, and for each cluster per channel the incident irradiance E_s, its
        vector Σ E·d and second moment Σ E·d dᵀ (xx, yy, zz, xy, xz, yz) that :meth:`ClusterTree.push`
        turns into each member's irradiance."""
        L, tree = self.links, self.tree
        fronts, twins = tree.powers(self.area[:, None] * b) if len(tree) else (np.zeros((0, 3)),) * 2
        element = np.zeros((len(self.area), 3))
        moments = np.zeros((len(tree), 3, 10))
        _cluster_gather(
            L.receiver,
            L.source,
            L.kernel,
            L.visibility,
            self.centre,
            self.area,
            np.ascontiguousarray(b, np.float64),
            fronts,
            twins,
            element,
            moments,
        )
        return element, moments

    def __matmul__(self, b: np.ndarray) -> np.ndarray:
        b = np.asarray(b, np.float64)
        out = np.asarray(self.element_gather @ b, np.float64).copy()
        if len(self.links):
            element, moments = self.cluster_irradiance(b)
            out += element
            self.tree.push(moments, self.normal, out)
        return out


#: the cluster gather's links are split into this many runs summed over the cores, each into its own
#: rows (one copy of the element rows and cluster moments per run after the first: 26 MB at
#: RenderPark's element count); fixed, so the sums' order, hence B to the last bit, does not depend
#: on the machine's cores
GATHER_RUNS = 2
#: fewer links than this are gathered in one run (the copies would cost more than they save)
GATHER_RUNS_FROM = 100_000


@numba.njit(parallel=True, cache=True)
def _cluster_gather(receiver, source, kernel, visibility, centre, area, b, fronts, twins, element, moments):
    """Each link's V·(G·P + G'·P') goes to its receiver: an element's row, or a cluster's moments
    along the unit direction from its centre to the source's (``centre``: elements' rows, then
    clusters'), as cluster_kernel takes it (one pass, where NumPy's gathers and bincounts cost 20×
    the element gather). V·G is formed here, not stored: 8 bytes a link the solve does not hold.
    The links in GATHER_RUNS runs over the cores, each summed into its own rows, then added."""
    count = len(receiver)
    runs = GATHER_RUNS if count >= GATHER_RUNS_FROM else 1
    extra_element = np.zeros((runs - 1,) + element.shape)
    extra_moments = np.zeros((runs - 1,) + moments.shape)
    for r in numba.prange(runs):
        lo, hi = count * r // runs, count * (r + 1) // runs
        if r == 0:
            _gather_run(lo, hi, receiver, source, kernel, visibility, centre, area, b, fronts, twins, element, moments)
        else:
            _gather_run(
                lo,
                hi,
                receiver,
                source,
                kernel,
                visibility,
                centre,
                area,
                b,
                fronts,
                twins,
                extra_element[r - 1],
                extra_moments[r - 1],
            )
    for r in range(runs - 1):
        element += extra_element[r]
        moments += extra_moments[r]


@numba.njit(cache=True)
def _gather_run(lo, hi, receiver, source, kernel, visibility, centre, area, b, fronts, twins, element, moments):
    """_cluster_gather over the links lo … hi − 1."""
    n = area.shape[0]
    for k in range(lo, hi):
        j, i = source[k], receiver[k]
        w, w_twin = kernel[k, 0] * visibility[k], kernel[k, 1] * visibility[k]  # float32, as stored
        d0 = d1 = d2 = 0.0
        if i < 0:
            rj = j if j >= 0 else n - 1 - j
            ri = n - 1 - i
            d0, d1, d2 = centre[rj, 0] - centre[ri, 0], centre[rj, 1] - centre[ri, 1], centre[rj, 2] - centre[ri, 2]
            length = np.sqrt(max(d0 * d0 + d1 * d1 + d2 * d2, 1e-300))
            d0, d1, d2 = d0 / length, d1 / length, d2 / length
        for c in range(3):
            flow = w * area[j] * b[j, c] if j >= 0 else w * fronts[-1 - j, c] + w_twin * twins[-1 - j, c]
            if i >= 0:
                element[i, c] += flow
            else:
                m = moments[-1 - i, c]
                m[0] += flow
                m[1] += flow * d0
                m[2] += flow * d1
                m[3] += flow * d2
                m[4] += flow * d0 * d0
                m[5] += flow * d1 * d1
                m[6] += flow * d2 * d2
                m[7] += flow * d0 * d1
                m[8] += flow * d0 * d2
                m[9] += flow * d1 * d2


#: the clamped cosine max(x, 0) on x ∈ [−1, 1] projected on the Legendre polynomials P0, P1, P2
#: (the irradiance's order-2 spherical harmonics, Ramamoorthi & Hanrahan 2001): 3/32 + x/2 + 15/32·x²
PUSH_COEFFICIENTS = (3 / 32, 1 / 2, 15 / 32)


@numba.njit(cache=True, inline="always")
def member_irradiance(m, n0, n1, n2):
    """A member's irradiance (W/m²) from the moments ``m`` (10,) of one channel and its normal n:
    Σ_l E_l·max(n·d_l, 0) with max(x, 0) ≈ 3/32 + x/2 + 15/32·x² (PUSH_COEFFICIENTS) — exact for
    light from all directions or from one hemisphere, 6 % high for light from one direction straight
    on, 0.06–0.09 of it where none should arrive (grazing, from behind) — and linear in the light,
    so B stays linear in the lamps' exitances (lamp sliders re-solve, relight's lamp basis)."""
    along = n0 * m[1] + n1 * m[2] + n2 * m[3]
    square = n0 * n0 * m[4] + n1 * n1 * m[5] + n2 * n2 * m[6] + 2 * (n0 * n1 * m[7] + n0 * n2 * m[8] + n1 * n2 * m[9])
    return PUSH_COEFFICIENTS[0] * m[0] + PUSH_COEFFICIENTS[1] * along + PUSH_COEFFICIENTS[2] * square


# --- refinement over nodes


def _node_arrays(h: Hierarchy, tree: ClusterTree) -> tuple:
    """The elements' (corners, centre, normal, area) and the clusters' (lo, hi, centre, normal, area):
    the arrays the node kernels (_fill_node_boxes, _triage) read a node's box and frame from."""
    return h.corners, h.centre, h.normal, h.area, tree.lo, tree.hi, tree.centre, tree.normal, tree.area


def _node_boxes(h: Hierarchy, tree: ClusterTree, nodes: np.ndarray):
    """(lo, hi, centre, area, normal) of ``nodes`` (elements and clusters mixed)."""
    n = len(nodes)
    lo, hi, centre, normal = (np.empty((n, 3)) for _ in range(4))
    area = np.empty(n)
    _fill_node_boxes(
        *_node_arrays(h, tree),
        np.asarray(nodes, np.int64),
        lo,
        hi,
        centre,
        area,
        normal,
    )
    return lo, hi, centre, area, normal


@numba.njit(parallel=True, cache=True)
def _fill_node_boxes(
    corners, e_centre, e_normal, e_area, c_lo, c_hi, c_centre, c_normal, c_area, nodes, lo, hi, centre, area, normal
):
    """_node_boxes' rows: an element's from its corners, a cluster's (node −1 − c) from the tree."""
    for i in numba.prange(len(nodes)):
        e = nodes[i]
        if e >= 0:
            for a in range(3):
                lo[i, a] = min(min(corners[e, 0, a], corners[e, 1, a]), min(corners[e, 2, a], corners[e, 3, a]))
                hi[i, a] = max(max(corners[e, 0, a], corners[e, 1, a]), max(corners[e, 2, a], corners[e, 3, a]))
                centre[i, a], normal[i, a] = e_centre[e, a], e_normal[e, a]
            area[i] = e_area[e]
        else:
            c = -1 - e
            for a in range(3):
                lo[i, a], hi[i, a] = c_lo[c, a], c_hi[c, a]
                centre[i, a], normal[i, a] = c_centre[c, a], c_normal[c, a]
            area[i] = c_area[c]


def mean_cosine(normal: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """c(d) = max(N̄·d, 0) + (1 − |N̄|)/4 (the module docstring), per row."""
    length = np.linalg.norm(normal, axis=1)
    return np.maximum((normal * direction).sum(axis=1), 0.0) + np.maximum(1 - length, 0.0) / 4


def _all_behind(lo, hi, centre, normal, tolerance=1e-9) -> np.ndarray:
    """Does the box [lo, hi] lie wholly behind the plane through ``centre`` with ``normal``? (rows)"""
    # the box corner farthest along the normal
    far = np.where(normal > 0, hi, lo)
    return ((far - centre) * normal).sum(axis=1) <= tolerance


def _box_distance(lo_a, hi_a, lo_b, hi_b) -> np.ndarray:
    gap = np.maximum(np.maximum(lo_a - hi_b, lo_b - hi_a), 0.0)
    return np.sqrt((gap * gap).sum(axis=1))


#: pairs a slice of transfer_bound's work: its boxes are ~250 bytes a pair, and re-testing every
#: cluster link at once (7.9M on the Graz office at RenderPark's element count) held 1.1 GB of them
BOUND_SLICE = 65_536


def transfer_bound(h, tree, receivers, sources, b_max_element, b_max_cluster, above: float | None = None):
    """T_ij = B_max,j · A_i · min(A_j/(π d²), 1) per pair (W): at most what the link can carry. With
    ``above``, the mask T_ij > above instead (a build's re-test of every cluster link: 1 byte a link
    held, not 8). (Refinement computes the same T inside :func:`_triage`.)"""
    if len(receivers) > BOUND_SLICE:  # sliced before anything is made per pair (int64 copies included)
        out = np.empty(len(receivers), np.float64 if above is None else bool)
        for at in range(0, len(receivers), BOUND_SLICE):
            part = slice(at, at + BOUND_SLICE)
            out[part] = transfer_bound(
                h,
                tree,
                receivers[part],
                sources[part],
                b_max_element,
                b_max_cluster,
                above,
            )
        return out
    receivers, sources = np.asarray(receivers, np.int64), np.asarray(sources, np.int64)
    lo_r, hi_r, _, area_r, _ = _node_boxes(h, tree, receivers)
    lo_s, hi_s, _, area_s, _ = _node_boxes(h, tree, sources)
    d = _box_distance(lo_r, hi_r, lo_s, hi_s)
    with np.errstate(divide="ignore"):
        ff = np.minimum(area_s / (np.pi * d * d), 1.0)
    source_b = np.where(
        sources >= 0,
        b_max_element[np.maximum(sources, 0)],
        b_max_cluster[np.maximum(-1 - sources, 0)] if len(tree) else 0.0,
    )
    bound = source_b * area_r * ff
    return bound if above is None else bound > above


#: what refinement does with a pair of its batch (_triage): drop it (an element end has the other
#: node's whole box behind its plane; or neither end can split), link it, or split one end
DROP, ACCEPT, SPLIT_SOURCE, SPLIT_RECEIVER = 0, 1, 2, 3


@numba.njit(cache=True, inline="always")
def _node_box(corners, e_centre, e_normal, e_area, c_lo, c_hi, c_centre, c_normal, c_area, e):
    """One row of _node_boxes as scalars: lo (3), hi (3), centre (3), normal (3), area."""
    if e >= 0:
        lo0 = min(min(corners[e, 0, 0], corners[e, 1, 0]), min(corners[e, 2, 0], corners[e, 3, 0]))
        lo1 = min(min(corners[e, 0, 1], corners[e, 1, 1]), min(corners[e, 2, 1], corners[e, 3, 1]))
        lo2 = min(min(corners[e, 0, 2], corners[e, 1, 2]), min(corners[e, 2, 2], corners[e, 3, 2]))
        hi0 = max(max(corners[e, 0, 0], corners[e, 1, 0]), max(corners[e, 2, 0], corners[e, 3, 0]))
        hi1 = max(max(corners[e, 0, 1], corners[e, 1, 1]), max(corners[e, 2, 1], corners[e, 3, 1]))
        hi2 = max(max(corners[e, 0, 2], corners[e, 1, 2]), max(corners[e, 2, 2], corners[e, 3, 2]))
        return (
            lo0, lo1, lo2, hi0, hi1, hi2,
            e_centre[e, 0], e_centre[e, 1], e_centre[e, 2],
            e_normal[e, 0], e_normal[e, 1], e_normal[e, 2],
            e_area[e],
        )  # fmt: skip
    c = -1 - e
    return (
        c_lo[c, 0], c_lo[c, 1], c_lo[c, 2], c_hi[c, 0], c_hi[c, 1], c_hi[c, 2],
        c_centre[c, 0], c_centre[c, 1], c_centre[c, 2],
        c_normal[c, 0], c_normal[c, 1], c_normal[c, 2],
        c_area[c],
    )  # fmt: skip


@numba.njit(cache=True, inline="always")
def _behind(lo0, lo1, lo2, hi0, hi1, hi2, c0, c1, c2, n0, n1, n2, tolerance):
    """_all_behind for one row: the box's corner farthest along the normal is behind the plane."""
    f0 = hi0 if n0 > 0 else lo0
    f1 = hi1 if n1 > 0 else lo1
    f2 = hi2 if n2 > 0 else lo2
    return (f0 - c0) * n0 + (f1 - c1) * n1 + (f2 - c2) * n2 <= tolerance


@numba.njit(parallel=True, cache=True)
def _triage(
    corners, e_centre, e_normal, e_area, c_lo, c_hi, c_centre, c_normal, c_area, recv, src, emits, threshold, min_area
):
    """Per pair of a refinement batch (nodes live, ρ_max,i and B_max,j = ``emits`` > 0): DROP where an
    element end has the other node's whole box behind its plane (_all_behind), ACCEPT where
    T_ij ≤ ``threshold`` (transfer_bound's T), else SPLIT_SOURCE where the source can split (a
    cluster, or an element whose quarter is at least ``min_area``) and its box diagonal is at least
    the receiver's or the receiver cannot split, else SPLIT_RECEIVER where the receiver can, else
    DROP — the same arithmetic as the NumPy statement in order (a test compares the two)."""
    out = np.empty(len(recv), np.int8)
    for i in numba.prange(len(recv)):
        r, s = recv[i], src[i]
        rl0, rl1, rl2, rh0, rh1, rh2, rc0, rc1, rc2, rn0, rn1, rn2, area_r = _node_box(
            corners, e_centre, e_normal, e_area, c_lo, c_hi, c_centre, c_normal, c_area, r
        )
        sl0, sl1, sl2, sh0, sh1, sh2, sc0, sc1, sc2, sn0, sn1, sn2, area_s = _node_box(
            corners, e_centre, e_normal, e_area, c_lo, c_hi, c_centre, c_normal, c_area, s
        )
        if (r >= 0 and _behind(sl0, sl1, sl2, sh0, sh1, sh2, rc0, rc1, rc2, rn0, rn1, rn2, 1e-9)) or (
            s >= 0 and _behind(rl0, rl1, rl2, rh0, rh1, rh2, sc0, sc1, sc2, sn0, sn1, sn2, 1e-9)
        ):
            out[i] = DROP
            continue
        g0 = max(max(rl0 - sh0, sl0 - rh0), 0.0)
        g1 = max(max(rl1 - sh1, sl1 - rh1), 0.0)
        g2 = max(max(rl2 - sh2, sl2 - rh2), 0.0)
        d = np.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
        # touching boxes: A_j/0 = inf, or 0/0 = NaN where A_j = 0 (never accepted), as NumPy has it
        ff = min(area_s / (np.pi * d * d), 1.0) if d > 0 else (1.0 if area_s > 0 else np.nan)
        if emits[i] * area_r * ff <= threshold:
            out[i] = ACCEPT
            continue
        size_r = np.sqrt((rh0 - rl0) ** 2 + (rh1 - rl1) ** 2 + (rh2 - rl2) ** 2)
        size_s = np.sqrt((sh0 - sl0) ** 2 + (sh1 - sl1) ** 2 + (sh2 - sl2) ** 2)
        can_r = r < 0 or area_r / 4 >= min_area
        can_s = s < 0 or area_s / 4 >= min_area
        if can_s and (size_s >= size_r or not can_r):
            out[i] = SPLIT_SOURCE
        elif can_r:
            out[i] = SPLIT_RECEIVER
        else:
            out[i] = DROP
    return out


def triage(h: Hierarchy, tree: ClusterTree, recv, src, emits, threshold: float, min_area: float) -> np.ndarray:
    """_triage over the hierarchy's and the tree's arrays: per pair DROP, ACCEPT, SPLIT_SOURCE or
    SPLIT_RECEIVER (int8)."""
    return _triage(
        *_node_arrays(h, tree),
        np.asarray(recv, np.int64),
        np.asarray(src, np.int64),
        np.asarray(emits, np.float64),
        float(threshold),
        float(min_area),
    )


@numba.njit(parallel=True, cache=True)
def _cluster_rays(
    corners,
    triangle,
    normal,
    reflect,
    bright,
    open_share,
    receivers,
    sources,
    roots_a,
    roots_b,
    seed,
    point_state,
    offset,
    origin,
    unit,
    up,
    dist,
    counted,
    weight,
    slot,
):
    """Per sample s of pair p (row i = p·k + s): the ray from a point of roots_a[p, s]'s own grid
    (visibility.element_uv of its ``point_state``: point s where the receiver is that element, else the
    point the stream's uniform of row i after the member's draws; ``slot``) to the point on
    roots_b[p, s] (uniform: its (u, v) the stream's uniforms of row i at the slots after the
    member's, ``seed`` the call's), both lifted by ``offset`` along their normals (origin, unit direction,
    the receiver's normal ``up``, length short of the target by ``offset``, float32, as Embree takes
    them), whether the ray counts — both points exist, it leaves the receiver's front toward the
    source's front, and it is longer than 2·offset — and its weight in V, ρ_a·cos θ_a·cos θ_b·B_b
    (the largest channel of ``reflect`` and ``bright``, per element (n, 3); 0 where it does not
    count), ρ_a and B_b times the member's ``open_share`` where that end (``receivers[p]``,
    ``sources[p]``) is a cluster."""
    n, k = roots_a.shape
    side = int(np.ceil(np.sqrt(k)))
    for p in numba.prange(n):
        for s in range(k):
            i = p * k + s
            ea, eb = roots_a[p, s], roots_b[p, s]
            weight[i] = 0.0
            if ea < 0 or eb < 0:
                counted[i] = False
                continue
            up[i, 0], up[i, 1], up[i, 2] = normal[ea, 0], normal[ea, 1], normal[ea, 2]
            at = np.uint64(i * DRAWS_PER_SAMPLE)
            # the receiving point is one of its member's own points: sample s of an element's own
            # grid, a drawn one of a member's (the probe's answer there is kept)
            t = s if receivers[p] >= 0 else min(int(stream_uniform(seed, at + np.uint64(RECEIVER_SLOT + 1)) * k), k - 1)
            slot[i] = t
            ua, va = element_uv(point_state[ea], t, side)
            ub = stream_uniform(seed, at + np.uint64(SOURCE_SLOT + 1))
            vb = stream_uniform(seed, at + np.uint64(SOURCE_SLOT + 2))
            a0, a1, a2 = point_on(corners, triangle, ea, ua, va)
            b0, b1, b2 = point_on(corners, triangle, eb, ub, vb)
            o0, o1, o2 = a0 + offset * normal[ea, 0], a1 + offset * normal[ea, 1], a2 + offset * normal[ea, 2]
            d0 = b0 + offset * normal[eb, 0] - o0
            d1 = b1 + offset * normal[eb, 1] - o1
            d2 = b2 + offset * normal[eb, 2] - o2
            length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            norm = max(length, 1e-300)
            u0, u1, u2 = d0 / norm, d1 / norm, d2 / norm
            cos_a = normal[ea, 0] * u0 + normal[ea, 1] * u1 + normal[ea, 2] * u2
            cos_b = -(normal[eb, 0] * u0 + normal[eb, 1] * u1 + normal[eb, 2] * u2)
            counted[i] = cos_a > 0 and cos_b > 0 and length > 2 * offset
            if counted[i]:
                receiving = max(max(reflect[ea, 0], reflect[ea, 1]), reflect[ea, 2])
                sending = max(max(bright[eb, 0], bright[eb, 1]), bright[eb, 2])
                if receivers[p] < 0:
                    receiving *= open_share[ea]
                if sources[p] < 0:
                    sending *= open_share[eb]
                weight[i] = receiving * cos_a * cos_b * sending
            origin[i, 0], origin[i, 1], origin[i, 2] = o0, o1, o2
            unit[i, 0], unit[i, 1], unit[i, 2] = u0, u1, u2
            dist[i] = max(length - offset, 0.0)


def cluster_visibility(h, tree, visibility, receivers, sources, counted_rays: bool = False, radiosity=None):
    """V_ij per pair: the weighted clear share of rays between random points of the two nodes that
    leave one surface's front toward the other's front (the module docstring; 0 where no sampled ray
    does), weighted by ``radiosity`` (the B estimate, default the hierarchy's); with
    ``counted_rays``, (V, how many rays counted)."""
    n, k = len(receivers), visibility.samples
    if n == 0:
        return (np.zeros(0), np.zeros(0, np.int64)) if counted_rays else np.zeros(0)
    receivers, sources = np.asarray(receivers, np.int64), np.asarray(sources, np.int64)
    # every point of the call from one seed: drawn in the kernels, by each sample's index
    seed = np.uint64(visibility.rng.integers(0, 2**63))
    roots_a = tree.node_members(h, receivers, k, seed, RECEIVER_SLOT)
    roots_b = tree.node_members(h, sources, k, seed, SOURCE_SLOT)
    origin, unit, up = (np.empty((n * k, 3), np.float32) for _ in range(3))
    dist, counted = np.empty(n * k, np.float32), np.empty(n * k, np.bool_)
    weight, slot = np.empty(n * k), np.zeros(n * k, np.uint8)  # (k ≤ 256)
    # a cluster's members weigh by their openness too: a closed box's inner faces and a board's
    # back against a wall neither receive nor send what the cluster carries (the members drawn here
    # measured, each once a scene: after a move's rebuild only those a recast pair draws)
    open_share = visibility.openness_array((roots_a, receivers < 0), (roots_b, sources < 0))
    _cluster_rays(
        h.corners,
        h.triangle,
        h.normal,
        np.ascontiguousarray(h.reflectance, np.float64),
        np.ascontiguousarray(h.radiosity if radiosity is None else radiosity, np.float64),
        open_share,
        receivers,
        sources,
        roots_a,
        roots_b,
        seed,
        visibility.point_states(),
        visibility.offset,
        origin,
        unit,
        up,
        dist,
        counted,
        weight,
        slot,
    )
    chosen = np.flatnonzero(counted)
    if len(chosen):
        # a receiving point in contact with something (a face against another, inside a closed
        # object) is not part of a visible surface: left out, as the element links' V leaves it
        counted[chosen] = visibility.exposed_points(roots_a.reshape(-1), slot, origin, up, chosen)
        chosen = chosen[counted[chosen]]
    clear = np.zeros(n * k, bool)
    if len(chosen):
        if visibility.empty:
            clear[chosen] = True
        else:
            hit = cast(visibility.scene, origin[chosen], unit[chosen], dist[chosen], "OCCLUDED")
            clear[chosen] = np.asarray(hit) < 0
            visibility.rays += len(chosen)
    v, seen = _clear_shares(counted, clear, weight, k)
    return (v, seen) if counted_rays else v


@numba.njit(parallel=True, cache=True)
def _clear_shares(counted, clear, weight, k):
    """(V, rays counted) per pair from its k samples (rows p·k … p·k + k − 1): the clear share
    of the counted samples weighted by ``weight``; unweighted where their weights sum to 0; 0 where
    none counted."""
    n = len(counted) // k
    v, seen = np.zeros(n), np.zeros(n, np.int64)
    for p in numba.prange(n):
        count, hits, total, carried = 0, 0, 0.0, 0.0
        for i in range(p * k, p * k + k):
            if counted[i]:
                count += 1
                total += weight[i]
                if clear[i]:
                    hits += 1
                    carried += weight[i]
        seen[p] = count
        if total > 0:
            v[p] = carried / total
        elif count > 0:
            v[p] = hits / count
    return v, seen


def cluster_kernel(h, tree, receivers, sources) -> tuple[np.ndarray, np.ndarray]:
    """(G_ij and G'_ij (n, 2) (1/m²), the unit direction d from receiver to source) per pair:
    G = c_i(d)·c_j(−d)/(π r² + A_j) with c_j over the source's fronts, G' with c_j over its twins
    (0 for an element source), for an element receiver; for a cluster receiver c_i is left out (the
    push orients by each member's own normal). (One kernel over the pairs; a test states it in
    NumPy.)"""
    n = len(receivers)
    kernel, unit = np.empty((n, 2)), np.empty((n, 3))
    _cluster_kernel(
        h.centre,
        h.normal,
        h.area,
        tree.centre,
        tree.area,
        tree.front_normal,
        tree.twin_normal,
        tree.twin_area,
        np.asarray(receivers, np.int64),
        np.asarray(sources, np.int64),
        kernel,
        unit,
    )
    return kernel, unit


@numba.njit(cache=True, inline="always")
def _mean_cosine(n0, n1, n2, d0, d1, d2):
    """mean_cosine for one row."""
    length = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    return max(n0 * d0 + n1 * d1 + n2 * d2, 0.0) + max(1 - length, 0.0) / 4


@numba.njit(parallel=True, cache=True)
def _cluster_kernel(
    e_centre,
    e_normal,
    e_area,
    c_centre,
    c_area,
    front_normal,
    twin_normal,
    twin_area,
    receivers,
    sources,
    kernel,
    unit,
):
    for i in numba.prange(len(receivers)):
        r, s = receivers[i], sources[i]
        if r >= 0:
            cr0, cr1, cr2 = e_centre[r, 0], e_centre[r, 1], e_centre[r, 2]
        else:
            cr0, cr1, cr2 = c_centre[-1 - r, 0], c_centre[-1 - r, 1], c_centre[-1 - r, 2]
        if s >= 0:
            cs0, cs1, cs2, area_s = e_centre[s, 0], e_centre[s, 1], e_centre[s, 2], e_area[s]
        else:
            c = -1 - s
            cs0, cs1, cs2, area_s = c_centre[c, 0], c_centre[c, 1], c_centre[c, 2], c_area[c]
        d0, d1, d2 = cs0 - cr0, cs1 - cr1, cs2 - cr2
        r2 = d0 * d0 + d1 * d1 + d2 * d2
        norm = np.sqrt(max(r2, 1e-300))
        u0, u1, u2 = d0 / norm, d1 / norm, d2 / norm
        unit[i, 0], unit[i, 1], unit[i, 2] = u0, u1, u2
        c_i = 1.0
        if r >= 0:
            c_i = _mean_cosine(e_normal[r, 0], e_normal[r, 1], e_normal[r, 2], u0, u1, u2)
        scale = c_i / (np.pi * r2 + area_s)
        if s >= 0:
            kernel[i, 0] = scale * _mean_cosine(e_normal[s, 0], e_normal[s, 1], e_normal[s, 2], -u0, -u1, -u2)
            kernel[i, 1] = 0.0
        else:
            c = -1 - s
            f = front_normal[c]
            kernel[i, 0] = scale * _mean_cosine(f[0], f[1], f[2], -u0, -u1, -u2)
            kernel[i, 1] = 0.0
            if twin_area[c] > 0:
                t = twin_normal[c]
                kernel[i, 1] = scale * _mean_cosine(t[0], t[1], t[2], -u0, -u1, -u2)


def _children(h, tree, nodes, position):
    """The child nodes of ``nodes`` (all splittable) and which of them each came from: a cluster's
    two (a member root excluded from the tree left out: it is linked on its own), an element's four."""
    cl = nodes < 0
    parents, kids = [], []
    c = -1 - nodes[cl]
    idx = np.flatnonzero(cl)
    for kid in (tree.left[c], tree.right[c]):
        root = kid >= 0
        keep = ~root | tree.included[np.maximum(position[np.maximum(kid, 0)], 0)]
        parents.append(idx[keep])
        kids.append(kid[keep])
    idx = np.flatnonzero(~cl)
    if len(idx):
        first = h.subdivide(nodes[idx])
        for q in range(4):
            parents.append(idx)
            kids.append(first + q)
    return np.concatenate(parents), np.concatenate(kids)


def _live(tree, nodes, counts) -> np.ndarray:
    """False for a cluster none of whose members is included (it carries nothing). ``counts``: the
    included members before each position of the tree's order (np.r_[0, cumsum(tree.included)],
    made once a refinement: the tree does not change during one)."""
    out = np.ones(len(nodes), bool)
    cl = nodes < 0
    if cl.any():
        c = -1 - nodes[cl]
        out[cl] = counts[tree.end[c]] > counts[tree.start[c]]
    return out


def refine_nodes(
    h: Hierarchy,
    tree: ClusterTree,
    visibility,
    receivers,
    sources,
    threshold: float,
    min_area: float,
    criterion: str,
    links,
    cluster_links: ClusterLinks,
    radiosity=None,
) -> None:
    """Refine node pairs (the module docstring) into ``cluster_links`` and, through
    :func:`refine.refine`, element ``links``. ``radiosity``: the B estimate (default the
    hierarchy's). A root excluded from the tree is never reached from a cluster, only when named."""
    # clusters' B_max and ρ_max from the roots (fixed); the elements' grow with every split (children
    # inherit their parent's values), so they are read again each round
    b_cluster = (
        tree.member_max(channel_max(h.radiosity if radiosity is None else radiosity)) if len(tree) else np.zeros(0)
    )
    rho_cluster = tree.member_max(channel_max(h.reflectance)) if len(tree) else np.zeros(0)
    position = np.full(len(h), -1)
    position[tree.order] = np.arange(len(tree.order))
    included = np.r_[0, np.cumsum(tree.included)]
    element_pairs = []
    queue = [(np.asarray(receivers, np.int64), np.asarray(sources, np.int64))]
    while queue:
        recv, src = queue.pop()
        if len(recv) > CHUNK:
            queue.append((recv[CHUNK:], src[CHUNK:]))
            recv, src = recv[:CHUNK], src[:CHUNK]
        both = (recv >= 0) & (src >= 0)
        if both.any():
            element_pairs.append((recv[both], src[both]))
            recv, src = recv[~both], src[~both]
        live = _live(tree, recv, included) & _live(tree, src, included)
        # the elements' largest channels read for this batch's pairs only (the whole hierarchy's, a
        # batch at a time, were 2.5 s of the Graz office's build at RenderPark's element count)
        b_element = h.radiosity if radiosity is None else radiosity
        reflects = np.where(
            recv >= 0, channel_max(h.reflectance[np.maximum(recv, 0)]), rho_cluster[np.maximum(-1 - recv, 0)]
        )
        emits = np.where(src >= 0, channel_max(b_element[np.maximum(src, 0)]), b_cluster[np.maximum(-1 - src, 0)])
        keep = live & (reflects > 0) & (emits > 0)
        recv, src, emits = recv[keep], src[keep], emits[keep]
        if not len(recv):
            continue
        # the boxes, the planes' test, the bound and the split decided in one pass (the NumPy
        # statement's copies of the boxes for the pairs kept were 6 % of a build)
        fate = triage(h, tree, recv, src, emits, threshold, min_area)
        accept = fate == ACCEPT
        if accept.any():
            r, s = recv[accept], src[accept]
            kernel, _ = cluster_kernel(h, tree, r, s)
            vis, seen = cluster_visibility(h, tree, visibility, r, s, counted_rays=True, radiosity=radiosity)
            # no sampled ray leaves a front toward a front: the two face away from each other (as
            # refine drops a pair of elements that do not face)
            faces = (seen > 0) & (kernel.max(axis=1) > 0)
            cluster_links.extend(r[faces], s[faces], kernel[faces], vis[faces])
        split_src, split_recv = fate == SPLIT_SOURCE, fate == SPLIT_RECEIVER
        # (one end is a cluster, which can always split: no pair is stuck)
        parent, kid = _children(h, tree, src[split_src], position)
        new_recv = [recv[split_src][parent]]
        new_src = [kid]
        parent, kid = _children(h, tree, recv[split_recv], position)
        new_recv.append(kid)
        new_src.append(src[split_recv][parent])
        queue.append((np.concatenate(new_recv), np.concatenate(new_src)))
    if element_pairs:
        r = np.concatenate([p[0] for p in element_pairs])
        s = np.concatenate([p[1] for p in element_pairs])
        element_pairs.clear()  # the parts' copies freed before refinement's own working set
        refine(h, visibility, r, s, threshold, min_area, criterion, radiosity=radiosity, links=links)
