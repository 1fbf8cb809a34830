"""A link cast again after something moved (Visibility.recast): per-pair sample points, the rays'
outcomes kept, and only the rays through the moved object's boxes cast again — exactly what a full
recast of the same rays gives."""

import numpy as np

from illusio.radiosity import HierarchyParams, Polygons, Radiosity, scene_polygons
from illusio.radiosity.polygons import quads_from_triangles
from illusio.radiosity.visibility import KEPT_SAMPLES, NO_RAYS, pair_grids
from illusio.scene import load_scene
from illusio.scene.builtin import shapes


def test_pair_grids_are_per_pair_stratified_and_repeatable(rng):
    receivers, sources = rng.integers(0, 10_000, 500), rng.integers(0, 10_000, 500)
    uv_r, uv_s = pair_grids(receivers, sources, 16, seed=3)
    assert uv_r.shape == (500, 16, 2) and (uv_r >= 0).all() and (uv_r < 1).all() and (uv_s < 1).all()
    for uv in (uv_r, uv_s):  # one point per cell of the 4×4 grid
        cell = (np.floor(uv[..., 1] * 4) * 4 + np.floor(uv[..., 0] * 4)).astype(int)
        assert (np.sort(cell, axis=1) == np.arange(16)).all()
    # the source's cells in another order than the receiver's, and pairs drawn apart
    same_order = (np.floor(uv_r * 4) == np.floor(uv_s * 4)).all(axis=(1, 2))
    assert same_order.mean() < 0.01
    assert not np.allclose(uv_r[0], uv_r[1])
    # a pair gets the same points whatever else is in the batch, and another seed others
    again_r, again_s = pair_grids(receivers[::-1][:100], sources[::-1][:100], 16, seed=3)
    np.testing.assert_array_equal(again_r, uv_r[::-1][:100])
    np.testing.assert_array_equal(again_s, uv_s[::-1][:100])
    other, _ = pair_grids(receivers, sources, 16, seed=4)
    assert not np.allclose(other, uv_r)
    # a grid that is not square (10 of 16 cells) still takes each cell once
    ten, _ = pair_grids(receivers, sources, 10, seed=3)
    cell = (np.floor(ten[..., 1] * 4) * 4 + np.floor(ten[..., 0] * 4)).astype(int)
    assert all(len(set(row)) == 10 for row in cell)
    # the source's alone (recast's): a grid of its own per pair, repeatable, not the pair's source grid
    none, alone = pair_grids(receivers, sources, 16, seed=3, source_only=True)
    cell = (np.floor(alone[..., 1] * 4) * 4 + np.floor(alone[..., 0] * 4)).astype(int)
    assert none is None and (np.sort(cell, axis=1) == np.arange(16)).all()
    np.testing.assert_array_equal(pair_grids(receivers[:50], sources[:50], 16, seed=3, source_only=True)[1], alone[:50])
    assert not np.isclose(alone, uv_s).all(axis=(1, 2)).any()


def _crate_in_cornell():
    sol = Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=2e-4)).build()
    box = shapes.box((0.12, 0.12, 0.12))
    corners, triangle = quads_from_triangles(np.asarray(box.vertices) + [0.3, 0.06, 0.3], box.faces)
    n = len(corners)
    sol.add_object(
        Polygons(corners, triangle, np.full((n, 3), 0.5), np.zeros((n, 3)), np.zeros(n, int), ["crate"]), "crate"
    )
    return sol


