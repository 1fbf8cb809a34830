"""Embree's ray queries over the cores: a batch cut into one slice per thread.

embreex releases the GIL while it traces a batch, so slices run side by side; each ray's answer
does not depend on the slice it ran in, so the result is the one call's, bit for bit (tested).
Small batches run in one call, where a thread's hand-over would cost more than it saves.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

__all__ = ["cast", "commit", "ray_threads"]

#: rays a thread takes at least (a hand-over costs ~50 µs; a ray ~80 ns in the scenes measured)
MIN_RAYS_PER_THREAD = 4096

_pools: dict[int, ThreadPoolExecutor] = {}


def ray_threads() -> int:
    """The threads a batch is cut into: the cores this process may run on, or
    ``ILLUSIO_RAY_THREADS`` (1: every batch in one call)."""
    override = os.environ.get("ILLUSIO_RAY_THREADS")
    if override:
        return max(1, int(override))
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def commit(scene) -> None:
    """Build ``scene``'s tree now (the first query does: before queries run on several threads)."""
    if not scene.is_committed:
        empty = np.zeros((0, 3), np.float32)
        scene.run(empty, empty)


def cast(scene, origins: np.ndarray, directions: np.ndarray, dists: np.ndarray | None = None, query: str | None = None):
    """``scene.run`` over threads. ``query="OCCLUDED"``: int32 (n,), negative where the segment of
    length ``dists`` (metres along the unit ``directions``) is clear. Otherwise the first hits (up to
    ``dists`` if given), as Embree's dict of arrays (u, v, Ng, tfar, primID −1 for none, geomID).
    ``origins``, ``directions`` (n, 3), ``dists`` (n,): float32 (converted if not)."""
    origins = np.ascontiguousarray(origins, np.float32)
    directions = np.ascontiguousarray(directions, np.float32)
    if dists is not None:
        dists = np.ascontiguousarray(dists, np.float32)
    n = len(origins)

    def run(part: slice):
        kw = {} if dists is None else {"dists": dists[part]}
        kw.update({"query": query} if query is not None else {"output": 1})
        return scene.run(origins[part], directions[part], **kw)

    threads = min(ray_threads(), n // MIN_RAYS_PER_THREAD)
    if threads <= 1:
        return run(slice(0, n))
    commit(scene)  # once, before the threads
    pool = _pools.get(threads) or _pools.setdefault(threads, ThreadPoolExecutor(threads, "illusio-rays"))
    bounds = np.linspace(0, n, threads + 1).astype(np.int64)
    parts = list(pool.map(run, [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:])]))
    if query is not None:
        return np.concatenate([np.asarray(p) for p in parts])
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}
