"""Form factor and visibility of a link, from one set of sample points.

Sample s of a link joins point x_s of the receiver i's own jittered grid (:func:`element_grids`:
drawn from a hash of the seed and i, the same for every link i receives) to a point y_s of a jittered
grid drawn for the link on the source j (both lifted off their surfaces by ``offset`` so a ray does
not hit its own ends); the rays are cast with Embree (embreex).

- F_ij: the exact point-to-polygon form factor (:func:`formfactor.point_polygon`) averaged over the
  first ``form_factor_points`` of the x_s: quadrature over the receiver, exact over the source;
- V_ij: the fraction of the rays x_s → y_s no polygon blocks, among the rays whose start x_s is
  exposed: a probe ray along the normal meets nothing within ``contact`` = 0.2 % of the scene's
  extent and does not meet the back of a face (the point is then inside a closed object). The part of
  an element under a board or behind a door in contact with it is not part of the surface anyone
  sees, and counting it would darken the whole element. A point's probe is cast once per scene and
  its answer kept for every link that starts there (:meth:`Visibility.exposed_points`); only the
  samples that go front to front are probed, only the exposed ones cast. Its type (VISIBLE,
  PARTIAL, INVISIBLE): all counted rays clear, some, none.

A link cast again because something moved near it (:meth:`Visibility.recast`: its ends did not move)
takes its source's points from its pair (a hash of receiver, source and seed) instead of the shared
stream, so the next recast of that link draws the same rays; it keeps what each ray gave (two 16-bit
masks, ``Links.rays``) and casts again only the rays that meet the boxes of what moved — a ray that
meets neither box gives what it gave before (what moved was inside them; nothing else changed:
every change of geometry recasts the links whose shafts it meets). Drettakis & Sillion's interactive
update keeps its shafts' contents for the same reason.
"""

from __future__ import annotations

import dataclasses
import threading
from concurrent.futures import Future

import numba
import numpy as np

from ..core import background
from ..core.errors import InputError
from ..core.rays import cast, commit
from .formfactor import point_polygon
from .hierarchy import Hierarchy, point_on

__all__ = [
    "Visibility",
    "LinkSamples",
    "VISIBLE",
    "PARTIAL",
    "INVISIBLE",
    "link_type",
    "pair_grids",
    "element_grids",
    "jittered_grid",
    "cosine_directions",
    "KEPT_SAMPLES",
    "NO_RAYS",
]

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


@numba.njit(cache=True, inline="always")
def _segment(a0, a1, a2, b0, b1, b2, receiver_normal, source_normal, p, offset, origins, directions, dists, up, i):
    """Row i of :func:`_segments`: the ray from point a to point b of pair p."""
    a0 = a0 + offset * receiver_normal[p, 0]
    a1 = a1 + offset * receiver_normal[p, 1]
    a2 = a2 + offset * receiver_normal[p, 2]
    d0 = b0 + offset * source_normal[p, 0] - a0
    d1 = b1 + offset * source_normal[p, 1] - a1
    d2 = b2 + offset * source_normal[p, 2] - a2
    length = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    norm = max(length, 1e-300)
    directions[i, 0], directions[i, 1], directions[i, 2] = d0 / norm, d1 / norm, d2 / norm
    dists[i] = max(length - offset, 0.0)
    origins[i, 0], origins[i, 1], origins[i, 2] = a0, a1, a2
    for c in range(3):
        up[i, c] = receiver_normal[p, c]


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
            _segment(
                a[p, s, 0],
                a[p, s, 1],
                a[p, s, 2],
                b[p, s, 0],
                b[p, s, 1],
                b[p, s, 2],
                receiver_normal,
                source_normal,
                p,
                offset,
                origins,
                directions,
                dists,
                up,
                p * k + s,
            )
    return origins, directions, dists, up


#: the most samples a link keeps its rays' outcomes for: clear bits 0–15, exposed bits 16–31, the
#: scene's epoch (its ray offsets) from bit 32; NO_RAYS: none kept
KEPT_SAMPLES = 16
NO_RAYS = -1

#: the most points of an element's grid whose exposure the scene keeps (Visibility.exposed_points):
#: bits 0–15 of a uint32 per element say which are known, bits 16–31 their answers (4 bytes an
#: element: the Graz office at RenderPark's element count is at its memory already)
CACHED_POINTS = 16

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)


@numba.njit(cache=True, inline="always")
def splitmix(z):
    """splitmix64's finaliser: a uint64 to a well-spread uint64."""
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


@numba.njit(cache=True, inline="always")
def stream_uniform(seed, counter):
    """Output ``counter`` of the SplitMix64 stream started at ``seed`` (both uint64: the state
    advanced ``counter`` + 1 times by the golden ratio, through :func:`splitmix`) as a double in
    [0, 1) from its top 53 bits: a random number any thread can draw by its index alone
    (reference.stream_uniform states it in NumPy)."""
    return float(splitmix(seed + (counter + np.uint64(1)) * _GOLDEN) >> np.uint64(11)) * 2.0**-53


@numba.njit(cache=True, inline="always")
def _pair_state(seed, receiver, source):
    """The stream state of pair (receiver, source) under ``seed`` (uint64): a hash of the three."""
    state = splitmix(np.uint64(seed) * _GOLDEN + splitmix(np.uint64(receiver) + np.uint64(1)))
    return splitmix(state ^ splitmix(np.uint64(source) + np.uint64(0x632BE59BD9B4E019)))


