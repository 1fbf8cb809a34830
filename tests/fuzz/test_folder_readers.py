"""Fuzzing the readers of folders: a reference-view set (references.json beside one .npz per view), a
TUM RGB-D sequence, and a relighting folder (model, photograph, camera.json)."""

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


@seed(SESSION_SEED)
@FUZZ
@given(target=st.sampled_from(TUM_TARGETS), mutations=MUTATIONS, drop=st.booleans())
def test_mutated_tum_sequences_are_read_or_refused(tum_seeds, target, mutations, drop, tmp_path_factory):
    """One file of the sequence mutated (or, with ``drop``, removed): frames read, or one line."""
    from illusio.ibr.captures import read_tum

    read_mutated_folder(read_tum, valid_frames, tum_seeds, target, mutations, drop, tmp_path_factory.mktemp("tum"))


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
