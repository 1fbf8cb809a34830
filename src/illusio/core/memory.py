"""Handing freed memory back to the system between the phases of a long computation.

glibc's allocator keeps the pages of freed blocks smaller than its mmap threshold (which rises to
32 MB once a block that large is freed) for the process to reuse; NumPy's arrays of a few MB — a
refinement batch's samples and rays — are such blocks. Between phases whose working sets differ
(the radiosity build's refinement, then its solve) those kept pages only add to the peak: the Graz
office's build at RenderPark's element count ends holding 0.22 GB freed but kept
(benchmarks/RESULTS.md, "Its memory"). ``malloc_trim(0)`` gives them back; it costs a few ms, so it
is called between phases, never inside a loop."""

from __future__ import annotations

import ctypes
import functools

__all__ = ["release_free_heap"]


@functools.cache
def _malloc_trim():
    """glibc's malloc_trim, or None (musl, macOS, Windows: nothing of the kind to call)."""
    try:
        libc = ctypes.CDLL(None)  # the C library the interpreter is linked with
    except (OSError, TypeError):  # Windows: no process-wide handle (LoadLibrary wants a name)
        return None
    trim = getattr(libc, "malloc_trim", None)
    if trim is not None:
        trim.argtypes, trim.restype = [ctypes.c_size_t], ctypes.c_int
    return trim


def release_free_heap() -> bool:
    """Return the heap's free pages to the system (glibc's ``malloc_trim(0)``). True where it ran
    (glibc), False where the C library has no such call; the memory in use is untouched."""
    trim = _malloc_trim()
    if trim is None:
        return False
    trim(0)
    return True
