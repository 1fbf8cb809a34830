"""What a long computation is doing: named phases, counted where they can be, reported to whoever
listens.

The library reports and never prints: code that takes long wraps its work in :func:`phase` (and
calls the ``advance`` it yields for each step of a known ``total``). A listener — a callable given
:class:`Progress` events — is installed with :func:`reporting`; with none, a phase costs a clock
read. The command line installs one (``illusio.cli.progress``): rich's progress bars on a terminal,
a plain line per finished phase elsewhere (CI, logs), nothing with ``--quiet``. A Python caller can
pass its own::

    from illusio.core.progress import reporting
    with reporting(lambda event: print(event.phase, event.done, event.total, event.finished)):
        renderer.render(frame, params)

Phases nest (``relight: prepare`` holds ``radiosity: refine``); each event carries its depth. The
times a command reports are those of its phases, so they are the ones it spent.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

__all__ = ["Progress", "install", "phase", "reporting"]


@dataclass(frozen=True)
class Progress:
    """One report. phase: what is being done ("radiosity: refine"); done, total: steps done of
    ``total`` (None: unknown); seconds: since the phase began; finished: the phase's last report;
    depth: 0 for an outermost phase."""

    phase: str
    done: int
    total: int | None
    seconds: float
    finished: bool
    depth: int


_local = threading.local()


def _listeners() -> list[Callable[[Progress], None]]:
    if not hasattr(_local, "listeners"):
        _local.listeners = []
        _local.depth = 0
    return _local.listeners


@contextmanager
def reporting(listener: Callable[[Progress], None] | None) -> Iterator[None]:
    """Send this thread's phases to ``listener`` inside the block (None: to nobody, as ``--quiet``)."""
    listeners = _listeners()
    saved = list(listeners)
    listeners[:] = [] if listener is None else [listener]
    try:
        yield
    finally:
        listeners[:] = saved


def install(listener: Callable[[Progress], None] | None) -> None:
    """Send this thread's phases to ``listener`` from now on (the command line's, for one command)."""
    _listeners()[:] = [] if listener is None else [listener]


@contextmanager
def phase(name: str, total: int | None = None) -> Iterator[Callable[[int], None]]:
    """A phase of work named ``name`` with ``total`` steps (None: unknown); yields ``advance(n=1)``.
    Its listener hears it begin, advance, and end (finished, also when it raises)."""
    listeners = _listeners()
    start = time.perf_counter()
    depth = _local.depth
    done = 0

    def tell(finished: bool) -> None:
        for listener in listeners:
            listener(Progress(name, done, total, time.perf_counter() - start, finished, depth))

    def advance(n: int = 1) -> None:
        nonlocal done
        done += n
        if listeners:
            tell(False)

    if listeners:
        tell(False)
    _local.depth = depth + 1
    try:
        yield advance
    finally:
        _local.depth = depth
        if listeners:
            tell(True)
