"""Whether numba's kernels are compiled yet, so a first run can say that it is compiling them.

numba compiles a kernel on its first call and, with ``cache=True``, writes the machine code beside
the source (or under ``NUMBA_CACHE_DIR``); later processes load it in milliseconds. The first run
after an install pays the compilation (the curvature kernels: about a minute on 2 cores) and would
otherwise be silent: :func:`compile_note` names it, with its expected time, in the phase around
the first call.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["cached_on_disk", "compile_note"]


def cached_on_disk(*kernels) -> bool:
    """Whether every one of ``kernels`` (numba dispatchers with ``cache=True``) has its compiled
    code on disk (numba's index file where this process would look for it). A dispatcher without
    a disk cache, or not a numba dispatcher, counts as cached: nothing to say about it."""
    for kernel in kernels:
        cache = getattr(kernel, "_cache", None)
        index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
        if index is not None and not kernel.signatures and not Path(index).is_file():
            return False
    return True


def compile_note(what: str, seconds: float, *kernels) -> str:
    """ "" when ``kernels`` are compiled (in this process or on disk), else the words a phase adds:
    " (compiling WHAT, once: about N s; later runs load them)"."""
    if cached_on_disk(*kernels):
        return ""
    return f" (compiling {what}, once: about {seconds:.0f} s; later runs load them)"
