"""One worker thread for the work an edit runs beside its own (a moved object's shafts recast while
its own links are made: radiosity.dynamic).

The worker's heavy parts are numba kernels compiled ``nogil`` and Embree's rays, which release the
GIL, so the two threads share the cores. numba's parallel kernels may then run on both threads at
once: the omp and tbb threading layers allow it, workqueue aborts the process — there the work runs
at once, on the caller's thread.
"""

from __future__ import annotations

import os
from concurrent.futures import Future, ThreadPoolExecutor

import numba

__all__ = ["submit", "threads_safe"]

_worker: ThreadPoolExecutor | None = None


def _forget_worker() -> None:
    global _worker
    _worker = None  # a forked child has none of its parent's threads: it starts its own


os.register_at_fork(after_in_child=_forget_worker)


def threads_safe() -> bool:
    """Can numba's parallel kernels run on two threads at once? (omp and tbb can; workqueue aborts;
    before any parallel kernel has run, the layer is not chosen yet: no)"""
    try:
        return numba.threading_layer() in ("omp", "tbb")
    except ValueError:
        return False


def submit(fn, *args) -> Future:
    """``fn(*args)`` on the worker thread, or at once where :func:`threads_safe` says no (the
    future then holds its result or its exception)."""
    global _worker
    if threads_safe():
        if _worker is None:
            _worker = ThreadPoolExecutor(1, "illusio-background")
        return _worker.submit(fn, *args)
    done: Future = Future()
    try:
        done.set_result(fn(*args))
    except BaseException as error:  # handed to whoever asks the future, as the worker's would be
        done.set_exception(error)
    return done
