"""The exposure probe (is a sample point part of a visible surface?) in a scene of two-sided faces
but for a few one-sided ones, as MGF's scenes are (their lamps): the probe in parts it casts there
(a short occlusion ray, an occlusion ray and then the first hit among the one-sided faces, an
occlusion ray up to a back)
against the first hit at any distance that the general test reads (a hit within ``contact``, or
the back of a one-sided face)."""

import warnings

import numpy as np

from illusio.radiosity import Polygons, scene_polygons
from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.polygons import rectangle
from illusio.radiosity.visibility import Visibility, _exposed
from illusio.scene.mgf import load_mgf


def test_a_mostly_two_sided_scene_probes_in_parts_and_answers_as_the_first_hit_does(mgf_scenes, rng):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the file's unused entities, said by the reader
        polygons = scene_polygons(load_mgf(mgf_scenes / "office2.mgf"))
    h = Hierarchy(polygons)
    visibility = Visibility(h)
    assert visibility.split_probe and visibility._backs is not None  # office2's three lamps have backs
    # every root, and more points under the lamps (points above a lamp see its back)
    lamps = np.flatnonzero(polygons.exitance.max(axis=1) > 0)
    elements = np.r_[rng.choice(h.roots, 20000), np.repeat(h.roots[np.isin(h.polygon[h.roots], lamps)], 50)]
    points = h.sample_points(elements, rng.random((len(elements), 1, 2)))[:, 0]
    up = h.normal[elements].astype(np.float32)
    origins = (points + visibility.offset * h.normal[elements]).astype(np.float32)
    short = visibility.exposed(origins, up)
    probe = visibility.scene.run(origins, up, output=1)  # the first hit, any distance
    general = _exposed(
        np.asarray(probe["primID"]), np.asarray(probe["tfar"]), np.asarray(probe["Ng"]), up, visibility.contact,
        visibility.two_sided,
    )  # fmt: skip
    np.testing.assert_array_equal(short, general)
    assert 0 < (~short).sum() < len(short)  # points in contact (a desk's foot, a board on a wall) and free ones


def test_the_back_of_a_one_sided_face_hides_a_point_unless_a_two_sided_face_comes_first(monkeypatch, rng):
    """A floor under a one-sided board facing up (its back to the floor), a two-sided shelf between
    them over half the floor: the floor under the shelf is exposed, the rest sees the board's back
    first and is not (a point inside a closed one-sided object); the probe in parts says so."""
    import illusio.radiosity.visibility as visibility_module

    monkeypatch.setattr(visibility_module, "SPLIT_PROBE_SHARE", 0.5)
    quad = [
        rectangle((0, 0, 0), (0, 0, 4), (4, 0, 0)),  # floor, facing up
        rectangle((0, 2, 0), (0, 0, 1), (1, 0, 0)),  # board, facing up, one-sided
        rectangle((-0.5, 1, 0), (0, 0, 1), (1, 0, 0)),  # shelf over x < 0, facing up
    ]
    polygons = Polygons(np.array(quad), np.zeros(3, bool), np.full((3, 3), 0.5), np.zeros((3, 3)), [0, 1, 2],
                        ["floor", "board", "shelf"], side=[1, 0, 1])  # fmt: skip
    h = Hierarchy(polygons)
    visibility = Visibility(h)
    assert visibility.split_probe and visibility._backs is not None
    points = np.c_[rng.uniform(-0.45, 0.45, 2000), np.full(2000, visibility.offset), rng.uniform(-0.45, 0.45, 2000)]
    up = np.tile(np.float32([0, 1, 0]), (2000, 1))
    exposed = visibility.exposed(points.astype(np.float32), up)
    np.testing.assert_array_equal(exposed, points[:, 0] < 0)


def test_elements_own_points_match_their_plain_statement_and_fill_the_grid(rng):
    """element_grids (numba) against reference.element_uv (NumPy) bit for bit; each element's 16
    points one per cell of its 4×4 grid; 10 points the first 10 of the 16; the same at every call,
    another set on another element or under another seed."""
    from illusio.radiosity import reference
    from illusio.radiosity.visibility import element_grids

    elements = rng.integers(0, 2**31, 500)
    seed = int(rng.integers(0, 2**63))
    uv = element_grids(elements, 16, seed)
    np.testing.assert_array_equal(uv, reference.element_uv(seed, elements[:, None], np.arange(16)[None], 16))
    cells = np.floor(uv * 4).astype(int)
    assert (np.sort(cells[..., 0] * 4 + cells[..., 1], axis=1) == np.arange(16)).all()
    np.testing.assert_array_equal(element_grids(elements, 10, seed), uv[:, :10])
    np.testing.assert_array_equal(element_grids(elements[::-1], 16, seed), uv[::-1])
    assert not np.isclose(element_grids(elements, 16, seed + 1), uv).any(axis=2).all()
    assert not np.isclose(uv[1:], uv[:-1]).all(axis=2).any()


def test_an_elements_point_is_probed_once_a_scene_and_answers_as_a_fresh_probe(mgf_scenes, rng):
    """Visibility.exposed_points: the answer of a fresh probe at each point asked (points of
    elements in contact and free ones, subdivided elements too), each distinct point probed once
    against the scene, none again when asked again, all again after a rebuild."""
    from illusio.radiosity.visibility import element_grids

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        polygons = scene_polygons(load_mgf(mgf_scenes / "office2.mgf"))
    h = Hierarchy(polygons)
    h.subdivide(rng.choice(h.roots, 200, replace=False))
    visibility = Visibility(h)
    k = visibility.samples
    elements = rng.choice(np.flatnonzero(h.active), 6000)
    slots = rng.integers(0, k, len(elements))
    uv = element_grids(elements, k, visibility.point_seed)[np.arange(len(elements)), slots]
    up = h.normal[elements].astype(np.float32)
    origins = (h.sample_points(elements, uv[:, None])[:, 0] + visibility.offset * h.normal[elements]).astype(np.float32)
    fresh = visibility.exposed(origins, up)
    assert 0 < (~fresh).sum() < len(fresh)
    distinct = len(np.unique(elements * k + slots))
    assert distinct < len(elements)  # some points asked twice
    start = visibility.rays
    rows = rng.permutation(len(elements))
    np.testing.assert_array_equal(visibility.exposed_points(elements, slots, origins, up, rows), fresh[rows])
    assert visibility.rays - start == distinct
    start = visibility.rays
    np.testing.assert_array_equal(visibility.exposed_points(elements, slots, origins, up), fresh)
    assert visibility.rays == start
    visibility.rebuild()
    np.testing.assert_array_equal(visibility.exposed_points(elements, slots, origins, up), fresh)
    assert visibility.rays - start == distinct
    # per pair: sample i is point i % k of the i // k-th element given (as links' samples are)
    some = elements[:300]
    all_points = h.sample_points(some, element_grids(some, k, visibility.point_seed)).reshape(-1, 3)
    lifted = (all_points + visibility.offset * np.repeat(h.normal[some], k, axis=0)).astype(np.float32)
    normals = np.repeat(up[:300], k, axis=0)
    rows = rng.permutation(len(lifted))[:2000]
    np.testing.assert_array_equal(
        visibility.exposed_points(some, None, lifted, normals, rows), visibility.exposed(lifted, normals)[rows]
    )
