"""load_scene: a built-in scene by name, or a scene described in a YAML file.

Schema (every key optional unless marked; units metres and degrees; colours linear RGB)::

    name: my-scene
    ambient: [0.05, 0.05, 0.05]
    background: [0, 0, 0]
    cameras:
      main: {position: [3, 2, 4], target: [0, 0.5, 0], up: [0, 1, 0], fov: 45, near: 0.05, far: 50}
    nodes:
      - name: floor                      # required, unique
        shape: plane                     # a built-in shape (see SHAPE_BUILDERS) ...
        params: {size: [6, 6], uv_scale: 1}
      - name: statue
        mesh: models/bunny.obj           # ... or a mesh file, relative to the YAML file
        normalise: 1.0                   # optional: rescale to this largest extent, resting on y = 0
        position: [0, 0, 0]
        rotation: [0, 30, 0]             # about x, then y, then z
        scale: 1.0                       # or [sx, sy, sz]
        material: {colour: [0.8, 0.7, 0.6], specular: 0.2, shininess: 40, emission: [0, 0, 0],
                   texture: checker}     # checker | planks | tiles | fabric | wallpaper | an image path
        tags: [host]
    lights:
      - {type: point, position: [2, 3, 2], colour: [1, 1, 1], intensity: 8, shadows: true}
      - {type: area, centre: [0, 2.9, 0], edge_u: [1, 0, 0], edge_v: [0, 0, 0.5], radiance: 8, samples: 2}
    curves:
      - {name: path, kind: bezier, points: [[0, 1, 3], [1, 1, 3], [2, 1, 2], [2, 1, 0]]}
    actions:                             # for scenarios (dof): the node sent along the curve from the actor
      - {name: fire, object: projectile, curve: path}

Every mistake raises InputError naming the file, the line and what was wrong.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from ..core.errors import IllusioError, InputError, did_you_mean
from ..core.files import read_yaml
from .builtin import shapes as builtin_shapes
from .builtin import textures as builtin_textures
from .builtin.scenes import SCENES, builtin_scene
from .camera import Camera, Pose, View
from .mesh import load_mesh
from .scene import Action, AreaLight, Curve, Material, Node, PointLight, Scene
from .transforms import compose, rotate_euler, scale, translate

__all__ = ["load_scene", "scene_from_dict", "SHAPE_BUILDERS"]

SHAPE_BUILDERS = {
    "plane": builtin_shapes.plane,
    "box": builtin_shapes.box,
    "sphere": builtin_shapes.sphere,
    "torus": builtin_shapes.torus,
    "torus-knot": builtin_shapes.torus_knot,
    "superquadric": builtin_shapes.superquadric,
    "gear": builtin_shapes.gear,
    "blob": builtin_shapes.blob,
    "cylinder": builtin_shapes.cylinder,
    "cone": builtin_shapes.cone,
}
TEXTURES = {
    "checker": builtin_textures.checker,
    "planks": builtin_textures.planks,
    "tiles": builtin_textures.tiles,
    "fabric": builtin_textures.fabric,
    "wallpaper": builtin_textures.wallpaper,
}


def load_scene(source: str | os.PathLike) -> Scene:
    """A built-in scene name (``living-room``, ``office``, ``museum``, ``turntable``), a YAML path,
    an MGF file (``.mgf``: the classic radiosity scenes; :mod:`illusio.scene.mgf`) or a glTF or OBJ
    scene as other tools write it (:func:`illusio.scene.scene_file.load_scene_file`)."""
    text = str(source)
    if text in SCENES:
        return builtin_scene(text)
    p = Path(source)
    if p.suffix.lower() == ".mgf":
        from .mgf import load_mgf

        return load_mgf(p)
    from .scene_file import SCENE_FILE_FORMATS, load_scene_file

    if p.suffix.lower() in SCENE_FILE_FORMATS:
        return load_scene_file(p)
    if p.suffix.lower() not in (".yaml", ".yml"):
        if not p.exists():
            raise InputError(
                f"{text}: not a built-in scene ({', '.join(SCENES)}) nor a YAML file{did_you_mean(text, SCENES)}"
            )
        raise InputError(f"{p}: scene files must be .yaml, .yml, .mgf, .glb, .gltf or .obj")
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    data = read_yaml(p, "scene")
    if not isinstance(data, dict):
        raise InputError(f"{p}: a scene file must be a mapping with nodes, lights, cameras")
    return scene_from_dict(data, base=p.parent, origin=str(p))


def _section(data: dict, key: str, kind: type, origin: str):
    """``data[key]`` when it is a ``kind`` (list or mapping), empty when absent."""
    value = data.get(key)
    if value is None:
        return kind()
    if not isinstance(value, kind):
        raise InputError(
            f"{origin}: {key} must be a {'list' if kind is list else 'mapping'}, got {type(value).__name__}"
        )
    return value


def _check_keys(d: dict, allowed: set[str], where: str) -> None:
    if not isinstance(d, dict):
        raise InputError(f"{where}: expected a mapping, got {type(d).__name__}")
    unknown = set(d) - allowed
    if unknown:
        raise InputError(
            f"{where}: unknown key(s) {', '.join(sorted(map(str, unknown)))}; allowed: {', '.join(sorted(allowed))}"
        )


def scene_from_dict(data: dict[str, Any], base: Path = Path("."), origin: str = "scene") -> Scene:
    """Build a Scene from the YAML schema above (already parsed)."""
    _check_keys(data, {"name", "ambient", "background", "cameras", "nodes", "lights", "curves", "actions"}, origin)
    try:
        scene = Scene(str(data.get("name", Path(origin).stem)))
        if "ambient" in data:
            scene.ambient = tuple(np.broadcast_to(np.asarray(data["ambient"], float), (3,)))
        if "background" in data:
            scene.background = tuple(np.broadcast_to(np.asarray(data["background"], float), (3,)))
        for i, nd in enumerate(_section(data, "nodes", list, origin)):
            scene.add(_node(nd, base, f"{origin}: nodes[{i}]"))
        for i, ld in enumerate(_section(data, "lights", list, origin)):
            scene.lights.append(_light(ld, f"{origin}: lights[{i}]"))
        for name, cd in _section(data, "cameras", dict, origin).items():
            scene.cameras[str(name)] = _camera(cd, f"{origin}: cameras.{name}")
        for i, cd in enumerate(_section(data, "curves", list, origin)):
            _check_keys(cd, {"name", "kind", "points"}, f"{origin}: curves[{i}]")
            curve = Curve(str(cd.get("name", f"curve-{i}")), cd.get("points", []), cd.get("kind", "polyline"))
            scene.curves[curve.name] = curve
        for i, ad in enumerate(_section(data, "actions", list, origin)):
            where = f"{origin}: actions[{i}]"
            _check_keys(ad, {"name", "object", "curve"}, where)
            action = Action(str(ad.get("name", f"action-{i}")), str(ad["object"]), str(ad["curve"]))
            if action.object not in {n.name for n in scene.nodes}:
                raise InputError(f"{where}: no node named {action.object!r}")
            if action.curve not in scene.curves:
                raise InputError(f"{where}: no curve named {action.curve!r}")
            scene.actions[action.name] = action
    except IllusioError:
        raise
    except (TypeError, ValueError, KeyError) as exc:
        raise InputError(f"{origin}: invalid value ({exc})") from None
    if not scene.nodes:
        raise InputError(f"{origin}: the scene has no nodes")
    if not scene.cameras:
        lo, hi = scene.bounds()
        centre = (lo + hi) / 2
        scene.cameras["main"] = View(
            Pose.orbit(tuple(centre), float(np.linalg.norm(hi - lo)) * 1.2, 30, 25), Camera(45.0, 0.05, 1000.0)
        )
    return scene


def _node(nd: dict, base: Path, where: str) -> Node:
    _check_keys(
        nd,
        {
            "name",
            "shape",
            "params",
            "mesh",
            "normalise",
            "position",
            "rotation",
            "scale",
            "material",
            "tags",
            "visible",
        },
        where,
    )
    if "name" not in nd:
        raise InputError(f"{where}: a node needs a name")
    where = f"{where} ({nd['name']})"
    if ("shape" in nd) == ("mesh" in nd):
        raise InputError(f"{where}: give exactly one of shape or mesh")
    if "shape" in nd:
        if nd["shape"] not in SHAPE_BUILDERS:
            raise InputError(f"{where}: unknown shape {nd['shape']!r}; choose one of {', '.join(SHAPE_BUILDERS)}")
        try:
            mesh = SHAPE_BUILDERS[nd["shape"]](**(nd.get("params") or {}))
        except TypeError as exc:
            raise InputError(f"{where}: bad shape params ({exc})") from None
    else:
        mesh = load_mesh(base / str(nd["mesh"]))
    if "normalise" in nd:
        mesh = mesh.normalised(float(nd["normalise"]))
    transform = compose(
        translate(nd.get("position", (0, 0, 0))),
        rotate_euler(nd.get("rotation", (0, 0, 0))),
        scale(nd.get("scale", 1.0)),
    )
    return Node(
        str(nd["name"]),
        mesh,
        transform,
        _material(nd.get("material") or {}, base, where),
        tuple(nd.get("tags") or ()),
        bool(nd.get("visible", True)),
    )


def _material(md: dict, base: Path, where: str) -> Material:
    _check_keys(md, {"colour", "color", "specular", "shininess", "emission", "texture"}, f"{where}: material")
    texture = None
    if "texture" in md:
        t = str(md["texture"])
        if t in TEXTURES:
            texture = TEXTURES[t]()
        else:
            from ..core.images import read_image

            texture = read_image(base / t)[..., :3]
    colour = md.get("colour", md.get("color", (1, 1, 1) if texture is not None else (0.7, 0.7, 0.7)))
    return Material(
        colour, texture, float(md.get("specular", 0.0)), float(md.get("shininess", 32.0)), md.get("emission", (0, 0, 0))
    )


def _light(ld: dict, where: str):
    kind = ld.get("type", "point") if isinstance(ld, dict) else None
    if kind == "point":
        _check_keys(ld, {"type", "position", "colour", "color", "intensity", "shadows", "name"}, where)
        return PointLight(
            ld["position"],
            ld.get("colour", ld.get("color", (1, 1, 1))),
            float(ld.get("intensity", 1.0)),
            bool(ld.get("shadows", True)),
            str(ld.get("name", "light")),
        )
    if kind == "area":
        _check_keys(
            ld,
            {
                "type",
                "centre",
                "center",
                "edge_u",
                "edge_v",
                "colour",
                "color",
                "radiance",
                "samples",
                "shadows",
                "name",
            },
            where,
        )
        return AreaLight(
            ld.get("centre", ld.get("center")),
            ld.get("edge_u", (0.5, 0, 0)),
            ld.get("edge_v", (0, 0, 0.5)),
            ld.get("colour", ld.get("color", (1, 1, 1))),
            float(ld.get("radiance", 1.0)),
            int(ld.get("samples", 2)),
            bool(ld.get("shadows", True)),
            str(ld.get("name", "lamp")),
        )
    raise InputError(f"{where}: light type must be point or area, got {kind!r}")


def _camera(cd: dict, where: str) -> View:
    _check_keys(cd, {"position", "target", "up", "fov", "near", "far"}, where)
    pose = Pose(
        tuple(cd.get("position", (0, 1, 3))), tuple(cd.get("target", (0, 0, 0))), tuple(cd.get("up", (0, 1, 0)))
    )
    return View(pose, Camera(float(cd.get("fov", 45.0)), float(cd.get("near", 0.05)), float(cd.get("far", 100.0))))
