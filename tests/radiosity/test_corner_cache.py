"""The corner gather with its form factors kept (radiosity.corner_cache) equals the plain corner
gather after every kind of change: lamps rescaled, an object added, moved, and the mesh refined."""

import numpy as np

from illusio.radiosity import HierarchyParams, Radiosity, scene_polygons
from illusio.radiosity.corner_cache import CornerGather
from illusio.radiosity.display import corner_gather
from illusio.radiosity.polygons import Polygons, quads_from_triangles
from illusio.scene import load_scene
from illusio.scene.builtin import shapes


def test_kept_form_factors_give_the_plain_gather_after_each_change():
    sol = Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=1e-3)).build()
    gather = CornerGather()

    def check(expect_reuse: bool):
        h = sol.hierarchy
        leaves = h.leaves()
        plain = corner_gather(h, sol.links, leaves, sol.exitance())
        kept = gather(h, sol.links, leaves, sol.exitance())
        assert np.allclose(kept, plain, rtol=1e-6, atol=1e-12)  # its form factors kept as float32
        assert (gather.reused > 0) == expect_reuse and gather.computed + gather.reused > 0

    check(False)
    sol.set_lamps({sol.lamp_names[0]: 0.3})  # B changes, links and geometry do not
    check(True)
    assert gather.computed == 0
    # a leaf split under receivers of many links: their blocks are redone, but only the new leaves'
    # form factors are computed, the others' taken from the blocks they had
    h = sol.hierarchy
    leaves = h.leaves()
    above = np.zeros(len(h), np.int64)  # each leaf's links with light, its own and its ancestors'
    np.add.at(above, sol.links.receiver[sol.links.visibility > 0], 1)
    for level in h.by_level()[1:]:
        above[level] += above[h.parent[level]]
    target = leaves[np.argmax(above[leaves])]
    h.subdivide(np.array([target]))
    check(True)
    assert 0 < gather.computed <= 4 * above[target] < gather.reused
    corners, triangle = quads_from_triangles(
        np.asarray(shapes.box((0.1, 0.1, 0.1)).vertices) + [0.25, 0.05, 0.3], shapes.box((0.1, 0.1, 0.1)).faces
    )
    n = len(corners)
    sol.add_object(
        Polygons(corners, triangle, np.full((n, 3), 0.5), np.zeros((n, 3)), np.zeros(n, int), ["crate"]), "crate"
    )
    check(True)
    move = np.eye(4)
    move[0, 3] = -0.1
    sol.move_object("crate", move)
    check(True)
    assert 0 < gather.computed < gather.reused
    for _ in range(5):  # a drag: the arena fills with fresh blocks and is compacted
        sol.move_object("crate", move if _ % 2 else np.linalg.inv(move))
        check(True)
        assert gather._used <= 2 * gather.pairs + 1024
    # links with V = 0 got a place but no form factors; one that starts carrying light gets them
    assert gather.deferred > 0 or (sol.links.visibility == 0).any()
    dark = np.flatnonzero(sol.links.visibility == 0)[:50]
    assert len(dark)
    sol.links.visibility[dark] = 0.5
    check(True)
    assert gather.computed > 0
    other = CornerGather()  # another cache over the same links: its own blocks, exact
    h = sol.hierarchy
    assert np.allclose(
        other(h, sol.links, h.leaves(), sol.exitance()),
        corner_gather(h, sol.links, h.leaves(), sol.exitance()),
        rtol=1e-6,
        atol=1e-12,
    )
    assert other.reused == 0
    check(False)  # and the first, whose tags the other took, starts afresh


