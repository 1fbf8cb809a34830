"""A prepared relighting session saved to one file and loaded back (``illusio relight prepare``), so
later edits start at once instead of redoing the estimates, the refinement and the texture work.

The file is a NumPy ``.npz`` archive read with ``allow_pickle=False``: arrays (the photograph, the
model's and the solution's polygons, the hierarchy's fields, the links, the textures, the display
factor, the lamps' basis) and one JSON record (format version, parameters, camera, names, scales).
Nothing in it is executed on load; a file of another version or with missing or misshapen arrays is
refused with the name of what is wrong."""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..core.errors import InputError
from ..core.files import load_npz
from ..core.images import atomic_output
from ..radiosity import HierarchyParams, Polygons
from ..radiosity.display import LeafMesh
from ..radiosity.engine import Radiosity
from ..radiosity.hierarchy import FIELDS as HIERARCHY_FIELDS
from ..radiosity.hierarchy import Hierarchy
from ..radiosity.links import Links
from ..scene.camera import Camera, Pose, View
from .params import RelightParams
from .photograph import RealScene

__all__ = ["save_session", "load_session", "FORMAT"]

#: the "format" field of a saved session's record
FORMAT = "illusio-relight-session/1"
_POLYGON_ARRAYS = ("corners", "triangle", "reflectance", "exitance", "group")
_SESSION_ARRAYS = (
    "pixel_polygon",
    "pixel_element",
    "texture",
    "texture_factor",
    "corner_d",
    "has_d",
    "mean_scene",
    "mean_reflectance",
)
_PER_PIXEL_ARRAYS = ("pixel_seen", "lamp_rows", "pixel_lamp", "pixel_indirect")
_MESH_ARRAYS = ("positions", "radiance", "corner", "element", "faces", "face_element")


def _polygons_out(prefix: str, p: Polygons, arrays: dict, record: dict) -> None:
    for name in _POLYGON_ARRAYS:
        arrays[f"{prefix}.{name}"] = np.asarray(getattr(p, name))
    record[prefix] = {"names": list(p.names), "lamps": [int(g) for g in p.lamps]}


def _polygons_in(prefix: str, arrays, record) -> Polygons:
    return Polygons(
        *(arrays[f"{prefix}.{name}"] for name in _POLYGON_ARRAYS),
        list(record[prefix]["names"]),
        [int(g) for g in record[prefix]["lamps"]],
    )


def save_session(session, path) -> Path:
    """Write ``session`` (a prepared RelightSession) to ``path`` (.npz), atomically."""
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise InputError(f"a prepared session is saved as .npz, got {path.name}")
    basis = session.lamp_basis()  # the lamps' basis, saved so edits start at once
    session.inherit_display_factor()  # per-element arrays cover elements made by edits
    sol = session.solution
    arrays: dict[str, np.ndarray] = {"photograph": session.real.photograph}
    record = {
        "format": FORMAT,
        "params": dataclasses.asdict(session.params),
        "view": dataclasses.asdict(session.real.view),
        "scales": session.scales,
        "virtual_groups": sorted(int(g) for g in session.virtual_groups),
        "times": session.times,
    }
    _polygons_out("real", session.real.polygons, arrays, record)
    _polygons_out("model", session.model, arrays, record)
    _polygons_out("solution", sol.polygons, arrays, record)
    record["solution_params"] = dataclasses.asdict(sol.params)
    # where the visibility's ray sampling stands, so that edits after loading sample as they would have
    record["visibility_rng"] = sol.visibility.rng.bit_generator.state
    for name, a in sol.hierarchy.arrays().items():
        arrays[f"hierarchy.{name}"] = a
    for name in ("receiver", "source", "form_factor", "visibility"):
        arrays[f"links.{name}"] = getattr(sol.links, name)
    arrays["lamp_scale"] = sol.lamp_scale
    for name in _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if session.params.method == "per-pixel" else ()):
        arrays[f"session.{name}"] = np.asarray(getattr(session, name))
    if basis is not None:
        key, responses, mesh = basis
        arrays["basis"] = np.stack(responses) if responses else np.zeros((0,) + mesh.radiance.shape)
        for name in _MESH_ARRAYS:
            arrays[f"basis_mesh.{name}"] = getattr(mesh, name)
        record["basis_key"] = [int(key[0]), int(key[1]), list(key[2])]
    arrays["record"] = np.array(json.dumps(record))
    with atomic_output(path) as tmp, open(tmp, "wb") as f:
        np.savez_compressed(f, **arrays)
    return path


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


