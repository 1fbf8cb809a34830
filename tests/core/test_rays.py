"""Embree's batches over threads (core.rays.cast): the same answer, ray for ray, as one call."""

import numpy as np
import pytest


@pytest.mark.parametrize("query", ["OCCLUDED", None])
def test_a_batch_cut_over_threads_answers_as_one_call(monkeypatch, rng, query):
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    from illusio.core import rays

    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, rng.uniform(-1, 1, (300, 3, 3)).astype(np.float32))
    n = 5 * rays.MIN_RAYS_PER_THREAD + 17  # cut in uneven slices
    origins = rng.uniform(-1, 1, (n, 3)).astype(np.float32)
    directions = rng.normal(size=(n, 3)).astype(np.float32)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    dists = rng.uniform(0, 1.5, n).astype(np.float32)
    monkeypatch.setenv("ILLUSIO_RAY_THREADS", "3")  # the tree is built by the first query, before the threads
    threaded = rays.cast(scene, origins, directions, dists, query)
    monkeypatch.setenv("ILLUSIO_RAY_THREADS", "1")
    single = rays.cast(scene, origins, directions, dists, query)
    if query:
        assert 0.1 < (np.asarray(single) >= 0).mean() < 0.9  # both answers occur
        np.testing.assert_array_equal(threaded, single)
    else:
        assert set(threaded) == set(single) and 0.1 < (single["primID"] >= 0).mean() < 0.9
        for key in single:
            np.testing.assert_array_equal(threaded[key], single[key])
