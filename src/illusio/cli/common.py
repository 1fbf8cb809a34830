"""Pieces every command uses: size parsing, scene resolution, progress bars."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import typer

from ..core.errors import InputError
from ..core.gl import check_size
from ..scene.sources import SCENE_RULE, resolve_mesh, resolve_scene

__all__ = [
    "parse_size",
    "resolve_scene",
    "resolve_mesh",
    "progress",
    "scene_inputs",
    "SCENE_HELP",
    "on_turntable_option",
]

#: what a command's SCENE argument accepts, the scene-or-shape rule included
SCENE_HELP = (
    "a built-in scene, a scene file (.gltf, .glb, .obj with its .mtl, .yaml, .mgf), a mesh file or a built-in "
    "shape; " + SCENE_RULE
)


def on_turntable_option():
    """The ``--on-turntable`` switch: read a glTF or OBJ scene file as one shape on the turntable."""
    return typer.Option(
        False, "--on-turntable/--as-scene", help="read a scene file as one merged shape on the turntable"
    )


def parse_size(text: str) -> tuple[int, int]:
    """'1920x1080' -> (1920, 1080)."""
    try:
        w, h = (int(v) for v in text.lower().replace("×", "x").split("x"))
    except ValueError:
        raise InputError(f"--size must look like 1920x1080, got {text!r}") from None
    try:
        return check_size((w, h))
    except InputError as exc:
        raise InputError(f"--size: {exc}") from None


def scene_inputs(source: str) -> list[str]:
    """Files a command reads for ``source`` (to refuse writing over them)."""
    return [source] if Path(source).exists() else []


@contextmanager
def progress(total: int, description: str):
    """A counted phase of the command (core.progress: a bar on a terminal, a line in a log, nothing
    with --quiet). Yields advance(n=1)."""
    from ..core.progress import phase

    with phase(description, total) as advance:
        yield advance


def parse_eye_target(text: str) -> tuple[tuple[float, ...], tuple[float, ...]] | None:
    """``x,y,z:x,y,z`` → (eye, target) in metres, or None when ``text`` is not of that form."""
    eye, sep, target = text.partition(":")
    try:
        e, t = tuple(float(v) for v in eye.split(",")), tuple(float(v) for v in target.split(","))
    except ValueError:
        return None
    return (e, t) if sep and len(e) == 3 and len(t) == 3 else None


def parse_view_angles(text: str) -> tuple[float, float]:
    """``AZ,EL`` in degrees (azimuth about +y from +z toward +x, elevation up from the horizon)."""
    try:
        az, el = (float(v) for v in text.split(","))
    except ValueError:
        raise InputError(f"--view takes AZ,EL in degrees (e.g. 30,20), got {text!r}") from None
    if not -90 < el < 90:
        raise InputError(f"--view elevation must be in ]-90, 90[ degrees, got {el:g}")
    return az, el
