"""Fuzzing the readers of folders: a reference-view set (references.json beside one .npz per view), a
TUM RGB-D sequence, an RGB-D folder (Redwood/Open3D layout), a COLMAP workspace, and a relighting
folder (model, photograph, camera.json)."""

from __future__ import annotations

import shutil
import warnings
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, seed
from hypothesis import strategies as st

from illusio.ibr.reference_views import ReferenceSet, ReferenceView, load_references, save_references
from illusio.scene.camera import Camera, Pose, View
from tests.conftest import SESSION_SEED
from tests.fuzz.harness import FUZZ, MUTATIONS, corpus_cases, must_refuse, must_refuse_or_succeed, mutate


@cache
def reference_files(folder: str) -> dict[str, bytes]:
    """A small two-view reference set, saved by save_references (file name → bytes)."""
    rng = np.random.default_rng(1)
    views = []
    for k in range(2):
        view = View(Pose((0.3 * k, 1.0, 3.0), (0.0, 0.0, 0.0)), Camera(45.0, 0.1, 20.0))
        h, w = 6, 8
        views.append(
            ReferenceView(
                view,
                rng.random((h, w, 4), np.float32),
                rng.random((h, w, 4), np.float32),
                np.zeros((h, w, 3), np.float32),
                rng.uniform(1, 4, (h, w)).astype(np.float32),
            )
        )
    out = Path(folder)
    save_references(ReferenceSet(views), out)
    return {p.name: p.read_bytes() for p in out.iterdir()}


def valid_references(refs) -> None:
    assert refs.views and len({v.size for v in refs.views}) == 1
    for v in refs.views:
        assert np.isfinite(v.depth).all() and (v.depth >= 0).all()
        assert np.isfinite(v.view.view_matrix()).all()
    for light in refs.lights:
        where = light.position if hasattr(light, "position") else light.centre
        assert np.isfinite(np.asarray(where, float)).all() and np.isfinite(np.asarray(light.colour, float)).all()


@pytest.fixture(scope="module")
def seeds(tmp_path_factory):
    return reference_files(str(tmp_path_factory.mktemp("refs-seed")))


def write_set(folder: Path, files: dict[str, bytes]) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)
    return folder


def read_mutated_folder(read, check, files, target, mutations, drop, folder: Path) -> None:
    """``files`` written to ``folder`` with ``target`` mutated (removed, with ``drop``), then read:
    a result ``check`` accepts, or one line (must_refuse_or_succeed)."""
    files = dict(files)
    if drop:
        del files[target]
    else:
        files[target] = mutate(files[target], mutations)
    must_refuse_or_succeed(read, write_set(folder, files), check)
    shutil.rmtree(folder)


def test_seed_set_reads(seeds, tmp_path):
    assert must_refuse_or_succeed(load_references, write_set(tmp_path / "refs", seeds), valid_references)


@seed(SESSION_SEED)
@FUZZ
@given(target=st.sampled_from(["references.json", "view-0.npz", "view-1.npz"]), mutations=MUTATIONS, drop=st.booleans())
def test_mutated_reference_sets_are_read_or_refused(seeds, target, mutations, drop, tmp_path_factory):
    """One file of the set mutated (or, with ``drop``, removed)."""
    drop = drop and target != "references.json"
    folder = tmp_path_factory.mktemp("refs")
    read_mutated_folder(load_references, valid_references, seeds, target, mutations, drop, folder)


@pytest.mark.parametrize("case", corpus_cases("references"), ids=lambda p: p.name)
def test_kept_reference_cases(seeds, case, tmp_path):
    """A kept references.json beside the seed's views, or a kept .npz in place of view 0."""
    files = {**seeds, "references.json" if case.suffix == ".json" else "view-0.npz": case.read_bytes()}
    must_refuse(load_references, write_set(tmp_path / "refs", files))


# --- a TUM RGB-D sequence (rgb.txt, depth.txt, groundtruth.txt, intrinsic.json and the images) ---