def test_recast_with_kept_rays_equals_a_full_recast():
    """A crate dragged over the Cornell box's floor: after each move, every link that kept its rays
    has exactly the masks and V that casting all its rays now gives (nothing it kept is stale), and
    the crate stays inside the box (a move that grows the scene's extent changes the rays' offsets:
    the links then keep nothing)."""
    sol = _crate_in_cornell()
    vis = sol.visibility
    assert vis.samples <= KEPT_SAMPLES
    move = np.eye(4)
    move[0, 3] = 0.03
    kept_links = []
    for step in range(6):
        sol.move_object("crate", move if step < 4 else np.linalg.inv(move))
        L = sol.links
        have = np.flatnonzero(L.rays >= 0)
        kept_links.append(len(have))
        start = vis.rays
        visibility, rays = vis.recast(L.receiver[have], L.source[have], np.full(len(have), NO_RAYS), [])
        np.testing.assert_array_equal(rays, L.rays[have])
        np.testing.assert_array_equal(visibility, L.visibility[have])
        # every ray, and a probe at each receiving point whose answer this scene has not kept
        cast_now = vis.rays - start
        assert vis.samples * len(have) <= cast_now <= 2 * vis.samples * len(have)
        # asked again: the same answer, and the probes' answers kept (each point probed once)
        start = vis.rays
        again, _ = vis.recast(L.receiver[have], L.source[have], np.full(len(have), NO_RAYS), [])
        np.testing.assert_array_equal(again, visibility)
        assert vis.rays - start == vis.samples * len(have)
    assert min(kept_links) > 0 and max(kept_links) > 50


def test_recast_casts_only_the_rays_through_the_boxes():
    """Links recast with what they kept and a box that meets none of their rays cast nothing and
    keep their V; with a box around the whole scene, every ray again."""
    sol = _crate_in_cornell()
    vis = sol.visibility
    move = np.eye(4)
    move[0, 3] = 0.03
    sol.move_object("crate", move)
    L = sol.links
    have = np.flatnonzero(L.rays >= 0)
    far = [(np.full(3, 50.0), np.full(3, 51.0))]
    start = vis.rays
    visibility, rays = vis.recast(L.receiver[have], L.source[have], L.rays[have], far)
    assert vis.rays == start
    np.testing.assert_array_equal(visibility, L.visibility[have])
    np.testing.assert_array_equal(rays, L.rays[have])
    everywhere = [(np.full(3, -50.0), np.full(3, 50.0))]
    visibility, _ = vis.recast(L.receiver[have], L.source[have], L.rays[have], everywhere)
    # every ray; the probes only at points this scene has not answered yet
    assert vis.samples * len(have) <= vis.rays - start < 2 * vis.samples * len(have)
    np.testing.assert_array_equal(visibility, L.visibility[have])


def test_the_probes_answers_kept_through_moves_are_what_a_fresh_probe_gives():
    """Visibility.rebuild(moved=boxes) keeps the exposure answers of points whose probe meets
    neither box: a crate dragged over the Cornell box's floor and onto the spot it left, every
    answer kept after each move against a probe cast afresh at that point, and the crate's own
    points (moved) and those under it asked again."""
    from illusio.radiosity.visibility import CACHED_POINTS, element_grids

    sol = _crate_in_cornell()
    vis, h = sol.visibility, sol.hierarchy
    k = vis.samples
    move = np.eye(4)
    move[0, 3] = 0.05
    for step in range(5):
        sol.move_object("crate", move if step < 3 else np.linalg.inv(move))
        cache = vis._exposure
        known = (cache[:, None] >> np.arange(k).astype(np.uint64)) & np.uint64(1) == 1
        elements, slots = np.nonzero(known)
        assert len(elements) > 1000
        uv = element_grids(elements, k, vis.point_seed)[np.arange(len(elements)), slots]
        up = h.normal[elements].astype(np.float32)
        origins = (h.sample_points(elements, uv[:, None])[:, 0] + vis.offset * h.normal[elements]).astype(np.float32)
        kept = ((cache[elements] >> (slots + CACHED_POINTS).astype(np.uint64)) & np.uint64(1)).astype(bool)
        np.testing.assert_array_equal(kept, vis.exposed(origins, up))
    # which answers a rebuild drops, against a plain slab test of each known point's probe ray
    box = (np.array([0.2, 0.0, 0.2]), np.array([0.45, 0.3, 0.45]))
    vis.rebuild(moved=[box])
    lo, hi = box[0] - vis.offset, box[1] + vis.offset
    o, d = origins.astype(np.float64), h.normal[elements]
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (lo - o) / d, (hi - o) / d
    inside = (o >= lo) & (o <= hi)
    near = np.where(d == 0, np.where(inside, -np.inf, np.inf), np.minimum(t0, t1)).max(axis=1)
    far = np.where(d == 0, np.where(inside, np.inf, -np.inf), np.maximum(t0, t1)).min(axis=1)
    meets = np.maximum(near, 0) <= far
    assert 0 < meets.sum() < len(meets)
    still = ((vis._exposure[elements] >> slots.astype(np.uint64)) & np.uint64(1)).astype(bool)
    np.testing.assert_array_equal(still, ~meets)


