"""Procedural shapes, all as :class:`~illusio.scene.mesh.Mesh` in metres, centred on the origin
(unless a docstring says otherwise), outward normals, uvs in [0, 1] (v up) where the surface has
a natural parametrisation. Nothing here reads a file."""

from __future__ import annotations

import numpy as np

from ..mesh import Mesh, crease_split, vertex_normals

__all__ = [
    "sphere",
    "torus",
    "torus_knot",
    "superquadric",
    "gear",
    "blob",
    "box",
    "cylinder",
    "cone",
    "plane",
    "SHAPES",
    "shape",
]


def _grid_mesh(points: np.ndarray, name: str) -> Mesh:
    """Mesh of a (nv+1, nu+1, 3) grid of points. Coincident points (seams, poles) share normals
    but keep their own uvs; triangles collapsed at the poles are dropped."""
    rows, cols, _ = points.shape
    idx = np.arange(rows * cols).reshape(rows, cols)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    faces = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    v = points.reshape(-1, 3).astype(np.float32)
    uu, vv = np.meshgrid(np.linspace(0, 1, cols), np.linspace(0, 1, rows))
    uvs = np.c_[uu.ravel(), vv.ravel()]
    # weld seams and coincident points (poles) for normals only
    _, weld = np.unique(np.round(v / 1e-6).astype(np.int64), axis=0, return_inverse=True)
    weld = weld.reshape(-1)
    welded_faces = weld[faces]
    ok = (
        (welded_faces[:, 0] != welded_faces[:, 1])
        & (welded_faces[:, 1] != welded_faces[:, 2])
        & (welded_faces[:, 0] != welded_faces[:, 2])
    )
    faces = faces[ok]
    welded = np.zeros((weld.max() + 1, 3), np.float32)
    welded[weld] = v
    normals = vertex_normals(welded, weld[faces])[weld]
    used = np.zeros(len(v), bool)
    used[faces.ravel()] = True
    remap = np.cumsum(used) - 1
    return Mesh(v[used], remap[faces], normals[used], uvs[used], name=name)


def sphere(radius: float = 1.0, segments: int = 64, rings: int = 32) -> Mesh:
    """UV sphere; u around +y from +x, v from the south pole (0) to the north pole (1)."""
    th = np.linspace(0, 2 * np.pi, segments + 1)
    ph = np.linspace(-np.pi / 2, np.pi / 2, rings + 1)
    t, p = np.meshgrid(th, ph)
    pts = np.stack([np.cos(p) * np.cos(t), np.sin(p), -np.cos(p) * np.sin(t)], axis=-1) * radius
    return _grid_mesh(pts, "sphere")


def torus(major: float = 1.0, minor: float = 0.35, segments: int = 96, sides: int = 32) -> Mesh:
    """Torus around the y axis."""
    th = np.linspace(0, 2 * np.pi, segments + 1)
    ph = np.linspace(0, 2 * np.pi, sides + 1)
    t, p = np.meshgrid(th, ph)
    r = major + minor * np.cos(p)
    pts = np.stack([r * np.cos(t), minor * np.sin(p), -r * np.sin(t)], axis=-1)
    return _grid_mesh(pts, "torus")


def torus_knot(
    p: int = 2,
    q: int = 3,
    major: float = 1.0,
    minor: float = 0.4,
    tube: float = 0.18,
    segments: int = 256,
    sides: int = 24,
) -> Mesh:
    """(p, q) torus knot: a tube of radius ``tube`` around a curve winding p times around the y axis
    and q times through the hole of a torus (major, minor)."""
    t = np.linspace(0, 2 * np.pi, segments + 1)

    def curve(s):
        r = major + minor * np.cos(q * s)
        return np.stack([r * np.cos(p * s), minor * np.sin(q * s), -r * np.sin(p * s)], axis=-1)

    c = curve(t)
    tangent = curve(t + 1e-4) - curve(t - 1e-4)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    core = np.stack([major * np.cos(p * t), np.zeros_like(t), -major * np.sin(p * t)], axis=-1)
    ref = c - core  # points away from the torus core: a periodic, twist-free reference
    n = ref - (ref * tangent).sum(1, keepdims=True) * tangent
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    b = np.cross(n, tangent)  # (n, b, tangent) right-handed: the tube's faces wind outward
    a = np.linspace(0, 2 * np.pi, sides + 1)[:, None, None]
    pts = c[None] + tube * (np.cos(a) * n[None] + np.sin(a) * b[None])
    return _grid_mesh(pts, "torus-knot")


