"""A prepared relighting session saved to one file and loaded back (``illusio relight prepare``), so
later edits start at once instead of redoing the estimates, the refinement and the texture work.

The file is a NumPy ``.npz`` archive read with ``allow_pickle=False``: arrays (the photograph, the
model's and the solution's polygons, the hierarchy's fields, the links, the textures, the display
factor, the lamps' basis) and one JSON record (format version, parameters, camera, names, scales).
Nothing in it is executed on load; a file of another version or with missing or misshapen arrays is
refused with the name of what is wrong. The format's version is bumped whenever what is saved
changes; a file of another version is refused with the command that prepares it again."""

from __future__ import annotations

import dataclasses
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..core.errors import InputError
from ..core.files import load_npz
from ..core.images import atomic_output
from ..radiosity import Hierarchy, HierarchyParams, LeafMesh, Links, Polygons, Radiosity
from ..scene.camera import Camera, Pose, View
from .params import RelightParams
from .photograph import RealScene
from .state_checks import check_arrays

__all__ = ["SavedSession", "save_session", "load_session", "FORMAT"]

#: the "format" field of a saved session's record
FORMAT = "illusio-relight-session/2"
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


@dataclass(frozen=True)
class SavedSession:
    """What a prepared RelightSession is saved as, and loaded back into: the photograph and its
    polygons, the estimated model, the solution (hierarchy and links), the session's per-pixel and
    per-element arrays (``arrays``: those of _SESSION_ARRAYS, and _PER_PIXEL_ARRAYS for the per-pixel
    method), the lamps' scales, the virtual groups, the phase times and the lamps' basis (key,
    responses, mesh) or None. ``load_seconds``: how long reading it took (0 when made from a session)."""

    real: RealScene
    params: RelightParams
    model: Polygons
    solution: Radiosity
    arrays: dict[str, np.ndarray]
    scales: dict[str, float]
    virtual_groups: frozenset[int]
    times: dict[str, float]
    basis: Any = None
    load_seconds: float = 0.0

    @classmethod
    def of(cls, session, basis=None) -> SavedSession:
        """The saved form of a prepared ``session`` with its lamps' ``basis`` (lamp_basis())."""
        names = _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if session.params.method == "per-pixel" else ())
        return cls(
            session.real,
            session.params,
            session.model,
            session.solution,
            {name: np.asarray(getattr(session, name)) for name in names},
            dict(session.scales),
            frozenset(session.virtual_groups),
            dict(session.times),
            basis,
        )

    def fields(self) -> dict:
        """The session's attributes this restores, by name."""
        return {
            "real": self.real,
            "params": self.params,
            "model": self.model,
            "solution": self.solution,
            "hierarchy_params": self.solution.params,
            **self.arrays,
            "scales": dict(self.scales),
            "virtual_groups": set(self.virtual_groups),
            "times": dict(self.times),
        }


def save_session(session: SavedSession, path) -> Path:
    """Write ``session`` to ``path`` (.npz), atomically."""
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise InputError(f"a prepared session is saved as .npz, got {path.name}")
    basis = session.basis
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
        if name == "uv":  # relighting's polygons carry no texture (the photograph is theirs): all NaN
            continue
        arrays[f"hierarchy.{name}"] = a
    for name in ("receiver", "source", "form_factor", "visibility"):
        arrays[f"links.{name}"] = getattr(sol.links, name)
    arrays["lamp_scale"] = sol.lamp_scale
    for name, a in session.arrays.items():
        arrays[f"session.{name}"] = a
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


def load_session(path) -> SavedSession:
    """What a file written by :func:`save_session` holds: ``RelightSession.load`` makes the session
    from it (this module does not know the class)."""
    path = Path(path)
    start = time.perf_counter()
    arrays = load_npz(path, "saved relighting session")
    try:
        record = json.loads(str(arrays["record"]))
        if not isinstance(record, dict):
            raise InputError(f"{path}: not a saved relighting session (its record is not an object)")
        if record.get("format") != FORMAT:
            raise InputError(
                f"{path}: saved as {record.get('format')!r}, this illusio reads {FORMAT!r}; "
                f"prepare it again (illusio relight prepare SCENE -o {path.name})"
            )
        check_arrays(path, arrays, record)
        p = record["params"]
        params = RelightParams(
            **{
                **p,
                "hierarchy": HierarchyParams(**p["hierarchy"]),
                "final_hierarchy": HierarchyParams(**p["final_hierarchy"]),
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
            HierarchyParams(**record["solution_params"]),
            hierarchy,
            links,
            arrays["lamp_scale"],
        )
        if "visibility_rng" in record:
            sol.visibility.rng.bit_generator.state = record["visibility_rng"]
        names = _SESSION_ARRAYS + (_PER_PIXEL_ARRAYS if params.method == "per-pixel" else ())
        session_arrays = {name: arrays[f"session.{name}"] for name in names}
        if (
            session_arrays["pixel_element"].shape != real.photograph.shape[:2]
            or session_arrays["texture"].shape != real.photograph.shape
        ):
            raise InputError(f"{path}: the saved maps do not match the photograph's size")
        basis = None
        if "basis_key" in record:
            key = record["basis_key"]
            basis = (
                (int(key[0]), int(key[1]), tuple(key[2])),
                list(arrays["basis"]),
                LeafMesh(*(arrays[f"basis_mesh.{n}"] for n in _MESH_ARRAYS)),
            )
        saved = SavedSession(
            real,
            params,
            _polygons_in("model", arrays, record),
            sol,
            session_arrays,
            {k: float(x) for k, x in record["scales"].items()},
            frozenset(int(g) for g in record["virtual_groups"]),
            {k: float(x) for k, x in record["times"].items()},
            basis,
        )
    except KeyError as exc:
        raise InputError(f"{path}: not a saved relighting session (no {exc.args[0]!r})") from None
    except (TypeError, ValueError, AttributeError, IndexError) as exc:  # a field of the wrong type or shape
        raise InputError(f"{path}: a saved relighting session with a bad field ({exc})") from None
    return dataclasses.replace(saved, load_seconds=time.perf_counter() - start)
