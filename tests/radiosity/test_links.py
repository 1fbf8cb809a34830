"""Links edited in place (numba compaction, growable buffers) equal the plain NumPy masks and
concatenations, tags and kept rays included, over random edits; refinement's per-row channel max
against NumPy's."""

import numpy as np

from illusio.radiosity.links import Links

NAMES = ("receiver", "source", "form_factor", "visibility", "tag", "rays")


def _assert_columns(links, plain, rows=slice(None)):
    for name, column in zip(NAMES, plain):
        np.testing.assert_array_equal(getattr(links, name), column[rows])


def _remove_then_extend(links, plain, drop, rng, rays=None):
    """Remove ``drop`` and append k random links (``rays(k)``: their rays, None: -1), checking
    what was removed and what is left against the plain columns; returns those columns."""
    _assert_columns(links.remove(drop), plain, drop)
    k = int(rng.integers(1, 3000))
    new = [rng.integers(0, 900, k), rng.integers(0, 900, k), rng.random(k), rng.random(k)]
    given = None if rays is None else rays(k)
    links.extend(*new, rays=given)
    added = new + [np.full(k, -1), np.full(k, -1) if given is None else given]
    plain = [np.concatenate([p[~drop], c]) for p, c in zip(plain, added)]
    _assert_columns(links, plain)
    return plain


