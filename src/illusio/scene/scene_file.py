"""Scenes made by other tools: glTF 2.0 (``.gltf``, ``.glb``) and OBJ with its MTL, read as a
:class:`Scene` that keeps the file's node and material names, colours, textures, lights and cameras.

trimesh reads the node graph, the transforms, the geometry with its uvs and the materials (glTF's
PBR materials, MTL's); pygltflib reads what trimesh drops: ``KHR_lights_punctual``, cameras,
``KHR_materials_emissive_strength``, ``KHR_texture_transform`` (applied to the uvs of the base colour
texture), the alpha cutoff, and the features illusio does not draw, named in one warning.

**Scene or shape** (:func:`is_scene_file`), one rule: a file with more than one mesh node, or any
material, light or camera, is a scene; any other mesh file is a shape that commands place on the
turntable (``--turntable`` forces that reading of a scene file).

**Materials** (glTF metallic-roughness onto Lambert + Phong), stated rules:
- diffuse colour = base colour factor × (1 − metallic); the base colour texture (sRGB, decoded to
  linear) multiplies it through the uvs;
- Phong specular k_s = 0.04·(1 − metallic) + metallic·mean(base colour factor); shininess
  n = 2/α² − 2 with α = roughness² (the Blinn-Phong exponent of the same highlight width),
  clamped to [1, 10⁴]. Absent factors take glTF's defaults (metallic 1, roughness 1);
- emission = emissive factor × emissive strength × the emissive texture's mean (linear);
- alpha mode MASK: opacity = the base colour factor's alpha × the texture's alpha, cut below
  ``alphaCutoff`` (default 0.5) in every rasterised pass and shadow; BLEND is drawn opaque (named);
- MTL: Kd is the diffuse colour (linear, as Blender's importer reads it; absent, 1 under a map_Kd and
  0.8 without), map_Kd its texture, Ks's mean k_s, Ns the shininess, Ke the emission. An MTL
  Blender wrote (its first line says so) holds Principled's terms: k_s = 0.08·Ks (the specular
  level's F0) and roughness 1 − √(Ns/1000), then the glTF rule above, so Blender's OBJ and glTF of
  one material agree. A node per
  ``o`` object, named after it ("object/material" for an object of several materials; a glTF mesh
  of several primitives likewise gives "node/material").

**Lights** (``KHR_lights_punctual``; photometric units converted with 683 lm/W, the luminous efficacy
at 555 nm), named by their node (else the light's own name): a point light of I cd is a
:class:`PointLight` of I/683 W/sr; a spot light is the point
light at its position (its cone is not drawn: named in the warning); a directional light of E lux is
a point light 100 scene radii away against its direction, of E/683 · d² W/sr, so its irradiance at
the scene is the same. A file with no light and no emissive material gets the turntable's two lamps
scaled to its bounds (said in the warning).

**Cameras**: a perspective camera is a named camera (its node's name, else the camera's); with none,
``main`` frames the scene's bounds. Its target (where IBR's rig of reference views looks) lies
along the view at the depth of the bounds' centre, or at the distance illusio's export wrote in the
camera's extras. Orthographic cameras are dropped (named in the warning).
"""

from __future__ import annotations

import io
import os
import warnings
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..core.images import srgb_to_linear
from .camera import Camera, Pose, View
from .mesh import Mesh, validate_arrays
from .scene import AreaLight, Material, Node, PointLight, Scene

__all__ = ["SCENE_FILE_FORMATS", "SceneFileWarning", "is_scene_file", "load_scene_file", "LUMENS_PER_WATT"]

SCENE_FILE_FORMATS = (".gltf", ".glb", ".obj")

#: lm/W: the luminous efficacy of 555 nm light, the photometric → radiometric factor
LUMENS_PER_WATT = 683.0

#: trimesh's OBJ reading: a node per ``o`` object (Blender writes one per object) and material
OBJ_OPTIONS = {"split_objects": True, "group_material": True}

#: how far a directional light's stand-in point light is, in scene radii
DIRECTIONAL_DISTANCE = 100.0


class SceneFileWarning(UserWarning):
    """What a scene file uses that illusio does not draw, or what it added (one line per file)."""


