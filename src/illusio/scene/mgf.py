"""Greg Ward's Materials and Geometry Format (MGF), the format of the classic radiosity test scenes
(as RenderPark and Radiance read them), to a Scene — the subset those scenes use:

- contexts: ``o`` objects, ``xf`` transforms (``-t``, ``-rx/-ry/-rz``, ``-s``, ``-mx/-my/-mz``,
  nested; applied to geometry where it is used, as MGF's own parser does), ``i`` includes (relative
  to the including file, with transform arguments);
- materials: ``m`` (define with ``=``, or select), ``c`` colours with ``cxy``, ``cspec``, ``cct``;
  ``rd`` diffuse reflectance, ``ed`` diffuse emission, ``sides`` (2, MGF's default: the node is
  tagged ``two-sided`` and radiosity gives each face a reversed twin, lit on its own side, as
  RenderPark does; 1: the face as wound); ``rs`` (specular) is read and
  ignored (radiosity is diffuse), as are ``td``/``ts``/``ir`` (transmission);
- geometry: ``v`` with ``p`` and ``n``, ``f`` polygons (triangulated by earcut, oriented by their
  vertex normals where given), and ``sph``, ``cyl``, ``cone``, ``ring``, ``prism``, ``torus``
  tessellated with ``segments`` sides around.

Colours: a chromaticity to linear sRGB through CIE XYZ, balanced so that MGF's white (x = y = 1/3)
is neutral; ``rd`` scales it (so ``rd`` is the luminous reflectance); ``ed``, a luminous exitance (lm/m²),
gives the exitance ed/683 W/m² in that colour (emitted radiance: that over π). MGF has no up axis and the classic
scenes differ (office2 and the cube have z up, office3 y up): by default up is the axis the lamps
face away from (ceiling lamps shine down), else the one along which the scene is thinnest, else
``up`` says; the scene is
turned to illusio's y up. A main camera is placed inside the scene's bounds. Unsupported entities are named in one
warning; a malformed one
is an InputError naming the file and the line."""

from __future__ import annotations

import math
import warnings
from collections import Counter
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.files import read_text
from .camera import Camera, Pose, View
from .mesh import Mesh
from .scene import Material, Node, Scene

__all__ = ["load_mgf", "SEGMENTS", "chromaticity_rgb"]

#: MGF's ed is a luminous exitance (lm/m²): divided by the efficacy of 555 nm light for W/m²
LUMENS_PER_WATT = 683.0
#: sides around a tessellated sphere, cylinder, cone, ring or torus (a sphere has half as many rings)
SEGMENTS = 12
#: a file's up axis to illusio's y up: z up turned by (x, y, z) → (x, z, −y); x up by (x, y, z) → (−y, x, z)
TO_Y_UP = {
    "x": np.array([[0, -1.0, 0, 0], [1.0, 0, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]]),
    "y": np.eye(4),
    "z": np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0], [0, -1.0, 0, 0], [0, 0, 0, 1.0]]),
}
_XYZ_TO_SRGB = np.array([[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]])


def _xy_rgb(x: float, y: float) -> np.ndarray:
    xyz = np.array([x / y, 1.0, (1.0 - x - y) / y])
    return _XYZ_TO_SRGB @ xyz


_WHITE = _xy_rgb(1 / 3, 1 / 3)


def chromaticity_rgb(x: float, y: float) -> np.ndarray:
    """Linear sRGB of luminance 1 at chromaticity (x, y), MGF's white (1/3, 1/3) mapped to grey."""
    rgb = _xy_rgb(x, y) / _WHITE
    return np.maximum(rgb, 0.0) / max(float(np.dot([0.2126, 0.7152, 0.0722], np.maximum(rgb, 0.0))), 1e-9)


def _cmf(wavelength: np.ndarray) -> np.ndarray:
    """CIE 1931 2° colour matching functions, (n, 3), by the multi-lobe fit of Wyman, Sloan &
    Shirley (2013): a few piecewise Gaussians, within a few per cent of the tables."""

    def g(mu, s1, s2):
        s = np.where(wavelength < mu, s1, s2)
        return np.exp(-0.5 * ((wavelength - mu) / s) ** 2)

    x = 1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2)
    y = 0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1)
    z = 1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8)
    return np.stack([x, y, z], axis=-1)