@numba.njit(cache=True, inline="always")
def _draw_grid(state, samples, side, perm, out, p):
    """out[p] (samples, 2): a jittered grid drawn from ``state`` (the cells shuffled by Fisher–Yates
    in ``perm``, one jittered point in each of the first ``samples``); returns the state after."""
    for c in range(side * side):
        perm[c] = c
    for c in range(side * side - 1, 0, -1):
        state += _GOLDEN
        q = int(splitmix(state) % np.uint64(c + 1))
        perm[c], perm[q] = perm[q], perm[c]
    for t in range(samples):
        state += _GOLDEN
        u = float(splitmix(state) >> np.uint64(11)) * 2.0**-53
        state += _GOLDEN
        v = float(splitmix(state) >> np.uint64(11)) * 2.0**-53
        out[p, t, 0] = (perm[t] % side + u) / side
        out[p, t, 1] = (perm[t] // side + v) / side
    return state


@numba.njit(cache=True)
def _pair_grids(receivers, sources, samples, seed, out_receiver, out_source, first):
    side = int(np.ceil(np.sqrt(samples)))
    perm = np.empty(side * side, np.int64)
    for p in range(len(receivers)):
        state = _pair_state(seed, receivers[p], sources[p])
        if first == 0:
            state = _draw_grid(state, samples, side, perm, out_receiver, p)
        _draw_grid(state, samples, side, perm, out_source, p)


def pair_grids(
    receivers: np.ndarray, sources: np.ndarray, samples: int, seed: int, source_only: bool = False
) -> tuple[np.ndarray | None, np.ndarray]:
    """(receiver, source) parameters (n, samples, 2) in [0, 1)² for each pair: jittered grids as
    :func:`jittered_grid` (one point per cell of a ⌈√samples⌉² grid, the cells in a random order,
    another order on the source), drawn from a hash of (receiver, source, seed): a pair gets the
    same points at every call. ``source_only``: (None, the source's), drawn first from the hash (not
    the source's grid of the pair: the receiver's draws are skipped)."""
    n = len(receivers)
    out_receiver = np.empty((0 if source_only else n, samples, 2))
    out_source = np.empty((n, samples, 2))
    if n:
        _pair_grids(
            np.asarray(receivers, np.int64),
            np.asarray(sources, np.int64),
            int(samples),
            int(seed),
            out_receiver,
            out_source,
            1 if source_only else 0,
        )
    return (None if source_only else out_receiver), out_source


@numba.njit(cache=True, inline="always")
def _element_state(seed, element):
    return splitmix(seed * _GOLDEN + splitmix(np.uint64(element) + np.uint64(1)))


@numba.njit(cache=True)
def _element_states(seed, elements, out):
    for p in range(len(elements)):
        out[p] = _element_state(seed, elements[p])


def element_states(seed: int, elements: np.ndarray) -> np.ndarray:
    """(n,) uint64: the state of each element's own points (:func:`element_uv`), a hash of
    (``seed``, element)."""
    elements = np.asarray(elements, np.int64)
    out = np.empty(len(elements), np.uint64)
    _element_states(np.uint64(seed), elements, out)
    return out


@numba.njit(cache=True, inline="always")
def element_uv(state, t, side):
    """(u, v) of point t of an element's own jittered grid (side × side cells), ``state`` its
    element_states': cell (shift + t·(side + 1)) mod side² — a stride prime to side², so the first
    points spread over rows and columns —, the shift and the jitter from the stream started at
    ``state``."""
    cells = side * side
    shift = int(splitmix(state + _GOLDEN) % np.uint64(cells))
    cell = (shift + t * (side + 1)) % cells
    u = stream_uniform(state, np.uint64(2 * t + 1))
    v = stream_uniform(state, np.uint64(2 * t + 2))
    return (cell % side + u) / side, (cell // side + v) / side


@numba.njit(cache=True)
def _element_grids(state, samples, out):
    side = int(np.ceil(np.sqrt(samples)))
    for p in range(len(state)):
        for t in range(samples):
            out[p, t, 0], out[p, t, 1] = element_uv(state[p], t, side)


def element_grids(elements: np.ndarray, samples: int, seed: int) -> np.ndarray:
    """(n, samples, 2) parameters in [0, 1)²: each element's own points (:func:`element_uv`), the
    same at every call — the receiving end of every link's samples, so that what a probe found at a
    point (Visibility.exposed_points) holds for every link that starts there."""
    out = np.empty((len(elements), samples, 2))
    _element_grids(element_states(seed, elements), int(samples), out)
    return out


@numba.njit(cache=True, inline="always")
def _point_of(elements, slots, per, i):
    """Row i's (element, point): per pair (``per`` > 0: sample i of pair i // per is point i % per
    of elements[i // per]) or per row (elements[i], slots[i])."""
    if per > 0:
        return elements[i // per], i % per
    return elements[i], slots[i]


@numba.njit(cache=True)
def _claim_points(cache, elements, slots, per, rows):
    """Of ``rows``, those whose point the cache does not know, each point once (its first row);
    marks them known (their answers are stored next, by _store_points)."""
    first = np.empty(len(rows), np.int64)
    n = 0
    for i in rows:
        e, t = _point_of(elements, slots, per, i)
        bit = np.uint64(1) << np.uint64(t)
        if not cache[e] & bit:
            cache[e] |= bit
            first[n] = i
            n += 1
    return first[:n]


@numba.njit(cache=True)
def _store_points(cache, elements, slots, per, rows, exposed):
    for r in range(len(rows)):
        if exposed[r]:
            e, t = _point_of(elements, slots, per, rows[r])
            cache[e] |= np.uint64(1) << np.uint64(CACHED_POINTS + t)


@numba.njit(cache=True)
def _read_points(cache, elements, slots, per, rows):
    out = np.empty(len(rows), np.bool_)
    for r in range(len(rows)):
        e, t = _point_of(elements, slots, per, rows[r])
        out[r] = (cache[e] >> np.uint64(CACHED_POINTS + t)) & np.uint64(1)
    return out


@numba.njit(parallel=True, cache=True)
def _forget_points(cache, state, samples, corners, triangle, normal, offset, box_lo, box_hi):
    """Clear the kept answers of the points whose probe (from the point lifted by ``offset``, along
    the normal, at any distance) meets a box: what moved is inside the boxes, so the others stand."""
    side = int(np.ceil(np.sqrt(samples)))
    for e in numba.prange(len(cache)):
        if cache[e] == 0:
            continue
        for t in range(samples):
            bit = np.uint64(1) << np.uint64(t)
            if not cache[e] & bit:
                continue
            u, v = element_uv(state[e], t, side)
            p0, p1, p2 = point_on(corners, triangle, e, u, v)
            o0, o1, o2 = p0 + offset * normal[e, 0], p1 + offset * normal[e, 1], p2 + offset * normal[e, 2]
            for b in range(box_lo.shape[0]):
                if _slab(o0, o1, o2, normal[e, 0], normal[e, 1], normal[e, 2], 1e300, box_lo[b], box_hi[b]):
                    cache[e] &= ~(bit | (bit << np.uint64(CACHED_POINTS)))
                    break


def cosine_directions(normal: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(n, k, 3) unit directions about each ``normal`` (n, 3), cosine-distributed (Malley's method:
    a uniform point ``uv`` (n, k, 2) on the unit disk — radius √u, angle 2πv —, lifted to the
    hemisphere: z = √(1 − u)), in the frame u = normal × (x or y axis, whichever is less parallel),
    v = normal × u."""
    normal = np.ascontiguousarray(normal, np.float64)
    out = np.empty(uv.shape[:2] + (3,))
    _cosine_directions(normal, np.ascontiguousarray(uv, np.float64), out)
    return out


@numba.njit(cache=True)
def _cosine_directions(normal, uv, out):
    for i in range(normal.shape[0]):
        nx, ny, nz = normal[i, 0], normal[i, 1], normal[i, 2]
        if abs(nx) < 0.9:  # u = n × x
            ux, uy, uz = 0.0, nz, -ny
        else:  # u = n × y
            ux, uy, uz = -nz, 0.0, nx
        length = np.sqrt(ux * ux + uy * uy + uz * uz)
        ux, uy, uz = ux / length, uy / length, uz / length
        vx, vy, vz = ny * uz - nz * uy, nz * ux - nx * uz, nx * uy - ny * ux
        for k in range(uv.shape[1]):
            r, phi = np.sqrt(uv[i, k, 0]), 2 * np.pi * uv[i, k, 1]
            x, y = r * np.cos(phi), r * np.sin(phi)
            z = np.sqrt(max(1 - uv[i, k, 0], 0.0))
            out[i, k, 0] = x * ux + y * vx + z * nx
            out[i, k, 1] = x * uy + y * vy + z * ny
            out[i, k, 2] = x * uz + y * vz + z * nz


@numba.njit(cache=True)
def _exposed(probe_prim, probe_distance, probe_normal, up, contact, two_sided):
    """Per sample: its probe met nothing within ``contact`` nor the back of a face (a two-sided
    surface, ``two_sided`` per triangle of the scene, has no back: its twin is there)."""
    out = np.ones(len(probe_prim), np.bool_)
    for i in range(len(probe_prim)):
        if probe_prim[i] >= 0:
            back = probe_normal[i, 0] * up[i, 0] + probe_normal[i, 1] * up[i, 1] + probe_normal[i, 2] * up[i, 2] > 0
            back = back and not two_sided[probe_prim[i]]
            if probe_distance[i] < contact or back:
                out[i] = False
    return out


@numba.njit(cache=True, inline="always")
def _slab(o0, o1, o2, d0, d1, d2, far, lo, hi):
    """Does the ray o + t·d, 0 ≤ t ≤ far, meet the box [lo, hi] (3,)?"""
    near, stop = 0.0, far
    for c in range(3):
        o = o0 if c == 0 else (o1 if c == 1 else o2)
        d = d0 if c == 0 else (d1 if c == 1 else d2)
        if abs(d) < 1e-30:
            if o < lo[c] or o > hi[c]:
                return False
            continue
        inverse = 1.0 / d  # one division, not two
        t0, t1 = (lo[c] - o) * inverse, (hi[c] - o) * inverse
        if t0 > t1:
            t0, t1 = t1, t0
        near, stop = max(near, t0), min(stop, t1)
        if near > stop:
            return False
    return True


@numba.njit(cache=True, inline="always")
def _faces_front(directions, receiver_normal, source_normal, i, p):
    """Does ray i (of pair p) leave the receiver's front and reach the source's front?"""
    up = (
        directions[i, 0] * receiver_normal[p, 0]
        + directions[i, 1] * receiver_normal[p, 1]
        + directions[i, 2] * receiver_normal[p, 2]
    )
    down = (
        directions[i, 0] * source_normal[p, 0]
        + directions[i, 1] * source_normal[p, 1]
        + directions[i, 2] * source_normal[p, 2]
    )
    return up > 0 and down < 0


@numba.njit(parallel=True, cache=True, nogil=True)
def _recast_samples(
    receivers, sources, samples, seed, point_seed, corners, triangle, receiver_normal, source_normal, offset,
    rays, epoch, box_lo, box_hi, origins, directions, dists, up, clear, exposed, facing, cast_ray, cast_probe,
):  # fmt: skip
    """Every sample of :meth:`Visibility.recast`'s pairs in one pass (each pair writes its own rows):
    its points (the receiver's own, element_grids; the source's, pair_grids' source-only draw), its
    ray and probe (_segments), whether it goes front to front (_front_to_front), and which to cast:
    every sample of a pair that kept nothing (or kept it under other ray offsets); else the rays and
    probes that meet a box, ``clear`` and ``exposed`` filled from what the pair kept."""
    side = int(np.ceil(np.sqrt(samples)))
    for p in numba.prange(len(receivers)):
        perm = np.empty(side * side, np.int64)
        uv = np.empty((1, samples, 2))
        _draw_grid(_pair_state(seed, receivers[p], sources[p]), samples, side, perm, uv, 0)
        state = _element_state(point_seed, receivers[p])
        kept = rays[p] >= 0 and (rays[p] >> 32) == epoch
        for t in range(samples):
            i = p * samples + t
            u, v = element_uv(state, t, side)
            a0, a1, a2 = point_on(corners, triangle, receivers[p], u, v)
            b0, b1, b2 = point_on(corners, triangle, sources[p], uv[0, t, 0], uv[0, t, 1])
            _segment(
                a0, a1, a2, b0, b1, b2, receiver_normal, source_normal, p, offset, origins, directions, dists, up, i
            )
            facing[i] = _faces_front(directions, receiver_normal, source_normal, i, p)
            if not kept:
                cast_ray[i] = cast_probe[i] = True
                continue
            clear[i] = (rays[p] >> t) & 1
            exposed[i] = (rays[p] >> (16 + t)) & 1
            o0, o1, o2 = float(origins[i, 0]), float(origins[i, 1]), float(origins[i, 2])
            for b in range(box_lo.shape[0]):
                if not cast_ray[i]:
                    cast_ray[i] = _slab(
                        o0,
                        o1,
                        o2,
                        float(directions[i, 0]),
                        float(directions[i, 1]),
                        float(directions[i, 2]),
                        float(dists[i]),
                        box_lo[b],
                        box_hi[b],
                    )
                if not cast_probe[i]:
                    cast_probe[i] = _slab(
                        o0, o1, o2, float(up[i, 0]), float(up[i, 1]), float(up[i, 2]), 1e300, box_lo[b], box_hi[b]
                    )


@numba.njit(cache=True)
def _unmeasured(known, members, rows):
    """The distinct ids (≥ 0) in the rows of ``members`` marked in ``rows`` whose openness ``known``
    lacks (NaN, or past its end), sorted: the loop over a call's samples without their copies."""
    fresh = [np.int64(0) for _ in range(0)]
    for i in range(members.shape[0]):
        if rows[i]:
            for m in members[i]:
                if m >= 0 and (m >= len(known) or np.isnan(known[m])):
                    fresh.append(m)
    return np.unique(np.array(fresh, dtype=np.int64))


@numba.njit(cache=True)
def _front_to_front(directions, receiver_normal, source_normal, samples):
    """Per sample: does its ray leave the receiver's front and reach the source's front? A pair that
    straddles a plane (a face standing on the floor and the floor) has samples behind one of them:
    they carry nothing (the form factor is clipped and one-sided), so they must not count in V
    either — as blocked rays they took a straddling pair's V down by the share behind."""
    out = np.empty(len(directions), np.bool_)
    for i in range(len(directions)):
        out[i] = _faces_front(directions, receiver_normal, source_normal, i, i // samples)
    return out


@numba.njit(cache=True, nogil=True)
def _fraction_and_masks(clear, exposed, samples, epoch, keep, facing):
    """V per pair (the clear fraction of its samples that are exposed and ``facing``, front to
    front; 0 when none is) and the masks to keep (clear and exposed bits)."""
    n = len(clear) // samples
    visibility = np.zeros(n)
    rays = np.full(n, -1, np.int64)
    for p in range(n):
        seen = hits = 0
        mask = np.int64(0)
        for t in range(samples):
            i = p * samples + t
            if exposed[i] and facing[i]:
                seen += 1
                if clear[i]:
                    hits += 1
            if keep:
                mask |= (np.int64(clear[i]) << t) | (np.int64(exposed[i]) << (16 + t))
        if seen > 0:
            visibility[p] = hits / seen
        if keep:
            rays[p] = mask | (np.int64(epoch) << 32)
    return visibility, rays


#: openness: how far (× the scene's extent) a ray from an element must travel to count as open, and
#: the rays per element (Visibility.openness)
OPEN_DISTANCE = 0.02
OPEN_RAYS = 8
OPEN_SLICE = 16_384

#: the most one-sided faces, as a share of the scene's triangles, for which the exposure probe runs
#: in parts (Visibility._probe): in a scene of one-sided faces one first hit is cheaper
SPLIT_PROBE_SHARE = 0.1


@dataclasses.dataclass(frozen=True)
class LinkSamples:
    """The sample points of n pairs (Visibility.form_factors): (n, k, 3) on each receiver and source."""

    receivers: np.ndarray
    sources: np.ndarray
    receiver_points: np.ndarray
    source_points: np.ndarray


class Visibility:
    """Ray casting against the polygons of a hierarchy (rebuilt with :meth:`rebuild` when they move)."""

    def __init__(self, hierarchy: Hierarchy, samples: int = 16, seed: int = 0, form_factor_points: int = 16):
        self.hierarchy = hierarchy
        self.samples = int(samples)
        self.form_factor_points = int(form_factor_points)
        self.seed = int(seed)
        #: the seed of every element's own points (element_grids): a link's receiving end
        self.point_seed = np.uint64((self.seed ^ 0x5A17E) & (2**63 - 1))
        self._states = np.zeros(0, np.uint64)
        self.rng = np.random.default_rng(seed)
        self.rays = 0
        self.epoch, self._lifts = 0, None
        # exposed_points' cache and the ray count are shared with recasts on the worker thread
        self._lock = threading.RLock()
        #: counts the rebuilds: what was measured against the scene before (reach) is stale after
        self.version = 0
        self.rebuild()

    def rebuild(self, exclude: np.ndarray | None = None, moved: list | None = None) -> None:
        """Rebuild the ray-casting scene from the active roots (``exclude``: root polygons left out).
        ``moved`` ([(lo, hi)], world metres): where everything that changed was and is — the probes'
        answers kept at points whose probe meets none of the boxes stand; otherwise none does."""
        try:
            from embreex import rtcore_scene
            from embreex.mesh_construction import TriangleMesh
        except ImportError:  # pragma: no cover - a dependency
            raise InputError("radiosity visibility needs embreex: pip install embreex") from None
        h = self.hierarchy
        roots = h.roots[h.active[h.roots]]
        if exclude is not None:
            roots = np.setdiff1d(roots, exclude)
        # a two-sided surface's back twin blocks what its front, at the same place, blocks: left out,
        # so no ray from or to either side hits a coincident twin at its own end
        roots = roots[h.polygons.sides()[h.polygon[roots]] != 2]
        c = h.corners[roots]
        tri = h.triangle[roots]
        tris = np.concatenate([c[:, [0, 1, 2]], c[~tri][:, [0, 2, 3]]])
        sided = h.polygons.sides()[h.polygon[roots]] == 1
        self.two_sided = np.r_[sided, sided[~tri]]  # per triangle of the scene, in its order
        #: the root each triangle of the scene belongs to (a hit's primID → its root)
        self.triangle_root = np.r_[roots, roots[~tri]].astype(np.int64)
        # reach counts the faces that reflect: what the solve scales is the reflected light (a black
        # lamp's own light is never scaled, so it is no part of the reach)
        polygon = h.polygon[roots]
        reflects = h.polygons.reflectance[polygon].max(axis=1) > 0
        self.reflects = np.r_[reflects, reflects[~tri]]
        extent = np.ptp(h.corners[h.roots].reshape(-1, 3), axis=0).max() if len(h.roots) else 1.0
        self.offset = 1e-5 * max(float(extent), 1e-6)
        self.extent = max(float(extent), 1e-6)
        self.contact = 2e-3 * self.extent
        kept = getattr(self, "_exposure", None) if moved is not None else None
        if self._lifts != (self.offset, self.contact):  # the rays a link kept were cast otherwise
            self._lifts, self.epoch = (self.offset, self.contact), self.epoch + 1
            kept = None
        self.version += 1
        self._open = np.full(0, np.nan)  # openness per element, measured against this scene
        self._exposure = np.zeros(0, np.uint32)  # exposure of elements' own points, this scene's
        if kept is not None and len(kept) and self.samples <= CACHED_POINTS:
            self._exposure = kept[: len(h)].copy()
            states = self.point_states()
            lo = np.array([b[0] for b in moved], np.float64).reshape(-1, 3) - self.offset
            hi = np.array([b[1] for b in moved], np.float64).reshape(-1, 3) + self.offset
            _forget_points(self._exposure, states, self.samples, h.corners, h.triangle, h.normal, self.offset, lo, hi)
        self.scene = rtcore_scene.EmbreeScene()
        if len(tris):
            TriangleMesh(self.scene, tris.astype(np.float32))
        self.empty = len(tris) == 0
        # the faces with a back, apart, where they are few (MGF's scenes: the lamps): see _probe
        one_sided = ~self.two_sided
        self.split_probe = len(tris) > 0 and one_sided.sum() <= SPLIT_PROBE_SHARE * len(tris)
        self._backs = None
        if self.split_probe and one_sided.any():
            self._backs = rtcore_scene.EmbreeScene()
            TriangleMesh(self._backs, tris[one_sided].astype(np.float32))

    def __call__(self, receivers: np.ndarray, sources: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F_ij, V_ij) for each (receiver, source) pair, (n,) float64 each."""
        form_factor, samples = self.form_factors(receivers, sources)
        return form_factor, self.cast_visibility(samples)

    def form_factors(self, receivers: np.ndarray, sources: np.ndarray) -> tuple[np.ndarray, LinkSamples]:
        """(F_ij (n,), the pairs' sample points): the receiver's own points (element_grids), the
        source's drawn from the shared stream, F from them;
        V from the same points when :meth:`cast_visibility` is asked (for the pairs that need it: a
        pair the bf criterion splits never uses its V)."""
        n, k = len(receivers), self.samples
        if n == 0:  # (draws nothing from the stream)
            none = np.zeros((0, k, 3))
            return np.zeros(0), LinkSamples(np.zeros(0, np.int64), np.zeros(0, np.int64), none, none)
        h = self.hierarchy
        a = h.sample_points(receivers, element_grids(receivers, k, self.point_seed))
        b = h.sample_points(sources, jittered_grid(n, k, self.rng))
        q = min(k, self.form_factor_points)
        form_factor = point_polygon(a[:, :q], h.normal[receivers], h.corners[sources], h.triangle[sources])
        return form_factor, LinkSamples(np.asarray(receivers), np.asarray(sources), a, b)

    def cast_visibility(self, samples: LinkSamples, rows: np.ndarray | None = None) -> np.ndarray:
        """V_ij (float64) of the pairs ``rows`` (a mask or indices; default all) of ``samples``."""
        receivers, sources, a, b = samples.receivers, samples.sources, samples.receiver_points, samples.source_points
        if rows is not None:
            receivers, sources, a, b = receivers[rows], sources[rows], a[rows], b[rows]
        n, k = len(receivers), self.samples
        if self.empty or n == 0:
            return np.ones(n)
        h = self.hierarchy
        receiver_normal = h.normal[receivers]
        origins, directions, dists, up = _segments(a, b, receiver_normal, h.normal[sources], self.offset)
        facing = _front_to_front(directions, receiver_normal, h.normal[sources], k)
        # a sample point with something right above it (under a board on a wall, behind a door in
        # contact) is not part of the surface anyone sees: a probe along the normal finds it
        # contact, or inside a closed object (the probe meets the back of a face: under a door that
        # stands on the wall, the points are inside the door). Only the samples that count are
        # probed, and only the exposed ones cast.
        rows = np.flatnonzero(facing)
        exposed = np.zeros(n * k, np.bool_)
        exposed[rows] = self.exposed_points(receivers, None, origins, up, rows)
        rows = rows[exposed[rows]]
        clear = np.zeros(n * k, np.bool_)
        clear[rows] = np.asarray(cast(self.scene, origins[rows], directions[rows], dists[rows], "OCCLUDED")) < 0
        self._count(len(rows))
        visibility, _ = _fraction_and_masks(clear, exposed, k, self.epoch, False, facing)
        return visibility

    def _probe(self, origins: np.ndarray, up: np.ndarray) -> np.ndarray:
        """:func:`_exposed` of probes from ``origins`` along ``up`` (float32 (n, 3) each): not exposed
        where the first hit is within ``contact`` or is the back of a one-sided face.

        Where one-sided faces are few (``split_probe``: MGF's scenes, two-sided but for their lamps)
        the same answer costs less in parts: an occlusion ray ``contact`` long for the contact; an
        occlusion ray among the one-sided faces alone (a small scene), and where it meets one, the
        first hit among them; where that is a back, an occlusion ray up to it through the whole
        scene — a two-sided face before it is the first hit and has no back. Otherwise one first
        hit at any distance, read as it is."""
        n = len(origins)
        if self.split_probe:
            touching = np.asarray(cast(self.scene, origins, up, np.full(n, self.contact, np.float32), "OCCLUDED"))
            exposed = touching < 0
            if self._backs is not None:
                # most probes meet none of the few one-sided faces: an occlusion ray finds which do
                # (half a first hit's cost), and the first hit is asked of those alone
                meets = np.asarray(cast(self._backs, origins, up, np.full(n, np.inf, np.float32), "OCCLUDED"))
                rows = np.flatnonzero(exposed & (meets >= 0))
                if len(rows):
                    first = cast(self._backs, origins[rows], up[rows])
                    prim, normal = np.asarray(first["primID"]), np.asarray(first["Ng"])
                    back = (prim >= 0) & ((normal * up[rows]).sum(axis=1) > 0)
                    # just short of the back, so the ray meets what lies before it, not the back itself
                    reach = np.asarray(first["tfar"])[back] * np.float32(1 - 1e-5)
                    rows = rows[back]
                    before = np.asarray(cast(self.scene, origins[rows], up[rows], reach, "OCCLUDED"))
                    exposed[rows[before < 0]] = False
            return exposed
        probe = cast(self.scene, origins, up)
        return _exposed(
            np.asarray(probe["primID"]),
            np.asarray(probe["tfar"]),
            np.asarray(probe["Ng"]),
            up,
            self.contact,
            self.two_sided,
        )

    def exposed(self, origins: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """Per point (lifted off its surface) with its unit normal: does a probe along the normal meet
        nothing within ``contact`` and no back of a face — is the point part of a visible surface?
        (The test the links' V makes of their receiver's samples, for callers with their own points.)"""
        if self.empty or not len(origins):
            return np.ones(len(origins), bool)
        self._count(len(origins))
        return self._probe(np.ascontiguousarray(origins, np.float32), np.ascontiguousarray(normals, np.float32))

    def exposed_points(self, elements, slots, origins, up, rows=None) -> np.ndarray:
        """:meth:`exposed` at ``rows`` (indices; default all) of the samples ``origins`` (each the
        point lifted) with their normals ``up``: sample i is point ``slots[i]`` of element
        ``elements[i]``'s own grid (element_grids), or, with ``slots`` None, point i % k of
        elements[i // k] (k samples per element given). Each point is probed once against this
        scene, its answer kept for every later link that starts there. Returns (len(rows),) bool."""
        with self._lock:
            elements, per = np.asarray(elements, np.int64), 0
            if slots is None:
                per, slots = len(origins) // max(len(elements), 1), np.zeros(0, np.uint8)
            rows = np.arange(len(origins)) if rows is None else np.asarray(rows, np.int64)
            if self.empty or self.samples > CACHED_POINTS or not len(rows):
                return self.exposed(origins[rows], up[rows])
            n = len(self.hierarchy)
            if len(self._exposure) < n:
                grown = np.zeros(max(n, 2 * len(self._exposure)), np.uint32)
                grown[: len(self._exposure)] = self._exposure
                self._exposure = grown
            first = _claim_points(self._exposure, elements, slots, per, rows)
            if len(first):
                probed = self.exposed(origins[first], up[first])
                _store_points(self._exposure, elements, slots, per, first, probed)
            return _read_points(self._exposure, elements, slots, per, rows)

    def _count(self, rays: int) -> None:
        with self._lock:
            self.rays += rays

    def point_states(self) -> np.ndarray:
        """(n,) uint64: every element's element_states (ids are never reused: grown, never redone)."""
        n, have = len(self.hierarchy), len(self._states)
        if have < n:
            self._states = np.r_[
                self._states, element_states(self.point_seed, np.arange(have, max(n, have + have // 4)))
            ]
        return self._states

    def reach(self, elements: np.ndarray, rays: int = 64) -> np.ndarray:
        """Per element (n,): Σ_j F_ej V_ej over reflecting surfaces as rays measure it — the share of
        cosine-weighted rays from jittered points of the element that meet the front of a face (or a
        two-sided face) that reflects (ρ > 0), the geometry any reflected light it gathers can come
        from; 1 in a closed room, less where its hemisphere opens onto nothing, a black wall or a
        lamp; counted over its exposed points only (NaN where none is), as the links' V is. (The
        seed's generator draws the points: deterministic.)"""
        n = len(elements)
        if n == 0:
            return np.zeros(0)
        if self.empty:
            return np.zeros(n)
        h = self.hierarchy
        elements = np.asarray(elements, np.int64)
        points = h.sample_points(elements, jittered_grid(n, rays, self.rng))
        normal = h.normal[elements]
        directions = cosine_directions(normal, jittered_grid(n, rays, self.rng))
        origins = (points + self.offset * normal[:, None]).reshape(-1, 3).astype(np.float32)
        directions = directions.reshape(-1, 3).astype(np.float32)
        hit = cast(self.scene, origins, directions)
        self._count(n * rays)
        prim = np.asarray(hit["primID"])
        facing = (np.asarray(hit["Ng"]) * directions).sum(axis=1) < 0
        seen = (prim >= 0) & (facing | self.two_sided[np.maximum(prim, 0)]) & self.reflects[np.maximum(prim, 0)]
        # as the links' V: a point in contact with another face or inside an object is no part of
        # the surface and does not count (a desk's leg standing on the floor)
        exposed = self.exposed(origins, np.repeat(normal, rays, axis=0)).reshape(n, rays)
        counted = exposed.sum(axis=1)
        hits = (seen.reshape(n, rays) & exposed).sum(axis=1)
        return np.where(counted > 0, hits / np.maximum(counted, 1), np.nan)

    def openness(self, elements: np.ndarray) -> np.ndarray:
        """Per element (n,): the share of cosine-weighted rays from its jittered points that travel
        farther than OPEN_DISTANCE × the scene's extent (or leave it): 0 for the inner faces of a
        closed two-sided box (the exposure probe finds no back on a two-sided face) and for a face a
        few centimetres from another, ~1 for a face open to a room. Each element is measured once
        per scene (again after a rebuild), with its own generator (a hash of the seed and the
        element), so the answer does not depend on the order elements are asked in."""
        elements = np.asarray(elements, np.int64)
        if self.empty or not len(elements):
            return np.ones(len(elements))
        if len(self._open) <= elements.max():
            grown = np.full(max(int(elements.max()) + 1, 2 * len(self._open)), np.nan)
            grown[: len(self._open)] = self._open
            self._open = grown
        unknown = np.isnan(self._open[elements])
        if unknown.any():  # (asked for every cluster link's samples: the known ones cost a lookup)
            fresh, h, k = np.unique(elements[unknown]), self.hierarchy, OPEN_RAYS
            for at in range(0, len(fresh), OPEN_SLICE):  # ~0.5 kB of points and rays an element
                part = fresh[at : at + OPEN_SLICE]
                uv_points, uv_rays = pair_grids(part, part, k, self.seed ^ 0x0BE7)
                normal = h.normal[part]
                directions = cosine_directions(normal, uv_rays).reshape(-1, 3).astype(np.float32)
                origins = (h.sample_points(part, uv_points) + self.offset * normal[:, None]).reshape(-1, 3)
                hit = cast(self.scene, origins.astype(np.float32), directions)
                self._count(len(origins))
                far = (np.asarray(hit["primID"]) < 0) | (np.asarray(hit["tfar"]) > OPEN_DISTANCE * self.extent)
                self._open[part] = far.reshape(len(part), k).mean(axis=1)
        return self._open[elements]

    def openness_array(self, *groups: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """The openness of every element measured so far (indexed by element; NaN where not
        measured, and no longer than the largest element measured), the elements of ``groups``
        measured first: for a kernel that looks up many samples' elements. Each group is (members
        (n, k) int64 element ids, −1 for none; rows (n,) bool): the members of the rows marked."""
        fresh = [_unmeasured(self._open, np.asarray(members, np.int64), rows) for members, rows in groups]
        self.openness(np.concatenate(fresh) if fresh else np.zeros(0, np.int64))
        return np.ones(len(self.hierarchy)) if self.empty or not len(self._open) else self._open

    def recast_in_background(self, receivers, sources, rays, boxes, chunk: int) -> Future:
        """:meth:`recast` on the worker thread (:mod:`illusio.core.background`), ``chunk`` pairs at a
        time (bounded memory), while the caller goes on (a moved object's own links are made
        meanwhile; what the two share — the probes' answers, the ray count — is locked). A future of
        (V, rays to keep) for every pair. Nothing may move, split or rebuild the scene's polygons
        until it is done; elements may be added (a refinement)."""
        receivers, sources = np.asarray(receivers, np.int64), np.asarray(sources, np.int64)
        rays = np.asarray(rays, np.int64)
        boxes = list(boxes)

        def run():
            parts = [
                self.recast(receivers[at : at + chunk], sources[at : at + chunk], rays[at : at + chunk], boxes)
                for at in range(0, len(receivers), chunk)
            ]
            if not parts:
                return np.zeros(0), np.zeros(0, np.int64)
            return np.concatenate([v for v, _ in parts]), np.concatenate([r for _, r in parts])

        for scene in (self.scene, self._backs):
            if scene is not None and not self.empty:
                commit(scene)  # the first query builds the tree: here, not on two threads at once
        return background.submit(run)

    def recast(
        self, receivers: np.ndarray, sources: np.ndarray, rays: np.ndarray, boxes: list
    ) -> tuple[np.ndarray, np.ndarray]:
        """(V_ij, rays) for pairs whose ends did not move, cast again after something moved inside
        ``boxes`` ([(lo, hi)], world metres, covering where it was and where it is): the receiver's own
        points (element_grids), the source's from :func:`pair_grids`; ``rays`` (n,) int64, what each
        pair kept at its last recast (NO_RAYS: none): only the samples whose ray or probe meets a box
        are cast again (a probe's answer kept by this scene is not). Returns V and what to keep."""
        n, k = len(receivers), self.samples
        rays = np.asarray(rays, np.int64)
        if n == 0:
            return np.zeros(0), np.zeros(0, np.int64)
        h = self.hierarchy
        keep = k <= KEPT_SAMPLES
        origins, directions, up = (np.empty((n * k, 3), np.float32) for _ in range(3))
        dists = np.empty(n * k, np.float32)
        clear, exposed = np.ones(n * k, np.bool_), np.ones(n * k, np.bool_)
        facing, cast_ray, cast_probe = np.empty(n * k, np.bool_), np.zeros(n * k, np.bool_), np.zeros(n * k, np.bool_)
        _recast_samples(
            np.asarray(receivers, np.int64),
            np.asarray(sources, np.int64),
            k,
            self.seed,
            self.point_seed,
            h.corners,
            h.triangle,
            h.normal[receivers],
            h.normal[sources],
            self.offset,
            rays if keep else np.full(n, NO_RAYS, np.int64),
            self.epoch,
            np.array([lo for lo, _ in boxes], np.float64).reshape(-1, 3) - self.offset,
            np.array([hi for _, hi in boxes], np.float64).reshape(-1, 3) + self.offset,
            origins,
            directions,
            dists,
            up,
            clear,
            exposed,
            facing,
            cast_ray,
            cast_probe,
        )
        if not self.empty:
            chosen = np.flatnonzero(cast_ray)
            if len(chosen):
                hit = cast(self.scene, origins[chosen], directions[chosen], dists[chosen], "OCCLUDED")
                clear[chosen] = np.asarray(hit) < 0
            chosen = np.flatnonzero(cast_probe)
            if len(chosen):
                exposed[chosen] = self.exposed_points(receivers, None, origins, up, chosen)
            self._count(int(cast_ray.sum()))
        else:
            clear[:], exposed[:] = True, True
        return _fraction_and_masks(clear, exposed, k, self.epoch, keep, facing)
