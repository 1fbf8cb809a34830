"""Triangle meshes: the Mesh container, normals, and load_mesh with validation and repair.

Mesh arrays: vertices (N, 3) float32 metres, faces (M, 3) int32 counter-clockwise seen from
outside, normals (N, 3) float32 unit, uvs (N, 2) float32 with v up (GL convention) or None.
"""

from __future__ import annotations

import io
import os
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from .mesh_counts import check_declared_counts, length_error

__all__ = ["Mesh", "MeshWarning", "as_mesh", "load_mesh", "vertex_normals", "crease_split", "weld", "MESH_FORMATS"]

MESH_FORMATS = (".obj", ".ply", ".off", ".stl", ".gltf", ".glb")


class MeshWarning(UserWarning):
    """A mesh was repaired on load (unreferenced vertices or duplicate faces dropped)."""


@dataclass(eq=False)
class Mesh:
    """An indexed triangle mesh. ``normals`` are computed (area-weighted) when not given."""

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None = None
    uvs: np.ndarray | None = None
    name: str = "mesh"
    notes: list[str] = field(default_factory=list)  # repairs made on load, for reports
    #: for a mesh read from a file, each row's vertex index in the file (repair drops unreferenced
    #: vertices; an STL's welded corners count as its vertices); None: the rows are the vertices
    source_index: np.ndarray | None = None

    def __post_init__(self):
        self.vertices = np.ascontiguousarray(self.vertices, dtype=np.float32).reshape(-1, 3)
        self.faces = np.ascontiguousarray(self.faces, dtype=np.int32).reshape(-1, 3)
        validate_arrays(self.vertices, self.faces, self.name)
        if self.normals is None:
            self.normals = vertex_normals(self.vertices, self.faces)
        self.normals = np.ascontiguousarray(self.normals, dtype=np.float32).reshape(-1, 3)
        if self.uvs is not None:
            uvs = np.asarray(self.uvs, dtype=np.float32)
            if (uvs.ndim == 2 and uvs.shape[1] != 2) or uvs.size % 2:
                # (an OBJ whose vt lines give u alone reads as one column)
                raise InputError(
                    f"{self.name}: texture coordinates must be (u, v) pairs, got an array of shape {uvs.shape}"
                )
            self.uvs = np.ascontiguousarray(uvs).reshape(-1, 2)
        if len(self.normals) != len(self.vertices) or (self.uvs is not None and len(self.uvs) != len(self.vertices)):
            raise InputError(f"{self.name}: normals/uvs must have one row per vertex")
        if self.source_index is not None:
            self.source_index = np.asarray(self.source_index, np.int64).reshape(-1)
            if len(self.source_index) != len(self.vertices):
                raise InputError(f"{self.name}: source_index must have one row per vertex")

    @classmethod
    def from_trimesh(cls, mesh, name: str | None = None) -> Mesh:
        """A Mesh of a ``trimesh.Trimesh`` (its vertices, faces and, with texture visuals, uvs; a
        ``trimesh.Scene`` is flattened with its transforms). Normals are computed as for any Mesh."""
        import trimesh

        if isinstance(mesh, trimesh.Scene):
            mesh = mesh.to_mesh() if hasattr(mesh, "to_mesh") else mesh.dump(concatenate=True)
        if not isinstance(mesh, trimesh.Trimesh):
            raise InputError(f"expected a trimesh.Trimesh or trimesh.Scene, got {type(mesh).__name__}")
        uv = getattr(mesh.visual, "uv", None)
        uvs = None if uv is None or len(uv) != len(mesh.vertices) else np.asarray(uv, np.float32)
        label = name or str(mesh.metadata.get("name") or mesh.metadata.get("file_name") or "trimesh")
        return cls(np.asarray(mesh.vertices), np.asarray(mesh.faces), uvs=uvs, name=label)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(min corner, max corner) of the referenced vertices."""
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def transformed(self, matrix: np.ndarray) -> Mesh:
        from .transforms import transform_normals, transform_points

        return replace(
            self,
            vertices=transform_points(matrix, self.vertices),
            normals=transform_normals(matrix, self.normals),
            notes=list(self.notes),
        )

    def normalised(self, size: float = 1.0) -> Mesh:
        """Centred on the origin in x and z, resting on y = 0, largest extent ``size``."""
        lo, hi = self.bounds
        s = size / float(np.max(hi - lo))
        centre = np.array([(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2], dtype=np.float32)
        return replace(self, vertices=(self.vertices - centre) * s, notes=list(self.notes))

    def with_crease_normals(self, angle: float = 30.0) -> Mesh:
        """Split vertices along edges sharper than ``angle`` degrees so that creases shade sharp."""
        v, f, n, uv, origin = crease_split(self.vertices, self.faces, angle, self.uvs, return_origin=True)
        source = None if self.source_index is None else self.source_index[origin]
        return replace(self, vertices=v, faces=f, normals=n, uvs=uv, notes=list(self.notes), source_index=source)


def as_mesh(mesh) -> Mesh:
    """``mesh`` as a :class:`Mesh`: a Mesh as it is, a ``trimesh.Trimesh`` or ``trimesh.Scene`` through
    :meth:`Mesh.from_trimesh`; anything else is refused in one line."""
    if isinstance(mesh, Mesh):
        return mesh
    module = type(mesh).__module__ or ""
    if module.split(".")[0] == "trimesh":
        return Mesh.from_trimesh(mesh)
    raise InputError(f"expected a mesh (illusio Mesh or trimesh.Trimesh), got {type(mesh).__name__}")


def weld(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(unique positions (K, 3), index of each input vertex's position (N,)): vertices at the same
    position — within 1e-9 of the mesh's extent — taken as one. Compared on that integer grid, not
    as floats: a seam built from sin 0 and sin 2π (0 against −2.4e-16), or −0.0 against 0.0, is the
    same point."""
    v = np.asarray(vertices, np.float64)
    finite = np.isfinite(v).all(axis=1)
    extent = float(np.ptp(v[finite], axis=0).max()) if finite.any() else 0.0
    key = np.zeros(v.shape, np.int64)
    key[finite] = np.round(v[finite] / max(extent * 1e-9, 1e-300)).astype(np.int64)
    key[~finite] = np.iinfo(np.int64).max - np.arange((~finite).sum())[:, None]  # never welded: refused later
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return v[first], inverse.reshape(-1)