def _spectrum_xy(wavelength: np.ndarray, power: np.ndarray) -> tuple[float, float]:
    xyz = (_cmf(wavelength) * power[:, None]).sum(axis=0)
    total = float(xyz.sum())
    if not total > 0:
        raise ValueError("a spectrum with no power in the visible range")
    return float(xyz[0] / total), float(xyz[1] / total)


@dataclass
class _Colour:
    x: float = 1 / 3
    y: float = 1 / 3

    def rgb(self) -> np.ndarray:
        return chromaticity_rgb(self.x, self.y)


#: the largest reflectance a surface is given (radiosity's iteration converges only below 1)
MAX_REFLECTANCE = 0.98


@dataclass
class _Material:
    rd: float = 0.0
    rd_colour: _Colour = field(default_factory=_Colour)
    ed: float = 0.0
    ed_colour: _Colour = field(default_factory=_Colour)
    colour: _Colour = field(default_factory=_Colour)  # the material's current colour context
    #: MGF's sides: 2 (its default) a two-sided surface (tagged ``two-sided``: radiosity gives each
    #: face a reversed twin, as RenderPark does); 1 the face as wound
    sides: int = 2

    def material(self) -> Material:
        rho = np.clip(self.rd * self.rd_colour.rgb(), 0.0, MAX_REFLECTANCE)  # radiosity needs ρ < 1
        emission = self.ed / LUMENS_PER_WATT * self.ed_colour.rgb() / math.pi  # exitance → radiance
        return Material(colour=tuple(rho), emission=tuple(emission))


@dataclass
class _Vertex:
    p: np.ndarray | None = None
    n: np.ndarray | None = None


def _xf_matrix(args: list[str], where: str) -> np.ndarray:
    """An ``xf`` argument list as one 4×4 (each transform applied after the ones before it)."""
    m = np.eye(4)
    k = 0

    def number() -> float:
        nonlocal k
        k += 1
        try:
            return float(args[k])
        except (IndexError, ValueError):
            raise InputError(f"{where}: xf {args[k - 1]} needs a number") from None

    while k < len(args):
        word = args[k]
        step = np.eye(4)
        if word == "-t":
            step[:3, 3] = [number(), number(), number()]
        elif word in ("-rx", "-ry", "-rz"):
            a = math.radians(number())
            c, s = math.cos(a), math.sin(a)
            i, j = {"-rx": (1, 2), "-ry": (2, 0), "-rz": (0, 1)}[word]
            step[i, i], step[i, j], step[j, i], step[j, j] = c, -s, s, c
        elif word == "-s":
            value = number()
            if not value > 0:
                raise InputError(f"{where}: xf -s needs a positive scale, got {value:g}")
            step[:3, :3] *= value
        elif word in ("-mx", "-my", "-mz"):
            step["xyz".index(word[2]), "xyz".index(word[2])] = -1.0
        else:
            raise InputError(f"{where}: xf {word} is not read (read: -t, -rx, -ry, -rz, -s, -mx, -my, -mz)")
        m = step @ m
        k += 1
    return m


@dataclass
class _State:
    segments: int
    materials: dict[str, _Material] = field(default_factory=dict)
    colours: dict[str, _Colour] = field(default_factory=dict)
    vertices: dict[str, _Vertex] = field(default_factory=dict)
    material: _Material = field(default_factory=_Material)
    material_name: str = "default"
    colour: _Colour = field(default_factory=_Colour)
    vertex: _Vertex | None = None
    objects: list[str] = field(default_factory=list)
    transforms: list[np.ndarray] = field(default_factory=lambda: [np.eye(4)])
    #: (object path, material name) -> (triangles (n, 3, 3), its Material, its sides: 1 or 2)
    geometry: dict[tuple[str, str], list] = field(default_factory=dict)
    ignored: Counter = field(default_factory=Counter)
    #: lines of ``rd 1`` (read as the reflectance cap, MAX_REFLECTANCE)
    full_reflectance: list[str] = field(default_factory=list)

    def point(self, name: str, where: str) -> np.ndarray:
        v = self.vertices.get(name)
        if v is None or v.p is None:
            raise InputError(f"{where}: vertex {name!r} is not defined (or has no p)")
        return (self.transforms[-1] @ np.append(v.p, 1.0))[:3]

    def normal(self, name: str) -> np.ndarray | None:
        v = self.vertices.get(name)
        if v is None or v.n is None or not np.linalg.norm(v.n) > 0:
            return None
        n = np.linalg.inv(self.transforms[-1][:3, :3]).T @ v.n
        return n / np.linalg.norm(n)

    def scale(self) -> float:
        return float(abs(np.linalg.det(self.transforms[-1][:3, :3])) ** (1 / 3))

    def add(self, triangles: np.ndarray) -> None:
        key = ("/".join(self.objects) or "scene", self.material_name)
        entry = self.geometry.setdefault(key, [[], self.material.material(), self.material.sides])
        entry[0].append(np.asarray(triangles, np.float64).reshape(-1, 3, 3))


