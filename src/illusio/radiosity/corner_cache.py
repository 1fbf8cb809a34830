"""The corner gather of the smooth display (:func:`illusio.radiosity.display.corner_gather` states it
plainly) in numba, with its form factors kept between calls, so that an edit that changes a few
links (a virtual object moved, a lamp added) pays only for the pairs it changed.

The gather at the corners of a leaf sums, over every link its element and its ancestors receive,
F(corner → source)·V·B_source. F depends only on the corner and the source's polygon, so it is kept
per link (receiver r, source j) for every leaf under r — one block of pairs per link, the blocks in
the order of the links' keys r·2³² + j. On the next call a link's block is reused when the link
(r, j) existed before, no leaf under r was split, merged, moved, or joined or left the leaves asked
for (a display that gathers only what it shows), and j did not move; every other
link's block is computed afresh. V and B are read at each call (they change with every solve). After
any change the result equals the plain gather (tested).

Why numba: at 5.5k leaves a relit office has 1.6M (link, leaf) pairs; copying the kept blocks and
summing them as NumPy index arrays cost 0.25 s a call, a loop over the blocks does it in a tenth of
that (benchmarks/RESULTS.md, relight).
"""

from __future__ import annotations

import numba
import numpy as np

from .display import leaves_under
from .formfactor import contour_integral
from .hierarchy import Hierarchy
from .links import Links

__all__ = ["CornerGather"]


def _link_keys(links: Links) -> np.ndarray:
    """One exact int64 key per link: receiver·2³² + source (element indices < 2³¹)."""
    return (links.receiver.astype(np.int64) << 32) | links.source.astype(np.int64)


@numba.njit(parallel=True, cache=True)
def _assemble(start, reuse, old_block, old_start, old_leaf, old_ff, first_under, leaf_under, fresh_start, pair_leaf,
              pair_ff, fresh_pair, fresh_link):
    """Fill each link's block of pairs: a reused link's from its old block, the others' leaves from
    the leaf table (their pairs listed from fresh_start[k] in fresh_pair / fresh_link, for the form
    factors)."""
    for k in numba.prange(len(start) - 1):
        a, n = start[k], start[k + 1] - start[k]
        if reuse[k]:
            o = old_start[old_block[k]]
            for q in range(n):
                pair_leaf[a + q] = old_leaf[o + q]
                for c in range(4):
                    pair_ff[a + q, c] = old_ff[o + q, c]
        else:
            f = fresh_start[k]
            for q in range(n):
                pair_leaf[a + q] = leaf_under[first_under[k] + q]
                fresh_pair[f + q] = a + q
                fresh_link[f + q] = k


@numba.njit(parallel=True, cache=True)
def _corner_form_factors(corners, centre, normal, triangle, leaf, source, out):
    """display.corner_form_factors for the pairs (leaf, source), read by index."""
    for p in numba.prange(len(leaf)):
        e, j = leaf[p], source[p]
        m = 3 if triangle[j] else 4
        for c in range(4):
            # 1 % of the way to the centre, as the reference takes it
            x0 = corners[e, c, 0] + 0.01 * (centre[e, 0] - corners[e, c, 0])
            x1 = corners[e, c, 1] + 0.01 * (centre[e, 1] - corners[e, c, 1])
            x2 = corners[e, c, 2] + 0.01 * (centre[e, 2] - corners[e, c, 2])
            out[p, c] = contour_integral(x0, x1, x2, normal[e, 0], normal[e, 1], normal[e, 2], corners[j], m)


#: the gather's partial sums: a fixed number of slices of the links, summed in order, so the result
#: does not depend on how many threads ran them
SLICES = 8


