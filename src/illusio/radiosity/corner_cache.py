"""The corner gather of the smooth display (:func:`illusio.radiosity.display.corner_gather` states it
plainly) in numba, with its form factors kept between calls, so that an edit that changes a few
links (a virtual object moved, a lamp added) pays only for the pairs it changed.

The gather at the corners of a leaf sums, over every link its element and its ancestors receive,
F(corner → source)·V·B_source. F depends only on the corner and the source's polygon, so it is kept
per link (receiver r, source j) for every leaf under r — one block of pairs per link, in an arena
that blocks are appended to and stay in. Each link carries its block's number (``Links.tag``,
kept through the removal of other links). On the next call a link keeps its block when no leaf
under r was split, merged, moved, or joined or left the leaves asked for (a display that gathers
only what it shows), and j did not move; a link made since (a shaft relinked, the pair refined
again) takes the block its pair (r, j) had if that block lost its link; every other link's block is
made afresh, at the arena's end — or only given its place while its link has V = 0 (never summed):
computed when the link carries light. A block made afresh because leaves under r changed (j
unmoved) takes the form factors of the leaves that did not from the block it had: only the new
leaves' are computed. When the arena holds twice the pairs in use, the blocks in use
are copied together. V and B are read at each call (they change with every solve). After any
change the result equals the plain gather (tested).

With a ``tolerance`` the sums are kept too (per leaf and corner, Σ F·V·B_used over the blocks in
use): a block no link holds is taken out, a block whose link's V changed is brought to it, and a
source's B_used moves to its B — all its blocks taking the difference — once it moved by more than
the tolerance × the largest reflected B. Each corner is then within that of the plain gather (ρ and
Σ F·V are at most 1; tested), and a relighting drag sums a few percent of the pairs a move.

Why numba: at 5.5k leaves a relit office has 1.6M (link, leaf) pairs; copying the kept blocks and
summing them as NumPy index arrays cost 0.25 s a call, a loop over the blocks does it in a tenth of
that. Why the arena and the tags: sorting the links' keys to find their blocks and copying every
kept block into a fresh array each call cost more than the gather (benchmarks/RESULTS.md, relight).
"""

from __future__ import annotations

import numba
import numpy as np

from .formfactor import contour_integral
from .hierarchy import Hierarchy, leaves_under
from .links import Links

__all__ = ["CornerGather"]


def _link_keys(receiver: np.ndarray, source: np.ndarray) -> np.ndarray:
    """One exact int64 key per link: receiver·2³² + source (element indices < 2³¹)."""
    return (receiver.astype(np.int64) << 32) | source.astype(np.int64)


@numba.njit(parallel=True, cache=True)
def _fresh_blocks(
    offset,
    count,
    first_under,
    leaf_under,
    source,
    ready,
    old_offset,
    old_count,
    kept_leaf,
    corners,
    centre,
    normal,
    triangle,
    arena_leaf,
    arena_ff,
):
    """Fill block q (its pairs from offset[q]): the leaves under its receiver, from the leaf table,
    and the form factors from each of their corners to its source (display.corner_form_factors);
    only its leaves where not ``ready[q]``. Where the pair had a block with form factors
    (old_offset[q] ≥ 0, its source unmoved), a leaf it held that is unchanged (``kept_leaf``) takes
    its form factors from there: the leaves common to both blocks come in the same order (a split
    or merge under the receiver adds and drops leaves, never reorders the others), so one pass
    along the old block finds them. Returns the pairs computed."""
    computed = np.zeros(len(offset), np.int64)
    for q in numba.prange(len(offset)):
        j = source[q]
        m = 3 if triangle[j] else 4
        at, end = old_offset[q], old_offset[q] + old_count[q]
        for p in range(count[q]):
            e = leaf_under[first_under[q] + p]
            arena_leaf[offset[q] + p] = e
            if not ready[q]:
                continue
            if at >= 0 and kept_leaf[e]:
                look = at
                while look < end and arena_leaf[look] != e:
                    look += 1
                if look < end:
                    for c in range(4):
                        arena_ff[offset[q] + p, c] = arena_ff[look, c]
                    at = look + 1
                    continue
            computed[q] += 1
            for c in range(4):
                # 1 % of the way to the centre, as the reference takes it
                x0 = corners[e, c, 0] + 0.01 * (centre[e, 0] - corners[e, c, 0])
                x1 = corners[e, c, 1] + 0.01 * (centre[e, 1] - corners[e, c, 1])
                x2 = corners[e, c, 2] + 0.01 * (centre[e, 2] - corners[e, c, 2])
                arena_ff[offset[q] + p, c] = contour_integral(
                    x0, x1, x2, normal[e, 0], normal[e, 1], normal[e, 2], corners[j], m
                )
    return computed


