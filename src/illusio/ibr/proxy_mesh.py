"""The first pass's input: an approximate surface of the scene rebuilt from the reference depths,
drawn into the new view's depth buffer whenever the camera moves (the text recomputes its depth
buffer only then). Our design: each reference's depth map becomes a grid mesh — a vertex every
``step`` pixels at the point the pixel sees, two triangles per cell — leaving out triangles with
nothing at a corner and those seen at more than ``grazing`` degrees from their normal (a triangle
bridging an occlusion edge lies almost along the reference's rays; a relative depth-jump test
instead cut floors seen at a low angle, whose depth grows fast from pixel to pixel); the meshes of
all references are drawn together with the z-buffer. A reference pixel lies on
the surface, so where any reference saw the surface the rebuilt depth is close to the true one;
the second pass then corrects it from the references.

A cell is drawn only where the mesh stands for every pixel in it: a seen pixel whose depth is off
the cell's surface (inverse depth interpolated from the corners) by more than 1 % cuts the cells it
touches. The reference pixels no drawn cell covers — thin objects a pixel or two wide, whose every
triangle bridged an occlusion edge, what a coarse grid stepped over, the pixels beside an invalid
one, the outermost pixels (the mesh joins pixel centres) — are drawn as points, each a square of
its own footprint, so that everything a reference saw reaches the new view's depth (a chair leg
dropped by the mesh alone cost the RGB-D benchmark 0.6 dB). A coarse grid (step ≥ 2·FINER) meshes
its cut cells again FINER times finer inside, with the same tests, so that a cell cut for one thin
object does not turn all its pixels into points (at step 16, 216k points a frame became 75k)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene.mesh import Mesh
from .reference_views import ReferenceSet, ReferenceView

__all__ = ["unproject", "reference_mesh", "uncovered_points", "Reconstruction", "reconstruction"]


def unproject(view, size, xs: np.ndarray, ys: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """World points (…, 3) seen at pixel coordinates (xs, ys) (pixels from the top-left corner,
    centres at +0.5) at linear view depth ``depth`` (metres along the view axis)."""
    w, h = size
    p = view.projection_matrix(w / h).astype(np.float64)
    ndc_x = xs / w * 2 - 1
    ndc_y = 1 - ys / h * 2
    z = np.asarray(depth, np.float64)
    x_view = (ndc_x * z + p[0, 2] * z) / p[0, 0]
    y_view = (ndc_y * z + p[1, 2] * z) / p[1, 1]
    camera = np.stack([x_view, y_view, -z, np.ones_like(z)], axis=-1)
    world = camera @ np.linalg.inv(view.view_matrix().astype(np.float64)).T
    return world[..., :3]


def reference_mesh(ref: ReferenceView, step: int = 2, grazing: float = 85.0) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of one reference's grid mesh (see the module docstring)."""
    vertices, faces, _ = _adaptive(ref, step, grazing)
    return vertices, faces


def uncovered_points(ref: ReferenceView, step: int = 2, grazing: float = 85.0) -> tuple[np.ndarray, np.ndarray]:
    """(points (N, 3), footprint (N,)) of the reference pixels with depth that no kept cell of
    :func:`reference_mesh` represents (see the module docstring), each to be drawn as a square of its
    own footprint (metres per pixel at its depth, depth / f_x)."""
    return _uncovered(ref, _adaptive(ref, step, grazing)[2])