def _triangulate(points: np.ndarray, normal: np.ndarray | None, where: str) -> np.ndarray:
    """(n, 3) polygon → (m, 3, 3) triangles facing ``normal`` (its vertex normals) or its winding."""
    import mapbox_earcut

    if len(points) < 3:
        raise InputError(f"{where}: a face needs at least 3 vertices")
    area = np.zeros(3)
    for a, b in zip(points, np.roll(points, -1, axis=0)):
        area += np.cross(a, b)  # Newell's normal: 2 × area
    if not np.linalg.norm(area) > 1e-12:
        return np.zeros((0, 3, 3))  # degenerate: nothing to draw
    axis = area / np.linalg.norm(area)
    u = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    v = np.cross(axis, u)
    flat = np.c_[points @ u, points @ v]
    if len(points) == 3:
        index = np.array([0, 1, 2])
    else:
        index = np.asarray(mapbox_earcut.triangulate_float64(flat, np.array([len(points)], np.uint32)), np.int64)
    tris = points[index.reshape(-1, 3)]
    e = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    tris = np.where((e @ axis < 0)[:, None, None], tris[:, ::-1], tris)  # every triangle as the polygon winds
    if normal is not None and float(axis @ normal) < 0:
        tris = tris[:, ::-1]  # the file's normals say which side
    return tris


def _frame(axis: np.ndarray):
    axis = axis / np.linalg.norm(axis)
    u = np.cross(axis, [1.0, 0, 0] if abs(axis[0]) < 0.9 else [0, 1.0, 0])
    u /= np.linalg.norm(u)
    return axis, u, np.cross(axis, u)


def _grid(ring_points: list[np.ndarray]) -> np.ndarray:
    """Quads between successive closed rings of points (each (k, 3)), as triangles."""
    tris = []
    for a, b in zip(ring_points[:-1], ring_points[1:]):
        a2, b2 = np.roll(a, -1, axis=0), np.roll(b, -1, axis=0)
        tris.append(np.stack([a, b, b2], axis=1))
        tris.append(np.stack([a, b2, a2], axis=1))
    return np.concatenate(tris)


def _circle(centre, axis, radius, segments):
    _, u, v = _frame(np.asarray(axis, np.float64))
    t = np.linspace(0, 2 * math.pi, segments, endpoint=False)
    return np.asarray(centre) + radius * (np.cos(t)[:, None] * u + np.sin(t)[:, None] * v)