def validate_arrays(vertices: np.ndarray, faces: np.ndarray, name: str) -> None:
    """Raise InputError for an empty mesh, non-finite vertices or out-of-range face indices."""
    if len(vertices) == 0 or len(faces) == 0:
        raise InputError(f"{name}: mesh is empty ({len(vertices)} vertices, {len(faces)} faces)")
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise InputError(f"{name}: vertices must have x, y and z, got an array of shape {vertices.shape}")
    bad = ~np.isfinite(vertices).all(axis=1)
    if bad.any():
        raise InputError(
            f"{name}: {int(bad.sum())} vertices are not finite (NaN or inf), first at index {int(np.argmax(bad))}"
        )
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise InputError(
            f"{name}: face indices out of range (vertex count {len(vertices)}, indices "
            f"{int(faces.min())}..{int(faces.max())})"
        )


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unnormalised face normals (length = 2 × area)."""
    v = vertices.astype(np.float64)
    return np.cross(v[faces[:, 1]] - v[faces[:, 0]], v[faces[:, 2]] - v[faces[:, 0]])


def _normalise(n: np.ndarray, fallback=(0.0, 1.0, 0.0)) -> np.ndarray:
    length = np.linalg.norm(n, axis=1, keepdims=True)
    out = np.where(length > 1e-30, n / np.maximum(length, 1e-30), np.asarray(fallback))
    return out.astype(np.float32)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals; isolated vertices get +y."""
    fn = face_normals(np.asarray(vertices, np.float32).reshape(-1, 3), np.asarray(faces, np.int64).reshape(-1, 3))
    corners = np.asarray(faces, np.int64).reshape(-1)
    per_corner = np.repeat(fn, 3, axis=0)  # each face's normal at its three corners
    # bincount sums per vertex as np.add.at does, a few times faster
    acc = np.stack([np.bincount(corners, per_corner[:, c], minlength=len(vertices)) for c in range(3)], axis=1)
    return _normalise(acc)