@numba.njit(parallel=True, cache=True)
def _gather(start, pair_leaf, pair_ff, visibility, source, radiosity, row, out):
    """out[slice, row of leaf, corner] += F·V·B_source over the pairs of each slice of the links."""
    links = len(start) - 1
    for t in numba.prange(out.shape[0]):
        for k in range(links * t // out.shape[0], links * (t + 1) // out.shape[0]):
            v = visibility[k]
            if v == 0.0:
                continue
            j = source[k]
            b0, b1, b2 = radiosity[j, 0], radiosity[j, 1], radiosity[j, 2]
            for p in range(start[k], start[k + 1]):
                r = row[pair_leaf[p]]
                for c in range(4):
                    w = pair_ff[p, c] * v
                    out[t, r, c, 0] += w * b0
                    out[t, r, c, 1] += w * b1
                    out[t, r, c, 2] += w * b2


class CornerGather:
    """Call as ``corner_gather(h, links, leaves, exitance)``; keeps the last call's form factors."""

    def __init__(self):
        self._keys = np.zeros(0, np.int64)      # sorted link keys of the last call
        self._start = np.zeros(1, np.int64)     # block of each key in the pair arrays
        self._pair_leaf = np.zeros(0, np.int64)
        self._pair_ff = np.zeros((0, 4))
        self._pair_leaf_buffer, self._pair_ff_buffer = self._pair_leaf, self._pair_ff
        self._spare = (np.zeros(0, np.int64), np.zeros((0, 4)))
        self._child = np.zeros(0, np.int64)
        self._corners = np.zeros((0, 4, 3))
        self._asked = np.zeros(0, bool)         # the leaves of the last call, as a mask
        self.reused = self.computed = 0         # pairs in the last call

    def _buffers(self, total: int) -> tuple[np.ndarray, np.ndarray]:
        """Pair arrays for this call: the spare pair of buffers (the last call's but one), grown when
        short. Reusing them spares the page faults of 50 MB of fresh memory a call (10 ms at 1.6M
        pairs); the last call's buffers are still being read from."""
        leaf, ff = self._spare
        if len(leaf) < total:
            leaf, ff = np.empty(int(total * 1.25) + 16, np.int64), np.empty((int(total * 1.25) + 16, 4))
        self._spare_in_use = (leaf, ff)
        return leaf[:total], ff[:total]

    def _changed(self, h: Hierarchy, asked: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(dirty (n,): some leaf under the element was split, merged, moved, asked for or no longer
        since the last call, moved (n,): the element's corners changed or it is new)."""
        n, old = len(h), len(self._child)
        keep = min(n, old)
        moved = np.ones(n, bool)
        moved[:keep] = np.any(h.corners[:keep] != self._corners[:keep], axis=(1, 2))
        changed = moved.copy()
        changed[:keep] |= (h.child[:keep] != self._child[:keep]) | (asked[:keep] != self._asked[:keep])
        changed &= h.active | (np.arange(n) < keep)
        dirty = np.zeros(n, bool)
        frontier = np.flatnonzero(changed)
        while len(frontier):
            frontier = frontier[~dirty[frontier]]
            dirty[frontier] = True
            frontier = h.parent[frontier]
            frontier = frontier[frontier >= 0]
        return dirty, moved

    def __call__(self, h: Hierarchy, links: Links, leaves: np.ndarray, exitance: np.ndarray) -> np.ndarray:
        asked = np.zeros(len(h), bool)
        asked[leaves] = True
        dirty, moved = self._changed(h, asked)
        keys = _link_keys(links)
        order = np.argsort(keys, kind="stable")     # links keep their order between edits: nearly sorted runs
        keys = keys[order]
        r, s = links.receiver[order], links.source[order]
        block = np.minimum(np.searchsorted(self._keys, keys), max(len(self._keys) - 1, 0))
        found = (self._keys[block] == keys) if len(self._keys) else np.zeros(len(keys), bool)
        reuse = found & ~dirty[r] & ~moved[s]
        count = np.zeros(len(keys), np.int64)
        count[reuse] = self._start[block[reuse] + 1] - self._start[block[reuse]]
        element, leaf_under = leaves_under(h, leaves)
        first_under = np.zeros(len(keys), np.int64)
        first_under[~reuse] = np.searchsorted(element, r[~reuse])
        count[~reuse] = np.searchsorted(element, r[~reuse], side="right") - first_under[~reuse]
        start = np.r_[0, np.cumsum(count)]
        total = int(start[-1])
        fresh_start = np.r_[0, np.cumsum(np.where(reuse, 0, count))]
        pair_leaf, pair_ff = self._buffers(total)
        fresh_pair = np.empty(int(fresh_start[-1]), np.int64)
        fresh_link = np.empty_like(fresh_pair)
        _assemble(start, reuse, block, self._start, self._pair_leaf, self._pair_ff, first_under, leaf_under,
                  fresh_start, pair_leaf, pair_ff, fresh_pair, fresh_link)
        if len(fresh_pair):
            ff = np.empty((len(fresh_pair), 4))
            _corner_form_factors(np.ascontiguousarray(h.corners, np.float64), np.ascontiguousarray(h.centre, np.float64),
                                 np.ascontiguousarray(h.normal, np.float64), np.ascontiguousarray(h.triangle, np.bool_),
                                 pair_leaf[fresh_pair], s[fresh_link], ff)
            pair_ff[fresh_pair] = ff
        self.computed = len(fresh_pair)
        self.reused = total - self.computed
        self._spare = (self._pair_leaf_buffer, self._pair_ff_buffer)
        self._pair_leaf_buffer, self._pair_ff_buffer = self._spare_in_use
        self._keys, self._start, self._pair_leaf, self._pair_ff = keys, start, pair_leaf, pair_ff
        self._child, self._corners, self._asked = h.child.copy(), h.corners.copy(), asked
        # the gather itself, with this call's V and B
        row = np.full(len(h), -1, np.int64)
        row[leaves] = np.arange(len(leaves))
        parts = np.zeros((SLICES, len(leaves), 4, 3))
        _gather(start, pair_leaf, pair_ff, np.ascontiguousarray(links.visibility[order], np.float64), s,
                np.ascontiguousarray(h.radiosity, np.float64), row, parts)
        irradiance = parts.sum(axis=0)
        return exitance[leaves][:, None] + h.reflectance[leaves][:, None] * irradiance
