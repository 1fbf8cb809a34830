"""What a command or the viewer accepts as a scene or a mesh: a built-in name or a file."""

from __future__ import annotations

from pathlib import Path

from ..core.errors import InputError, did_you_mean
from .builtin import SCENES, SHAPES, shape, turntable
from .loader import load_scene
from .mesh import MESH_FORMATS, Mesh, load_mesh
from .scene import Scene

__all__ = ["resolve_scene", "resolve_mesh", "is_mesh_source", "scene_subject", "mesh_subject"]


def is_mesh_source(source: str) -> bool:
    """Whether ``source`` names a single mesh (a built-in shape or a mesh file) rather than a scene."""
    return source in SHAPES or Path(source).suffix.lower() in MESH_FORMATS


def resolve_mesh(source: str) -> Mesh:
    """A built-in shape or a mesh file."""
    if source in SHAPES:
        return shape(source)
    if Path(source).suffix.lower() in MESH_FORMATS:
        return load_mesh(source)
    if not Path(source).exists():
        raise InputError(
            f"{source}: no such file, and not a built-in shape ({', '.join(SHAPES)}){did_you_mean(source, SHAPES)}"
        )
    raise InputError(f"{source}: not a mesh ({', '.join(MESH_FORMATS)})")


def resolve_scene(source: str) -> Scene:
    """A built-in scene, a YAML scene file, a mesh file or a built-in shape (on the turntable)."""
    if source in SCENES or Path(source).suffix.lower() in (".yaml", ".yml", ".mgf"):
        return load_scene(source)
    if is_mesh_source(source):
        return turntable(resolve_mesh(source))
    if not Path(source).exists():
        raise InputError(
            f"{source}: no such file, and not a built-in scene ({', '.join(SCENES)}) or shape "
            f"({', '.join(SHAPES)}){did_you_mean(source, list(SCENES) + list(SHAPES))}"
        )
    raise InputError(f"{source}: not a scene (.yaml, .mgf) or mesh ({', '.join(MESH_FORMATS)})")


def scene_subject(source: str, size: tuple[int, int], ctx=None) -> Scene:
    """``resolve_scene`` as a technique's subject maker (core.technique: size and ctx unused)."""
    return resolve_scene(source)


def mesh_subject(source: str, size: tuple[int, int], ctx=None) -> Mesh:
    """``resolve_mesh`` as a technique's subject maker (core.technique: size and ctx unused)."""
    return resolve_mesh(source)