def _slab_numpy(origins, directions, far, lo, hi):
    """Does each ray o + t·d, 0 ≤ t ≤ far, meet the box [lo, hi]? (the slab test, in NumPy)"""
    o, d = origins.astype(np.float64), directions.astype(np.float64)
    flat = np.abs(d) < 1e-30
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (lo - o) / d, (hi - o) / d
    near = np.where(flat, 0.0, np.minimum(t0, t1)).max(axis=1).clip(min=0.0)
    stop = np.minimum(np.where(flat, np.inf, np.maximum(t0, t1)).min(axis=1), far)
    inside = ~(flat & ((o < lo) | (o > hi))).any(axis=1)
    return inside & (near <= stop)


def test_recasts_samples_in_one_pass_equal_the_pieces_they_replace(rng):
    """recast's one-pass kernel against the pieces it fuses, on random pairs of a built scene, kept
    masks and boxes: the points (element_grids, pair_grids' source-only draw, sample_points), the rays
    (_segments) and front-to-front test the same to the bit, and the samples to cast those whose
    pair kept nothing or whose ray or probe meets a box (a NumPy slab test)."""
    from illusio.radiosity.visibility import (
        _front_to_front,
        _recast_samples,
        _segments,
        element_grids,
    )

    sol = _crate_in_cornell()
    vis, h = sol.visibility, sol.hierarchy
    n, k = 700, vis.samples
    receivers, sources = rng.integers(0, len(h), n), rng.integers(0, len(h), n)
    rays = rng.integers(0, 2**32, n).astype(np.int64) | (np.int64(vis.epoch) << 32)
    rays[rng.random(n) < 0.2] = NO_RAYS
    rays[rng.random(n) < 0.1] ^= np.int64(1) << 32  # kept under another epoch: cast afresh
    box_lo = rng.uniform(0.0, 0.4, (2, 3))
    box_hi = box_lo + rng.uniform(0.05, 0.3, (2, 3))
    out = [np.empty((n * k, 3), np.float32) for _ in range(3)] + [np.empty(n * k, np.float32)]
    clear, exposed = np.ones(n * k, bool), np.ones(n * k, bool)
    facing, cast_ray, cast_probe = np.empty(n * k, bool), np.zeros(n * k, bool), np.zeros(n * k, bool)
    origins, directions, up, dists = out
    _recast_samples(
        receivers, sources, k, vis.seed, vis.point_seed, h.corners, h.triangle, h.normal[receivers],
        h.normal[sources], vis.offset, rays, vis.epoch, box_lo, box_hi, origins, directions, dists, up, clear,
        exposed, facing, cast_ray, cast_probe,
    )  # fmt: skip
    _, uv_source = pair_grids(receivers, sources, k, vis.seed, source_only=True)
    a = h.sample_points(receivers, element_grids(receivers, k, vis.point_seed))
    b = h.sample_points(sources, uv_source)
    expected = _segments(a, b, h.normal[receivers], h.normal[sources], vis.offset)
    for got, want in zip((origins, directions, dists, up), expected):
        np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal(facing, _front_to_front(expected[1], h.normal[receivers], h.normal[sources], k))
    kept = np.repeat((rays >= 0) & ((rays >> 32) == vis.epoch), k)
    through_ray = np.zeros(n * k, bool)
    through_probe = np.zeros(n * k, bool)
    for lo, hi in zip(box_lo, box_hi):
        through_ray |= _slab_numpy(origins, directions, dists.astype(np.float64), lo, hi)
        through_probe |= _slab_numpy(origins, up, np.full(n * k, 1e300), lo, hi)
    np.testing.assert_array_equal(cast_ray, ~kept | through_ray)
    np.testing.assert_array_equal(cast_probe, ~kept | through_probe)
    assert 0 < through_ray[kept].sum() < kept.sum()  # the boxes meet some rays, not all
    bit = np.tile(np.arange(k), n)
    rows = np.repeat(rays, k)
    np.testing.assert_array_equal(clear[kept], ((rows >> bit) & 1)[kept] == 1)
    np.testing.assert_array_equal(exposed[kept], ((rows >> (16 + bit)) & 1)[kept] == 1)
    assert clear[~kept].all() and exposed[~kept].all()