def _check_arrays(path: Path, arrays: dict, record: dict) -> None:
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


def load_session(path) -> dict:
    """What a file written by :func:`save_session` holds, by the RelightSession's public names, and
    ``basis`` (the lamps' basis: key, responses, mesh, or None): ``RelightSession.load`` makes the
    session from them (this module does not know the class)."""
    path = Path(path)
    start = time.perf_counter()
    arrays = load_npz(path, "saved relighting session")
    try:
        record = json.loads(str(arrays["record"]))
        if not isinstance(record, dict):
            raise InputError(f"{path}: not a saved relighting session (its record is not an object)")
        if record.get("format") != FORMAT:
            raise InputError(f"{path}: saved as {record.get('format')!r}, this illusio reads {FORMAT!r}")
        _check_arrays(path, arrays, record)
        # a session saved before these knobs existed was prepared as the chapter has it
        p = {"estimate": "brightness", "reference_weight": "full", **record["params"]}
        params = RelightParams(
            **{
                **p,
                "hierarchy": HierarchyParams(**{"clusters": False, **p["hierarchy"]}),
                "final_hierarchy": HierarchyParams(**{"clusters": False, **p["final_hierarchy"]}),
                "lamp_scales": tuple(tuple(x) for x in p["lamp_scales"]),
            }
        )
        v = record["view"]
        view = View(Pose(**v["pose"]), Camera(**{**v["camera"], "shift": tuple(v["camera"]["shift"])}))
        real = RealScene(_polygons_in("real", arrays, record), view, arrays["photograph"])
        solution_polygons = _polygons_in("solution", arrays, record)
        hierarchy = Hierarchy.from_arrays(
            solution_polygons, {k.split(".", 1)[1]: a for k, a in arrays.items() if k.startswith("hierarchy.")}
        )
        links = Links(*(np.asarray(arrays[f"links.{n}"]) for n in ("receiver", "source", "form_factor", "visibility")))
        if len(links) and (links.receiver.max() >= len(hierarchy) or links.source.max() >= len(hierarchy)):
            raise InputError(f"{path}: a link names an element the saved hierarchy does not have")
        sol = Radiosity.from_state(
            solution_polygons,
            HierarchyParams(**{"clusters": False, **record["solution_params"]}),
            hierarchy,
            links,
            arrays["lamp_scale"],
        )
        if "visibility_rng" in record:
            sol.visibility.rng.bit_generator.state = record["visibility_rng"]
        s = SimpleNamespace(
            real=real,
            params=params,
            model=_polygons_in("model", arrays, record),
            solution=sol,
            hierarchy_params=sol.params,
            basis=None,
        )
        names = _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if params.method == "per-pixel" else ())
        for name in names:
            setattr(s, name, arrays[f"session.{name}"])
        if s.pixel_element.shape != real.photograph.shape[:2] or s.texture.shape != real.photograph.shape:
            raise InputError(f"{path}: the saved maps do not match the photograph's size")
        s.scales = {k: float(x) for k, x in record["scales"].items()}
        s.virtual_groups = {int(g) for g in record["virtual_groups"]}
        s.times = {k: float(x) for k, x in record["times"].items()}
        if "basis_key" in record:
            saved = record["basis_key"]
            s.basis = (
                (int(saved[0]), int(saved[1]), tuple(saved[2])),
                list(arrays["basis"]),
                LeafMesh(*(arrays[f"basis_mesh.{n}"] for n in _MESH_ARRAYS)),
            )
    except KeyError as exc:
        raise InputError(f"{path}: not a saved relighting session (no {exc.args[0]!r})") from None
    except (TypeError, ValueError, AttributeError, IndexError) as exc:  # a field of the wrong type or shape
        raise InputError(f"{path}: a saved relighting session with a bad field ({exc})") from None
    s.times["load"] = time.perf_counter() - start
    return vars(s)