def is_scene_file(path: str | os.PathLike) -> bool:
    """Whether the mesh file at ``path`` is a scene (more than one mesh node, or any material, light
    or camera) rather than one shape for the turntable. False for formats that hold one mesh."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in SCENE_FILE_FORMATS or not p.is_file():
        return False
    if suffix == ".obj":
        return _obj_is_scene(p)
    gltf = _read_gltf(p)
    mesh_nodes = sum(1 for n in gltf.nodes if n.mesh is not None)
    lights = (gltf.extensions or {}).get("KHR_lights_punctual", {}).get("lights", [])
    return mesh_nodes > 1 or bool(gltf.materials) or bool(gltf.cameras) or bool(lights)


def _obj_is_scene(p: Path) -> bool:
    objects, materials = 0, False
    with open(p, "rb") as f:
        for raw in f:
            word = raw.split(maxsplit=1)[:1]
            if word == [b"o"]:
                objects += 1
            elif word in ([b"mtllib"], [b"usemtl"]):
                materials = True
    return objects > 1 or materials


def _read_gltf(p: Path):
    import pygltflib

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            gltf = pygltflib.GLTF2().load(str(p))
    except Exception as exc:  # pygltflib raises many kinds on corrupt input
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise InputError(f"{p}: cannot read glTF ({reason})") from None
    if gltf is None:
        raise InputError(f"{p}: cannot read glTF (not a glTF 2.0 file)")
    return gltf


def _check_external_files(p: Path, gltf) -> None:
    """InputError naming the first image or buffer file the glTF refers to and the folder lacks
    (trimesh would draw the scene without it)."""
    from urllib.parse import unquote

    for kind, items in (("image", gltf.images), ("buffer", gltf.buffers)):
        for k, item in enumerate(items or ()):
            uri = getattr(item, "uri", None)
            if uri and not uri.startswith("data:") and not (p.parent / unquote(uri)).is_file():
                raise InputError(f"{p}: {kind} {k} refers to {unquote(uri)!r}, which is not in {p.parent}")


def _check_obj_files(p: Path) -> None:
    """InputError naming the first material library or texture map an OBJ names and its folder lacks
    (trimesh would draw it untextured without a word)."""
    for library in _obj_words(p.read_bytes(), b"mtllib"):
        mtl = p.parent / library
        if not mtl.is_file():
            raise InputError(f"{p}: its material library {library!r} is not in {p.parent}")
        for image in _obj_words(mtl.read_bytes(), b"map_Kd", b"map_Ke"):
            if not (mtl.parent / image).is_file():
                raise InputError(f"{mtl}: texture {image!r} is not in {mtl.parent}")


def _obj_objects(data: bytes) -> list[str]:
    """The names of an OBJ's ``o`` objects, in file order."""
    out = []
    for line in data.splitlines():
        if line.startswith(b"o ") or line.startswith(b"o\t"):
            name = line[2:].strip().decode("utf-8", "replace")
            if name and name not in out:
                out.append(name)
    return out


def _obj_node_names(p: Path, tscene) -> dict[str, str]:
    """Each of trimesh's OBJ geometries named after its ``o`` object (trimesh names them
    "object_material" when the file has several materials); an object of several materials gives a
    node per material, "object/material"."""
    objects = set(_obj_objects(p.read_bytes()))
    owner = {}
    for name in tscene.graph.nodes_geometry:
        geometry = tscene.geometry[tscene.graph[name][1]]
        material = getattr(getattr(geometry.visual, "material", None), "name", None)
        stem = name[: -len(material) - 1] if material and name.endswith("_" + material) else name
        owner[name] = (stem, material) if stem in objects else (name, None)
    count = {}
    for stem, _ in owner.values():
        count[stem] = count.get(stem, 0) + 1
    return {
        name: f"{stem}/{material}" if count[stem] > 1 and material else stem for name, (stem, material) in owner.items()
    }