def _moved_links(background: bool, monkeypatch=None):
    """A crate moved in the Cornell box the way move_object does it, its shafts' V cast on the worker
    thread (while the crate's own links are made) or inside the refinement; the links after."""
    from illusio.radiosity import dynamic

    sol = _crate_in_cornell()
    move = np.eye(4)
    move[0, 3] = 0.04
    group, elements, old_box = dynamic._detach(sol, "crate")
    sol.hierarchy.transform(elements, move)
    sol.polygons = sol.polygons.moved(group, move)
    sol.hierarchy.polygons = sol.polygons
    new_box = dynamic._object_box(sol, elements)
    sol.visibility.rebuild(moved=[old_box, new_box])
    shafts = dynamic._shafts_started(sol, [old_box, new_box], background=background)
    assert (shafts.recast is not None) == background
    h = sol.hierarchy
    dynamic._link_object(sol, h.roots[sol.polygons.group[h.polygon[h.roots]] == group])
    shafts.wait()
    redone = shafts.finish()
    L = sol.links
    return redone, L.receiver.copy(), L.source.copy(), L.visibility.copy(), L.rays.copy(), sol.visibility.rays


def test_the_shafts_cast_on_the_worker_thread_give_what_the_refinement_casts(monkeypatch):
    """The links whose shafts the moved crate meets, their V cast on the worker thread while the
    crate's own links are refined (both casting, both asking the probes' shared answers) — and cast
    at once where numba's threading layer cannot run two kernels together —, end as the same links
    with the same V and kept rays, and the same rays counted, as when the refinement casts them."""
    from illusio.core import background

    inline = _moved_links(background=False)
    assert inline[0] > 50
    for got, want in zip(_moved_links(background=True), inline):
        np.testing.assert_array_equal(got, want)
    monkeypatch.setattr(background, "threads_safe", lambda: False)
    for got, want in zip(_moved_links(background=True), inline):
        np.testing.assert_array_equal(got, want)


def test_a_recast_on_the_worker_thread_in_chunks_equals_one_recast():
    """recast_in_background's pieces (a few pairs at a time, as memory bounds them) put together give
    what one recast of all the pairs gives."""
    sol = _crate_in_cornell()
    vis, L = sol.visibility, sol.links
    boxes = [(np.array([0.2, 0.0, 0.2]), np.array([0.45, 0.2, 0.45]))]
    rows = np.flatnonzero(L.rays >= 0)[:300]
    want = vis.recast(L.receiver[rows], L.source[rows], L.rays[rows], boxes)
    got = vis.recast_in_background(L.receiver[rows], L.source[rows], L.rays[rows], boxes, chunk=7).result()
    for g, w in zip(got, want):
        np.testing.assert_array_equal(g, w)
