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
