"""The corner gather of the smooth display (:func:`illusio.radiosity.display.corner_gather` is one
call of it with nothing kept), with its form factors kept between calls, so that an edit that changes a few links (a virtual object moved, a lamp added) pays
only for the pairs it changed.

The gather at the corners of a leaf sums, over every link its element and its ancestors receive,
F(corner → source)·V·B_source. F depends only on the corner and the source's polygon, so it is kept
per link (receiver r, source j) for every leaf under r — one block of pairs per link. On the next call
a link's block is reused when the link (r, j) existed before, no leaf under r was split, merged or
moved, and j did not move; every other link's block is computed afresh. V and B are read at each
call (they change with every solve). After any change the result equals a fresh gather (tested).
"""

from __future__ import annotations

import numpy as np

from .formfactor import point_polygon
from .hierarchy import Hierarchy
from .links import Links

__all__ = ["CornerGather"]


def _link_keys(links: Links) -> np.ndarray:
    """One exact complex key per link: receiver + i·source (indices < 2^53)."""
    return links.receiver.astype(np.float64) + 1j * links.source.astype(np.float64)


class CornerGather:
    """Call as ``corner_gather(h, links, leaves, exitance)``; keeps the last call's form factors."""

    def __init__(self):
        self._keys = np.zeros(0, complex)       # sorted link keys of the last call
        self._start = np.zeros(1, np.int64)     # block of each key in the pair arrays
        self._pair_leaf = np.zeros(0, np.int64)
        self._pair_ff = np.zeros((0, 4))
        self._child = np.zeros(0, np.int64)
        self._corners = np.zeros((0, 4, 3))
        self.reused = self.computed = 0         # pairs in the last call

    def _changed(self, h: Hierarchy) -> tuple[np.ndarray, np.ndarray]:
        """(dirty (n,): some leaf under the element was split, merged or moved since the last call,
        moved (n,): the element's corners changed or it is new)."""
        n, old = len(h), len(self._child)
        keep = min(n, old)
        moved = np.ones(n, bool)
        moved[:keep] = np.any(h.corners[:keep] != self._corners[:keep], axis=(1, 2))
        changed = moved.copy()
        changed[:keep] |= h.child[:keep] != self._child[:keep]
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
        dirty, moved = self._changed(h)
        keys = _link_keys(links)
        order = np.argsort(keys, kind="stable")
        keys = keys[order]
        pos = np.minimum(np.searchsorted(self._keys, keys), max(len(self._keys) - 1, 0))
        found = (self._keys[pos] == keys) if len(self._keys) else np.zeros(len(keys), bool)
        r, s = links.receiver[order], links.source[order]
        reuse = found & ~dirty[r] & ~moved[s]
        # pairs of the reused links: their old blocks
        count_old = np.zeros(len(keys), np.int64)
        count_old[reuse] = self._start[pos[reuse] + 1] - self._start[pos[reuse]]
        # pairs of the others: every leaf under the receiver (from a leaf → ancestor table)
        anc_leaf, anc = [], []
        element, of = leaves.copy(), leaves.copy()
        while len(element):
            anc_leaf.append(of)
            anc.append(element)
            up = h.parent[element] >= 0
            element, of = h.parent[element[up]], of[up]
        anc_leaf, anc = np.concatenate(anc_leaf), np.concatenate(anc)
        by_anc = np.argsort(anc, kind="stable")
        anc_sorted = anc[by_anc]
        lo, hi = np.searchsorted(anc_sorted, r), np.searchsorted(anc_sorted, r, side="right")
        count_new = np.where(reuse, 0, hi - lo)
        count = count_old + count_new
        start = np.r_[0, np.cumsum(count)]
        total = int(start[-1])
        pair_link = np.repeat(np.arange(len(keys)), count)                # row in the sorted links
        offset = np.arange(total) - np.repeat(start[:-1], count)
        pair_leaf = np.empty(total, np.int64)
        pair_ff = np.empty((total, 4))
        old = reuse[pair_link]
        src_pair = self._start[pos[pair_link[old]]] + offset[old]
        pair_leaf[old] = self._pair_leaf[src_pair]
        pair_ff[old] = self._pair_ff[src_pair]
        fresh = ~old
        leaf = anc_leaf[by_anc[lo[pair_link[fresh]] + offset[fresh]]]
        pair_leaf[fresh] = leaf
        if fresh.any():
            # a corner on a seam lies in the neighbouring polygon's plane (F = 0 there): 1 % inward
            corners = h.corners[leaf] + 0.01 * (h.centre[leaf][:, None] - h.corners[leaf])
            src = s[pair_link[fresh]]
            pair_ff[fresh] = point_polygon(corners, h.normal[leaf], h.corners[src], h.triangle[src], average=False)
        self.reused, self.computed = int(old.sum()), int(fresh.sum())
        self._keys, self._start, self._pair_leaf, self._pair_ff = keys, start, pair_leaf, pair_ff
        self._child, self._corners = h.child.copy(), h.corners.copy()
        # the gather itself, with this call's V and B
        row = np.full(len(h), -1)
        row[leaves] = np.arange(len(leaves))
        link_v = links.visibility[order][pair_link]
        b = h.radiosity[s[pair_link]]
        weight = pair_ff * link_v[:, None]
        index = (row[pair_leaf][:, None] * 4 + np.arange(4)).reshape(-1)
        irradiance = np.stack([np.bincount(index, weights=(weight * b[:, c, None]).reshape(-1), minlength=4 * len(leaves))
                               for c in range(3)], axis=1).reshape(len(leaves), 4, 3)
        return exitance[leaves][:, None] + h.reflectance[leaves][:, None] * irradiance