def test_in_place_edits_equal_masks_and_concatenation(rng):
    n = 5000
    columns = [rng.integers(0, 900, n), rng.integers(0, 900, n), rng.random(n), rng.random(n)]
    links = Links(*columns, rays=rng.integers(-1, 2**40, n))
    links.tag = rng.integers(-1, 50, n)
    plain = columns + [links.tag.copy(), links.rays.copy()]
    for step in range(6):
        drop = rng.random(len(links)) < 0.2
        if step == 3:  # only the newest links (a drag removes its object's)
            drop[: len(links) * 9 // 10] = False
        plain = _remove_then_extend(
            links, plain, drop, rng, (lambda k: rng.integers(-1, 2**40, k)) if step % 2 else None
        )
    assert len(links) == len(plain[0])
    # the matrix: K·x as the plain sum over the links
    x = rng.random((900, 3))
    want = np.zeros((900, 3))
    np.add.at(want, plain[0], (plain[2] * plain[3])[:, None] * x[plain[1]])
    np.testing.assert_allclose(links.matrix(900) @ x, want, rtol=1e-12, atol=1e-12)
    # the solver's operator: the same sums in the same order as the CSR product, so the same bits
    np.testing.assert_array_equal(links.gather_operator(900) @ x, links.matrix(900) @ x)
    np.testing.assert_array_equal(links.gather_operator(900) @ x[:, 0], links.matrix(900) @ x[:, 0])


def test_the_gather_split_by_receivers_gives_the_products_bits(rng, monkeypatch):
    """LinkGather's threads each sum a range of receivers: any number of ranges gives the CSR
    product's bits (each row in link order), and the ranges cover every receiver once."""
    from illusio.radiosity import links as module

    monkeypatch.setattr(module, "LINKS_PER_RANGE", 100)
    n, m = 700, 20_000
    links = Links(rng.integers(0, n, m), rng.integers(0, n, m), rng.random(m), rng.random(m))
    x = rng.random((n, 3))
    want = links.matrix(n) @ x
    weight = links.form_factor * links.visibility
    for ranges in (1, 2, 3, 8):
        bounds = module.receiver_ranges(links.receiver, n, ranges)
        assert len(bounds) == ranges + 1 and bounds[0] == 0 and bounds[-1] == n
        assert np.all(np.diff(bounds) >= 0)
        out = np.zeros((n, 3))
        module._scatter_gather(links.receiver, links.source, weight, x, out, bounds)
        np.testing.assert_array_equal(out, want)


def test_pairs_with_a_new_object_equal_the_unique_pairs(rng):
    """dynamic._pairs_with (built sorted) equals np.unique over both directions' pairs."""
    from illusio.radiosity.dynamic import _pairs_with

    for _ in range(50):
        others = np.unique(rng.integers(0, 400, int(rng.integers(1, 60))))
        roots = np.sort(rng.choice(others, int(rng.integers(1, len(others) + 1)), replace=False))
        recv = np.r_[np.repeat(roots, len(others)), np.repeat(others, len(roots))]
        src = np.r_[np.tile(others, len(roots)), np.tile(roots, len(others))]
        want = np.unique(np.c_[recv, src], axis=0)
        got = np.c_[_pairs_with(others, roots)]
        np.testing.assert_array_equal(got, want)


def test_facing_pairs_equal_the_numpy_facing_test(rng):
    """formfactor.facing_pairs (numba, by index) equals formfactor.facing on gathered corners, on random
    quads some of which share a plane or straddle one."""
    from illusio.radiosity.formfactor import facing, facing_pairs

    n = 300
    centre = rng.uniform(-1, 1, (n, 3))
    centre[: n // 3, 1] = 0.0  # a third on one plane (the floor)
    normal = rng.normal(size=(n, 3))
    normal[: n // 3] = (0, 1, 0)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    u = np.cross(normal, rng.normal(size=(n, 3)))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    v = np.cross(normal, u)
    size = rng.uniform(0.05, 0.8, (n, 1))
    corners = centre[:, None] + size[:, None] * (
        np.array([-1, 1, 1, -1])[None, :, None] * u[:, None] + np.array([-1, -1, 1, 1])[None, :, None] * v[:, None]
    )
    recv, src = rng.integers(0, n, 4000), rng.integers(0, n, 4000)
    want = facing(corners[recv], normal[recv], centre[recv], corners[src], normal[src], centre[src])
    got = facing_pairs(corners, normal, centre, recv, src)
    some, every = want
    assert 0 < some.sum() < len(recv) and (some & ~every).any() and (some & every).any()
    np.testing.assert_array_equal(got[0], want[0])
    np.testing.assert_array_equal(got[1], want[1])


def test_a_link_is_36_bytes_and_keeps_element_indices_to_two_billion(rng):
    """Receiver, source and tag in 32 bits, F, V and the kept rays in 64: 36 bytes a link (the Graz
    office at RenderPark's element count holds 2.9M element links); indices up to 2³¹ − 1 come back."""
    n = 1000
    receiver = rng.integers(0, 2**31 - 1, n)
    receiver[0] = 2**31 - 1
    links = Links(receiver, receiver[::-1], rng.random(n), rng.random(n), rays=rng.integers(-1, 2**40, n))
    links.tag = rng.integers(-1, 2**31 - 1, n)
    assert links.item_bytes() == 36
    np.testing.assert_array_equal(links.receiver, receiver)
    np.testing.assert_array_equal(links.source, receiver[::-1])


def test_a_builds_links_store_no_tags_or_rays_until_one_has_them(rng):
    """A build's links have neither (24 bytes a link): they read as -1 through removals and growth;
    the first rays or tag stored start their column with -1 for the links before, kept aligned."""
    n = 3000
    columns = [rng.integers(0, 900, n), rng.integers(0, 900, n), rng.random(n), rng.random(n)]
    links = Links(*columns)
    plain = columns + [np.full(n, -1), np.full(n, -1)]
    for step in range(5):
        drop = rng.random(len(links)) < 0.2
        plain = _remove_then_extend(
            links, plain, drop, rng, lambda k: rng.integers(-1, 2**40, k) if step >= 2 else np.full(k, -1)
        )
        if step == 3:
            plain[4] = rng.integers(-1, 50, len(links))
            links.tag = plain[4]
        assert links.item_bytes() == 24 + 8 * (step >= 2) + 4 * (step >= 3)
        _assert_columns(links, plain)
        kept = plain[0] < 450
        _assert_columns(links.take(kept), plain, kept)


def test_channel_max_is_the_largest_channel_of_each_row(rng):
    """refine.channel_max (a numba pass over the rows) against NumPy's max over the channels, on
    float64 and float32 rows and on a view of the first rows of a larger buffer (the hierarchy's
    fields are such views)."""
    from illusio.radiosity.refine import channel_max

    buffer = rng.random((3000, 3)) * rng.choice([0.0, 1.0, 1e3], (3000, 3))
    for rgb in (buffer, buffer.astype(np.float32), buffer[:1234], buffer[:0]):
        out = channel_max(rgb)
        assert out.dtype == np.float64 and out.shape == (len(rgb),)
        np.testing.assert_array_equal(out, rgb.max(axis=1))
