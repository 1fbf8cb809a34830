"""Fuzzing the readers of folders: a reference-view set (references.json beside one .npz per view)."""

from __future__ import annotations

import shutil
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
        (folder / name).write_bytes(data)
    return folder


def test_seed_set_reads(seeds, tmp_path):
    assert must_refuse_or_succeed(load_references, write_set(tmp_path / "refs", seeds), valid_references)


@seed(SESSION_SEED)
@FUZZ
@given(target=st.sampled_from(["references.json", "view-0.npz", "view-1.npz"]), mutations=MUTATIONS, drop=st.booleans())
def test_mutated_reference_sets_are_read_or_refused(seeds, target, mutations, drop, tmp_path_factory):
    """One file of the set mutated (or, with ``drop``, removed)."""
    files = dict(seeds)
    if drop and target != "references.json":
        del files[target]
    else:
        files[target] = mutate(files[target], mutations)
    folder = write_set(tmp_path_factory.mktemp("refs"), files)
    must_refuse_or_succeed(load_references, folder, valid_references)
    shutil.rmtree(folder)


@pytest.mark.parametrize("case", corpus_cases("references"), ids=lambda p: p.name)
def test_kept_reference_cases(seeds, case, tmp_path):
    """A kept references.json beside the seed's views, or a kept .npz in place of view 0."""
    files = {**seeds, "references.json" if case.suffix == ".json" else "view-0.npz": case.read_bytes()}
    must_refuse(load_references, write_set(tmp_path / "refs", files))
