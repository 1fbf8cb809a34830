"""Fuzzing the mesh readers (OBJ, PLY ascii/binary/triangle strips, OFF, STL ascii/binary, GLB)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, seed
from hypothesis import strategies as st

from illusio.core.errors import InputError
from illusio.scene.mesh import Mesh, load_mesh
from tests.conftest import SESSION_SEED
from tests.fuzz.harness import FUZZ, MUTATIONS, corpus_cases, must_refuse, must_refuse_or_succeed, mutate
from tests.fuzz.seeds import mesh_seeds


def read_quietly(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_mesh(path)


def valid_mesh(mesh: Mesh) -> None:
    v, f = mesh.vertices, mesh.faces
    assert v.ndim == 2 and v.shape[1] == 3 and len(v) > 0 and np.isfinite(v).all()
    assert f.ndim == 2 and f.shape[1] == 3 and len(f) > 0
    assert f.min() >= 0 and f.max() < len(v)


@pytest.mark.parametrize("name", sorted(mesh_seeds()))
def test_seed_meshes_read(name, tmp_path):
    path = tmp_path / name
    path.write_bytes(mesh_seeds()[name])
    valid_mesh(read_quietly(path))


@pytest.mark.parametrize("name", sorted(mesh_seeds()))
@seed(SESSION_SEED)
@FUZZ
@given(mutations=MUTATIONS)
def test_mutated_meshes_are_read_or_refused(name, mutations, tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / name
    path.write_bytes(mutate(mesh_seeds()[name], mutations))
    must_refuse_or_succeed(read_quietly, path, valid_mesh)


@pytest.mark.parametrize("case", corpus_cases("mesh"), ids=lambda p: p.name)
def test_kept_mesh_cases(case):
    message = must_refuse(read_quietly, case)
    if case.name.startswith("cut-short"):
        assert "cut short" in message


COUNTED = [
    "sphere-ascii.ply",
    "sphere-binary.ply",
    "sphere.off",
    "sphere-ascii.stl",
    "sphere-binary.stl",
    "sphere.glb",
    "strips-ascii.ply",
    "strips-binary.ply",
]


@pytest.mark.parametrize("name", COUNTED)
@seed(SESSION_SEED)
@FUZZ
@given(fraction=st.floats(0.3, 1.0, exclude_max=True))
def test_cut_short_files_are_refused_naming_what_was_declared(name, fraction, tmp_path_factory):
    """A file whose header declares more than it holds (a truncated download) is refused, and the
    error says so — never drawn from the part that was read. Text files are cut before their last
    line starts (a cut inside the last number leaves a shorter number, which no count can tell)."""
    data = mesh_seeds()[name]
    binary = name.endswith((".glb", "binary.ply", "binary.stl"))
    end = len(data) - 1 if binary else data.rstrip().rfind(b"\n")
    path = tmp_path_factory.mktemp("cut") / name
    path.write_bytes(data[: int(end * fraction)])
    with pytest.raises(InputError, match="declares|cut short"):
        read_quietly(path)
