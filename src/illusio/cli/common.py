"""Pieces every command uses: size parsing, scene resolution, progress bars."""

from __future__ import annotations

import sys
from contextlib import contextmanager
from pathlib import Path

from ..core.errors import InputError
from ..scene.builtin import SCENES, SHAPES, shape, turntable
from ..scene.loader import load_scene
from ..scene.mesh import MESH_FORMATS, load_mesh
from ..scene.scene import Scene

__all__ = ["parse_size", "resolve_scene", "progress", "scene_inputs"]


def parse_size(text: str) -> tuple[int, int]:
    """'1920x1080' -> (1920, 1080)."""
    try:
        w, h = (int(v) for v in text.lower().replace("×", "x").split("x"))
    except ValueError:
        raise InputError(f"--size must look like 1920x1080, got {text!r}") from None
    if not (1 <= w <= 8192 and 1 <= h <= 8192):
        raise InputError(f"--size {w}x{h} is out of range (1..8192 per side)")
    return w, h


def resolve_scene(source: str) -> Scene:
    """A built-in scene, a YAML scene file, a mesh file or a built-in shape (on the turntable)."""
    if source in SCENES or Path(source).suffix.lower() in (".yaml", ".yml"):
        return load_scene(source)
    if source in SHAPES:
        return turntable(shape(source))
    if Path(source).suffix.lower() in MESH_FORMATS:
        return turntable(load_mesh(source))
    if not Path(source).exists():
        raise InputError(f"{source}: no such file, and not a built-in scene ({', '.join(SCENES)}) or shape ({', '.join(SHAPES)})")
    raise InputError(f"{source}: not a scene (.yaml) or mesh ({', '.join(MESH_FORMATS)})")


def scene_inputs(source: str) -> list[str]:
    """Files a command reads for ``source`` (to refuse writing over them)."""
    return [source] if Path(source).exists() else []


@contextmanager
def progress(total: int, description: str):
    """A rich progress bar on a terminal; nothing when output is piped. Yields advance()."""
    if not sys.stderr.isatty():
        yield lambda n=1: None
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                  TimeElapsedColumn(), transient=True) as bar:
        task = bar.add_task(description, total=total)
        yield lambda n=1: bar.advance(task, n)