def _primitive(state: _State, kind: str, args: list[str], where: str) -> np.ndarray:
    s = state.segments

    def num(k: int) -> float:
        try:
            return float(args[k])
        except (IndexError, ValueError):
            raise InputError(f"{where}: {kind} expects {_SHAPES[kind]}") from None

    if kind == "sph":
        c, r = state.point(args[0] if args else "", where), num(1) * state.scale()
        rings = []
        for k in range(1, s // 2):
            polar = math.pi * k / (s // 2)
            rings.append(_circle(c + np.array([0, 0, r * math.cos(polar)]), (0, 0, 1), r * math.sin(polar), s))
        tris = [_grid(rings)]
        top, bottom = c + (0, 0, r), c - (0, 0, r)
        tris.append(np.stack([np.repeat(top[None], s, 0), rings[0], np.roll(rings[0], -1, 0)], axis=1))
        tris.append(np.stack([np.repeat(bottom[None], s, 0), np.roll(rings[-1], -1, 0), rings[-1]], axis=1))
        out = np.concatenate(tris)
        return out if num(1) > 0 else out[:, ::-1]  # a negative radius faces inwards
    if kind in ("cyl", "cone"):
        a = state.point(args[0] if args else "", where)
        if kind == "cyl":
            b, r0 = state.point(args[2] if len(args) > 2 else "", where), num(1)
            r1 = r0
        else:
            b, r0, r1 = state.point(args[2] if len(args) > 2 else "", where), num(1), num(3)
        axis = b - a
        if not np.linalg.norm(axis) > 0:
            raise InputError(f"{where}: {kind} has its two ends at one point")
        k = state.scale()
        out = _grid([_circle(a, axis, abs(r0) * k, s), _circle(b, axis, abs(r1) * k, s)])[:, ::-1]
        return out if (r0 if kind == "cyl" else max(r0, r1)) > 0 else out[:, ::-1]
    if kind == "ring":
        c, normal = state.point(args[0] if args else "", where), state.normal(args[0] if args else "")
        if normal is None:
            raise InputError(f"{where}: ring needs a vertex with a normal (n)")
        r0, r1 = sorted((num(1) * state.scale(), num(2) * state.scale()))
        if r0 <= 0:
            fan = _circle(c, normal, r1, s)
            return np.stack([np.repeat(c[None], s, 0), fan, np.roll(fan, -1, 0)], axis=1)
        return _grid([_circle(c, normal, r0, s), _circle(c, normal, r1, s)])
    if kind == "torus":
        c, normal = state.point(args[0] if args else "", where), state.normal(args[0] if args else "")
        if normal is None:
            raise InputError(f"{where}: torus needs a vertex with a normal (n)")
        inner, outer = sorted((num(1) * state.scale(), num(2) * state.scale()))
        major, minor = (inner + outer) / 2, (outer - inner) / 2
        axis, u, v = _frame(normal)
        rings = []
        for k in range(s + 1):
            t = 2 * math.pi * k / s
            radial = math.cos(t) * u + math.sin(t) * v
            rings.append(
                c
                + major * radial
                + minor
                * (
                    np.cos(np.linspace(0, 2 * math.pi, s, endpoint=False))[:, None] * radial
                    + np.sin(np.linspace(0, 2 * math.pi, s, endpoint=False))[:, None] * axis
                )
            )
        return _grid(rings)
    if kind == "prism":
        if len(args) < 4:
            raise InputError(f"{where}: prism expects {_SHAPES['prism']}")
        points = np.array([state.point(a, where) for a in args[:-1]])
        length = num(len(args) - 1) * state.scale()
        cap = _triangulate(points, None, where)
        axis = np.cross(cap[0, 1] - cap[0, 0], cap[0, 2] - cap[0, 0])
        offset = length * axis / np.linalg.norm(axis)
        sides = _grid([points[::-1], (points + offset)[::-1]])
        return np.concatenate([cap[:, ::-1], cap + offset, sides])
    raise AssertionError(kind)


_SHAPES = {
    "sph": "a centre vertex and a radius",
    "cyl": "a vertex, a radius and a vertex",
    "cone": "a vertex, a radius, a vertex and a radius",
    "ring": "a centre vertex and two radii",
    "torus": "a centre vertex and two radii",
    "prism": "three or more vertices and a length",
}
#: read and not used: specular, transmission, index of refraction, and what RenderPark ignores too
_IGNORED = {
    "rs": "specular",
    "td": "transmission",
    "ts": "transmission",
    "ir": "index of refraction",
    "cmix": "colour mixtures",
    "ies": "IES luminaires",
    "fh": "faces with holes",
    "es": "specular emission",
}


def _parse(path: Path, state: _State, depth: int = 0) -> None:
    if depth > 16:
        raise InputError(f"{path}: includes nested more than 16 deep")
    text = read_text(path, "MGF scene")
    lines = text.replace("\\\n", " ").splitlines()
    for number, line in enumerate(lines, 1):
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        where = f"{path}:{number}"
        kind, args = words[0], words[1:]
        try:
            _entity(path, state, kind, args, where, depth)
        except InputError:
            raise
        except (ValueError, IndexError) as exc:
            raise InputError(f"{where}: malformed {kind} ({exc})") from None


def _numbers(args: list[str], count: int, kind: str, where: str) -> np.ndarray:
    if len(args) != count:
        raise InputError(f"{where}: {kind} takes {count} numbers, got {len(args)}")
    try:
        values = np.array([float(a) for a in args])
    except ValueError:
        raise InputError(f"{where}: {kind} takes numbers, got {' '.join(args)!r}") from None
    if not np.isfinite(values).all():
        raise InputError(f"{where}: {kind} holds a non-finite number")
    return values


def _entity(path: Path, state: _State, kind: str, args: list[str], where: str, depth: int) -> None:
    if kind == "o":
        if args:
            state.objects.append(args[0])
        elif state.objects:
            state.objects.pop()
    elif kind == "xf":
        if args:
            state.transforms.append(state.transforms[-1] @ _xf_matrix(args, where))
        elif len(state.transforms) > 1:
            state.transforms.pop()
    elif kind == "i":
        if not args:
            raise InputError(f"{where}: i needs a file name")
        target = path.parent / args[0]
        if not target.is_file():
            raise InputError(f"{where}: included file {args[0]} not found")
        if len(args) > 1:
            state.transforms.append(state.transforms[-1] @ _xf_matrix(args[1:], where))
        _parse(target, state, depth + 1)
        if len(args) > 1:
            state.transforms.pop()
    elif kind == "m":
        if not args:
            state.material, state.material_name = _Material(), "default"
        elif len(args) >= 2 and args[1] == "=":
            base = state.materials.get(args[2]) if len(args) > 2 else None
            state.material = replace(base) if base is not None else _Material()
            state.materials[args[0]] = state.material
            state.material_name = args[0]
        else:
            if args[0] not in state.materials:
                raise InputError(f"{where}: material {args[0]!r} is not defined")
            state.material, state.material_name = state.materials[args[0]], args[0]
    elif kind == "c":
        if not args:
            state.material.colour = _Colour()
        elif len(args) >= 2 and args[1] == "=":
            state.colours[args[0]] = state.material.colour = _Colour()
        else:
            if args[0] not in state.colours:
                raise InputError(f"{where}: colour {args[0]!r} is not defined")
            state.material.colour = replace(state.colours[args[0]])
    elif kind == "cxy":
        x, y = _numbers(args, 2, kind, where)
        if not (x >= 0 and y > 0 and x + y <= 1):
            raise InputError(f"{where}: cxy needs a chromaticity with x ≥ 0, y > 0, x + y ≤ 1, got {x:g} {y:g}")
        state.material.colour.x, state.material.colour.y = float(x), float(y)
    elif kind == "cspec":
        values = _numbers(args, len(args), kind, where)
        if len(values) < 4 or not values[0] < values[1]:
            raise InputError(f"{where}: cspec takes λmin λmax and two or more samples")
        wavelength = np.linspace(values[0], values[1], len(values) - 2)
        state.material.colour.x, state.material.colour.y = _spectrum_xy(wavelength, values[2:])
    elif kind == "cct":
        (temperature,) = _numbers(args, 1, kind, where)
        if not temperature > 0:
            raise InputError(f"{where}: cct needs a positive temperature")
        wavelength = np.linspace(380.0, 780.0, 81)
        lam = wavelength * 1e-9
        planck = 1.0 / (lam**5 * (np.exp(1.4388e-2 / (lam * temperature)) - 1.0))
        state.material.colour.x, state.material.colour.y = _spectrum_xy(wavelength, planck)
    elif kind == "rd":
        (value,) = _numbers(args, 1, kind, where)
        if not 0 <= value <= 1:
            raise InputError(f"{where}: rd must be in [0, 1], got {value:g}")
        if value >= 1:  # RenderPark reads it too (and warns): all the light reflected
            state.full_reflectance.append(where.rpartition(":")[2] or where)
        state.material.rd, state.material.rd_colour = float(value), replace(state.material.colour)
    elif kind == "ed":
        (value,) = _numbers(args, 1, kind, where)
        if not value >= 0:
            raise InputError(f"{where}: ed must be ≥ 0, got {value:g}")
        state.material.ed, state.material.ed_colour = float(value), replace(state.material.colour)
    elif kind == "sides":
        (value,) = _numbers(args, 1, kind, where)
        if value not in (1, 2):
            raise InputError(f"{where}: sides is 1 or 2, got {value:g}")
        state.material.sides = int(value)
    elif kind == "v":
        if len(args) < 2 or args[1] != "=":
            raise InputError(f"{where}: a vertex is defined as 'v NAME ='")
        base = state.vertices.get(args[2]) if len(args) > 2 else None
        state.vertex = _Vertex(base.p, base.n) if base is not None else _Vertex()
        state.vertices[args[0]] = state.vertex
    elif kind in ("p", "n"):
        if state.vertex is None:
            raise InputError(f"{where}: {kind} outside a vertex definition (v NAME =)")
        setattr(state.vertex, kind, _numbers(args, 3, kind, where))
    elif kind == "f":
        points = np.array([state.point(a, where) for a in args])
        normals = [state.normal(a) for a in args]
        known = [n for n in normals if n is not None]
        state.add(_triangulate(points, np.mean(known, axis=0) if known else None, where))
    elif kind in _SHAPES:
        state.add(_primitive(state, kind, args, where))
    elif kind in _IGNORED:
        state.ignored[f"{kind} ({_IGNORED[kind]})"] += 1
    else:
        state.ignored[kind] += 1


def _guess_up(state: _State, geometry: dict, points: np.ndarray) -> str:
    """The axis lamps face away from (ceiling lamps shine down), else the one along which the scene
    is thinnest (a room is wider than it is tall)."""
    facing = np.zeros(3)
    for key, (_, mat, _) in state.geometry.items():
        if max(mat.emission) > 0 and len(geometry[key]):
            t = geometry[key]
            facing += np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]).sum(axis=0)  # area-weighted
    if np.linalg.norm(facing) > 0:
        d = facing / np.linalg.norm(facing)
        k = int(np.argmax(np.abs(d)))
        if d[k] < -0.7:
            return "xyz"[k]
    return "xyz"[int(np.argmin(np.ptp(points, axis=0)))]


