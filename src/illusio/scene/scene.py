"""Scenes: named nodes (mesh + transform + material + tags), lights, named cameras and curves.

A Scene is plain data; the GPU copy lives in ``illusio.passes.gpu_scene``. Units are metres,
colours linear RGB in [0, 1]. Light intensities:
- PointLight.intensity: radiant intensity I (W/sr); irradiance at distance r is I·cosθ/r².
- AreaLight.radiance: emitted radiance L of a one-sided rectangle, emitting along its normal.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError
from .camera import View
from .mesh import Mesh
from .transforms import identity

__all__ = ["Material", "Node", "PointLight", "AreaLight", "Curve", "Action", "Scene"]


def _vec(value, n: int, name: str) -> tuple[float, ...]:
    a = np.asarray(value, dtype=float).reshape(-1)
    if a.size == 1:
        a = np.repeat(a, n)
    if a.shape != (n,) or not np.isfinite(a).all():
        raise InputError(f"{name} must be {n} finite numbers, got {value!r}")
    return tuple(float(x) for x in a)


@dataclass
class Material:
    """Surface appearance for Lambert + Phong shading.

    colour: diffuse albedo ρ_d (linear RGB). texture: optional (H, W, 3) float32 image (row 0 on
    top) multiplied with colour through the mesh's uvs. specular: Phong coefficient k_s.
    shininess: Phong exponent n. emission: emitted radiance added as is (lamp shades, screens).
    opacity: optional (H, W) float32 in [0, 1] beside ``texture`` (glTF's alpha mask): where it is
    below ``alpha_cutoff`` the surface is cut away (not drawn, casts no shadow).
    """

    colour: tuple[float, float, float] = (0.7, 0.7, 0.7)
    texture: np.ndarray | None = None
    specular: float = 0.0
    shininess: float = 32.0
    emission: tuple[float, float, float] = (0.0, 0.0, 0.0)
    opacity: np.ndarray | None = None
    alpha_cutoff: float = 0.5

    def __post_init__(self):
        self.colour = _vec(self.colour, 3, "material colour")
        self.emission = _vec(self.emission, 3, "material emission")
        if not 0 <= self.specular <= 1 or not self.shininess >= 1:
            raise InputError(
                f"material needs specular in [0, 1] and shininess ≥ 1, got {self.specular}, {self.shininess}"
            )
        if self.texture is not None:
            t = np.asarray(self.texture, dtype=np.float32)
            if t.ndim == 2:
                t = np.repeat(t[:, :, None], 3, axis=2)
            if t.ndim != 3 or t.shape[2] not in (3, 4):
                raise InputError(f"material texture must be H×W×3, got shape {t.shape}")
            self.texture = t[:, :, :3]
        if self.opacity is not None:
            o = np.asarray(self.opacity, dtype=np.float32)
            if self.texture is None or o.shape != self.texture.shape[:2]:
                raise InputError(
                    f"material opacity must be H×W beside an H×W×3 texture, got {o.shape} and "
                    f"{None if self.texture is None else self.texture.shape}"
                )
            self.opacity = o
        if not 0 < self.alpha_cutoff <= 1:
            raise InputError(f"material alpha cutoff must be in (0, 1], got {self.alpha_cutoff}")

    def mean_albedo(self) -> np.ndarray:
        """(3,) float64: the colour × the texture's mean over its texels left by the alpha mask (the
        one reflectance of the surface, where a technique takes one per node)."""
        colour = np.asarray(self.colour, np.float64)
        if self.texture is None:
            return colour
        texels = np.asarray(self.texture, np.float64).reshape(-1, 3)
        if self.opacity is not None:
            kept = self.opacity.reshape(-1) >= self.alpha_cutoff
            texels = texels[kept] if kept.any() else texels
        return colour * texels.mean(axis=0)


@dataclass
class Node:
    """A mesh placed in the scene. ``transform``: local -> world 4×4; ``tags``: free labels
    techniques use to find things (``host`` for the surface an autostereogram is shown on)."""

    name: str
    mesh: Mesh
    transform: np.ndarray = field(default_factory=identity)
    material: Material = field(default_factory=Material)
    tags: tuple[str, ...] = ()
    visible: bool = True

    def __post_init__(self):
        from .mesh import as_mesh

        self.mesh = as_mesh(self.mesh)  # a trimesh.Trimesh is taken too
        self.transform = np.asarray(self.transform, dtype=np.float32).reshape(4, 4)
        if not np.isfinite(self.transform).all():
            raise InputError(f"node {self.name!r}: transform is not finite")
        self.tags = tuple(self.tags)


@dataclass
class PointLight:
    position: tuple[float, float, float]
    colour: tuple[float, float, float] = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    shadows: bool = True
    name: str = "light"

    def __post_init__(self):
        self.position = _vec(self.position, 3, "light position")
        self.colour = _vec(self.colour, 3, "light colour")

    def sample_points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(positions (K, 3), emitter normals (K, 3) or zeros for isotropic, weights (K, 3) RGB)."""
        return (
            np.array([self.position], np.float32),
            np.zeros((1, 3), np.float32),
            np.array([self.colour], np.float32) * self.intensity,
        )