def test_gathering_only_the_shown_leaves_keeps_their_corners_exact(rng):
    """vertex_radiosity(shown=…): a random half of the leaves shown; every corner of a shown leaf
    equals the full gather's (its neighbours sharing a corner were gathered too), and the gather
    kept between calls follows a change of the shown set."""
    from illusio.radiosity.display import vertex_radiosity

    sol = Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=1e-3)).build()
    h = sol.hierarchy
    leaves = h.leaves()
    full = vertex_radiosity(h, leaves, sol.links, sol.exitance())
    gather = CornerGather()
    for call in range(2):
        shown = np.zeros(len(h), bool)
        shown[rng.choice(leaves, len(leaves) // 2, replace=False)] = True
        part = vertex_radiosity(h, leaves, sol.links, sol.exitance(), gather=gather, shown=shown)
        assert np.allclose(part[shown[leaves]], full[shown[leaves]], rtol=1e-6, atol=1e-12)
        if call:  # another half: the blocks of the links above both kept
            assert gather.reused > 0 and gather.computed > 0
    # and the leaves left out were left out: fewer pairs than the full gather
    every = CornerGather()
    every(h, sol.links, leaves, sol.exitance())
    assert gather.pairs < every.pairs


def test_the_solves_scale_acts_on_the_reflected_light_at_the_corners_and_never_on_the_lamps(rng):
    """With the solve's scale s per element (the gain cap, the reach) the corners show E + ρ·(H_lamps
    + s·(H − H_lamps)), as the solve has it: kept and plain gathers agree on random scales; s = 1 is
    the unscaled gather; s = 0 leaves exactly the lamps' light (the gather of their exitance alone)."""
    sol = Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=1e-3)).build()
    h, leaves, exitance = sol.hierarchy, sol.hierarchy.leaves(), sol.exitance()
    lamp = sol.lamp_radiosity()
    scale = rng.uniform(0.5, 1.5, len(h))
    plain = corner_gather(h, sol.links, leaves, exitance, scale, lamp)
    kept = CornerGather()(h, sol.links, leaves, exitance, scale, lamp)
    np.testing.assert_allclose(kept, plain, rtol=1e-6, atol=1e-12)
    unscaled = corner_gather(h, sol.links, leaves, exitance)
    np.testing.assert_allclose(corner_gather(h, sol.links, leaves, exitance, np.ones(len(h)), lamp), unscaled)
    assert not np.allclose(plain, unscaled)
    only_lamps = corner_gather(h, sol.links, leaves, exitance, np.zeros(len(h)), lamp)
    bright = h.radiosity.copy()
    h.radiosity[:] = lamp
    np.testing.assert_allclose(only_lamps, corner_gather(h, sol.links, leaves, exitance), rtol=1e-12)
    h.radiosity[:] = bright


def test_the_cluster_links_light_on_display_takes_the_solves_scale_on_its_reflected_part(monkeypatch):
    """Radiosity.display_exitance, what the cluster links add to the corners: E + ρ·(C(lamps) + s·C(B −
    lamps)), C the cluster links' irradiance pushed down. With s = 1 it is the unscaled light of B;
    with s = 0 only the lamps' own light through the clusters is left; at s = ½ halfway."""
    from illusio.radiosity import Radiosity as Engine

    sol = Radiosity(scene_polygons(load_scene("office")), HierarchyParams()).build()
    assert len(sol.cluster_links)
    h, exitance = sol.hierarchy, sol.exitance()
    n = len(h)
    monkeypatch.setattr(Engine, "display_scale", lambda self: np.ones(n))
    whole = sol.display_exitance()
    monkeypatch.setattr(Engine, "display_scale", lambda self: np.zeros(n))
    lamps_only = sol.display_exitance()
    monkeypatch.setattr(Engine, "display_scale", lambda self: np.full(n, 0.5))
    half = sol.display_exitance()
    np.testing.assert_allclose(half, 0.5 * (whole + lamps_only), rtol=1e-9, atol=1e-12)
    bright = h.radiosity.copy()
    h.radiosity[:] = sol.lamp_radiosity()
    monkeypatch.setattr(Engine, "display_scale", lambda self: None)
    np.testing.assert_allclose(lamps_only, sol.display_exitance(), rtol=1e-9, atol=1e-12)
    h.radiosity[:] = bright
    assert np.abs(whole - lamps_only).max() > 0.1 * np.abs(whole - exitance).max()  # the reflected part counts