def crease_split(vertices, faces, angle: float, uvs=None, return_origin: bool = False):
    """Per-corner normals averaged over the faces around the vertex whose normal is within
    ``angle`` degrees of the corner's face; corners with equal (vertex, normal) share a vertex.
    Returns (vertices, faces, normals, uvs[, the input vertex of each new one])."""
    vertices = np.asarray(vertices, np.float32)
    faces = np.asarray(faces, np.int64)
    fn = face_normals(vertices, faces)
    unit = _normalise(fn).astype(np.float64)
    corner_vertex = faces.reshape(-1)
    corner_face = np.repeat(np.arange(len(faces)), 3)
    # all (corner, face sharing the corner's vertex) pairs
    order = np.argsort(corner_vertex, kind="stable")
    sorted_vertex = corner_vertex[order]
    starts = np.searchsorted(sorted_vertex, np.arange(len(vertices)))
    counts = np.bincount(corner_vertex, minlength=len(vertices))
    reps = counts[corner_vertex]
    pair_corner = np.repeat(np.arange(len(corner_vertex)), reps)
    offs = np.arange(len(pair_corner)) - np.repeat(np.cumsum(reps) - reps, reps)
    pair_face = corner_face[order[starts[corner_vertex[pair_corner]] + offs]]
    keep = (unit[corner_face[pair_corner]] * unit[pair_face]).sum(axis=1) >= np.cos(np.radians(angle)) - 1e-9
    acc = np.zeros((len(corner_vertex), 3))
    np.add.at(acc, pair_corner[keep], fn[pair_face[keep]])
    normals = _normalise(acc)
    # merge corners of the same vertex with the same normal
    key = np.c_[corner_vertex, np.round(normals * 1e4).astype(np.int64)]
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    new_v = vertices[corner_vertex[first]]
    new_uv = None if uvs is None else np.asarray(uvs, np.float32)[corner_vertex[first]]
    out = (new_v, inverse.reshape(-1, 3).astype(np.int32), normals[first], new_uv)
    return out + (corner_vertex[first],) if return_origin else out


def _repair(vertices: np.ndarray, faces: np.ndarray, uvs, name: str, notes: list[str]):
    """Drop degenerate faces (silently), duplicate faces and unreferenced vertices (with a warning).
    Returns (vertices, faces, uvs, index of each kept vertex in the input)."""
    f = faces
    degenerate = (f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 0] == f[:, 2])
    degenerate |= np.linalg.norm(face_normals(vertices, f), axis=1) <= 1e-20
    if degenerate.any():
        notes.append(f"ignored {int(degenerate.sum())} degenerate faces")
        f = f[~degenerate]
    if len(f) == 0:
        raise InputError(f"{name}: every face is degenerate (zero area)")
    _, first = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
    if len(first) < len(f):
        msg = f"dropped {len(f) - len(first)} duplicate faces"
        notes.append(msg)
        warnings.warn(f"{name}: {msg}", MeshWarning, stacklevel=3)
        f = f[np.sort(first)]
    used = np.zeros(len(vertices), dtype=bool)
    used[f.reshape(-1)] = True
    if not used.all():
        msg = f"dropped {int((~used).sum())} unreferenced vertices"
        notes.append(msg)
        warnings.warn(f"{name}: {msg}", MeshWarning, stacklevel=3)
        remap = np.cumsum(used) - 1
        f = remap[f]
        vertices = vertices[used]
        uvs = None if uvs is None else uvs[used]
    return vertices, f, uvs, np.flatnonzero(used)