def _gltf_node_names(tscene) -> dict[str, str]:
    """Each of trimesh's geometry nodes named after its glTF node: a mesh of several primitives
    (Blender writes one per material) is a child per primitive, which trimesh names with a hash;
    those are "node/material"."""
    parents = tscene.graph.transforms.parents
    geometry_nodes = set(tscene.graph.nodes_geometry)
    children: dict = {}
    for name in geometry_nodes:
        children[parents.get(name)] = children.get(parents.get(name), 0) + 1
    out = {}
    for name in tscene.graph.nodes_geometry:
        parent = parents.get(name)
        if parent in (None, tscene.graph.base_frame) or parent in geometry_nodes or children[parent] < 2:
            out[name] = name
            continue
        geometry = tscene.geometry[tscene.graph[name][1]]
        material = getattr(getattr(geometry.visual, "material", None), "name", None)
        out[name] = f"{parent}/{material}" if material else name
    return out


def _obj_words(data: bytes, *keys: bytes) -> list[str]:
    """The file names after each of ``keys`` (the last word of the line: options such as -s come
    first in MTL)."""
    out = []
    for line in data.splitlines():
        words = line.split()
        if len(words) >= 2 and words[0] in keys:
            out.append(words[-1].decode("utf-8", "replace"))
    return out