def _uncovered(ref: ReferenceView, covered: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    w, h = ref.size
    depth = np.asarray(ref.depth, np.float64)
    lone = (depth > 0) & ~covered
    ys, xs = np.nonzero(lone)
    points = unproject(ref.view, (w, h), xs + 0.5, ys + 0.5, depth[lone])
    focal = ref.view.projection_matrix(w / h)[0, 0] * w / 2
    return points, depth[lone] / focal


@dataclass
class _Grid:
    vertices: np.ndarray  # (V, 3) world, the grid's pixels' points
    faces: np.ndarray  # (2·cells, 3): every cell's upper-left triangle, then every lower-right one
    keep: np.ndarray  # (2·cells,) which are drawn
    depth: np.ndarray  # (H, W) the reference's depth
    covered: np.ndarray  # (H, W) pixels every cell touching them is kept (drawn by the mesh)
    rows: np.ndarray  # the grid's pixel rows and columns
    cols: np.ndarray
    cell_ok: np.ndarray  # (rows − 1, cols − 1) cells whose two triangles pass every test
    touching: list  # per pixel, the cells touching it: (cell row, cell column, where) × 4


def _covered(touching, cell_drawn: np.ndarray, shape) -> np.ndarray:
    """(H, W) pixels every cell touching them is drawn; the outermost pixels never (the mesh joins
    pixel centres: their outer halves are left to points)."""
    covered = np.ones(shape, bool)
    for i, j, where in touching:
        covered &= ~where | cell_drawn[np.maximum(i, 0), np.maximum(j, 0)]
    covered[[0, -1], :] = False
    covered[:, [0, -1]] = False
    return covered


def _grid(ref: ReferenceView, step: int, grazing: float) -> _Grid:
    w, h = ref.size
    rows = np.unique(np.r_[np.arange(0, h, step), h - 1])
    cols = np.unique(np.r_[np.arange(0, w, step), w - 1])
    depth = np.asarray(ref.depth, np.float64)
    gys, gxs = np.meshgrid(rows, cols, indexing="ij")
    d = depth[gys, gxs]
    vertices = unproject(ref.view, (w, h), gxs + 0.5, gys + 0.5, d).reshape(-1, 3)
    gh, gw = d.shape
    idx = np.arange(gh * gw).reshape(gh, gw)
    a, b, c, e = idx[:-1, :-1], idx[:-1, 1:], idx[1:, :-1], idx[1:, 1:]
    faces = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([b, c, e], -1).reshape(-1, 3)])
    seen = (d.reshape(-1)[faces] > 0).all(axis=1)
    p0, p1, p2 = (vertices[faces[:, k]] for k in range(3))
    normal = np.cross(p1 - p0, p2 - p0)
    ray = (p0 + p1 + p2) / 3 - np.asarray(ref.view.pose.position, np.float64)
    cosine = np.abs((normal * ray).sum(1)) / np.maximum(
        np.linalg.norm(normal, axis=1) * np.linalg.norm(ray, axis=1), 1e-30
    )
    keep = seen & (cosine > np.cos(np.radians(grazing)))
    # every pixel against its cell's surface: inverse depth (linear across a plane's image)
    # interpolated from the corners; a seen pixel off it by more than 1 % cuts every cell it touches
    ys, xs = np.mgrid[0:h, 0:w]
    ci = np.clip(np.searchsorted(rows, ys, "right") - 1, 0, gh - 2)
    cj = np.clip(np.searchsorted(cols, xs, "right") - 1, 0, gw - 2)
    fy = (ys - rows[ci]) / (rows[ci + 1] - rows[ci])
    fx = (xs - cols[cj]) / (cols[cj + 1] - cols[cj])
    inverse = np.where(d > 0, 1 / np.where(d > 0, d, 1), 0.0)
    surface = (inverse[ci, cj] * (1 - fx) + inverse[ci, cj + 1] * fx) * (1 - fy) + (
        inverse[ci + 1, cj] * (1 - fx) + inverse[ci + 1, cj + 1] * fx
    ) * fy
    off = (depth > 0) & (np.abs(surface * depth - 1) > 0.01)
    on_row, on_col = (ys == rows[ci]) & (ci > 0), (xs == cols[cj]) & (cj > 0)
    touching = [
        (ci, cj, np.ones((h, w), bool)),
        (ci - 1, cj, on_row),
        (ci, cj - 1, on_col),
        (ci - 1, cj - 1, on_row & on_col),
    ]
    cell_ok = keep.reshape(2, gh - 1, gw - 1).all(axis=0)
    for i, j, where in touching:
        cell_ok[i[off & where], j[off & where]] = False
    keep &= np.tile(cell_ok.reshape(-1), 2)
    return _Grid(vertices, faces, keep, depth, _covered(touching, cell_ok, (h, w)), rows, cols, cell_ok, touching)


#: a cut cell of a grid coarser than this many pixels is meshed again FINER times finer inside
FINER = 4


def _adaptive(ref: ReferenceView, step: int, grazing: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vertices, faces, covered) of a reference's mesh at ``step``, with every cut cell meshed again
    at step // FINER where that is at least 2 (the finer cells that pass the same tests are drawn
    inside cut coarse ones): the pixels of a coarse cell cut for one thin object need not all become
    points. ``covered`` (H, W) as :class:`_Grid`'s, over both grids."""
    coarse = _grid(ref, step, grazing)
    if step // FINER < 2:
        return coarse.vertices, coarse.faces[coarse.keep], coarse.covered
    fine = _grid(ref, step // FINER, grazing)
    # each fine cell lies inside one coarse cell (the coarse rows are among the fine ones)
    parent_row = np.searchsorted(coarse.rows, fine.rows[:-1], "right") - 1
    parent_col = np.searchsorted(coarse.cols, fine.cols[:-1], "right") - 1
    parent_drawn = coarse.cell_ok[parent_row[:, None], parent_col[None, :]]
    inside_cut = fine.cell_ok & ~parent_drawn
    fine_faces = fine.faces[np.tile(inside_cut.reshape(-1), 2)]
    covered = _covered(fine.touching, fine.cell_ok | parent_drawn, fine.depth.shape)
    used, remap = np.unique(fine_faces, return_inverse=True)
    vertices = np.concatenate([coarse.vertices, fine.vertices[used]])
    faces = np.concatenate([coarse.faces[coarse.keep], remap.reshape(-1, 3) + len(coarse.vertices)])
    return vertices, faces, covered


@dataclass(frozen=True)
class Reconstruction:
    """The first pass's input for a reference set: ``mesh`` every reference's grid mesh (world
    coordinates); ``points`` (N, 3) float32 world and ``footprint`` (N,) float32 metres, the pixels
    the meshes leave out (:func:`uncovered_points`)."""

    mesh: Mesh
    points: np.ndarray
    footprint: np.ndarray


def reconstruction(refs: ReferenceSet, step: int = 2, grazing: float = 85.0) -> Reconstruction:
    """Every reference's grid mesh in one Mesh, and the points they leave out."""
    all_v, all_f, all_p, all_s, offset = [], [], [np.zeros((0, 3))], [np.zeros(0)], 0
    for ref in refs.views:
        vertices, faces, covered = _adaptive(ref, step, grazing)
        all_v.append(vertices)
        all_f.append(faces + offset)
        offset += len(vertices)
        points, footprint = _uncovered(ref, covered)
        all_p.append(points)
        all_s.append(footprint)
    faces = np.concatenate(all_f) if all_f else np.zeros((0, 3), np.int64)
    if len(faces) == 0:
        faces = np.zeros((1, 3), np.int64)  # nothing seen: one degenerate triangle draws nothing
    vertices = np.concatenate(all_v) if all_v else np.zeros((1, 3))
    mesh = Mesh(vertices.astype(np.float32), faces.astype(np.int32), name="ibr-reconstruction")
    return Reconstruction(mesh, np.concatenate(all_p).astype(np.float32), np.concatenate(all_s).astype(np.float32))
