"""Running one task: the illusio command itself, in this process (no subprocess), with its output
under the job's out folder. The process keeps its GL context and the renderers the commands keep on
it (``core.context.default_context``), so the second task of a worker starts warm."""

from __future__ import annotations

import contextlib
import io
import os
import socket
import time
from pathlib import Path

from ..core.errors import IllusioError
from ..core.lazy import load
from .job import APP, Task

#: how the app reads a command line (aliases joined): see :data:`job.APP`
EXPAND = "illusio.cli.main:expand"

__all__ = ["run_task", "TaskFailed", "worker_name"]


class TaskFailed(Exception):
    """A task ended in an error: ``message`` is its one line."""


def worker_name() -> str:
    return f"{socket.gethostname()}:{os.getpid()}"


def run_task(task: Task, out_dir: str) -> tuple[str, float, str]:
    """Run ``task`` writing into ``out_dir``; returns (output path, seconds, worker). Raises TaskFailed."""
    import typer

    app, expand = load(APP), load(EXPAND)

    output = Path(out_dir) / task.output
    output.parent.mkdir(parents=True, exist_ok=True)
    argv = expand(list(task.argv) + ["-o", str(output)])
    start = time.perf_counter()
    quiet = io.StringIO()
    try:
        with contextlib.redirect_stdout(quiet):
            typer.main.get_command(app).main(args=argv, standalone_mode=False, prog_name="illusio")
    except IllusioError as exc:
        raise TaskFailed(exc.one_line()) from None
    except Exception as exc:  # a usage error (typer's click), or a bug in a command: reported, the batch goes on
        message = exc.format_message() if hasattr(exc, "format_message") else f"{type(exc).__name__}: {exc}"
        raise TaskFailed(" ".join(message.split())) from None
    if not output.exists():
        raise TaskFailed(f"{' '.join(task.argv[:2])} wrote no {task.output}")
    return str(output), time.perf_counter() - start, worker_name()
