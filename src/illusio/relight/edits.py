"""Edits of the scene's geometry (Loscos 4.4.1): a virtual lamp, a virtual object added and moved.
The element methods only: the per-pixel method relights the photograph's own surfaces."""

from __future__ import annotations

import time

import numpy as np

from ..core.errors import InputError
from ..radiosity import (
    Polygons,
    quads_from_triangles,
)
from .corners import geometry_changed
from .params import VIRTUAL_LAMP_SIZE


def require_elements(s, what: str) -> None:
    if not s.strategy.edits_geometry:
        raise InputError(f"{what} is not available with the {s.params.method} method yet; use baseline or loscos")


def add_lamp(
    s, centre, size: float = VIRTUAL_LAMP_SIZE, exitance=(30.0, 30.0, 30.0), name: str = "virtual-lamp"
) -> np.ndarray:
    """A virtual rectangular lamp (size × size m, facing down, exitance W/m² RGB) linked at the
    leaves (Loscos 4.4.1); returns the new image."""
    require_elements(s, "a virtual lamp")
    start = time.perf_counter()
    s.solution.add_lamp(centre, (size, 0, 0), (0, 0, size), exitance, name)
    geometry_changed(s)
    s.virtual_groups.add(s.solution.polygons.names.index(name))
    s.times["add lamp"] = time.perf_counter() - start
    return s.image()


def add_object(s, mesh, name: str, at=(0.0, 0.0, 0.0), reflectance=(0.6, 0.6, 0.6)) -> np.ndarray:
    """A virtual object (a Mesh, its triangles paired into quads where they can be) placed at
    ``at`` (metres); it casts shadows and is shown by its own radiosity; returns the new image."""
    require_elements(s, "a virtual object")
    start = time.perf_counter()
    corners, triangle = quads_from_triangles(
        np.asarray(mesh.vertices, np.float64) + np.asarray(at, np.float64), mesh.faces
    )
    n = len(corners)
    polygons = Polygons(
        corners,
        triangle,
        np.repeat(np.asarray(reflectance, np.float64)[None], n, axis=0),
        np.zeros((n, 3)),
        np.zeros(n, int),
        [name],
    )
    s.solution.add_object(polygons, name)
    geometry_changed(s)
    s.virtual_groups.add(s.solution.polygons.names.index(name))
    s.times["add object"] = time.perf_counter() - start
    return s.image()


def move_object(s, name: str, offset) -> np.ndarray:
    """Move a virtual object by ``offset`` (metres); returns the new image."""
    require_elements(s, "moving an object")
    if name not in s.solution.polygons.names or s.solution.polygons.names.index(name) not in s.virtual_groups:
        raise InputError(f"no virtual object named {name!r}")
    start = time.perf_counter()
    move = np.eye(4)
    move[:3, 3] = offset
    s.solution.move_object(name, move)
    geometry_changed(s)
    s.times["move object"] = time.perf_counter() - start
    return s.image()
