"""Fuzzing the image, depth, scene, scenario, camera-path, camera-list and batch-job readers."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, seed
from hypothesis import strategies as st

from illusio.batch.job import load_job
from illusio.core.images import read_image
from illusio.dof.scenario import load_scenario, shipped_scenario
from illusio.ibr.reference_views import load_cameras
from illusio.scene.camera import Camera
from illusio.scene.loader import load_scene
from illusio.sis.depth import read_depth
from illusio.viewer.path import CameraPath
from tests.conftest import REPO, SESSION_SEED
from tests.fuzz.harness import FUZZ, MUTATIONS, corpus_cases, must_refuse, must_refuse_or_succeed, mutate
from tests.fuzz.seeds import image_seeds


def valid_image(img) -> None:
    assert img.dtype == np.float32 and img.ndim == 3 and img.shape[0] > 0 and img.shape[1] > 0
    assert 1 <= img.shape[2] <= 4


def valid_depth(d) -> None:
    assert d.dtype == np.float32 and d.ndim == 2 and d.size > 0
    assert np.isfinite(d).all() and d.min() >= 0 and d.max() <= 1


def valid_scene(scene) -> None:
    assert scene.nodes
    for node in scene.nodes:
        v, f = node.mesh.vertices, node.mesh.faces
        assert np.isfinite(v).all() and len(f) and f.min() >= 0 and f.max() < len(v)
        assert np.isfinite(node.transform).all()


def valid_scenario(scenario) -> None:
    assert all(c.kind for c in scenario.commands)


def valid_path(path) -> None:
    for t in (0.0, path.duration / 2, path.duration):
        assert np.isfinite(path.view(t, Camera()).view_matrix()).all()


def valid_cameras(views) -> None:
    assert 1 <= len(views) <= 16
    assert all(np.isfinite(v.view_matrix()).all() and np.isfinite(v.projection_matrix(1.5)).all() for v in views)


def valid_job(job) -> None:
    assert job.tasks


def read_quietly(reader):
    def read(path):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return reader(path)

    return read


PATH_SEED = (
    b'[{"t": 0, "eye": [0, 1, 3], "target": [0, 0, 0]},\n {"t": 1.5, "eye": [2, 1, 2], "target": [0, 0.5, 0]},\n'
    b' {"t": 3, "eye": [3, 2, 0], "target": [0, 0, 0]}]\n'
)
CAMERAS_SEED = (
    b'[{"eye": [0, 1, 3], "target": [0, 0, 0], "fov": 45, "near": 0.1, "far": 20},\n'
    b' {"eye": [1, 1, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 50, "near": 0.05, "far": 30, '
    b'"shift": [0.1, 0]}]\n'
)

MGF_SEED = (
    b"# a floor and a lamp\nm grey =\n\tc\n\trd 0.5\n"
    b"v a =\n\tp 0 0 0\nv b =\n\tp 4 0 0\nv c =\n\tp 4 4 0\nv d =\n\tp 0 4 0\nf a b c d\n"
    b"m lamp =\n\tc\n\t\tcxy 0.333333 0.333333\n\ted 683\n"
    b"v l0 =\n\tp 1 1 3\nv l1 =\n\tp 2 1 3\nv l2 =\n\tp 2 2 3\nv l3 =\n\tp 1 2 3\nf l3 l2 l1 l0\n"
    b"o ball\nv o =\n\tp 2 2 1\nsph o 0.5\no -\n"
)
CAMERA_JSON_SEED = (
    b'{"position": [0.2, 1.2, 2.6], "target": [0, 0.6, -1], "up": [0, 1, 0], "width": 160, "height": 120,\n'
    b' "fx": 118.0, "fy": 126.0, "cx": 80.5, "cy": 60.2, "distortion": [0.01, -0.002, 0, 0]}\n'
)
POINTS_SEED = b"u v x y z\n" + b"".join(
    f"{10 + 17 * k % 140} {8 + 29 * k % 100} {k % 3 * 0.5} {k % 2 * 0.7} {-(k % 4) * 0.3}\n".encode() for k in range(8)
)


def gltf_seeds() -> dict[str, bytes]:
    """A scene as trimesh and pygltflib write one: two meshes, a texture, a point light, a camera."""
    import io

    import pygltflib
    import trimesh
    from PIL import Image
    from trimesh.visual.material import PBRMaterial

    scene = trimesh.Scene()
    box = trimesh.creation.box((1, 1, 1))
    texture = Image.fromarray((np.indices((8, 8)).sum(0) % 2 * 200 + 30).astype(np.uint8)).convert("RGB")
    box.visual = trimesh.visual.TextureVisuals(
        uv=box.vertices[:, :2] + 0.5, material=PBRMaterial("crate", baseColorTexture=texture, metallicFactor=0.0)
    )
    scene.add_geometry(box, node_name="crate", geom_name="crate")
    ball = trimesh.creation.icosphere(1, 0.4)
    ball.visual = trimesh.visual.TextureVisuals(material=PBRMaterial("paint", baseColorFactor=[0.2, 0.6, 0.3, 1.0]))
    scene.add_geometry(
        ball, node_name="ball", geom_name="ball", transform=trimesh.transformations.translation_matrix([1.5, 0, 0])
    )
    gltf = pygltflib.GLTF2.load_from_bytes(scene.export(file_type="glb"))
    gltf.extensionsUsed = ["KHR_lights_punctual"]
    gltf.extensions = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 900.0}]}}
    gltf.cameras = [pygltflib.Camera(type="perspective", perspective=pygltflib.Perspective(yfov=0.8, znear=0.1))]
    gltf.nodes += [
        pygltflib.Node(name="bulb", translation=[0, 3, 1], extensions={"KHR_lights_punctual": {"light": 0}}),
        pygltflib.Node(name="shot", camera=0, translation=[0.5, 1, 5]),
    ]
    gltf.scenes[0].nodes += [len(gltf.nodes) - 2, len(gltf.nodes) - 1]
    glb = b"".join(gltf.save_to_bytes())
    gltf.convert_buffers(pygltflib.BufferFormat.DATAURI)
    text = io.StringIO()
    text.write(gltf.to_json())
    return {"scene.glb": glb, "scene.gltf": text.getvalue().encode()}


def obj_scene_seeds() -> dict[str, bytes]:
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    # usemtl names without a library: a scene of two materials (default colours)
    lines = ["o Cube"] + [f"v {x} {y} {z}" for x, y, z in corners]
    lines += ["vt 0 0", "vt 1 0", "vt 1 1", "vt 0 1"]
    for k, quad in enumerate(quads):
        lines.append("usemtl " + ("wood" if k < 3 else "paint"))
        lines.append("f " + " ".join(f"{v - 8}/{t - 4}" for t, v in enumerate(quad)))
    return {"cube.obj": ("\n".join(lines) + "\n").encode()}


def colmap_seed() -> dict[str, bytes]:
    depth = np.linspace(0.5, 3.0, 12 * 9, dtype="<f4").reshape(9, 12)
    return {"depth.geometric.bin": b"12&9&1&" + depth.T.reshape(-1, order="F").tobytes()}


def valid_points(points) -> None:
    uv, xyz = points
    assert uv.shape[1:] == (2,) and xyz.shape == (len(uv), 3) and np.isfinite(uv).all() and np.isfinite(xyz).all()


def valid_camera(camera) -> None:
    view, _, _ = camera
    assert np.isfinite(view.view_matrix()).all()


def valid_array(a) -> None:
    assert a.dtype == np.float32 and a.ndim == 2 and np.isfinite(a).all()


def _read_scene_file(path):
    from illusio.scene.scene_file import load_scene_file

    return load_scene_file(path)


def _read_camera(path):
    from illusio.relight.calibrate import read_camera

    return read_camera(path)


def _read_points(path):
    from illusio.relight.calibrate import read_points

    return read_points(path)


def _read_colmap_array(path):
    from illusio.ibr.captures import read_colmap_array

    return read_colmap_array(path)


# reader name → (seed files: name → bytes, reader, check)
READERS = {
    "image": (lambda: image_seeds(), read_quietly(read_image), valid_image),
    "depth": (
        lambda: {k: v for k, v in image_seeds().items() if k.startswith("ramp")},
        read_quietly(read_depth),
        valid_depth,
    ),
    "scene": (
        lambda: {"still-life.yaml": (REPO / "examples" / "still-life.yaml").read_bytes()},
        read_quietly(load_scene),
        valid_scene,
    ),
    "scenario": (
        lambda: {"futuristic.txt": shipped_scenario("futuristic").read_bytes()},
        load_scenario,
        valid_scenario,
    ),
    "camera-path": (
        lambda: {"walk.json": PATH_SEED},
        lambda p: CameraPath.parse(Path(p).read_text("utf-8", "replace"), str(p)),
        valid_path,
    ),
    "cameras": (lambda: {"cameras.json": CAMERAS_SEED}, load_cameras, valid_cameras),
    "batch-job": (lambda: {"job.yaml": (REPO / "examples" / "batch-job.yaml").read_bytes()}, load_job, valid_job),
    "mgf": (lambda: {"room.mgf": MGF_SEED}, read_quietly(load_scene), valid_scene),
    "gltf": (gltf_seeds, read_quietly(_read_scene_file), valid_scene),
    "obj-scene": (obj_scene_seeds, read_quietly(_read_scene_file), valid_scene),
    "colmap-bin": (colmap_seed, _read_colmap_array, valid_array),
    "camera-json": (lambda: {"camera.json": CAMERA_JSON_SEED}, _read_camera, valid_camera),
    "calibration-points": (lambda: {"points.txt": POINTS_SEED}, _read_points, valid_points),
}
CASES = [(reader, name) for reader, (seeds, _, _) in READERS.items() for name in sorted(seeds())]


@pytest.mark.parametrize("reader, name", CASES)
def test_seed_files_read(reader, name, tmp_path):
    seeds, read, check = READERS[reader]
    path = tmp_path / name
    path.write_bytes(seeds()[name])
    assert must_refuse_or_succeed(read, path, check) is not None


@pytest.mark.parametrize("reader, name", CASES)
@seed(SESSION_SEED)
@FUZZ
@given(mutations=MUTATIONS)
def test_mutated_files_are_read_or_refused(reader, name, mutations, tmp_path_factory):
    seeds, read, check = READERS[reader]
    path = tmp_path_factory.mktemp(reader) / name
    path.write_bytes(mutate(seeds()[name], mutations))
    must_refuse_or_succeed(read, path, check)


KEPT = [(reader, case) for reader in READERS for case in corpus_cases(reader)]


@pytest.mark.parametrize("reader, case", KEPT, ids=lambda x: getattr(x, "name", x))
def test_kept_cases(reader, case):
    must_refuse(READERS[reader][1], case)


@pytest.mark.parametrize("name", sorted(image_seeds()))
@seed(SESSION_SEED)
@FUZZ
@given(fraction=st.floats(0.0, 1.0, exclude_max=True))
def test_cut_short_images_are_refused(name, fraction, tmp_path_factory):
    """An image or array cut anywhere is refused — never decoded from the rows that are left."""
    data = image_seeds()[name]
    path = tmp_path_factory.mktemp("cut") / name
    path.write_bytes(data[: int((len(data) - 1) * fraction)])
    must_refuse(READERS["image"][1], path)