def load_scene_file(path: str | os.PathLike) -> Scene:
    """The scene in the glTF or OBJ file at ``path`` (see the module docstring for the rules).
    InputError naming the file on anything it cannot read; one :class:`SceneFileWarning` listing
    what is not drawn."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    if p.suffix.lower() not in SCENE_FILE_FORMATS:
        raise InputError(f"{p}: not a scene file ({', '.join(SCENE_FILE_FORMATS)})")
    gltf = _read_gltf(p) if p.suffix.lower() != ".obj" else None
    if gltf is not None:
        _check_external_files(p, gltf)
    else:
        _check_obj_files(p)
    unsupported: list[str] = [] if gltf is None else _unsupported(gltf)
    try:
        scene = _scene_from_trimesh(p, _load_trimesh(p), gltf, unsupported)
        if gltf is not None:
            _lights_and_cameras(gltf, scene, unsupported)
            _scene_extras(gltf, scene)
    except InputError as exc:
        raise InputError(f"{p}: {exc}" if str(p) not in str(exc) else str(exc)) from None
    if not scene.cameras:
        scene.cameras["main"] = framing_view(scene)
    if not scene.lights and not any(max(n.material.emission) > 0 for n in scene.nodes):
        _add_lamps(scene)
        unsupported.append("no light in the file: two lamps added (key and fill, as the turntable's)")
    if unsupported:
        warnings.warn(f"{p}: " + "; ".join(unsupported), SceneFileWarning, stacklevel=2)
    return scene


def _load_trimesh(p: Path):
    import trimesh

    from .obj_indices import absolute_indices

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            absolute = absolute_indices(p.read_bytes()) if p.suffix.lower() == ".obj" else None
            if absolute is not None:  # relative indices: the spec's meaning, not trimesh's
                resolver = trimesh.resolvers.FilePathResolver(str(p))
                loaded = trimesh.load(
                    io.BytesIO(absolute),
                    file_type="obj",
                    resolver=resolver,
                    force="scene",
                    process=False,
                    **OBJ_OPTIONS,
                )
            else:
                options = OBJ_OPTIONS if p.suffix.lower() == ".obj" else {}
                loaded = trimesh.load(str(p), force="scene", process=False, **options)
    except Exception as exc:  # trimesh raises many kinds on corrupt input
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise InputError(f"{p}: cannot read scene ({reason})") from None
    return loaded


def _scene_from_trimesh(p: Path, tscene, gltf, unsupported: list[str]) -> Scene:
    import trimesh

    materials = _gltf_materials(gltf)
    extras = _node_extras(gltf)
    scene = Scene(p.stem)
    others = 0
    blender_mtl = gltf is None and _written_by_blender(p)
    if gltf is not None:
        names = _gltf_node_names(tscene)
        nodes = {n.name: i for i, n in enumerate(gltf.nodes)}
        order = {name: nodes.get(name.split("/")[0], len(nodes)) for name in names.values()}
    else:
        names = _obj_node_names(p, tscene)
        objects = _obj_objects(p.read_bytes())
        order = {n: objects.index(n.split("/")[0]) for n in names.values() if n.split("/")[0] in objects}
    for graph_name in sorted(tscene.graph.nodes_geometry, key=lambda n: order.get(names[n], len(order))):
        node_name = names[graph_name]
        own = extras.get(node_name, {})
        if "area_light" in own:  # illusio's own lamp, exported as a panel: read back as the lamp
            scene.lights.append(_area_light(own["area_light"], node_name))
            continue
        transform, geometry_name = tscene.graph[graph_name]
        geometry = tscene.geometry[geometry_name]
        if not isinstance(geometry, trimesh.Trimesh):
            others += 1
            continue
        vertices = np.asarray(geometry.vertices, np.float64)
        faces = np.asarray(geometry.faces, np.int64).reshape(-1, 3)
        validate_arrays(vertices, faces, f"node {node_name!r}")
        uv = getattr(geometry.visual, "uv", None)
        uvs = np.asarray(uv, np.float32) if uv is not None and len(uv) == len(vertices) else None
        # the file's normals (trimesh keeps them in its cache); else ours, computed by Mesh (trimesh's
        # angle-weighted ones take 0.8 s a million triangles)
        normals = geometry.vertex_normals if "vertex_normals" in geometry._cache else None
        used = np.zeros(len(vertices), bool)
        used[faces.reshape(-1)] = True
        if not used.all():  # a primitive's share of a buffer other primitives use too: not the file's count
            remap = np.cumsum(used) - 1
            vertices, faces = vertices[used], remap[faces]
            normals = None if normals is None else normals[used]
            uvs = None if uvs is None else uvs[used]
        material = _material(geometry.visual, materials, unsupported, blender_mtl)
        transform_uv = _texture_transform(
            materials.get(getattr(getattr(geometry.visual, "material", None), "name", None))
        )
        if uvs is not None and transform_uv is not None and material.texture is not None:
            uvs = _transformed_uvs(uvs, transform_uv)
        mesh = Mesh(vertices.astype(np.float32), faces.astype(np.int32), normals=normals, uvs=uvs, name=str(node_name))
        if material.texture is not None and uvs is None:
            unsupported.append(f"node {node_name!r}: a texture but no texture coordinates (drawn untextured)")
            material.texture = None
        scene.add(
            Node(
                _unique(scene, str(node_name)),
                mesh,
                np.asarray(transform, np.float64),
                material,
                tags=tuple(own.get("tags", ())),
                visible=bool(own.get("visible", True)),
            )
        )
    if others:
        unsupported.append(f"{others} point clouds or lines (no triangles)")
    if not scene.nodes:
        raise InputError(f"{p}: holds no triangle mesh")
    return scene


def _illusio_extras(item) -> dict:
    extras = getattr(item, "extras", None)
    own = extras.get("illusio") if isinstance(extras, dict) else None
    return own if isinstance(own, dict) else {}


def _node_extras(gltf) -> dict:
    """illusio's own data (written by illusio.scene.export) of each uniquely named glTF node."""
    if gltf is None:
        return {}
    names = [n.name for n in gltf.nodes]
    return {n.name: _illusio_extras(n) for n in gltf.nodes if n.name and names.count(n.name) == 1}


def _area_light(record: dict, name: str) -> AreaLight:
    try:
        return AreaLight(**{k: tuple(v) if isinstance(v, list) else v for k, v in record.items()})
    except TypeError as exc:
        raise InputError(f"node {name!r}: extras.illusio.area_light is not an area light ({exc})") from None


def _unique(scene: Scene, name: str) -> str:
    taken = {n.name for n in scene.nodes}
    candidate, k = name, 1
    while candidate in taken:
        k += 1
        candidate = f"{name}-{k}"
    return candidate


def _gltf_materials(gltf) -> dict:
    """glTF materials by name (unique names only): their float factors and extensions, which
    trimesh rounds to bytes or drops."""
    if gltf is None:
        return {}
    names = [m.name for m in gltf.materials]
    return {m.name: m for m in gltf.materials if m.name and names.count(m.name) == 1}