@cache
def tum_files(folder: str) -> dict[str, bytes]:
    """Two frames of a TUM sequence as its tools write it (file name → bytes)."""
    from illusio.core.images import write_image

    out = Path(folder)
    (out / "rgb").mkdir(parents=True, exist_ok=True)
    (out / "depth").mkdir(exist_ok=True)
    rng = np.random.default_rng(2)
    rgb, depth, truth = ["# color images"], ["# depth maps"], ["# timestamp tx ty tz qx qy qz qw"]
    for k in range(2):
        t = 1305031102.0 + 0.5 * k
        write_image(out / "rgb" / f"{t:.6f}.png", rng.random((6, 8, 3)).astype(np.float32))
        write_image(out / "depth" / f"{t:.6f}.png", np.full((6, 8), 0.1, np.float32), bit_depth=16, srgb=False)
        rgb.append(f"{t:.6f} rgb/{t:.6f}.png")
        depth.append(f"{t:.6f} depth/{t:.6f}.png")
        truth.append(f"{t:.4f} {0.1 * k:.6f} 0.0 1.5 0.0 0.0 0.0 1.0")
    for name, lines in (("rgb.txt", rgb), ("depth.txt", depth), ("groundtruth.txt", truth)):
        (out / name).write_text("\n".join(lines) + "\n")
    (out / "intrinsic.json").write_text('{"width": 8, "height": 6, "fx": 7.0, "fy": 7.0, "cx": 4.0, "cy": 3.0}\n')
    return {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}


def valid_frames(frames) -> None:
    assert frames
    for f in frames:
        assert np.isfinite(f.pose).all() and f.colour.ndim == 3 and np.isfinite(f.depth).all()


@pytest.fixture(scope="module")
def tum_seeds(tmp_path_factory):
    return tum_files(str(tmp_path_factory.mktemp("tum-seed")))


def test_seed_tum_sequence_reads(tum_seeds, tmp_path):
    from illusio.ibr.captures import read_tum

    assert must_refuse_or_succeed(read_tum, write_set(tmp_path / "tum", tum_seeds), valid_frames)


TUM_TARGETS = ["rgb.txt", "depth.txt", "groundtruth.txt", "intrinsic.json", "rgb/1305031102.000000.png"]


# --- an RGB-D folder as Open3D's and Redwood's tools write it (color/, depth/, intrinsic.json, .log) ---


def _images(out: Path, colour_dir: str, depth_dir: str, names: list[str], rng, depth_file) -> None:
    from illusio.core.images import write_image

    (out / colour_dir).mkdir(parents=True, exist_ok=True)
    (out / depth_dir).mkdir(parents=True, exist_ok=True)
    for name in names:
        write_image(out / colour_dir / name, rng.random((6, 8, 3)).astype(np.float32))
        depth_file(out / depth_dir, name)


def _tree(out: Path) -> dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}


@cache
def rgbd_files(folder: str) -> dict[str, bytes]:
    """Two frames: colour PNGs, 16-bit depth PNGs in millimetres, intrinsic.json, trajectory.log."""
    from illusio.core.images import write_image

    out = Path(folder)
    names = ["000000.png", "000001.png"]
    depth = np.full((6, 8), 1500 / 65535, np.float32)  # 1.5 m at 1000 units per metre
    _images(
        out,
        "color",
        "depth",
        names,
        np.random.default_rng(4),
        lambda d, n: write_image(d / n, depth, bit_depth=16, srgb=False),
    )
    (out / "intrinsic.json").write_text('{"width": 8, "height": 6, "fx": 7.0, "fy": 7.0, "cx": 4.0, "cy": 3.0}\n')
    log = []
    for k in range(2):
        log += [f"{k} {k} {k + 1}", f"1 0 0 {0.1 * k}", "0 1 0 0", "0 0 1 1.5", "0 0 0 1"]
    (out / "trajectory.log").write_text("\n".join(log) + "\n")
    return _tree(out)


RGBD_TARGETS = ["intrinsic.json", "trajectory.log", "color/000000.png", "depth/000001.png"]


def test_seed_rgbd_folder_reads(tmp_path):
    from illusio.ibr.captures import read_rgbd_folder

    files = rgbd_files(str(tmp_path / "seed"))
    assert must_refuse_or_succeed(read_rgbd_folder, write_set(tmp_path / "rgbd", files), valid_frames)


# --- a COLMAP workspace (sparse/ text model, images/, stereo/depth_maps/*.geometric.bin) ---


def colmap_array(depth: np.ndarray) -> bytes:
    """COLMAP's dense map format: ``width&height&channels&`` then float32, column-major."""
    h, w = depth.shape
    return f"{w}&{h}&1&".encode() + np.asarray(depth, "<f4").reshape(-1, order="F").tobytes()