@dataclass
class AreaLight:
    """A one-sided rectangular lamp: centre, two edge vectors (their cross product is the emitting
    normal, edge_u × edge_v), emitted radiance ``radiance`` × ``colour``. ``samples``: the lamp is
    approximated by samples × samples point emitters, each carrying L·cosθ_e·area/K."""

    centre: tuple[float, float, float]
    edge_u: tuple[float, float, float] = (0.5, 0.0, 0.0)
    edge_v: tuple[float, float, float] = (0.0, 0.0, -0.5)
    colour: tuple[float, float, float] = (1.0, 1.0, 1.0)
    radiance: float = 1.0
    samples: int = 2
    shadows: bool = True
    name: str = "lamp"

    def __post_init__(self):
        self.centre = _vec(self.centre, 3, "area light centre")
        self.edge_u = _vec(self.edge_u, 3, "area light edge_u")
        self.edge_v = _vec(self.edge_v, 3, "area light edge_v")
        self.colour = _vec(self.colour, 3, "area light colour")
        if not 1 <= int(self.samples) <= 8:
            raise InputError(f"area light samples must be 1..8 per side, got {self.samples}")
        if np.linalg.norm(self.normal_unnormalised) < 1e-12:
            raise InputError("area light edges are parallel or zero")

    @property
    def normal_unnormalised(self) -> np.ndarray:
        return np.cross(self.edge_u, self.edge_v)

    @property
    def normal(self) -> np.ndarray:
        n = self.normal_unnormalised
        return (n / np.linalg.norm(n)).astype(np.float32)

    @property
    def area(self) -> float:
        return float(np.linalg.norm(self.normal_unnormalised))

    def sample_points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        k = int(self.samples)
        t = (np.arange(k) + 0.5) / k - 0.5
        su, sv = np.meshgrid(t, t)
        pos = (
            np.asarray(self.centre)
            + su.reshape(-1, 1) * np.asarray(self.edge_u)
            + sv.reshape(-1, 1) * np.asarray(self.edge_v)
        )
        weight = np.asarray(self.colour) * self.radiance * self.area / (k * k)
        return (
            pos.astype(np.float32),
            np.repeat(self.normal[None], k * k, axis=0),
            np.repeat(weight[None], k * k, axis=0).astype(np.float32),
        )


@dataclass
class Curve:
    """A polyline or a cubic Bézier chain (control points P0 P1 P2 P3 P4 P5 P6 ..., 3n+1 points)."""

    name: str
    points: np.ndarray
    kind: str = "polyline"  # or "bezier"

    def __post_init__(self):
        self.points = np.asarray(self.points, dtype=np.float64).reshape(-1, 3)
        if self.kind not in ("polyline", "bezier"):
            raise InputError(f"curve {self.name!r}: kind must be polyline or bezier, got {self.kind!r}")
        if len(self.points) < 2 or (self.kind == "bezier" and (len(self.points) - 1) % 3):
            raise InputError(f"curve {self.name!r}: a polyline needs ≥ 2 points, a Bézier chain 3n+1")
        if not np.isfinite(self.points).all():
            raise InputError(f"curve {self.name!r}: points are not finite")

    def evaluate(self, t) -> np.ndarray:
        """Points at parameters t in [0, 1] (uniform in segment index), shape (..., 3)."""
        t = np.clip(np.asarray(t, dtype=np.float64), 0.0, 1.0)
        segments = len(self.points) - 1 if self.kind == "polyline" else (len(self.points) - 1) // 3
        s = np.minimum((t * segments).astype(int), segments - 1)
        u = (t * segments - s)[..., None]
        if self.kind == "polyline":
            return self.points[s] * (1 - u) + self.points[s + 1] * u
        p0, p1, p2, p3 = (self.points[3 * s + k] for k in range(4))
        return (1 - u) ** 3 * p0 + 3 * (1 - u) ** 2 * u * p1 + 3 * (1 - u) * u**2 * p2 + u**3 * p3