def _material(visual, gltf_materials: dict, unsupported: list[str], blender_mtl: bool = False) -> Material:
    from trimesh.visual.material import PBRMaterial, SimpleMaterial

    source = getattr(visual, "material", None)
    if isinstance(source, PBRMaterial):
        return _pbr_material(source, gltf_materials.get(source.name), unsupported)
    if isinstance(source, SimpleMaterial):
        return _mtl_material(source, blender_mtl)
    colours = getattr(visual, "vertex_colors", None) if getattr(visual, "kind", None) else None
    if colours is not None and len(colours):
        return Material(colour=srgb_to_linear(np.asarray(colours, np.float64)[:, :3].mean(axis=0) / 255))
    return Material()


def _factor(value, n: int, default) -> np.ndarray:
    if value is None:
        return np.asarray(default, np.float64)
    a = np.asarray(value, np.float64).reshape(-1)[:n]
    return a / 255 if np.asarray(value).dtype == np.uint8 else a


def _pixels(image, mode: str) -> np.ndarray:
    """A texture's pixels (float32 in [0, 1]) in PIL ``mode``: the image is decoded here (trimesh
    hands it over unread), so a damaged one is refused in one line, not a traceback."""
    from PIL import Image

    try:
        return np.asarray(image.convert(mode), np.float32) / 255
    except (OSError, ValueError, SyntaxError, IndexError, Image.DecompressionBombError) as exc:
        said = str(exc).strip().splitlines()
        raise InputError(f"a texture is not a readable image ({said[0] if said else type(exc).__name__})") from None


def _texture(image) -> np.ndarray | None:
    if image is None:
        return None
    return srgb_to_linear(_pixels(image, "RGB"))


def _opacity(image, factor: float) -> np.ndarray | None:
    """glTF's alpha: the base colour factor's alpha × the texture's (linear, not sRGB-coded)."""
    if image is None:
        return None
    return _pixels(image, "RGBA")[:, :, 3] * np.float32(factor)


def _pbr_material(source, gltf_material, unsupported: list[str]) -> Material:
    pbr = getattr(gltf_material, "pbrMetallicRoughness", None)
    base = _factor(getattr(pbr, "baseColorFactor", None) or source.baseColorFactor, 3, (1.0, 1.0, 1.0))
    metallic = float(_first(getattr(pbr, "metallicFactor", None), source.metallicFactor, 1.0))
    roughness = float(_first(getattr(pbr, "roughnessFactor", None), source.roughnessFactor, 1.0))
    emission = _factor(getattr(gltf_material, "emissiveFactor", None) or source.emissiveFactor, 3, (0.0, 0.0, 0.0))
    extensions = getattr(gltf_material, "extensions", None) or {}
    strength = float(extensions.get("KHR_materials_emissive_strength", {}).get("emissiveStrength", 1.0))
    emissive_texture = _texture(source.emissiveTexture)
    if emissive_texture is not None:
        emission = emission * emissive_texture.reshape(-1, 3).mean(axis=0)
    own = _illusio_extras(gltf_material)
    mode = getattr(gltf_material, "alphaMode", None) or getattr(source, "alphaMode", None)
    name = source.name or "unnamed"
    texture = _texture(source.baseColorTexture)
    opacity, cutoff = None, 0.5
    if mode == "BLEND":
        unsupported.append(f"material {name!r}: alpha blend (drawn opaque)")
    elif mode == "MASK":
        cutoff = float(_first(getattr(gltf_material, "alphaCutoff", None), getattr(source, "alphaCutoff", None), 0.5))
        factor = _factor(getattr(pbr, "baseColorFactor", None) or source.baseColorFactor, 4, (1.0, 1.0, 1.0, 1.0))
        factor_alpha = float(factor[3]) if len(factor) > 3 else 1.0
        opacity = _opacity(source.baseColorTexture, factor_alpha)
        if opacity is None and factor_alpha < cutoff:
            unsupported.append(f"material {name!r}: alpha mask cuts it all away (drawn opaque)")
    return Material(
        colour=tuple(np.clip(base * (1 - metallic), 0, 1)),
        texture=texture,
        specular=float(own.get("specular", np.clip(0.04 * (1 - metallic) + metallic * base.mean(), 0, 1))),
        shininess=float(own.get("shininess", _phong_exponent(roughness))),
        emission=tuple(emission * strength),
        opacity=opacity,
        alpha_cutoff=min(max(cutoff, 1e-6), 1.0),
    )