def _kept_sums_through_edits(tolerance: float) -> tuple[list[float], list[int]]:
    """A CornerGather(tolerance) against the plain gather through lamps rescaled, an object added
    and moved, the mesh refined: per call, the largest difference over the largest reflected B, and
    the pairs summed."""
    sol = Radiosity(scene_polygons(load_scene("cornell-box")), HierarchyParams(epsilon=1e-3)).build()
    gather = CornerGather(tolerance)
    errors, summed = [], []

    def check():
        h = sol.hierarchy
        leaves, exitance = h.leaves(), sol.exitance()
        plain = corner_gather(h, sol.links, leaves, exitance)
        reflected = np.abs(h.radiosity - exitance).max()
        errors.append(np.abs(gather(h, sol.links, leaves, exitance) - plain).max() / reflected)
        summed.append(gather.summed)

    check()
    sol.set_lamps({sol.lamp_names[0]: 0.5})
    check()
    check()  # nothing changed
    sol.set_lamps({sol.lamp_names[0]: 0.49})  # B moves by 2 %
    check()
    box = shapes.box((0.12, 0.12, 0.12))
    corners, triangle = quads_from_triangles(np.asarray(box.vertices) + [0.3, 0.06, 0.3], box.faces)
    n = len(corners)
    sol.add_object(
        Polygons(corners, triangle, np.full((n, 3), 0.5), np.zeros((n, 3)), np.zeros(n, int), ["crate"]), "crate"
    )
    check()
    move = np.eye(4)
    move[0, 3] = 0.03
    for _ in range(3):
        sol.move_object("crate", move)
        check()
    h = sol.hierarchy
    sol.rerefine(np.flatnonzero(np.isin(sol.links.receiver, h.leaves()[:40])))
    sol.solve()
    check()
    return errors, summed


def test_kept_sums_stay_within_their_tolerance_of_the_plain_gather():
    """CornerGather(tolerance): the sums kept between calls, a source's B carried into them once it
    moved by more than tolerance × the largest reflected B: every corner within that of the plain
    gather (ρ·Σ F·V ≤ 1) after each edit, fewer pairs summed than at tolerance 0, where it equals
    the plain gather; nothing summed again when nothing changed."""
    tolerance = 3e-3
    errors, summed = _kept_sums_through_edits(tolerance)
    exact_errors, exact_summed = _kept_sums_through_edits(0.0)
    assert max(errors) <= tolerance * (1 + 1e-6)
    assert max(errors) > 0.05 * tolerance  # the tolerance was used
    assert max(exact_errors) < 1e-6  # (the form factors kept as float32)
    assert summed[2] == exact_summed[2] == 0  # nothing changed
    assert all(a <= b for a, b in zip(summed, exact_summed)) and sum(summed[5:8]) < 0.9 * sum(exact_summed[5:8])


def test_the_kept_sums_changes_give_the_same_bits_in_any_number_of_leaf_ranges(rng):
    """corner_cache._add_blocks: each thread adds the listed changes to its range of leaves, in list
    order, so one range or several give the same bits, and both equal the changes added one by one."""
    from illusio.radiosity.corner_cache import _add_blocks

    leaves, blocks = 500, 300
    count = rng.integers(0, 12, blocks)
    offset = np.cumsum(count) - count
    leaf = rng.integers(0, leaves, int(count.sum())).astype(np.int32)
    ff = rng.random((int(count.sum()), 4)).astype(np.float32)
    ops = rng.integers(0, blocks, 2000)
    weights, values = rng.normal(size=2000), rng.random((2000, 3))
    want = np.zeros((leaves, 4, 3))
    for o in range(len(ops)):  # the plain statement
        for p in range(offset[ops[o]], offset[ops[o]] + count[ops[o]]):
            for c in range(4):
                want[leaf[p], c] += (ff[p, c] * weights[o]) * values[o]
    for ranges in (1, 2, 5):
        sums = np.zeros((leaves, 4, 3))
        _add_blocks(sums, ops, weights, values, offset, count, leaf, ff, ranges)
        np.testing.assert_array_equal(sums, want)