def load_mesh(path: str | os.PathLike, *, repair: bool = True) -> Mesh:
    """Read an OBJ, PLY, OFF, STL or glTF/GLB file through trimesh (scenes are flattened).

    Raises InputError naming the file when it is missing, unreadable, empty, has non-finite
    vertices or out-of-range face indices. With ``repair`` (default), unreferenced vertices and
    duplicate faces are dropped with a :class:`MeshWarning`, degenerate faces are ignored.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    if p.suffix.lower() not in MESH_FORMATS:
        raise InputError(f"{p}: unsupported mesh format {p.suffix!r}; use one of {', '.join(MESH_FORMATS)}")
    if p.stat().st_size == 0:
        raise InputError(f"{p}: file is empty")
    check_declared_counts(p, p.read_bytes())
    vertices, faces, uvs = _read_with_trimesh(p)
    name = p.name
    if len(vertices) == 0 or len(faces) == 0:
        raise InputError(f"{p}: mesh is empty ({len(vertices)} vertices, {len(faces)} faces)")
    validate_arrays(vertices.astype(np.float32), faces, str(p))
    notes: list[str] = []
    index = np.arange(len(vertices))
    if repair:
        vertices, faces, uvs, index = _repair(vertices, faces, uvs, str(p), notes)
    return Mesh(vertices, faces, uvs=uvs, name=name, notes=notes, source_index=index)


def _read_with_trimesh(p: Path):
    import trimesh

    from .obj_indices import absolute_indices
    from .ply_strips import has_tristrips, read_ply_tristrips

    if p.suffix.lower() == ".ply" and has_tristrips(p):
        try:
            vertices, faces = read_ply_tristrips(p)
        except InputError:
            raise
        except (ValueError, IndexError, KeyError) as exc:
            raise InputError(f"{p}: cannot read PLY triangle strips ({exc})") from None
        return vertices, faces, None

    absolute = absolute_indices(p.read_bytes()) if p.suffix.lower() == ".obj" else None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if absolute is not None:  # relative indices: the spec's meaning, not trimesh's
                loaded = trimesh.load(
                    io.BytesIO(absolute),
                    file_type="obj",
                    resolver=trimesh.resolvers.FilePathResolver(str(p)),
                    process=False,
                    maintain_order=True,
                )
            else:
                loaded = trimesh.load(str(p), process=False, maintain_order=True)
    except Exception as exc:  # trimesh raises many kinds on corrupt input
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        if "expected length" in reason:  # trimesh's PLY and GLB readers check the declared sizes
            raise length_error(p, reason) from None
        raise InputError(f"{p}: cannot read mesh ({reason})") from None
    if isinstance(loaded, trimesh.Scene):
        geoms = [g for g in loaded.dump() if isinstance(g, trimesh.Trimesh)] if loaded.geometry else []
        if not geoms:
            raise InputError(f"{p}: mesh is empty (no triangles in the file)")
        shared = all(
            len(g.vertices) == len(geoms[0].vertices) and np.array_equal(g.vertices, geoms[0].vertices) for g in geoms
        )
        if len(geoms) > 1 and shared:
            # one vertex list that each material's faces index (an OBJ's, read in order): kept once,
            # so an unreferenced count is the file's
            loaded = trimesh.Trimesh(geoms[0].vertices, np.concatenate([g.faces for g in geoms]), process=False)
        else:
            loaded = trimesh.util.concatenate(geoms) if len(geoms) > 1 else geoms[0]
    if not isinstance(loaded, trimesh.Trimesh):
        raise InputError(f"{p}: holds no triangle mesh (found {type(loaded).__name__})")
    vertices = np.asarray(loaded.vertices, dtype=np.float64)
    faces = np.asarray(loaded.faces, dtype=np.int64).reshape(-1, 3)
    uv = getattr(loaded.visual, "uv", None)
    uvs = np.asarray(uv, dtype=np.float32) if uv is not None and len(uv) == len(vertices) else None
    if p.suffix.lower() == ".stl" and len(vertices):
        # STL stores three separate corners per facet: weld identical positions so that the
        # surface is connected (smooth normals, and topology for curvature)
        vertices, inverse = weld(vertices)
        faces = inverse[faces]
    return vertices, faces, uvs
