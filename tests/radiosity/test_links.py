"""Links edited in place (numba compaction, growable buffers) equal the plain NumPy masks and
concatenations, tags included, over random edits."""

import numpy as np

from illusio.radiosity.links import Links


def test_in_place_edits_equal_masks_and_concatenation(rng):
    n = 5000
    columns = [rng.integers(0, 900, n), rng.integers(0, 900, n), rng.random(n), rng.random(n)]
    links = Links(*columns)
    links.tag = rng.integers(-1, 50, n)
    plain = columns + [links.tag.copy()]
    for _ in range(6):
        drop = rng.random(len(links)) < 0.2
        gone = links.remove(drop)
        for name, column in zip(("receiver", "source", "form_factor", "visibility", "tag"), plain):
            np.testing.assert_array_equal(getattr(gone, name), column[drop])
        plain = [column[~drop] for column in plain]
        k = int(rng.integers(0, 3000))
        new = [rng.integers(0, 900, k), rng.integers(0, 900, k), rng.random(k), rng.random(k)]
        links.extend(*new)
        plain = [np.concatenate([p, c]) for p, c in zip(plain, new + [np.full(k, -1)])]
        for name, column in zip(("receiver", "source", "form_factor", "visibility", "tag"), plain):
            np.testing.assert_array_equal(getattr(links, name), column)
    assert len(links) == len(plain[0])
    # the matrix by counting sort: K·x as the plain sum over the links
    x = rng.random((900, 3))
    want = np.zeros((900, 3))
    np.add.at(want, plain[0], (plain[2] * plain[3])[:, None] * x[plain[1]])
    np.testing.assert_allclose(links.matrix(900) @ x, want, rtol=1e-12, atol=1e-12)
