"""What a command or the viewer accepts as a scene or a mesh: a built-in name or a file."""

from __future__ import annotations

from pathlib import Path

from ..core.errors import InputError, did_you_mean
from .builtin import SCENES, SHAPES, shape, turntable
from .loader import load_scene
from .mesh import MESH_FORMATS, Mesh, load_mesh
from .scene import Scene
from .scene_file import is_scene_file, load_scene_file

__all__ = ["SCENE_RULE", "resolve_scene", "resolve_mesh", "is_mesh_source", "scene_subject", "mesh_subject"]


#: the one rule, as ``--help`` and the docs state it
SCENE_RULE = (
    "a glTF or OBJ file with more than one mesh node, or any material, light or camera, is a scene (its "
    "own lights and cameras); any other mesh file is a shape on the turntable (--on-turntable forces that)"
)


def is_mesh_source(source: str, turntable: bool = False) -> bool:
    """Whether ``source`` names a single mesh (a built-in shape, or a mesh file that is not a scene
    by :data:`SCENE_RULE`, or any mesh file with ``turntable``) rather than a scene."""
    if source in SHAPES:
        return True
    return Path(source).suffix.lower() in MESH_FORMATS and (turntable or not is_scene_file(source))


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


def resolve_scene(source: str, on_turntable: bool = False) -> Scene:
    """A built-in scene, a YAML or MGF scene file, a glTF or OBJ scene file (:data:`SCENE_RULE`), or
    a mesh file or built-in shape on the turntable (any mesh file with ``on_turntable``)."""
    if source in SCENES or Path(source).suffix.lower() in (".yaml", ".yml", ".mgf"):
        return load_scene(source)
    if is_mesh_source(source, on_turntable):
        return turntable(resolve_mesh(source))
    if is_scene_file(source):
        return load_scene_file(source)
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