@dataclass(frozen=True)
class Action:
    """A scripted action (the scenario language's ``demarre action A objet N``): the node ``object``
    is placed where the actor N stands and sent along ``curve``, translated so that the curve's
    first point is at the actor (a projectile fired from N)."""

    name: str
    object: str
    curve: str


@dataclass
class Scene:
    """Everything that is drawn and from where. ``ambient``: constant irradiance-like term (linear
    RGB) standing in for indirect light; ``background``: colour where nothing is hit."""

    name: str = "scene"
    nodes: list[Node] = field(default_factory=list)
    lights: list[PointLight | AreaLight] = field(default_factory=list)
    cameras: dict[str, View] = field(default_factory=dict)
    curves: dict[str, Curve] = field(default_factory=dict)
    actions: dict[str, Action] = field(default_factory=dict)
    ambient: tuple[float, float, float] = (0.08, 0.08, 0.09)
    background: tuple[float, float, float] = (0.02, 0.02, 0.025)

    def add(self, node: Node) -> Node:
        if any(n.name == node.name for n in self.nodes):
            raise InputError(f"scene {self.name!r}: a node named {node.name!r} exists already")
        self.nodes.append(node)
        return node

    def node(self, name: str) -> Node:
        for n in self.nodes:
            if n.name == name:
                return n
        raise InputError(f"scene {self.name!r} has no node {name!r} (nodes: {', '.join(n.name for n in self.nodes)})")

    def tagged(self, tag: str) -> list[Node]:
        return [n for n in self.nodes if tag in n.tags]

    def camera(self, name: str | None = None) -> View:
        """The named camera, or the first one (``main`` when present) for None."""
        if not self.cameras:
            raise InputError(f"scene {self.name!r} has no camera")
        if name is None:
            return self.cameras.get("main", next(iter(self.cameras.values())))
        if name not in self.cameras:
            raise InputError(f"scene {self.name!r} has no camera {name!r} (cameras: {', '.join(self.cameras)})")
        return self.cameras[name]

    def bounds(self, nodes: Iterable[Node] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """World-space bounding box of the visible nodes."""
        from .transforms import transform_points

        pts = [
            transform_points(n.transform, np.array(_corners(*n.mesh.bounds)))
            for n in (nodes or self.nodes)
            if n.visible
        ]
        if not pts:
            raise InputError(f"scene {self.name!r} has nothing to draw")
        allp = np.concatenate(pts)
        return allp.min(axis=0), allp.max(axis=0)

    def check_in_view(self, view, size: tuple[int, int]) -> None:
        """InputError when ``view`` sees none of the visible nodes: every node's bounding box lies
        wholly outside one plane of the view frustum (near and far included). Conservative: a box
        that merely straddles planes counts as seen."""
        from .transforms import transform_points

        clip_from_world = np.asarray(view.view_projection(size), np.float64)
        for node in self.nodes:
            if not node.visible:
                continue
            corners = transform_points(node.transform, np.array(_corners(*node.mesh.bounds)))
            clip = np.c_[corners, np.ones(len(corners))] @ clip_from_world.T
            x, y, z, w = clip.T
            outside = [x < -w, x > w, y < -w, y > w, z < -w, z > w]
            if not any(side.all() for side in outside):
                return
        eye = ", ".join(f"{c:g}" for c in view.pose.position)
        target = ", ".join(f"{c:g}" for c in view.pose.target)
        lo, hi = (", ".join(f"{c:.3g}" for c in corner) for corner in self.bounds())
        raise InputError(
            f"the camera at ({eye}) looking at ({target}) sees nothing of scene {self.name!r}: "
            f"point it at the scene (its bounds run from ({lo}) to ({hi}))"
        )


def _corners(lo, hi):
    return [[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
