"""Scenes made by other tools (glTF written by trimesh and pygltflib, OBJ with MTL and a PNG written by
trimesh, as Blender and public sample sets make them) keep their names, colours, textures, lights and
cameras; the built-in scenes round-trip through glTF; bad files give one line."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from illusio.scene.scene_file import LUMENS_PER_WATT, SceneFileWarning, is_scene_file, load_scene_file
from illusio.scene.sources import resolve_scene
from tests.cli.test_cli import assert_one_line_error, illusio

trimesh = pytest.importorskip("trimesh")
pygltflib = pytest.importorskip("pygltflib")


def _checker(n=64, cell=8):
    from PIL import Image

    return Image.fromarray(((np.indices((n, n)) // cell).sum(0) % 2 * 180 + 40).astype(np.uint8)).convert("RGB")


def make_room(path, extras=None):
    """Six meshes with PBR base colours, an image texture, an emissive panel (made by trimesh), a
    KHR_lights_punctual point light and a perspective camera (added with pygltflib)."""
    from trimesh.visual.material import PBRMaterial

    scene = trimesh.Scene()

    def add(mesh, name, colour, at, **kw):
        uv = kw.pop("uv", None)
        material = PBRMaterial(
            name=name + "-paint", baseColorFactor=colour, metallicFactor=0.0, roughnessFactor=0.6, **kw
        )
        mesh.visual = trimesh.visual.TextureVisuals(uv=uv, material=material)
        scene.add_geometry(
            mesh, node_name=name, geom_name=name, transform=trimesh.transformations.translation_matrix(at)
        )

    floor = trimesh.creation.box((6, 0.1, 6))
    add(
        floor,
        "floor",
        [1.0, 1.0, 1.0, 1.0],
        [0, -0.05, 0],
        uv=floor.vertices[:, [0, 2]] / 6 + 0.5,
        baseColorTexture=_checker(),
    )
    add(trimesh.creation.box((0.8, 0.8, 0.8)), "red-box", [0.8, 0.1, 0.1, 1.0], [-1, 0.4, 0])
    add(trimesh.creation.icosphere(3, 0.5), "green-ball", [0.1, 0.7, 0.2, 1.0], [1, 0.5, 0])
    add(trimesh.creation.cylinder(0.3, 1.2), "blue-pillar", [0.1, 0.2, 0.8, 1.0], [0, 0.6, -1.2])
    add(
        trimesh.creation.box((1.0, 0.6, 0.02)),
        "panel",
        [0.1, 0.1, 0.1, 1.0],
        [0, 1.5, -2.5],
        emissiveFactor=[1.0, 0.9, 0.6],
    )
    add(trimesh.creation.box((0.4, 0.4, 0.4)), "yellow-cube", [0.9, 0.8, 0.1, 1.0], [0.2, 0.2, 1.2])
    scene.export(str(path))
    gltf = pygltflib.GLTF2().load(str(path))
    gltf.extensionsUsed = ["KHR_lights_punctual"]
    gltf.extensions = {
        "KHR_lights_punctual": {
            "lights": [{"type": "point", "color": [1, 0.95, 0.9], "intensity": 6000.0, "name": "bulb"}]
        }
    }
    gltf.cameras = [
        pygltflib.Camera(
            type="perspective", name="cam", perspective=pygltflib.Perspective(yfov=0.8, znear=0.1, zfar=50.0)
        )
    ]
    tilt = -0.4  # about x: looking down
    gltf.nodes.append(
        pygltflib.Node(name="lamp-node", translation=[0.5, 3.0, 1.0], extensions={"KHR_lights_punctual": {"light": 0}})
    )
    gltf.nodes.append(
        pygltflib.Node(
            name="shot", camera=0, translation=[0, 2.5, 5.0], rotation=[math.sin(tilt / 2), 0, 0, math.cos(tilt / 2)]
        )
    )
    gltf.scenes[0].nodes += [len(gltf.nodes) - 2, len(gltf.nodes) - 1]
    for change in extras or ():
        change(gltf)
    gltf.save(str(path))
    return path


@pytest.fixture(scope="module")
def room(tmp_path_factory):
    return make_room(tmp_path_factory.mktemp("room") / "room.glb")


def test_a_glb_keeps_its_names_colours_texture_emission_light_and_camera(room):
    assert is_scene_file(room)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing dropped, nothing to say
        scene = load_scene_file(room)
    assert [n.name for n in scene.nodes] == ["floor", "red-box", "green-ball", "blue-pillar", "panel", "yellow-cube"]
    box = scene.node("red-box").material
    written = pygltflib.GLTF2().load(str(room))  # trimesh wrote the factor through a byte: 0.1 → 26/255
    factor = next(m for m in written.materials if m.name == "red-box-paint").pbrMetallicRoughness.baseColorFactor
    assert np.allclose(box.colour, factor[:3], atol=1e-7)  # metallic 0: the base colour, exactly
    assert box.shininess == pytest.approx(2 / 0.6**4 - 2)  # n = 2/α² − 2, α = roughness²
    floor = scene.node("floor")
    assert floor.material.texture is not None and floor.mesh.uvs is not None
    # the checker's dark and light cells, decoded from sRGB: 40/255 → 0.0213, 220/255 → 0.716
    assert sorted(np.unique(np.round(floor.material.texture, 3)))[:1] == [pytest.approx(0.021, abs=1e-3)]
    assert np.allclose(scene.node("panel").material.emission, (1.0, 0.9, 0.6))
    (bulb,) = scene.lights
    # named by its node, as cameras are
    assert bulb.name == "lamp-node" and bulb.intensity == pytest.approx(6000 / LUMENS_PER_WATT)
    assert np.allclose(bulb.position, (0.5, 3.0, 1.0))
    (name,) = scene.cameras
    view = scene.camera("shot")
    assert name == "shot" and view.camera.fov_y == pytest.approx(math.degrees(0.8))
    right, up, forward = view.pose.axes()
    assert np.allclose(forward, (0, math.sin(-0.4), -math.cos(-0.4)), atol=1e-6)


def test_a_rendered_glb_shows_its_colours_where_its_camera_sees_them(room, ctx):
    from illusio.passes.scene_renderer import render_scene

    scene = load_scene_file(room)
    view = scene.camera()
    size = (160, 100)
    image = render_scene(scene, view, size, ctx)
    for name, channel in (("red-box", 0), ("green-ball", 1)):
        node = scene.node(name)
        centre = node.transform[:3, 3] + (node.mesh.bounds[0] + node.mesh.bounds[1]) / 2
        pixels, _ = view.project(centre[None], size)
        x, y = (int(v) for v in pixels[0])
        pixel = image[y, x, :3]
        others = [c for c in range(3) if c != channel]
        assert pixel[channel] > 2 * pixel[others].max(), (name, pixel)
    # the emissive panel is bright: its centre at least its emission
    panel = scene.node("panel").transform[:3, 3]
    pixels, _ = view.project(panel[None], size)
    x, y = (int(v) for v in pixels[0])
    assert image[y, x, 0] >= 0.99


def test_the_scene_or_shape_rule(tmp_path, room):
    plain = trimesh.creation.icosphere(2)
    plain.export(tmp_path / "ball.glb")
    plain.export(tmp_path / "ball.obj")
    assert not is_scene_file(tmp_path / "ball.glb") and not is_scene_file(tmp_path / "ball.obj")
    assert resolve_scene(str(tmp_path / "ball.glb")).name == "turntable"
    assert resolve_scene(str(room)).name == "room"
    assert resolve_scene(str(room), on_turntable=True).name == "turntable"  # --on-turntable


def test_an_obj_with_its_mtl_and_png_keeps_materials_and_texture_and_counts_nothing_dropped(tmp_path):
    """As trimesh writes a textured OBJ (mtllib, usemtl, map_Kd, per-corner uvs: seams), plus a
    second object with a colour-only material."""
    ball = trimesh.creation.icosphere(3)
    ball.visual = trimesh.visual.TextureVisuals(uv=(ball.vertices[:, :2] + 1) / 2, image=_checker(32, 4))
    folder = tmp_path / "obj"
    folder.mkdir()
    ball.export(folder / "ball.obj")
    assert {p.suffix for p in folder.iterdir()} == {".obj", ".mtl", ".png"}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = load_scene_file(folder / "ball.obj")
    (said,) = [str(w.message) for w in caught]
    assert said.endswith("no light in the file: two lamps added (key and fill, as the turntable's)")
    (node,) = scene.nodes
    assert node.material.texture is not None and node.mesh.uvs is not None
    assert len(node.mesh.vertices) == len(ball.vertices)  # all used: nothing dropped
    assert scene.lights and scene.cameras  # none in the file: added (lamps said in a warning)


def test_an_obj_of_two_materials_and_uv_seams(tmp_path):
    """A cube as Blender writes it: 8 positions, 4 uvs a face, two materials from the .mtl."""
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = ["mtllib cube.mtl", "o Cube"] + [f"v {x} {y} {z}" for x, y, z in corners]
    lines += ["vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1"]
    for k, quad in enumerate(quads):
        lines.append("usemtl " + ("wood" if k < 3 else "paint"))
        lines.append("f " + " ".join(f"{v + 1}/{t + 1}" for t, v in enumerate(quad)))
    (tmp_path / "cube.obj").write_text("\n".join(lines) + "\n")
    (tmp_path / "cube.mtl").write_text("newmtl wood\nKd 0.8 0.5 0.2\nmap_Kd wood.png\nnewmtl paint\nKd 0.1 0.3 0.9\n")
    _checker(16, 4).save(tmp_path / "wood.png")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = load_scene_file(tmp_path / "cube.obj")
    assert not [w for w in caught if "unreferenced" in str(w.message)]
    colours = sorted(tuple(n.material.colour) for n in scene.nodes)
    assert np.allclose(colours, [(0.1, 0.3, 0.9), (0.8, 0.5, 0.2)], atol=0.5 / 255)  # trimesh keeps Kd in bytes
    wood = next(n for n in scene.nodes if n.material.texture is not None)
    assert sum(len(n.mesh.faces) for n in scene.nodes) == 12 and wood.mesh.uvs is not None


def test_what_is_not_drawn_is_named_in_one_warning(tmp_path):
    def spot_and_transmission(gltf):
        gltf.extensions["KHR_lights_punctual"]["lights"][0]["type"] = "spot"
        gltf.extensionsUsed += ["KHR_materials_transmission"]

    path = make_room(tmp_path / "spot.glb", [spot_and_transmission])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_scene_file(path)
    said = [str(w.message) for w in caught if issubclass(w.category, SceneFileWarning)]
    assert len(said) == 1 and "spot light 'lamp-node'" in said[0] and "KHR_materials_transmission" in said[0]


@pytest.mark.parametrize("name", ["cornell-box", "living-room", "office", "museum", "futuristic", "turntable"])
def test_every_builtin_scene_round_trips_through_gltf(name, tmp_path, ctx):
    """Exported and read back: the same nodes, lamps and cameras, and the same image within 2/255
    (8-bit sRGB textures) — the tolerance table of docs/scene-files.md."""
    from illusio.passes.scene_renderer import render_scene
    from illusio.scene import builtin_scene
    from illusio.scene.export import export_gltf

    original = builtin_scene(name)
    export_gltf(original, tmp_path / f"{name}.glb")
    back = load_scene_file(tmp_path / f"{name}.glb")
    assert [n.name for n in back.nodes] == [n.name for n in original.nodes]
    assert sorted(light.name for light in back.lights) == sorted(light.name for light in original.lights)
    assert list(back.cameras) == list(original.cameras) and back.curves.keys() == original.curves.keys()
    assert [n.tags for n in back.nodes] == [n.tags for n in original.nodes]
    for camera in original.cameras:
        a = render_scene(original, original.camera(camera), (128, 80), ctx)
        b = render_scene(back, back.camera(camera), (128, 80), ctx)
        assert np.abs(a - b).max() <= 2 / 255, (camera, float(np.abs(a - b).max()) * 255)


def test_export_then_render_from_the_command_line(tmp_path):
    r = illusio("export", "office", "-o", tmp_path / "office.glb")
    assert r.returncode == 0, r.stderr
    r = illusio("render", tmp_path / "office.glb", "--camera", "top", "-o", tmp_path / "top.png", "--size", "64x40")
    assert r.returncode == 0, r.stderr


def _nan_matrix(gltf):
    gltf.nodes[1].matrix = [1234.5] + [0.0] * 15  # made NaN in the file's text below (JSON has no NaN)


def _accessor_out_of_range(gltf):
    gltf.accessors[gltf.meshes[0].primitives[0].indices].byteOffset = 10**9


def _missing_texture(gltf):
    gltf.images[0].bufferView = None
    gltf.images[0].uri = "no-such-texture.png"


@pytest.mark.parametrize(
    "change, words",
    [(_nan_matrix, "not finite"), (_accessor_out_of_range, "room.glb"), (_missing_texture, "room.glb")],
    ids=["nan-matrix", "accessor-out-of-range", "missing-texture"],
)
def test_a_bad_scene_file_is_one_line_and_exit_2(tmp_path, change, words):
    path = make_room(tmp_path / "room.glb", [change])
    path.write_bytes(path.read_bytes().replace(b"1234.5", b"NaN   "))  # as a broken exporter writes it
    assert_one_line_error(illusio("render", path, "-o", tmp_path / "x.png", "--size", "32x20"), words)


def test_a_truncated_glb_is_one_line_and_exit_2(tmp_path, room):
    data = room.read_bytes()
    (tmp_path / "cut.glb").write_bytes(data[: len(data) // 2])
    assert_one_line_error(illusio("render", tmp_path / "cut.glb", "-o", tmp_path / "x.png"), "cut.glb")


def test_a_multi_material_obj_read_as_one_mesh_counts_the_files_unreferenced_vertices(tmp_path):
    """Two cubes of two materials and one stray vertex: read as one shape (lines), the one stray
    vertex is dropped and said, not each material's copy of the other cube's eight."""
    from illusio.scene.mesh import MeshWarning, load_mesh

    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines = (
        ["mtllib two.mtl"] + [f"v {x} {y} {z}" for x, y, z in corners] + [f"v {x + 3} {y} {z}" for x, y, z in corners]
    )
    lines.append("v 9 9 9")
    for material, offset in (("red", 0), ("blue", 8)):
        lines += [f"o {material}-cube", f"usemtl {material}"]
        lines += ["f " + " ".join(str(v + 1 + offset) for v in quad) for quad in quads]
    (tmp_path / "two.obj").write_text("\n".join(lines) + "\n")
    (tmp_path / "two.mtl").write_text("newmtl red\nKd 0.8 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.8\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = load_mesh(tmp_path / "two.obj")
    said = [str(w.message) for w in caught if issubclass(w.category, MeshWarning)]
    assert said == [f"{tmp_path / 'two.obj'}: dropped 1 unreferenced vertices"], said
    assert len(mesh.vertices) == 16 and len(mesh.faces) == 24
    scene = load_scene_file(tmp_path / "two.obj")  # as a scene: two nodes, their own colours
    assert len(scene.nodes) == 2


@pytest.mark.parametrize("technique", ["plain", "sis", "lines", "dof", "ibr", "radiosity", "relight"])
def test_every_viewer_mode_opens_a_gltf_scene(technique, room, tmp_path, ctx):
    """`illusio view room.glb --technique T`: each mode draws the file (its camera, its lamps; the sis
    mode's stereogram on the file's largest surface with uvs, the relighting's photograph of it)."""
    if technique in ("relight",):
        pytest.importorskip("mitsuba", reason="the photo extra: the scene's photograph")
    from illusio.viewer.offscreen import record
    from illusio.viewer.path import CameraPath, Keyframe

    frames = []
    path = CameraPath([Keyframe(0.0, (0, 2.5, 5), (0, 0.5, 0)), Keyframe(1.0, (1, 2.5, 5), (0, 0.5, 0))])
    count = record(
        technique,
        str(room),
        None,
        (64, 40),
        path,
        1.0,
        tmp_path / "v.mp4",
        ctx=ctx,
        on_frame=lambda i, viewer: frames.append(viewer.image()),
    )
    assert count == 2 and (tmp_path / "v.mp4").stat().st_size > 0
    assert max(float(np.std(f)) for f in frames) > 0.01, "blank frames"


def test_commands_take_the_files_names(room, tmp_path):
    """--focus-object, --host and --set-lamp name the file's own nodes and lamps."""
    r = illusio("dof", room, "--focus-object", "green-ball", "-o", tmp_path / "d.png", "--size", "64x40")
    assert r.returncode == 0, r.stderr
    assert "focus 5.38 m" in r.stdout  # the ball's distance along the file camera's axis
    r = illusio("sis-scene", room, "--host", "floor", "--emission", "0", "-o", tmp_path / "s.png", "--size", "96x64")
    assert r.returncode == 0, r.stderr
    r = illusio("radiosity", room, "--set-lamp", "lamp-node=2", "-o", tmp_path / "r.png", "--size", "64x40")
    assert r.returncode == 0, r.stderr
    assert_one_line_error(
        illusio("sis-scene", room, "--host", "panel", "-o", tmp_path / "x.png", "--size", "96x64"),
        "no texture coordinates",
        "floor",
    )


def test_an_obj_whose_texture_or_library_is_missing_is_one_line(tmp_path):
    """trimesh draws such a file untextured without a word: refused, naming the file it lacks."""
    ball = trimesh.creation.icosphere(2)
    ball.visual = trimesh.visual.TextureVisuals(uv=(ball.vertices[:, :2] + 1) / 2, image=_checker(16, 4))
    ball.export(tmp_path / "ball.obj")
    (png,) = tmp_path.glob("*.png")
    png.unlink()
    assert_one_line_error(illusio("render", tmp_path / "ball.obj", "-o", tmp_path / "x.png"), png.name)
    (mtl,) = tmp_path.glob("*.mtl")
    mtl.unlink()
    assert_one_line_error(illusio("render", tmp_path / "ball.obj", "-o", tmp_path / "x.png"), mtl.name)


def test_a_scenario_names_a_gltf_scenes_nodes(room, tmp_path):
    """dof's scenario language takes the file's node names: focus on the green ball, then the box."""
    (tmp_path / "focus.txt").write_text(
        "temps 0\nnettete objet green-ball\ntemps 500\nnettete objet red-box\nenleve objet yellow-cube\n"
    )
    r = illusio(
        "dof",
        room,
        "--scenario",
        tmp_path / "focus.txt",
        "--video",
        tmp_path / "f.gif",
        "--duration",
        "1",
        "--fps",
        "4",
        "--size",
        "64x40",
    )
    assert r.returncode == 0, r.stderr
    (tmp_path / "bad.txt").write_text("temps 0\nnettete objet blue-box\n")
    assert_one_line_error(
        illusio("dof", room, "--scenario", tmp_path / "bad.txt", "-o", tmp_path / "x.png", "--size", "64x40"),
        "blue-box",
        "green-ball",
    )


def test_a_scene_file_hides_in_a_stereogram_as_its_placed_nodes(room, tmp_path):
    """sis-scene --hidden takes a scene file: every node where the file's transforms put it (the
    merged mesh spans the scene's bounds), and the command draws it."""
    from illusio.scene.sources import resolve_mesh

    mesh, scene = resolve_mesh(str(room)), load_scene_file(room)
    assert np.allclose(mesh.vertices.min(0), scene.bounds()[0], atol=1e-5)
    assert np.allclose(mesh.vertices.max(0), scene.bounds()[1], atol=1e-5)
    r = illusio("sis-scene", "living-room", "--hidden", room, "-o", tmp_path / "s.png", "--size", "160x96")
    assert r.returncode == 0, r.stderr


def test_a_glb_whose_texture_image_is_damaged_is_one_line(room, tmp_path):
    """Found by the fuzz target (seed 1538875605: one byte of a GLB's embedded PNG flipped): PIL
    decodes the texture only when its pixels are read, and its OSError was a traceback."""
    data = bytearray(room.read_bytes())
    idat = data.index(b"IDAT")
    data[idat + 40] ^= 0xFF  # inside the compressed pixels
    broken = tmp_path / "broken.glb"
    broken.write_bytes(bytes(data))
    from illusio.core.errors import InputError

    with pytest.raises(InputError, match="not a readable image"):
        load_scene_file(broken)
    assert_one_line_error(illusio("render", broken, "-o", tmp_path / "x.png"), "broken.glb", "texture")


def test_an_obj_whose_texture_coordinates_give_u_alone_is_refused_in_words(tmp_path):
    """vt lines with one number (the fuzzer's cut of a cube's) read as one column: an InputError that
    says what is wrong, not NumPy's reshape error."""
    from illusio.core.errors import InputError

    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0\nvt 1\nvt 0.5\nf 1/1 2/2 3/3\n"
    (tmp_path / "u.obj").write_text(text)
    with pytest.raises(InputError, match=r"\(u, v\) pairs"):
        load_scene_file(tmp_path / "u.obj")
