"""The checks a saved relighting session passes before anything in it is used (relight.state): every
array's dtype kind and shape against what save_session writes, sizes that agree between arrays,
finite floats, indices in range."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..radiosity import HIERARCHY_FIELDS

__all__ = ["check_arrays"]


# every array save_session writes: its dtype kind (f float, i integer, b bool) and shape, in the
# sizes H×W (photograph), P_real, P_model, P (solution polygons), G (groups), n (elements), L
# (links), K (lamp rows), S (pixels seen), N (lamps), V and F (the basis mesh's vertices and faces)
_SCHEMA = {
    "photograph": ("f", ("H", "W", 3)),
    "lamp_scale": ("f", ("G",)),
    **{
        f"{prefix}.{name}": (kind, (size,) + tail)
        for prefix, size in (("real", "P_real"), ("model", "P_model"), ("solution", "P"))
        for name, kind, tail in (
            ("corners", "f", (4, 3)),
            ("triangle", "b", ()),
            ("reflectance", "f", (3,)),
            ("exitance", "f", (3,)),
            ("group", "i", ()),
        )
    },
    **{
        f"hierarchy.{name}": ("b" if dtype is bool else np.dtype(dtype).kind, ("n",) + shape)
        for name, (shape, dtype) in HIERARCHY_FIELDS.items()
    },
    "hierarchy.roots": ("i", ("P",)),
    **{
        f"links.{name}": (kind, ("L",))
        for name, kind in (("receiver", "i"), ("source", "i"), ("form_factor", "f"), ("visibility", "f"))
    },
    "session.pixel_polygon": ("i", ("H", "W")),
    "session.pixel_element": ("i", ("H", "W")),
    "session.texture": ("f", ("H", "W", 3)),
    "session.texture_factor": ("f", ("n", 3)),
    "session.corner_d": ("f", ("n", 4, 3)),
    "session.has_d": ("b", ("n",)),
    "session.mean_scene": ("f", (3,)),
    "session.mean_reflectance": ("f", (3,)),
    "session.pixel_seen": ("b", ("H", "W")),
    "session.lamp_rows": ("i", ("K",)),
    "session.pixel_lamp": ("f", ("S", "K", 3)),
    "session.pixel_indirect": ("f", ("S", 3)),
    "basis": ("f", ("N", "V", 3)),
    "basis_mesh.positions": ("f", ("V", 3)),
    "basis_mesh.radiance": ("f", ("V", 3)),
    "basis_mesh.corner": ("f", ("V", 3)),
    "basis_mesh.element": ("f", ("V",)),
    "basis_mesh.faces": ("i", ("F", 3)),
    "basis_mesh.face_element": ("i", ("F",)),
}
# integer (and element) arrays that index others: name → (least, bound); a bound names a size above
# (the quadtree's own links, parent, child and roots, are checked by Hierarchy.from_arrays)
_INDEX = {
    "hierarchy.polygon": (0, "P"),
    "links.receiver": (0, "n"),
    "links.source": (0, "n"),
    "session.pixel_polygon": (-1, "P_model"),
    "session.pixel_element": (-1, "n"),
    "session.lamp_rows": (0, "P_model"),
    "basis_mesh.element": (0, "n"),
    "basis_mesh.face_element": (0, "n"),
    "basis_mesh.faces": (0, "V"),
}


def check_arrays(path: Path, arrays: dict, record: dict) -> None:
    """Refuse a session whose arrays cannot be what save_session wrote: a wrong dtype or shape,
    sizes that disagree between arrays, non-finite floats, indices out of range. (The gather and
    the ray caster index without bounds checks: a bad index would crash, not raise.)"""
    sizes = {"G": len(record["solution"]["names"])}
    for name, a in arrays.items():
        if name not in _SCHEMA:
            continue
        kind, shape = _SCHEMA[name]
        if a.dtype.kind != kind and not (kind == "i" and a.dtype.kind == "u"):
            raise InputError(f"{path}: saved array {name} has dtype {a.dtype}, expected kind {kind!r}")
        if a.ndim != len(shape):
            raise InputError(f"{path}: saved array {name} has shape {a.shape}, expected {len(shape)} axes")
        for axis, (size, want) in enumerate(zip(a.shape, shape)):
            if isinstance(want, str):
                want = sizes.setdefault(want, size)
            if size != want:
                raise InputError(f"{path}: saved array {name} has {size} along axis {axis}, other arrays {want}")
        if kind == "f" and not np.isfinite(a).all():
            raise InputError(f"{path}: saved array {name} holds NaN or infinite values")
    for name, (least, bound) in _INDEX.items():
        a = arrays.get(name)
        if a is not None and a.size and (a.min() < least or a.max() >= sizes.get(bound, 0)):
            raise InputError(f"{path}: saved array {name} holds indices outside {least}..{sizes.get(bound, 0) - 1}")
    for prefix in ("real", "model", "solution"):
        names, group = len(record[prefix]["names"]), arrays[f"{prefix}.group"]
        if (group.size and (group.min() < 0 or group.max() >= names)) or any(
            not 0 <= int(g) < names for g in record[prefix]["lamps"]
        ):
            raise InputError(f"{path}: saved {prefix} polygons name groups outside their {names} names")
