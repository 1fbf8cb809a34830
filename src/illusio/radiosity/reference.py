"""The algorithms stated plainly, loop by loop: the specification the vectorised engine and the GPU
display are tested against (tests/radiosity/)."""

from __future__ import annotations

import math

import numpy as np

from ..scene.camera import View

__all__ = [
    "point_polygon_form_factor",
    "gather",
    "cluster_gather",
    "push_pull",
    "solve_dense",
    "display",
    "stream_uniform",
]


def point_polygon_form_factor(x, normal, corners) -> float:
    """F from the point x (normal n) to the polygon ``corners`` (m, 3), unoccluded:
    (1/2π)·|Σ_e γ_e · n·(R_e × R_{e+1}) / |R_e × R_{e+1}||, R_e = corner_e − x, over the polygon
    clipped to x's tangent plane (the part behind it cannot send x anything); 0 when x lies behind
    the polygon's plane (its normal (c_1 − c_0) × (c_{m−1} − c_0): a surface emits to its front)."""
    x, normal = np.asarray(x, float), np.asarray(normal, float)
    corners = [np.asarray(c, float) for c in corners]
    if np.cross(corners[1] - corners[0], corners[-1] - corners[0]) @ (x - corners[0]) <= 0:
        return 0.0
    clipped = []  # Sutherland–Hodgman: keep the corners above the plane, cut the edges that cross it
    for e in range(len(corners)):
        a, b = corners[e], corners[(e + 1) % len(corners)]
        ha, hb = float(normal @ (a - x)), float(normal @ (b - x))
        if ha >= 0:
            clipped.append(a)
        if (ha >= 0) != (hb >= 0):
            clipped.append(a + ha / (ha - hb) * (b - a))
    total = 0.0
    m = len(clipped)
    if m < 3:
        return 0.0
    for e in range(m):
        a = clipped[e] - x
        b = clipped[(e + 1) % m] - x
        c = np.cross(a, b)
        norm = float(np.linalg.norm(c))
        if norm < 1e-300:
            continue
        gamma = math.atan2(norm, float(a @ b))
        total += gamma * float(normal @ c) / norm
    return min(abs(total) / (2 * math.pi), 1.0)


def gather(receivers, sources, form_factors, visibilities, radiosity, n: int) -> np.ndarray:
    """H_i = Σ over links j → i of F_ij·V_ij·B_j, one link at a time."""
    h = np.zeros((n, 3))
    for i, j, f, v in zip(receivers, sources, form_factors, visibilities):
        h[i] += f * v * radiosity[j]
    return h


def cluster_gather(
    members, receivers, sources, kernels, visibilities, directions, area, normal, radiosity, n: int, twin=None
) -> np.ndarray:
    """The irradiance cluster links bring (radiosity.clusters): ``members[c]`` lists the roots of
    cluster c, a node is an element (≥ 0) or cluster −1 − c. A link carries E = V_ij·(G_ij·P_j +
    G'_ij·P'_j) (``kernels`` rows (G, G')): P_j = Σ A_k B_k over the source's members that are not
    ``twin`` (per element; default none is), P'_j over those that are (A_j B_j and 0 for an
    element). An element receiver gains E. A member k of receiving clusters gains Σ E_l·f(n_k·d_l)
    over every link l to a cluster holding it, f(x) = 3/32 + x/2 + 15/32·x² (the clamped cosine to
    order 2). One link, one member at a time."""
    twin = np.zeros(n, bool) if twin is None else np.asarray(twin, bool)
    h = np.zeros((n, 3))
    for i, j, g, v, d in zip(receivers, sources, kernels, visibilities, directions):
        if j >= 0:
            power = g[0] * area[j] * radiosity[j]
        else:
            power = sum((g[1 if twin[k] else 0] * area[k] * radiosity[k] for k in members[-1 - j]), np.zeros(3))
        e = v * np.asarray(power, float)
        if i >= 0:
            h[i] += e
            continue
        for k in members[-1 - i]:
            x = float(normal[k] @ np.asarray(d, float))
            h[k] += e * (3 / 32 + x / 2 + 15 / 32 * x * x)
    return h


def push_pull(parent, children, area, reflectance, exitance, irradiance, roots) -> np.ndarray:
    """B of every element, recursively from each root: push the irradiance gathered above down to the
    leaves, B = E + ρ·H there, and pull the area-weighted mean of the children's B up."""
    b = np.zeros((len(parent), 3))

    def visit(e, above):
        total = above + irradiance[e]
        kids = children[e]
        if not kids:
            b[e] = exitance[e] + reflectance[e] * total
        else:
            b[e] = sum(area[c] * visit(c, total) for c in kids) / area[e]
        return b[e]

    for r in roots:
        visit(r, np.zeros(3))
    return b