@numba.njit(parallel=True, cache=True)
def _copy_blocks(offset, count, new_offset, leaf, ff, new_leaf, new_ff):
    """Block q's pairs from offset[q] in (leaf, ff) to new_offset[q] in (new_leaf, new_ff)."""
    for q in numba.prange(len(offset)):
        for p in range(count[q]):
            new_leaf[new_offset[q] + p] = leaf[offset[q] + p]
            for c in range(4):
                new_ff[new_offset[q] + p, c] = ff[offset[q] + p, c]


#: the arena's form factors: float32, as the display draws them, and its leaves int32 (half the
#: memory the gather reads and a compaction copies); the sums are float64
FF_DTYPE = np.float32

#: the gather's partial sums: a fixed number of slices of the links, summed in order, so the result
#: does not depend on how many threads ran them
SLICES = 8


@numba.njit(parallel=True, cache=True)
def _gather(offset, count, arena_leaf, arena_ff, visibility, source, radiosity, row, out):
    """out[slice, row of leaf, corner] += F·V·B_source over the pairs of each slice of the links
    (link k's pairs: count[k] from offset[k] in the arena)."""
    links = len(offset)
    for t in numba.prange(out.shape[0]):
        for k in range(links * t // out.shape[0], links * (t + 1) // out.shape[0]):
            v = visibility[k]
            if v == 0.0:
                continue
            j = source[k]
            b0, b1, b2 = radiosity[j, 0], radiosity[j, 1], radiosity[j, 2]
            for p in range(offset[k], offset[k] + count[k]):
                r = row[arena_leaf[p]]
                for c in range(4):
                    w = arena_ff[p, c] * v
                    out[t, r, c, 0] += w * b0
                    out[t, r, c, 1] += w * b1
                    out[t, r, c, 2] += w * b2


@numba.njit(cache=True)
def _orphans(block, live):
    """The blocks the last call used (``live``) that no link holds now (``block``, -1: none)."""
    orphan = live.copy()
    for b in block:
        if b >= 0:
            orphan[b] = False
    return np.flatnonzero(orphan)


@numba.njit(cache=True)
def _stale(block, dirty, moved, receiver, source, visibility, ready):
    """The links whose block must be computed afresh: none yet, a leaf under the receiver changed, the
    source moved, or the link now carries light and its block was left uncomputed."""
    out = np.empty(len(block), np.int64)
    n = 0
    for k in range(len(block)):
        if block[k] < 0 or dirty[receiver[k]] or moved[source[k]] or (visibility[k] > 0 and not ready[block[k]]):
            out[n] = k
            n += 1
    return out[:n]


@numba.njit(cache=True)
def _live_blocks(block, count, blocks):
    """(mask of the blocks in use, the pairs they hold)."""
    live = np.zeros(blocks, np.bool_)
    pairs = 0
    for b in block:
        live[b] = True
        pairs += count[b]
    return live, pairs


@numba.njit(parallel=True, cache=True)
def _add_blocks(sums, ops, weights, values, offset, count, arena_leaf, arena_ff, ranges):
    """sums[leaf, corner] += F·weight·values over each listed block's pairs, in list order. One
    thread per range of leaves: each reads every listed pair's leaf and adds only its own, so every
    sum takes its terms in list order whatever the number of ranges (the same bits)."""
    n = sums.shape[0]
    for t in numba.prange(ranges):
        lo, hi = n * t // ranges, n * (t + 1) // ranges
        for o in range(len(ops)):
            b = ops[o]
            for p in range(offset[b], offset[b] + count[b]):
                e = arena_leaf[p]
                if e < lo or e >= hi:
                    continue
                for c in range(4):
                    w = arena_ff[p, c] * weights[o]
                    sums[e, c, 0] += w * values[o, 0]
                    sums[e, c, 1] += w * values[o, 1]
                    sums[e, c, 2] += w * values[o, 2]


@numba.njit(cache=True)
def _sums_changes(summed_v, b_used, live, block, ready, visibility, radiosity, threshold, count, key):
    """What brings the kept sums (Σ over the blocks in use of F·summed_v·b_used[source]) to this
    call: take out the blocks the last call used (``live``) that no link holds now, bring each held
    block to its link's V (0 where its form factors wait: not ``ready``), then carry each source
    whose B moved by more than ``threshold`` (any channel; ≥ 0) to its B, every block from it
    taking the difference. Updates summed_v and b_used; returns (the changes, in order, as blocks,
    weights and RGB values for :func:`_add_blocks`; the pairs they sum)."""
    # room for every change there can be (untouched pages cost nothing: a drag's move lists ~13k)
    most = len(live) + 2 * len(block)
    ops, weights, values = np.empty(most, np.int64), np.empty(most), np.empty((most, 3))
    n = 0
    held = np.zeros(len(summed_v), np.bool_)
    for b in block:
        held[b] = True
    summed = 0
    for b in range(len(live)):
        if live[b] and not held[b] and summed_v[b] != 0.0:
            j = key[b] & 0xFFFFFFFF
            ops[n], weights[n], values[n] = b, -summed_v[b], b_used[j]
            n += 1
            summed_v[b] = 0.0
            summed += count[b]
    changed = np.zeros(len(radiosity), np.bool_)
    for j in range(len(radiosity)):
        for c in range(3):
            if abs(radiosity[j, c] - b_used[j, c]) > threshold:
                changed[j] = True
    for k in range(len(block)):
        b = block[k]
        j = key[b] & 0xFFFFFFFF
        v = visibility[k] if ready[b] else 0.0
        if v != summed_v[b]:
            if b_used[j, 0] != 0.0 or b_used[j, 1] != 0.0 or b_used[j, 2] != 0.0:
                ops[n], weights[n], values[n] = b, v - summed_v[b], b_used[j]
                n += 1
                summed += count[b]
            summed_v[b] = v
        if changed[j] and v != 0.0:
            ops[n], weights[n], values[n] = b, v, radiosity[j] - b_used[j]
            n += 1
            summed += count[b]
    for j in range(len(radiosity)):
        if changed[j]:
            b_used[j] = radiosity[j]
    return ops[:n], weights[:n], values[:n], summed


class CornerGather:
    """Call as ``corner_gather(h, links, leaves, exitance)``; keeps its form factors in ``links``'
    tags and its arena between calls. ``computed``, ``reused`` and ``deferred`` (left uncomputed: their
    link has V = 0): pairs of the last call; ``pairs``: the pairs it gathered; ``summed``: the
    products F·V·B it summed (a pair taken out and put back counts twice).

    ``tolerance`` (None: every call sums every pair): keep the sums between calls too, and carry a
    source's B into them only where it moved by more than ``tolerance`` × the largest reflected B
    since it was last carried — each corner then within tolerance × that B × ρ·Σ F·V (≤ 1) of the
    plain gather. A relighting drag's solve moves 2 % of the pairs' sources by more than 10⁻³ of
    it, 6 % by more than 3·10⁻⁴, 25 % by more than 10⁻⁴ (the solve's own tolerance)."""

    def __init__(self, tolerance: float | None = None):
        self.tolerance = tolerance
        # per block: its first pair in the arena, its pairs, its link's key and the V it is summed
        # with (views of buffers with room to grow: a drag appends a few thousand blocks to ~200k a
        # call)
        self._set_blocks(
            np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, bool), np.zeros(0)
        )
        self._sums = np.zeros((0, 4, 3))  # per leaf and corner: Σ F·V·B of the blocks in use
        self._b_used = np.zeros((0, 3))  # per source: the B the sums hold
        self.summed = 0
        self._live = np.zeros(0, bool)  # the blocks the last call's links used
        self._leaf = np.zeros(0, np.int32)  # the arena: leaf and F at its 4 corners per pair
        self._ff = np.zeros((0, 4), FF_DTYPE)
        self._used = 0
        self._child = np.zeros(0, np.int64)
        self._corners = np.zeros((0, 4, 3))
        self._asked = np.zeros(0, bool)  # the leaves of the last call, as a mask
        self.reused = self.computed = self.deferred = self.pairs = 0

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

    def _blocks(self, links: Links) -> np.ndarray:
        """Each link's block from the last call (-1: none): its tag, or for a link made since, the
        block of the same pair that lost its link."""
        if links.tag_owner is not self or len(links.tag) != len(links):
            return np.full(len(links), -1, np.int64)
        block = links.tag.copy()
        new = np.flatnonzero(block < 0)
        if len(new):
            orphan = _orphans(block, self._live)
            if len(orphan):
                order = np.argsort(self._key[orphan])
                keys = self._key[orphan][order]
                wanted = _link_keys(links.receiver[new], links.source[new])
                at = np.minimum(np.searchsorted(keys, wanted), len(keys) - 1)
                hit = keys[at] == wanted
                block[new[hit]] = orphan[order[at[hit]]]
        return block

    def _grow(self, size: int) -> None:
        if size > len(self._leaf):
            capacity = int(size * 1.25) + 16
            leaf, ff = np.empty(capacity, np.int32), np.empty((capacity, 4), FF_DTYPE)
            leaf[: self._used], ff[: self._used] = self._leaf[: self._used], self._ff[: self._used]
            self._leaf, self._ff = leaf, ff

    def _compact(self, block: np.ndarray) -> np.ndarray:
        """Copy the blocks in use together, number them 0…; returns ``block`` renumbered."""
        used, block = np.unique(block, return_inverse=True)
        count = self._count[used]
        offset = (np.cumsum(count) - count).astype(np.int64)
        size = int(count.sum() * 1.25) + 16
        leaf, ff = np.empty(size, np.int32), np.empty((size, 4), FF_DTYPE)
        _copy_blocks(self._offset[used], count, offset, self._leaf, self._ff, leaf, ff)
        self._leaf, self._ff, self._used = leaf, ff, int(count.sum())
        self._set_blocks(offset, count, self._key[used], self._ready[used], self._summed_v[used])
        return block.astype(np.int64)

    def _set_blocks(self, offset, count, key, ready, summed_v) -> None:
        self._buffers = [offset, count, key, ready, summed_v]
        self._offset, self._count, self._key, self._ready, self._summed_v = self._buffers

    def _append_blocks(self, offset, count, key, ready) -> None:
        n, k = len(self._offset), len(offset)
        if n + k > len(self._buffers[0]):
            grown = [np.empty(int((n + k) * 1.5) + 16, old.dtype) for old in self._buffers]
            for new, old in zip(grown, self._buffers):
                new[:n] = old[:n]
            self._buffers = grown
        for buffer, values in zip(self._buffers, (offset, count, key, ready, 0.0)):
            buffer[n : n + k] = values
        self._offset, self._count, self._key, self._ready, self._summed_v = (
            buffer[: n + k] for buffer in self._buffers
        )

    def _carried(self, h: Hierarchy, block, visibility, leaves, exitance) -> np.ndarray:
        """The kept sums brought to this call's blocks, V and B (within the tolerance); (n, 4, 3) at
        ``leaves``."""
        n = len(h)
        if len(self._sums) < n:
            for name, shape in (("_sums", (4, 3)), ("_b_used", (3,))):
                old = getattr(self, name)
                grown = np.zeros((max(n, int(len(old) * 1.25) + 16),) + shape)
                grown[: len(old)] = old
                setattr(self, name, grown)
        radiosity = np.ascontiguousarray(h.radiosity, np.float64)
        reflected = float(np.abs(radiosity - exitance).max()) if n else 0.0
        ops, weights, values, self.summed = _sums_changes(
            self._summed_v,
            self._b_used,
            self._live,
            block,
            self._ready,
            visibility,
            radiosity,
            self.tolerance * reflected,
            self._count,
            self._key,
        )
        _add_blocks(
            self._sums, ops, weights, values, self._offset, self._count, self._leaf, self._ff, numba.get_num_threads()
        )
        return self._sums[leaves].copy()

    def __call__(
        self,
        h: Hierarchy,
        links: Links,
        leaves: np.ndarray,
        exitance: np.ndarray,
        scale: np.ndarray | None = None,
        lamp: np.ndarray | None = None,
    ) -> np.ndarray:
        """``scale`` and ``lamp``: as :func:`display.corner_gather`'s."""
        asked = np.zeros(len(h), bool)
        asked[leaves] = True
        dirty, moved = self._changed(h, asked)
        r, s = links.receiver, links.source
        block = self._blocks(links)
        visibility = np.ascontiguousarray(links.visibility, np.float64)
        fresh = _stale(block, dirty, moved, r, s, visibility, self._ready)
        # a block redone because leaves under its receiver changed keeps the form factors of the
        # leaves that did not (a split under a wall redoes the wall's every link: 35–72k pairs of a
        # drag's move where 17k are new)
        old = block[fresh]
        reusable = (old >= 0) & ~moved[s[fresh]]
        reusable[reusable] = self._ready[old[reusable]]
        old_offset, old_count = np.full(len(fresh), -1, np.int64), np.zeros(len(fresh), np.int64)
        old_offset[reusable], old_count[reusable] = self._offset[old[reusable]], self._count[old[reusable]]
        kept_leaf = np.zeros(len(h), np.bool_)
        kept_leaf[: len(self._asked)] = self._asked[: len(h)]
        kept_leaf &= ~moved
        # a link that carries no light (V = 0: the crate's face on the floor) is never summed: its
        # block gets its place but no form factors until it does (a third of a drag's fresh pairs)
        ready = visibility[fresh] > 0
        element, leaf_under = leaves_under(h, leaves)
        first_under = np.searchsorted(element, r[fresh])
        count = np.searchsorted(element, r[fresh], side="right") - first_under
        offset = (self._used + np.cumsum(count) - count).astype(np.int64)
        self._grow(self._used + int(count.sum()))
        computed = _fresh_blocks(
            offset,
            count,
            first_under,
            leaf_under,
            s[fresh],
            ready,
            old_offset,
            old_count,
            kept_leaf,
            np.ascontiguousarray(h.corners, np.float64),
            np.ascontiguousarray(h.centre, np.float64),
            np.ascontiguousarray(h.normal, np.float64),
            np.ascontiguousarray(h.triangle, np.bool_),
            self._leaf,
            self._ff,
        )
        self._used += int(count.sum())
        block[fresh] = len(self._offset) + np.arange(len(fresh))
        self._append_blocks(offset, count, _link_keys(r[fresh], s[fresh]), ready)
        live, pairs = _live_blocks(block, self._count, len(self._offset))
        self.pairs = int(pairs)
        self.computed = int(computed.sum())
        self.deferred = int(count[~ready].sum())
        self.reused = self.pairs - self.computed - self.deferred
        if self.tolerance is not None and scale is None:
            irradiance = self._carried(h, block, visibility, leaves, exitance)
        else:
            irradiance = None
            self._summed_v[:] = 0.0  # (the sums are not kept: a later call with a tolerance starts over)
            self._sums[:] = 0.0
            self._b_used[:] = 0.0
        self._live = live
        if self._used > 2 * self.pairs + 1024:
            block = self._compact(block)
            self._live = np.ones(len(self._offset), bool)
        links.tag, links.tag_owner = block, self
        self._child, self._corners, self._asked = h.child.copy(), h.corners.copy(), asked
        if irradiance is not None:
            return exitance[leaves][:, None] + h.reflectance[leaves][:, None] * irradiance
        # the gather itself, with this call's V and B
        self.summed = self.pairs
        row = np.full(len(h), -1, np.int64)
        row[leaves] = np.arange(len(leaves))
        parts = np.zeros((SLICES, len(leaves), 4, 3))
        _gather(
            self._offset[block],
            self._count[block],
            self._leaf,
            self._ff,
            visibility,
            s,
            np.ascontiguousarray(h.radiosity, np.float64),
            row,
            parts,
        )
        irradiance = parts.sum(axis=0)
        if scale is not None:
            # the lamps' light gathered again alone (links from other sources skipped as V = 0), so
            # the scale acts on the reflected light only, as in the solve
            lamp = np.ascontiguousarray(lamp, np.float64)
            parts[:] = 0.0
            lamp_visibility = np.where(lamp[s].any(axis=1), visibility, 0.0)
            _gather(self._offset[block], self._count[block], self._leaf, self._ff, lamp_visibility, s, lamp, row, parts)
            from_lamps = parts.sum(axis=0)
            irradiance = from_lamps + np.asarray(scale)[leaves][:, None, None] * (irradiance - from_lamps)
        return exitance[leaves][:, None] + h.reflectance[leaves][:, None] * irradiance
