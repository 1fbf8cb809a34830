"""Procedural built-in content: shapes, textures and scenes (no data files)."""

from .scenes import SCENES, builtin_scene, turntable
from .shapes import SHAPES, shape

__all__ = ["SCENES", "SHAPES", "builtin_scene", "shape", "turntable"]