def superquadric(exponents=(0.4, 0.4), size=(1.0, 1.0, 1.0), segments: int = 96, rings: int = 64) -> Mesh:
    """Superellipsoid with east-west and north-south exponents (ε₁, ε₂): 1 gives an ellipsoid,
    small values a rounded box."""
    e1, e2 = exponents

    def spow(x, e):
        return np.sign(x) * np.abs(x) ** e

    th = np.linspace(-np.pi, np.pi, segments + 1)
    ph = np.linspace(-np.pi / 2, np.pi / 2, rings + 1)
    t, p = np.meshgrid(th, ph)
    pts = np.stack(
        [
            spow(np.cos(p), e2) * spow(np.cos(t), e1) * size[0],
            spow(np.sin(p), e2) * size[1],
            -spow(np.cos(p), e2) * spow(np.sin(t), e1) * size[2],
        ],
        axis=-1,
    )
    return _grid_mesh(pts, "superquadric")


def blob(radius: float = 1.0, bumpiness: float = 0.18, seed: int = 7, subdivisions: int = 128) -> Mesh:
    """A bumpy organic shape: a sphere displaced by a sum of seeded random low-frequency waves."""
    rng = np.random.default_rng(seed)
    m = sphere(1.0, subdivisions, subdivisions // 2)
    d = m.vertices.astype(np.float64)
    disp = np.zeros(len(d))
    for freq, amp in ((1.5, 1.0), (2.7, 0.55), (4.9, 0.3), (8.3, 0.12)):
        for _ in range(3):
            k = rng.normal(size=3)
            k *= freq / np.linalg.norm(k)
            disp += amp * np.sin(d @ k + rng.uniform(0, 2 * np.pi))
    disp /= np.abs(disp).max()
    v = d * (radius * (1 + bumpiness * disp))[:, None]
    return Mesh(v, m.faces, None, m.uvs, name="blob")


def gear(
    teeth: int = 14,
    radius: float = 1.0,
    tooth_depth: float = 0.16,
    hole: float = 0.35,
    thickness: float = 0.3,
    samples_per_tooth: int = 16,
) -> Mesh:
    """A spur gear with a bore: a creased mechanical part (flat faces meeting at sharp edges),
    axis along y, centred on the origin."""
    n = teeth * samples_per_tooth
    theta = np.linspace(0, 2 * np.pi, n, endpoint=False)
    phase = (theta * teeth / (2 * np.pi)) % 1.0
    # trapezoidal tooth over the first half of each period: rise, top land, fall; then bottom land
    profile = np.where(phase < 0.5, np.clip(phase / 0.15, 0, 1) * np.clip((0.5 - phase) / 0.15, 0, 1), 0)
    r_out = radius - tooth_depth + tooth_depth * np.minimum(profile * 1.6, 1.0)
    cos, sin = np.cos(theta), -np.sin(theta)
    h = thickness / 2
    outer_top = np.c_[r_out * cos, np.full(n, h), r_out * sin]
    outer_bot = np.c_[r_out * cos, np.full(n, -h), r_out * sin]
    inner_top = np.c_[hole * cos, np.full(n, h), hole * sin]
    inner_bot = np.c_[hole * cos, np.full(n, -h), hole * sin]
    v = np.r_[outer_top, outer_bot, inner_top, inner_bot]
    i = np.arange(n)
    j = (i + 1) % n
    ot, ob, it, ib = i, i + n, i + 2 * n, i + 3 * n
    otj, obj_, itj, ibj = j, j + n, j + 2 * n, j + 3 * n
    faces = np.r_[
        np.c_[ot, it, itj],
        np.c_[ot, itj, otj],  # top annulus (normal +y)
        np.c_[ob, obj_, ibj],
        np.c_[ob, ibj, ib],  # bottom annulus
        np.c_[ot, otj, obj_],
        np.c_[ot, obj_, ob],  # outer wall
        np.c_[it, ib, ibj],
        np.c_[it, ibj, itj],  # bore wall (facing the axis)
    ]
    # orient every face outward: top faces up, walls away from/towards the axis
    v64 = v.astype(np.float64)
    fn = np.cross(v64[faces[:, 1]] - v64[faces[:, 0]], v64[faces[:, 2]] - v64[faces[:, 0]])
    centre = v64[faces].mean(axis=1)
    expected = np.zeros_like(centre)
    k = len(faces) // 8
    expected[: 2 * k, 1] = 1
    expected[2 * k : 4 * k, 1] = -1
    radial = centre * np.array([1, 0, 1])
    expected[4 * k : 6 * k] = radial[4 * k : 6 * k]
    expected[6 * k :] = -radial[6 * k :]
    flip = (fn * expected).sum(axis=1) < 0
    faces[flip] = faces[flip][:, ::-1]
    vs, fs, ns, _ = crease_split(v, faces, 35.0)
    return Mesh(vs, fs, ns, None, name="gear")


def box(size=(1.0, 1.0, 1.0), uv_scale: float | None = None) -> Mesh:
    """Axis-aligned box centred on the origin with flat faces. uvs: metres / uv_scale when given
    (textures tile in world units), else 0..1 per face."""
    sx, sy, sz = (float(s) / 2 for s in size)
    axes = [
        ((1, 0, 0), (0, 0, -1), (0, 1, 0), sx, 2 * sz, 2 * sy),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0), sx, 2 * sz, 2 * sy),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1), sy, 2 * sx, 2 * sz),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1), sy, 2 * sx, 2 * sz),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0), sz, 2 * sx, 2 * sy),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0), sz, 2 * sx, 2 * sy),
    ]
    verts, norms, uvs, faces = [], [], [], []
    for k, (n, u, w, dist, lu, lw) in enumerate(axes):
        n, u, w = (np.asarray(x, float) for x in (n, u, w))
        centre = n * dist
        for cu, cw in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            verts.append(centre + u * cu * lu / 2 + w * cw * lw / 2)
            norms.append(n)
            s = (lu / uv_scale, lw / uv_scale) if uv_scale else (1.0, 1.0)
            uvs.append(((cu + 1) / 2 * s[0], (cw + 1) / 2 * s[1]))
        b = 4 * k
        faces += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
    return Mesh(np.array(verts), np.array(faces), np.array(norms), np.array(uvs), name="box")