def load_mgf(path, segments: int = SEGMENTS, up: str = "auto") -> Scene:
    """The MGF file at ``path`` (and what it includes) as a Scene: a node per object and material,
    in metres if the file's units are (MGF has none), turned so that ``up`` ("x", "y", "z", or
    "auto": the axis of the smallest extent) is y. Raises InputError naming the file and line of a
    malformed entity; warns once naming what was ignored."""
    p = Path(path)
    if up not in ("auto", "x", "y", "z"):
        raise InputError(f"MGF up axis must be auto, x, y or z, got {up!r}")
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    if not 3 <= segments <= 256:
        raise InputError(f"MGF tessellation takes 3 to 256 segments, got {segments}")
    state = _State(segments)
    _parse(p, state)
    if state.ignored:
        warnings.warn(
            f"{p.name}: MGF entities read and not used: "
            + ", ".join(f"{name} × {count}" for name, count in sorted(state.ignored.items())),
            stacklevel=2,
        )
    if state.full_reflectance:
        lines = state.full_reflectance
        warnings.warn(
            f"{p.name}: rd 1 at line{'s' if len(lines) > 1 else ''} {', '.join(lines[:5])}"
            f"{' …' if len(lines) > 5 else ''}: read as {MAX_REFLECTANCE:g} (a surface reflecting all its light "
            "never lets a closed room's radiosity converge)",
            stacklevel=2,
        )
    scene = Scene(p.stem, ambient=(0.0, 0.0, 0.0), background=(0.0, 0.0, 0.0))
    names = Counter()
    geometry = {key: np.concatenate(parts) for key, (parts, _, _) in state.geometry.items()}
    points = np.concatenate([t.reshape(-1, 3) for t in geometry.values()]) if geometry else np.zeros((0, 3))
    if up == "auto" and len(points):
        up = _guess_up(state, geometry, points)
    turn = TO_Y_UP.get(up, TO_Y_UP["z"])
    for (obj, material), (_, mat, sides) in state.geometry.items():
        tris = geometry[obj, material]
        if not len(tris):
            continue
        world = (np.c_[tris.reshape(-1, 3), np.ones(len(tris) * 3)] @ turn.T)[:, :3]
        name = f"{obj}/{material}"
        names[name] += 1
        if names[name] > 1:
            name = f"{name}-{names[name]}"
        mesh = Mesh(world, np.arange(len(world)).reshape(-1, 3), name=name)
        tags = (("emitter",) if max(mat.emission) > 0 else ()) + (("two-sided",) if sides == 2 else ())
        scene.add(Node(name, mesh, material=mat, tags=tags))
    if not scene.nodes:
        raise InputError(f"{p}: no geometry (f, sph, cyl, cone, ring, prism or torus)")
    lo, hi = scene.bounds()
    centre, extent = (lo + hi) / 2, hi - lo
    eye = centre + np.array([0.35, 0.1, 0.35]) * extent  # inside, near a corner, a little high
    target = centre - np.array([0.2, 0.1, 0.2]) * extent
    diagonal = float(np.linalg.norm(extent))
    scene.cameras["main"] = View(Pose(tuple(eye), tuple(target)), Camera(60.0, diagonal * 1e-3, diagonal * 4))
    return scene
