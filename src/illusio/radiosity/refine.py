"""Link refinement (Hanrahan, Salzman & Aupperle 1991): each candidate pair (receiver i, source j)
becomes a link when its estimated transfer is small enough, else the larger of the two elements is
split and the pair replaced by the four pairs with its children.

Breadth first and vectorised: every round evaluates all pending pairs at once (form factors, one
batch of visibility rays, the criterion), accepts some, splits elements for the others and makes the
next round's pairs. The criteria (``params.CRITERIA``), with Φ the total emitted power:

- bf: refine when B_j·F_ij·A_i > ε·Φ — the transfer as if nothing were in the way (Loscos 4.2's
  "BF": the mesh as fine in the shadows as in the light);
- bfv: refine when B_j·F_ij·V_ij·A_i > ε·Φ — the transfer the link carries (HSA91's BFV, as the
  chapter uses it: coarser in the shadows, finer in the light, fewer links).
(Before issue 31, bf was the second and bfv refined partial links further.) Under bf a pair's F comes
first and its V (the rays) only where it is read: a pair that splits never reads it.

A pair straddling a plane (some corners of one behind the other) is refined while it can be: its
centre-to-centre estimate is unreliable: it is refined while the bound B_j·A_j·A_i/(π r² + A_j) (both
cosines taken as 1) exceeds ε·Φ. No element is split below ``min_area``.
"""

from __future__ import annotations

import numba
import numpy as np

from ..core.errors import InputError
from .formfactor import facing_pairs
from .hierarchy import Hierarchy
from .links import Links
from .visibility import NO_RAYS, Visibility

__all__ = ["refine", "transfer_estimate", "needs_refinement", "CHUNK"]

#: pairs evaluated in one batch at most. A batch's sample points and rays are ~150 bytes a sample, 16
#: samples a pair: at 200k pairs, fresh memory the kernel faults in on every batch (a kernel that
#: runs at 17 ns a sample in reused arrays took 72 in fresh ones); at 50k office2 builds in 0.6× the
#: time and 0.7× the peak memory, the Graz office in the same time (at 20k, per-batch costs win)
CHUNK = 50_000


def channel_max(rgb: np.ndarray) -> np.ndarray:
    """max over RGB of (n, 3), float64 (n,). Refinement asks it of every element per batch of pairs
    (9k calls in the Graz office's build at RenderPark's element count): one numba pass over the rows
    is 0.13 ms at 305k elements, three strided NumPy columns 0.9–2 ms (8 s of that build), a
    reduction along the short axis 8 ms."""
    return _channel_max(rgb)


@numba.njit(cache=True)
def _channel_max(rgb):
    out = np.empty(rgb.shape[0])
    for i in range(rgb.shape[0]):
        m = max(rgb[i, 0], rgb[i, 1])
        out[i] = max(m, rgb[i, 2])
    return out


def transfer_estimate(h: Hierarchy, receiver, source, form_factor, radiosity=None) -> np.ndarray:
    """B_j·F_ij·A_i (W, max over RGB) for each pair: the power the link would carry unoccluded."""
    b = channel_max(h.radiosity if radiosity is None else radiosity)[source]  # per element, then pair
    return b * form_factor * h.area[receiver]


def needs_refinement(transfer, visibility, threshold: float, criterion: str) -> np.ndarray:
    """The criterion of the module docstring, given B_j·F_ij·A_i and V_ij."""
    if criterion == "bf":
        return transfer > threshold
    return transfer * visibility > threshold


