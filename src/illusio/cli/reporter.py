"""How the command line shows core.progress: rich's progress bars on a terminal (stderr, gone when
done), a plain line for each phase that took at least a second elsewhere (stdout: CI and logs keep
it beside the command's own lines), nothing with ``--quiet``."""

from __future__ import annotations

import sys

from ..core.progress import Progress

__all__ = ["LineReporter", "TerminalReporter", "reporter"]

#: a finished phase shorter than this is not worth a line in a log
MIN_SECONDS = 1.0


class LineReporter:
    """One line per finished phase of at least MIN_SECONDS: ``illusio: radiosity: refine: 2.1 s``."""

    def __init__(self, stream=None):
        self.stream = stream

    def __call__(self, event: Progress) -> None:
        if not event.finished or event.seconds < MIN_SECONDS:
            return
        steps = f" ({event.done:,} of {event.total:,})" if event.total else ""
        stream = self.stream or sys.stdout
        print(f"illusio: {'  ' * event.depth}{event.phase}{steps}: {event.seconds:.1f} s", file=stream, flush=True)


class TerminalReporter:
    """rich's live progress on stderr: a bar with its ETA for a phase with a total, a spinner and the
    time spent for one without; each removed when it ends."""

    def __init__(self):
        from rich.console import Console
        from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn

        self.bars = Progress(
            SpinnerColumn(),
            TextColumn("{task.description}"),
            BarColumn(),
            TextColumn("{task.completed}/{task.total}"),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
            console=Console(stderr=True),
            transient=True,
        )
        self.tasks: dict[tuple[str, int], int] = {}

    def __call__(self, event: Progress) -> None:
        key = (event.phase, event.depth)
        if event.finished:
            task = self.tasks.pop(key, None)
            if task is not None:
                self.bars.remove_task(task)
            if not self.tasks:
                self.bars.stop()
            return
        if key not in self.tasks:
            if not self.tasks:
                self.bars.start()
            self.tasks[key] = self.bars.add_task("  " * event.depth + event.phase, total=event.total)
        self.bars.update(self.tasks[key], completed=event.done)


def reporter(quiet: bool = False):
    """The listener for this process's output: None with ``quiet``."""
    if quiet:
        return None
    return TerminalReporter() if sys.stderr.isatty() else LineReporter()
