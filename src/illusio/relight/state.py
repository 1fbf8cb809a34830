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
import zipfile
from pathlib import Path

import numpy as np

from ..core.context import Context, default_context
from ..core.errors import InputError
from ..core.images import atomic_output
from ..radiosity import DisplayPass, HierarchyParams, Polygons
from ..radiosity.corner_cache import CornerGather
from ..radiosity.display import LeafMesh
from ..radiosity.hierarchy import Hierarchy
from ..radiosity.links import Links
from ..radiosity.solution import Radiosity
from ..scene.camera import Camera, Pose, View
from .params import RelightParams
from .photograph import RealScene

__all__ = ["save_session", "load_session", "FORMAT"]

#: the "format" field of a saved session's record
FORMAT = "illusio-relight-session/1"
_POLYGON_ARRAYS = ("corners", "triangle", "reflectance", "exitance", "group")
_SESSION_ARRAYS = ("pixel_polygon", "pixel_element", "texture", "texture_factor", "corner_d", "has_d", "mean_scene",
                   "mean_reflectance")
_PER_PIXEL_ARRAYS = ("pixel_seen", "lamp_rows", "pixel_lamp", "pixel_indirect")
_MESH_ARRAYS = ("positions", "radiance", "corner", "element", "faces", "face_element")


def _polygons_out(prefix: str, p: Polygons, arrays: dict, record: dict) -> None:
    for name in _POLYGON_ARRAYS:
        arrays[f"{prefix}.{name}"] = np.asarray(getattr(p, name))
    record[prefix] = {"names": list(p.names), "lamps": [int(g) for g in p.lamps]}


def _polygons_in(prefix: str, arrays, record) -> Polygons:
    return Polygons(*(arrays[f"{prefix}.{name}"] for name in _POLYGON_ARRAYS), list(record[prefix]["names"]),
                    [int(g) for g in record[prefix]["lamps"]])


def save_session(session, path) -> Path:
    """Write ``session`` (a prepared RelightSession) to ``path`` (.npz), atomically."""
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise InputError(f"a prepared session is saved as .npz, got {path.name}")
    session._corner_radiosity()                       # the lamps' basis, saved so edits start at once
    sol = session.solution
    arrays: dict[str, np.ndarray] = {"photograph": session.real.photograph}
    record = {"format": FORMAT, "params": dataclasses.asdict(session.params),
              "view": dataclasses.asdict(session.real.view), "scales": session.scales,
              "virtual_groups": sorted(int(g) for g in session.virtual_groups), "times": session.times}
    _polygons_out("real", session.real.polygons, arrays, record)
    _polygons_out("model", session.model, arrays, record)
    _polygons_out("solution", sol.polygons, arrays, record)
    record["solution_params"] = dataclasses.asdict(sol.params)
    for name, a in sol.hierarchy.arrays().items():
        arrays[f"hierarchy.{name}"] = a
    for name in ("receiver", "source", "form_factor", "visibility"):
        arrays[f"links.{name}"] = getattr(sol.links, name)
    arrays["lamp_scale"] = sol.lamp_scale
    for name in _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if session.params.method == "per-pixel" else ()):
        arrays[f"session.{name}"] = np.asarray(getattr(session, name))
    if getattr(session, "_basis_key", None) is not None:
        arrays["basis"] = np.stack(session._basis) if session._basis else np.zeros((0,) + session._basis_mesh.radiance.shape)
        for name in _MESH_ARRAYS:
            arrays[f"basis_mesh.{name}"] = getattr(session._basis_mesh, name)
        record["basis_key"] = [int(session._basis_key[0]), int(session._basis_key[1]), list(session._basis_key[2])]
    arrays["record"] = np.array(json.dumps(record))
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez_compressed(f, **arrays)
    return path


def load_session(path, ctx: Context | None = None):
    """A RelightSession from a file written by :func:`save_session`."""
    from .session import RelightSession

    path = Path(path)
    start = time.perf_counter()
    try:
        with np.load(path, allow_pickle=False) as archive:
            arrays = {k: archive[k] for k in archive.files}
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise InputError(f"{path}: not a saved relighting session ({exc})") from None
    try:
        record = json.loads(str(arrays["record"]))
        if record.get("format") != FORMAT:
            raise InputError(f"{path}: saved as {record.get('format')!r}, this illusio reads {FORMAT!r}")
        p = dict(record["params"])
        params = RelightParams(**{**p, "hierarchy": HierarchyParams(**p["hierarchy"]),
                                  "final_hierarchy": HierarchyParams(**p["final_hierarchy"]),
                                  "lamp_scales": tuple(tuple(x) for x in p["lamp_scales"])})
        v = record["view"]
        view = View(Pose(**v["pose"]), Camera(**{**v["camera"], "shift": tuple(v["camera"]["shift"])}))
        real = RealScene(_polygons_in("real", arrays, record), view, arrays["photograph"])
        solution_polygons = _polygons_in("solution", arrays, record)
        hierarchy = Hierarchy.from_arrays(solution_polygons, {k.split(".", 1)[1]: a for k, a in arrays.items()
                                                              if k.startswith("hierarchy.")})
        links = Links(*(np.asarray(arrays[f"links.{n}"]) for n in ("receiver", "source", "form_factor", "visibility")))
        if len(links) and (links.receiver.max() >= len(hierarchy) or links.source.max() >= len(hierarchy)):
            raise InputError(f"{path}: a link names an element the saved hierarchy does not have")
        sol = Radiosity.from_state(solution_polygons, HierarchyParams(**record["solution_params"]), hierarchy, links,
                                   arrays["lamp_scale"])
        s = RelightSession.__new__(RelightSession)
        s.real, s.params, s.ctx = real, params, ctx or default_context()
        s.model = _polygons_in("model", arrays, record)
        s.solution, s.renderer = sol, None
        s.hierarchy_params = sol.params
        names = _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if params.method == "per-pixel" else ())
        for name in names:
            setattr(s, name, arrays[f"session.{name}"])
        if s.pixel_element.shape != real.photograph.shape[:2] or s.texture.shape != real.photograph.shape:
            raise InputError(f"{path}: the saved maps do not match the photograph's size")
        s.scales = {k: float(x) for k, x in record["scales"].items()}
        s.virtual_groups = {int(g) for g in record["virtual_groups"]}
        s.times = {k: float(x) for k, x in record["times"].items()}
        s.display = DisplayPass(s.ctx)
        s._gather = CornerGather()
        key = (len(hierarchy), len(links), tuple(sol.lamp_names))
        s._geometry_key = key
        if "basis_key" in record:
            saved = record["basis_key"]
            s._basis_key = (int(saved[0]), int(saved[1]), tuple(saved[2]))
            s._basis = list(arrays["basis"])
            s._basis_mesh = LeafMesh(*(arrays[f"basis_mesh.{n}"] for n in _MESH_ARRAYS))
    except KeyError as exc:
        raise InputError(f"{path}: not a saved relighting session (no {exc.args[0]!r})") from None
    except (TypeError, ValueError) as exc:
        raise InputError(f"{path}: a saved relighting session with a bad field ({exc})") from None
    s.times["load"] = time.perf_counter() - start
    return s