def refine(
    h: Hierarchy,
    visibility: Visibility,
    receivers,
    sources,
    threshold: float,
    min_area: float,
    criterion: str = "bfv",
    radiosity=None,
    links: Links | None = None,
    form_factor: np.ndarray | None = None,
    rays: np.ndarray | None = None,
    boxes=(),
    recast: tuple[np.ndarray, np.ndarray] | None = None,
) -> Links:
    """Refine the candidate pairs into links (appended to ``links``, which is returned). ``radiosity``:
    the B estimate of the criterion (default: the hierarchy's). ``form_factor``: the candidates' F
    where already known (links taken out to be tested again after something moved inside ``boxes``,
    their ends unmoved): only V is cast for them, by :meth:`Visibility.recast` from what each kept
    (``rays``, default none) — or, where ``recast`` is given, taken from it: (V, rays to keep) of
    those candidates, recast already (:meth:`Visibility.recast_in_background`). Elements are created
    as needed."""
    links = Links() if links is None else links
    accepted, made = [], 0
    receivers = np.asarray(receivers, np.int64)
    if form_factor is not None and rays is None:
        rays = np.full(len(receivers), NO_RAYS, np.int64)
    recast_v, recast_rays = (None, None) if recast is None else recast
    queue = [(receivers, np.asarray(sources, np.int64), form_factor, rays, recast_v, recast_rays)]
    while queue:
        recv, src, known, kept_rays, cast_v, cast_rays = queue.pop()
        if len(recv) > CHUNK:  # bounded memory: a round holds k samples × 3 coordinates per pair
            rest = [None if a is None else a[CHUNK:] for a in (known, kept_rays, cast_v, cast_rays)]
            queue.append((recv[CHUNK:], src[CHUNK:], *rest))
            recv, src = recv[:CHUNK], src[:CHUNK]
            known, kept_rays, cast_v, cast_rays = [
                None if a is None else a[:CHUNK] for a in (known, kept_rays, cast_v, cast_rays)
            ]
        useful = (h.polygon[recv] != h.polygon[src]) & (channel_max(h.reflectance)[recv] > 0)
        some, every = facing_pairs(h.corners, h.normal, h.centre, recv[useful], src[useful])
        kept = np.flatnonzero(useful)[some]
        recv, src, every = recv[kept], src[kept], every[some]
        if not len(recv):
            continue
        if known is None:
            ff, samples = visibility.form_factors(recv, src)
            vis, cast = None, np.full(len(recv), NO_RAYS, np.int64)
        else:
            ff = known[kept]
            if cast_v is not None:
                vis, cast = cast_v[kept], cast_rays[kept]
            else:
                vis, cast = visibility.recast(recv, src, kept_rays[kept], boxes)
        transfer = transfer_estimate(h, recv, src, ff, radiosity)
        area_r, area_s = h.area[recv], h.area[src]
        can_r, can_s = area_r / 4 >= min_area, area_s / 4 >= min_area
        if vis is None and criterion == "bf":
            # bf splits on the unoccluded transfer: a pair it splits never reads its V (the straddle
            # test below only adds splits), so its rays are not cast — unless it is at the minimum
            # area on both ends and stays a link
            splits = needs_refinement(transfer, None, threshold, criterion) & (can_r | can_s)
            vis = np.zeros(len(recv))
            vis[~splits] = visibility.cast_visibility(samples, ~splits)
        elif vis is None:
            vis = visibility.cast_visibility(samples)
        split = needs_refinement(transfer, vis, threshold, criterion)
        straddle = ~every & (vis > 0)
        if straddle.any():
            d2 = ((h.centre[src[straddle]] - h.centre[recv[straddle]]) ** 2).sum(axis=1)
            a_s = h.area[src[straddle]]
            point_bound = a_s / (np.pi * d2 + a_s)
            b = channel_max(h.radiosity if radiosity is None else radiosity)[src[straddle]]
            split[straddle] |= b * point_bound * h.area[recv[straddle]] > threshold
        split_src = split & can_s & ((area_s >= area_r) | ~can_r)
        split_recv = split & ~split_src & can_r
        accept = ~(split_src | split_recv)
        accepted.append((recv[accept], src[accept], ff[accept], vis[accept], cast[accept]))
        made += int(accept.sum())
        if links.budget is not None and len(links) + made > links.budget:
            raise InputError(
                f"radiosity: the refinement passed its budget of {links.budget:,} links (--max-links) before "
                f"it ended ({len(h):,} elements so far): raise ε (--epsilon) or the minimum element area "
                "(--min-area), or the budget if the memory allows (about 100 bytes a link)"
            )
        first_s = h.subdivide(src[split_src])
        first_r = h.subdivide(recv[split_recv])
        quad = np.arange(4)
        new_recv = np.r_[np.repeat(recv[split_src], 4), (first_r[:, None] + quad).reshape(-1)]
        new_src = np.r_[(first_s[:, None] + quad).reshape(-1), np.repeat(src[split_recv], 4)]
        if len(new_recv):
            queue.append((new_recv, new_src, None, None, None, None))
    if accepted:
        links.extend(*(np.concatenate(part) for part in zip(*accepted)))
    return links