def _texture_transform(gltf_material) -> np.ndarray | None:
    """The 3×3 matrix of the base colour texture's ``KHR_texture_transform`` (glTF's uv convention,
    origin at the top left): translation · rotation · scale, as the extension defines it."""
    info = getattr(getattr(gltf_material, "pbrMetallicRoughness", None), "baseColorTexture", None)
    record = (getattr(info, "extensions", None) or {}).get("KHR_texture_transform")
    if not isinstance(record, dict):
        return None
    try:
        offset = np.asarray(record.get("offset", (0.0, 0.0)), np.float64).reshape(2)
        rotation = float(record.get("rotation", 0.0))
        scale = np.asarray(record.get("scale", (1.0, 1.0)), np.float64).reshape(2)
    except (TypeError, ValueError):
        raise InputError(
            f"material {gltf_material.name!r}: KHR_texture_transform is not offset/rotation/scale"
        ) from None
    if not (np.isfinite(offset).all() and np.isfinite(scale).all() and np.isfinite(rotation)):
        raise InputError(f"material {gltf_material.name!r}: KHR_texture_transform has a non-finite value")
    c, s = np.cos(rotation), np.sin(rotation)
    translation = np.array([[1, 0, offset[0]], [0, 1, offset[1]], [0, 0, 1]])
    rotate = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
    return translation @ rotate @ np.diag([scale[0], scale[1], 1.0])


