"""Welded test surfaces with known principal curvatures (sphere, torus, ellipsoid closed; a
corrugated sheet and an open cylinder), for the curvature and line tests and the accuracy benchmark. Curvatures
follow lines.curvature's convention
(positive on a sphere with outward normals)."""

from __future__ import annotations

import numpy as np

from ..scene.mesh import Mesh

__all__ = ["icosphere", "torus", "ellipsoid", "corrugated", "cylinder", "add_noise"]


def icosphere(subdivisions: int = 3, radius: float = 1.0) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """Returns (mesh, k_min, k_max): a subdivided icosahedron, every vertex on the sphere."""
    v, f = _icosahedron()
    for _ in range(subdivisions):
        v, f = _subdivide(v, f)
    v = v / np.linalg.norm(v, axis=1, keepdims=True) * radius
    k = np.full(len(v), 1.0 / radius)
    return Mesh(v, f, name=f"icosphere-{subdivisions}"), k, k.copy()


def torus(
    major: float = 1.0, minor: float = 0.35, segments: int = 96, sides: int = 32
) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """Returns (mesh, k_min, k_max) of a welded torus around z. Around the tube k = 1/minor; along
    the ring k = cos φ / (major + minor cos φ) (negative on the inner side)."""
    th, ph = np.meshgrid(
        np.arange(segments) * 2 * np.pi / segments, np.arange(sides) * 2 * np.pi / sides, indexing="ij"
    )
    rr = major + minor * np.cos(ph)
    v = np.stack([rr * np.cos(th), rr * np.sin(th), minor * np.sin(ph)], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(segments), np.arange(sides), indexing="ij")
    a = i * sides + j
    b = ((i + 1) % segments) * sides + j
    c = ((i + 1) % segments) * sides + (j + 1) % sides
    d = i * sides + (j + 1) % sides
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    k_ring = (np.cos(ph) / rr).reshape(-1)
    k_tube = np.full_like(k_ring, 1.0 / minor)
    return Mesh(v, f, name=f"torus-{segments}x{sides}"), np.minimum(k_ring, k_tube), np.maximum(k_ring, k_tube)


def ellipsoid(axes=(1.0, 0.7, 0.5), subdivisions: int = 4) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """Returns (mesh, k_min, k_max) of an icosphere scaled by ``axes``, curvatures from the implicit
    form x²/a² + y²/b² + z²/c² = 1 (Goldman 2005)."""
    sphere, _, _ = icosphere(subdivisions)
    v = sphere.vertices.astype(np.float64) * np.asarray(axes, np.float64)
    inv = 1.0 / np.asarray(axes, np.float64) ** 2
    g = 2 * v * inv  # gradient of F
    hess = 2 * inv  # diagonal Hessian of F
    gn = np.linalg.norm(g, axis=1)
    mean = -((g * g * hess).sum(1) - gn**2 * hess.sum()) / (2 * gn**3)  # sign: outward normals positive
    gauss = (g * g * np.roll(hess, 1) * np.roll(hess, 2)).sum(1) / gn**4
    disc = np.sqrt(np.maximum(mean**2 - gauss, 0))
    return Mesh(v, sphere.faces, name=f"ellipsoid-{subdivisions}"), mean - disc, mean + disc


def _grid_faces(rows: int, columns: int, wrap: bool = False) -> np.ndarray:
    """Two triangles per cell of a rows × columns vertex grid (row-major), columns wrapped or not."""
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(columns if wrap else columns - 1), indexing="ij")
    a = i * columns + j
    b = i * columns + (j + 1) % columns
    c, d = b + columns, a + columns
    return np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])


def corrugated(
    amplitude: float = 0.1, wavenumber: float = 2 * np.pi, extent: float = 2.0, n: int = 161
) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """Returns (mesh, k_min, k_max) of the sheet z = a·sin(k x) over [−extent/2, extent/2]², wound with
    normals up
    (+z). Across the folds κ = a k² sin(k x) / (1 + a²k² cos² k x)^{3/2} (positive on the crests),
    along them 0."""
    x, y = np.meshgrid(np.linspace(-extent / 2, extent / 2, n), np.linspace(-extent / 2, extent / 2, n), indexing="ij")
    v = np.stack([x, y, amplitude * np.sin(wavenumber * x)], -1).reshape(-1, 3)
    across = (
        amplitude
        * wavenumber**2
        * np.sin(wavenumber * x)
        / (1 + (amplitude * wavenumber * np.cos(wavenumber * x)) ** 2) ** 1.5
    ).reshape(-1)
    return Mesh(v, _grid_faces(n, n)[:, ::-1], name="corrugated"), np.minimum(across, 0.0), np.maximum(across, 0.0)


def cylinder(
    radius: float = 0.5, length: float = 2.0, segments: int = 128, rings: int = 64
) -> tuple[Mesh, np.ndarray, np.ndarray]:
    """Returns (mesh, k_min, k_max) of an open cylinder of axis y (outward normals): k_max = 1/radius
    around it, k_min = 0 along it."""
    y, t = np.meshgrid(
        np.linspace(-length / 2, length / 2, rings), np.arange(segments) * 2 * np.pi / segments, indexing="ij"
    )
    v = np.stack([radius * np.sin(t), y, radius * np.cos(t)], -1).reshape(-1, 3)
    f = _grid_faces(rings, segments, wrap=True)
    k = np.full(len(v), 1.0 / radius)
    return Mesh(v, f, name="cylinder"), np.zeros_like(k), k


def add_noise(mesh: Mesh, amount: float, seed: int = 0) -> Mesh:
    """Move every vertex along its normal by Gaussian noise of ``amount`` × mean edge length."""
    rng = np.random.default_rng(seed)
    e = mesh.vertices[mesh.faces[:, 1]] - mesh.vertices[mesh.faces[:, 0]]
    step = float(np.linalg.norm(e, axis=1).mean()) * amount
    v = mesh.vertices + mesh.normals * rng.normal(0.0, step, (len(mesh.vertices), 1))
    return Mesh(v, mesh.faces, name=f"{mesh.name}+noise{amount:g}")


def _icosahedron():
    t = (1 + 5**0.5) / 2
    v = np.array(
        [
            [-1, t, 0],
            [1, t, 0],
            [-1, -t, 0],
            [1, -t, 0],
            [0, -1, t],
            [0, 1, t],
            [0, -1, -t],
            [0, 1, -t],
            [t, 0, -1],
            [t, 0, 1],
            [-t, 0, -1],
            [-t, 0, 1],
        ],
        np.float64,
    )
    f = np.array(
        [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ],
        np.int64,
    )
    return v / np.linalg.norm(v, axis=1, keepdims=True), f


def _subdivide(v, f):
    """Split each triangle in four, sharing edge midpoints."""
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mids = (v[unique[:, 0]] + v[unique[:, 1]]) / 2
    mids /= np.linalg.norm(mids, axis=1, keepdims=True)
    m = inverse.reshape(3, -1).T + len(v)
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    ab, bc, ca = m[:, 0], m[:, 1], m[:, 2]
    nf = np.concatenate(
        [np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1), np.stack([ab, bc, ca], 1)]
    )
    return np.concatenate([v, mids]), nf