def plane(size=(1.0, 1.0), uv_scale: float | None = None) -> Mesh:
    """A rectangle in the xz plane facing +y, centred on the origin. uvs: u along +x, v along −z."""
    w, d = size[0] / 2, size[1] / 2
    v = np.array([(-w, 0, d), (w, 0, d), (w, 0, -d), (-w, 0, -d)], float)
    s = (size[0] / uv_scale, size[1] / uv_scale) if uv_scale else (1.0, 1.0)
    uv = np.array([(0, 0), (s[0], 0), (s[0], s[1]), (0, s[1])], float)
    return Mesh(v, np.array([(0, 1, 2), (0, 2, 3)]), np.tile([0.0, 1.0, 0.0], (4, 1)), uv, name="plane")


def cylinder(radius: float = 0.5, height: float = 1.0, segments: int = 48, caps: bool = True) -> Mesh:
    """Cylinder along y, from y = 0 to y = height (it stands on the origin), sharp rims."""
    th = np.linspace(0, 2 * np.pi, segments, endpoint=False)
    ring = np.c_[radius * np.cos(th), np.zeros(segments), -radius * np.sin(th)]
    v = [ring, ring + [0, height, 0]]
    i = np.arange(segments)
    j = (i + 1) % segments
    faces = [np.c_[i, j, j + segments], np.c_[i, j + segments, i + segments]]
    if caps:
        v += [np.array([[0, 0, 0], [0, height, 0]])]
        c0, c1 = 2 * segments, 2 * segments + 1
        faces += [np.c_[np.full(segments, c0), j, i], np.c_[np.full(segments, c1), i + segments, j + segments]]
    vs, fs, ns, _ = crease_split(np.concatenate(v), np.concatenate(faces), 40.0)
    return Mesh(vs, fs, ns, None, name="cylinder")


def cone(radius: float = 0.5, height: float = 1.0, top_radius: float = 0.0, segments: int = 48) -> Mesh:
    """Truncated cone along y from y = 0 (radius) to y = height (top_radius), open (a lamp shade)."""
    th = np.linspace(0, 2 * np.pi, segments + 1)
    hh = np.array([0.0, height])
    t, y = np.meshgrid(th, hh)
    r = np.where(y == 0, radius, top_radius)
    pts = np.stack([r * np.cos(t), y, -r * np.sin(t)], axis=-1)
    return _grid_mesh(pts, "cone")


SHAPES = {
    "sphere": sphere,
    "torus": torus,
    "torus-knot": torus_knot,
    "superquadric": superquadric,
    "gear": gear,
    "blob": blob,
    "box": box,
    "cylinder": cylinder,
}


def shape(name: str) -> Mesh:
    """A built-in shape by name (see SHAPES), with default parameters."""
    from ...core.errors import InputError

    if name not in SHAPES:
        raise InputError(f"no built-in shape {name!r}; choose one of {', '.join(SHAPES)}")
    return SHAPES[name]()