def _transformed_uvs(uvs: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """``uvs`` as trimesh gives them (v up) through a glTF-convention (v down) uv matrix."""
    gltf_uv = np.c_[uvs[:, 0], 1.0 - uvs[:, 1], np.ones(len(uvs))] @ matrix.T
    return np.c_[gltf_uv[:, 0], 1.0 - gltf_uv[:, 1]].astype(np.float32)


def _first(*values):
    return next(v for v in values if v is not None)


def _phong_exponent(roughness: float) -> float:
    """n = 2/α² − 2 with α = roughness², in [1, 10⁴] (the Blinn-Phong lobe of the same width)."""
    alpha = max(roughness**2, 1e-3)
    return float(np.clip(2 / alpha**2 - 2, 1, 1e4))


def _written_by_blender(p: Path) -> bool:
    """Whether the OBJ's material libraries are Blender's (their first line says so)."""
    for library in _obj_words(p.read_bytes(), b"mtllib"):
        with open(p.parent / library, "rb") as f:
            if not f.readline().startswith(b"# Blender"):
                return False
    return bool(_obj_words(p.read_bytes(), b"mtllib"))


def _mtl_material(source, blender: bool = False) -> Material:
    kwargs = {str(k).lower(): v for k, v in (getattr(source, "kwargs", {}) or {}).items()}  # trimesh lowercases
    emission = kwargs.get("ke")
    ks = kwargs.get("ks", source.specular)  # the file's floats (trimesh rounds its own copy to bytes)
    specular = _factor(ks, 3, (0.0, 0.0, 0.0)) if ks is not None else np.zeros(3)
    shininess = float(np.clip(source.glossiness or 1.0, 1, 1e4))
    if blender:  # Ks is Principled's specular level (F0 = 0.08·Ks), Ns = 1000·(1 − roughness)²
        specular = 0.08 * specular
        shininess = _phong_exponent(1 - np.sqrt(np.clip(float(source.glossiness or 0.0), 0, 1000) / 1000))
    if "kd" in kwargs:
        colour = _factor(kwargs["kd"], 3, (0.8, 0.8, 0.8))
    else:  # no Kd: the texture alone (Blender writes no Kd where an image gives the colour), else 0.8
        colour = np.ones(3) if source.image is not None else np.full(3, 0.8)
    return Material(
        colour=tuple(np.clip(colour, 0, 1)),
        texture=_texture(source.image),
        specular=float(np.clip(specular.mean(), 0, 1)),
        shininess=shininess,
        emission=tuple(float(v) for v in np.asarray(emission, np.float64).reshape(-1)[:3])
        if emission is not None
        else (0.0, 0.0, 0.0),
    )


def _unsupported(gltf) -> list[str]:
    """What the file uses that illusio does not draw (the lights and cameras are checked as read)."""
    out = []
    counts = {
        "skins": len(gltf.skins or ()),
        "animations": len(gltf.animations or ()),
        "meshes with morph targets": sum(1 for m in gltf.meshes if any(p.targets for p in m.primitives)),
        "meshes with a second uv set (TEXCOORD_1)": sum(
            1 for m in gltf.meshes if any(getattr(p.attributes, "TEXCOORD_1", None) is not None for p in m.primitives)
        ),
    }
    out += [f"{n} {what}" for what, n in counts.items() if n]
    drawn = {"KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"}
    used = sorted(set(gltf.extensionsUsed or ()) - drawn)
    if used:
        out.append("extensions " + ", ".join(used))
    return out


def _node_matrices(gltf) -> list[np.ndarray]:
    """Each glTF node's local → world 4×4 (matrix, or translation · rotation · scale)."""
    from trimesh.transformations import quaternion_matrix

    local = []
    for node in gltf.nodes:
        if node.matrix is not None:
            m = np.asarray(node.matrix, np.float64).reshape(4, 4).T  # glTF stores columns
        else:
            m = np.eye(4)
            if node.scale is not None:
                m = np.diag([*node.scale, 1.0]) @ m
            if node.rotation is not None:
                x, y, z, w = node.rotation
                m = quaternion_matrix([w, x, y, z]) @ m
            if node.translation is not None:
                m[:3, 3] += node.translation
        if not np.isfinite(m).all():
            raise InputError(f"node {node.name or gltf.nodes.index(node)!r}: its transform is not finite")
        local.append(m)
    parent = {c: i for i, n in enumerate(gltf.nodes) for c in (n.children or ())}
    world: dict[int, np.ndarray] = {}

    def resolve(i: int, depth: int = 0) -> np.ndarray:
        if depth > len(gltf.nodes):
            raise InputError("the node hierarchy has a cycle")
        if i not in world:
            world[i] = (resolve(parent[i], depth + 1) if i in parent else np.eye(4)) @ local[i]
        return world[i]

    return [resolve(i) for i in range(len(gltf.nodes))]


def _lights_and_cameras(gltf, scene: Scene, unsupported: list[str]) -> None:
    lights = (gltf.extensions or {}).get("KHR_lights_punctual", {}).get("lights", [])
    matrices = _node_matrices(gltf)
    lo, hi = scene.bounds()
    centre, radius = (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
    for i, node in enumerate(gltf.nodes):
        m = matrices[i]
        position = m[:3, 3]
        forward = -m[:3, 2] / max(np.linalg.norm(m[:3, 2]), 1e-12)
        light_ref = (node.extensions or {}).get("KHR_lights_punctual")
        if light_ref is not None:
            index = light_ref.get("light")
            if not isinstance(index, int) or not 0 <= index < len(lights):
                raise InputError(f"node {node.name!r}: light {index!r} is not in KHR_lights_punctual")
            # the node's name, as for cameras (what Blender's outliner shows; its light data is "Light")
            name = _illusio_extras(node).get("name") or node.name or lights[index].get("name") or f"light-{index}"
            scene.lights.append(_light(lights[index], name, position, forward, centre, radius))
            scene.lights[-1].shadows = bool(_illusio_extras(node).get("shadows", True))
            if lights[index].get("type") == "spot":
                unsupported.append(f"spot light {scene.lights[-1].name!r}: its cone is not drawn (a point light)")
        if node.camera is not None:
            if not 0 <= node.camera < len(gltf.cameras):
                raise InputError(f"node {node.name!r}: camera {node.camera} does not exist")
            camera = gltf.cameras[node.camera]
            name = node.name or camera.name or f"camera-{node.camera}"
            if camera.type != "perspective" or camera.perspective is None:
                unsupported.append(f"orthographic camera {name!r}")
                continue
            p = camera.perspective
            near = float(p.znear or 0.05)
            far = float(p.zfar) if p.zfar else max(1000 * near, 4 * radius + float(np.linalg.norm(position - centre)))
            own = _illusio_extras(camera)
            up = m[:3, 1] / max(np.linalg.norm(m[:3, 1]), 1e-12)
            distance = own.get("target_distance") or max(float(np.dot(centre - position, forward)), near * 2)
            target = position + forward * float(distance)
            up = _written_up(own.get("up"), up, forward)
            lens = Camera(
                float(np.degrees(p.yfov)),
                near,
                far,
                shift=tuple(own.get("shift", (0.0, 0.0))),
                pixel_aspect=float(own.get("pixel_aspect", 1.0)),
            )
            scene.cameras[name] = View(Pose(tuple(position), tuple(target), tuple(up)), lens)


def _written_up(written, up: np.ndarray, forward: np.ndarray):
    """illusio's own up hint for a camera (export's extras) where the node's rotation still agrees
    with it (no roll added in another tool), else the node's own up axis."""
    if written is None:
        return up
    hint = np.asarray(written, np.float64)
    side = np.cross(forward, hint)
    if np.linalg.norm(side) < 1e-9:
        return up
    derived = np.cross(side / np.linalg.norm(side), forward)
    return hint if float(np.dot(derived, up)) > 1 - 1e-6 else up


def _light(light: dict, name: str, position, forward, centre, radius) -> PointLight:
    kind = light.get("type")
    colour = tuple(float(c) for c in light.get("color", (1.0, 1.0, 1.0)))
    intensity = float(light.get("intensity", 1.0))
    if kind in ("point", "spot"):
        return PointLight(tuple(position), colour, intensity / LUMENS_PER_WATT, name=name)
    if kind == "directional":
        distance = DIRECTIONAL_DISTANCE * radius
        return PointLight(
            tuple(centre - forward * distance), colour, intensity / LUMENS_PER_WATT * distance**2, name=name
        )
    raise InputError(f"light {name!r}: unknown type {kind!r} (point, spot or directional)")


def _scene_extras(gltf, scene: Scene) -> None:
    """The scene-wide data illusio.scene.export writes: name, ambient, background, curves, actions."""
    from .scene import Action, Curve

    own = _illusio_extras(gltf.scenes[gltf.scene or 0]) if gltf.scenes else {}
    scene.name = str(own.get("name", scene.name))
    for key in ("ambient", "background"):
        if key in own:
            setattr(scene, key, tuple(float(v) for v in own[key]))
    for record in own.get("curves", ()):
        scene.curves[record["name"]] = Curve(
            record["name"], np.asarray(record["points"]), record.get("kind", "polyline")
        )
    for record in own.get("actions", ()):
        scene.actions[record["name"]] = Action(record["name"], record["object"], record["curve"])


def framing_view(scene: Scene, azimuth: float = 30.0, elevation: float = 20.0, fov_y: float = 40.0) -> View:
    """A camera orbiting the centre of the scene's bounds that fits their bounding sphere in view."""
    lo, hi = scene.bounds()
    centre, radius = (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
    distance = radius * 1.1 / np.sin(np.radians(fov_y) / 2)
    pose = Pose.orbit(tuple(centre), distance, azimuth, elevation)
    return View(pose, Camera(fov_y, max(distance - 2 * radius, distance * 1e-3), distance + 2 * radius))


def _add_lamps(scene: Scene) -> None:
    lo, hi = scene.bounds()
    centre, radius = (lo + hi) / 2, max(float(np.linalg.norm(hi - lo)) / 2, 1e-6)
    side = 0.8 * radius
    scene.lights.append(
        AreaLight(
            tuple(centre + np.array([1.5, 3.0, 1.5]) * radius),
            (side, 0, 0),
            (0, 0, side),
            (1.0, 0.97, 0.92),
            35.0,
            name="key",
        )
    )
    scene.lights.append(
        PointLight(tuple(centre + np.array([-2.5, 1.0, 1.0]) * radius), (0.75, 0.85, 1.0), 2.5 * radius**2, name="fill")
    )
