"""Curvature by jet fitting: analytic surfaces, the sign convention, dirty meshes, the cache."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.lines import analytic
from illusio.lines.curvature import Curvature, estimate_curvature
from illusio.scene.mesh import Mesh


def mean_relative_error(k, ref):
    return float(np.mean(np.abs(k - ref) / np.maximum(np.abs(ref), 0.1 * np.abs(ref).max())))


@pytest.mark.parametrize("make, bound", [(lambda: analytic.icosphere(4, 2.0), 0.03), (lambda: analytic.torus(1.0, 0.35, 96, 32), 0.12),
                                         (lambda: analytic.ellipsoid((1.0, 0.7, 0.5), 4), 0.05)])
def test_principal_curvatures_of_analytic_surfaces(make, bound):
    mesh, k_min, k_max = make()
    c = estimate_curvature(mesh, cache=False)
    assert c.valid.all()
    assert mean_relative_error(c.k_min, k_min) < bound
    assert mean_relative_error(c.k_max, k_max) < bound
    # directions are unit, tangent and orthogonal; normals agree with the mesh's
    for e in (c.e_min, c.e_max):
        np.testing.assert_allclose(np.linalg.norm(e, axis=1), 1, atol=1e-4)
        assert np.abs((e * c.normals).sum(1)).max() < 1e-3
    assert np.abs((c.e_min * c.e_max).sum(1)).max() < 1e-3
    assert ((c.normals * mesh.normals).sum(1) > 0.99).all()


def test_sign_convention_sphere_positive_torus_inner_saddle():
    sphere, _, _ = analytic.icosphere(3, 0.5)
    c = estimate_curvature(sphere, cache=False)
    assert (c.k_min > 0).all()
    torus, k_min, _ = analytic.torus(1.0, 0.3, 96, 32)
    c = estimate_curvature(torus, cache=False)
    inner = k_min < -0.3
    assert inner.any() and (c.k_min[inner] < 0).all() and (c.k_max[inner] > 0).all()


def test_torus_directions_follow_the_tube():
    """Around the tube (curvature 1/r) is e_max: perpendicular to the ring direction."""
    torus, _, _ = analytic.torus(1.0, 0.3, 96, 32)
    c = estimate_curvature(torus, cache=False)
    v = torus.vertices.astype(np.float64)
    ring = np.stack([-v[:, 1], v[:, 0], np.zeros(len(v))], 1)
    ring /= np.linalg.norm(ring, axis=1, keepdims=True)
    assert np.median(np.abs((c.e_max * ring).sum(1))) < 0.05


def test_dirty_meshes_give_finite_values(rng):
    sphere, _, _ = analytic.icosphere(2)
    v = np.vstack([sphere.vertices, [[5.0, 5.0, 5.0]], sphere.vertices[:3]])  # unreferenced + duplicates
    f = sphere.faces.copy()
    f = f[f.max(1) < len(sphere.vertices)]
    dup = len(sphere.vertices) + 1
    f = np.vstack([f[10:], [[dup, dup + 1, dup + 2]], f[:1]])  # a hole, a separate duplicate triangle, a repeated face
    f = np.vstack([f, [[f[0, 0], f[0, 1], 0 if f[0, 2] != 0 else 1]]])  # a third face on one edge: non-manifold
    mesh = Mesh(v, f, name="dirty")
    c = estimate_curvature(mesh, cache=False)
    for a in (c.k_min, c.k_max, c.e_min, c.e_max, c.normals, c.dcurv):
        assert np.isfinite(a).all()
    assert not c.valid[len(sphere.vertices)]  # the unreferenced vertex has no fit


def test_nan_vertices_are_refused():
    sphere, _, _ = analytic.icosphere(1)
    v = sphere.vertices.copy()
    v[3] = np.nan
    with pytest.raises(InputError):
        estimate_curvature(_unchecked(v, sphere.faces), cache=False)


def _unchecked(v, f):
    m = object.__new__(Mesh)
    m.vertices, m.faces, m.name = v, f, "nan"
    return m


def test_second_run_reads_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ILLUSIO_CACHE", str(tmp_path))
    mesh, _, _ = analytic.ellipsoid((1, 0.8, 0.6), 2)
    first = estimate_curvature(mesh)
    files = list((tmp_path / "curvature").glob("*.npz"))
    assert len(files) == 1
    # poison the cache file's content: a second run must come from it, not from a new fit
    poisoned = Curvature(**{**first.__dict__, "k_max": first.k_max + 123.0})
    poisoned.save(files[0])
    assert np.allclose(estimate_curvature(mesh).k_max, first.k_max + 123.0)
    # another setting is another key
    assert not np.allclose(estimate_curvature(mesh, degree=2).k_max, first.k_max + 123.0)