@cache
def colmap_files(folder: str) -> dict[str, bytes]:
    """Two photos of a PINHOLE camera, as ``colmap model_converter --output_type TXT`` and
    ``colmap patch_match_stereo`` leave a workspace."""
    out = Path(folder)
    names = ["a.png", "b.png"]
    depth = np.linspace(1.0, 2.0, 48, dtype=np.float32).reshape(6, 8)
    _images(
        out, "images", "stereo/depth_maps", names, np.random.default_rng(5),
        lambda d, n: (d / f"{n}.geometric.bin").write_bytes(colmap_array(depth)),
    )  # fmt: skip
    (out / "sparse").mkdir()
    (out / "sparse" / "cameras.txt").write_text(
        "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
        "# Number of cameras: 1\n1 PINHOLE 8 6 7.0 7.0 4.0 3.0\n"
    )
    (out / "sparse" / "images.txt").write_text(
        "# Image list with two lines of data per image:\n"
        "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
        "1 1 0 0 0 0 0 1.5 1 a.png\n1.5 2.5 -1\n"
        "2 0.9998 0 0.02 0 -0.1 0 1.5 1 b.png\n\n"
    )
    return _tree(out)


COLMAP_TARGETS = ["sparse/cameras.txt", "sparse/images.txt", "images/a.png", "stereo/depth_maps/b.png.geometric.bin"]


def test_seed_colmap_workspace_reads(tmp_path):
    from illusio.ibr.captures import read_colmap

    files = colmap_files(str(tmp_path / "seed"))
    frames = must_refuse_or_succeed(read_colmap, write_set(tmp_path / "colmap", files), valid_frames)
    assert [f.name for f in frames] == ["a.png", "b.png"]


def _capture_reader(name: str):
    def read(path):
        from illusio.ibr import captures

        return getattr(captures, name)(path)

    return read


#: the capture folders fuzzed alike: (the seed's files by folder, the reader in ibr.captures, the files mutated)
CAPTURE_FOLDERS = {
    "tum": (tum_files, "read_tum", TUM_TARGETS),
    "rgbd": (rgbd_files, "read_rgbd_folder", RGBD_TARGETS),
    "colmap": (colmap_files, "read_colmap", COLMAP_TARGETS),
}


@pytest.mark.parametrize("kind", CAPTURE_FOLDERS)
@seed(SESSION_SEED)
@FUZZ
@given(data=st.data(), mutations=MUTATIONS, drop=st.booleans())
def test_mutated_capture_folders_are_read_or_refused(kind, data, mutations, drop, tmp_path_factory):
    """One file of a TUM sequence, an RGB-D folder or a COLMAP workspace mutated (or, with ``drop``,
    removed): frames read, or one line."""
    make, reader, targets = CAPTURE_FOLDERS[kind]
    target = data.draw(st.sampled_from(targets), label="target")
    files = make(str(tmp_path_factory.getbasetemp() / f"{kind}-seed"))
    folder = tmp_path_factory.mktemp(kind)
    read_mutated_folder(_capture_reader(reader), valid_frames, files, target, mutations, drop, folder)


# --- a relighting folder (a model as Blender writes it, its photograph and camera.json) ---

BLENDER = Path(__file__).parents[1] / "data" / "blender"


@cache
def relight_files() -> dict[str, bytes]:
    """Blender's glTF as the model (its point light the lamp relighting estimates), a small
    photograph and a camera.json with a vertical fov."""
    import io

    from PIL import Image

    photo = io.BytesIO()
    Image.fromarray((np.random.default_rng(3).random((24, 32, 3)) * 255).astype(np.uint8)).save(photo, "PNG")
    camera = (
        '{"position": [7.36, 4.96, 6.93], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 23, "width": 32, "height": 24}\n'
    )
    return {
        "scene.glb": (BLENDER / "blender.glb").read_bytes(),
        "photograph.png": photo.getvalue(),
        "camera.json": camera.encode(),
    }


def valid_real_scene(real) -> None:
    assert len(real.polygons) and np.isfinite(real.photograph).all()
    assert real.photograph.shape[:2] == (24, 32)


def _load_real(folder):
    from illusio.relight.photograph import load_real_scene

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # what the model does not draw is said once; not the point here
        return load_real_scene(folder)


def test_seed_relighting_folder_reads(tmp_path):
    assert must_refuse_or_succeed(_load_real, write_set(tmp_path / "real", relight_files()), valid_real_scene)


@seed(SESSION_SEED)
@FUZZ
@given(
    target=st.sampled_from(["scene.glb", "photograph.png", "camera.json"]),
    mutations=MUTATIONS,
    drop=st.booleans(),
)
def test_mutated_relighting_folders_are_read_or_refused(target, mutations, drop, tmp_path_factory):
    """One file of the folder mutated (or, with ``drop``, removed): the real scene, or one line."""
    folder = tmp_path_factory.mktemp("real")
    read_mutated_folder(_load_real, valid_real_scene, relight_files(), target, mutations, drop, folder)