def solve_dense(exitance, reflectance, kernel) -> np.ndarray:
    """The radiosity equation on one level of elements, B = E + ρ·(K B), solved exactly:
    (I − diag(ρ) K) B = E per channel. ``kernel``: K[i, j] = F_ij·V_ij (n, n)."""
    n = len(exitance)
    out = np.zeros((n, 3))
    for c in range(3):
        out[:, c] = np.linalg.solve(np.eye(n) - reflectance[:, c, None] * kernel, exitance[:, c])
    return out


def display(positions, radiance, faces, view: View, size) -> tuple[np.ndarray, np.ndarray]:
    """The leaf mesh seen through the pixel centres: (radiance image (H, W, 3) interpolated with the
    barycentric coordinates of each hit, face index (H, W), −1 off the mesh). Rays cast with Embree."""
    from embreex import rtcore_scene
    from embreex.mesh_construction import TriangleMesh

    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, np.asarray(positions, np.float32)[np.asarray(faces)])
    w, h = size
    directions = view.ray_directions((w, h)).reshape(-1, 3).astype(np.float32)
    origins = np.repeat(np.asarray(view.pose.position, np.float32)[None], len(directions), axis=0)
    hit = scene.run(origins, directions, output=1)
    face = np.asarray(hit["primID"]).reshape(-1)
    u, v = np.asarray(hit["u"]), np.asarray(hit["v"])
    image = np.zeros((w * h, 3), np.float32)
    ok = face >= 0
    f = np.asarray(faces)[face[ok]]
    rad = np.asarray(radiance)
    image[ok] = (
        (1 - u[ok] - v[ok])[:, None] * rad[f[:, 0]] + u[ok][:, None] * rad[f[:, 1]] + v[ok][:, None] * rad[f[:, 2]]
    )
    return image.reshape(h, w, 3), face.reshape(h, w)


#: the display's plain statement under the name radiosity exports (relight's reference uses it)
reference_display = display


def stream_uniform(seed: int, counter: np.ndarray) -> np.ndarray:
    """Outputs ``counter`` of the SplitMix64 stream started at ``seed``: the state advances by the
    golden ratio 0x9E3779B97F4A7C15 before each output, and an output is the state through the
    finaliser z ← (z ⊕ z≫30)·0xBF58476D1CE4E5B9, z ← (z ⊕ z≫27)·0x94D049BB133111EB, z ⊕ z≫31
    (arithmetic mod 2⁶⁴), read as a double in [0, 1) from its top 53 bits."""
    z = np.uint64(seed) + (np.asarray(counter, np.uint64) + np.uint64(1)) * np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return (z >> np.uint64(11)).astype(np.float64) * 2.0**-53


def splitmix(z: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser (stream_uniform's) over uint64 values, mod 2⁶⁴."""
    z = np.asarray(z, np.uint64)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def element_uv(seed: int, elements: np.ndarray, t: np.ndarray, samples: int) -> np.ndarray:
    """(..., 2) point t of each element's own grid of ``samples`` points: a side × side grid
    (side = ⌈√samples⌉), the element's state s = splitmix(seed·φ + splitmix(element + 1)) (φ the
    golden ratio 0x9E3779B97F4A7C15), its shift splitmix(s + φ) mod side², point t in cell
    (shift + t·(side + 1)) mod side², jittered by outputs 2t + 1 and 2t + 2 of the stream started
    at s (stream_uniform's)."""
    golden = np.uint64(0x9E3779B97F4A7C15)
    side = int(np.ceil(np.sqrt(samples)))
    cells = side * side
    t = np.asarray(t, np.int64)
    with np.errstate(over="ignore"):
        state = splitmix(np.uint64(seed) * golden + splitmix(np.asarray(elements, np.uint64) + np.uint64(1)))
        shift = (splitmix(state + golden) % np.uint64(cells)).astype(np.int64)
        jitter = [
            (splitmix(state + (np.asarray(2 * t + extra, np.uint64) + np.uint64(1)) * golden) >> np.uint64(11)).astype(
                np.float64
            )
            * 2.0**-53
            for extra in (1, 2)
        ]
    cell = (shift + t * (side + 1)) % cells
    return np.stack([(cell % side + jitter[0]) / side, (cell // side + jitter[1]) / side], axis=-1)
