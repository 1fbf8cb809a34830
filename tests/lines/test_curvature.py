"""Curvature by jet fitting: analytic surfaces, the sign convention, dirty meshes, the cache."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.lines import analytic
from illusio.lines.curvature import Curvature, estimate_curvature
from illusio.scene.mesh import Mesh


def mean_relative_error(k, ref):
    return float(np.mean(np.abs(k - ref) / np.maximum(np.abs(ref), 0.1 * np.abs(ref).max())))


@pytest.mark.parametrize(
    "make, bound",
    [
        (lambda: analytic.icosphere(4, 2.0), 0.03),
        (lambda: analytic.torus(1.0, 0.35, 96, 32), 0.12),
        (lambda: analytic.ellipsoid((1.0, 0.7, 0.5), 4), 0.05),
    ],
)
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


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_every_jet_degree_without_adaptation(degree):
    """Each degree alone: the quartic has the least bias on a clean sphere (its height is not a cubic)."""
    mesh, k_min, k_max = analytic.icosphere(3)
    c = estimate_curvature(mesh, degree=degree, adaptive=False, smoothing=0, cache=False)
    error = mean_relative_error(c.k_min, k_min) + mean_relative_error(c.k_max, k_max)
    assert error < {2: 0.15, 3: 0.15, 4: 0.02}[degree]


def test_adaptive_support_averages_noise_and_keeps_clean_fits():
    """ICI rule with the inverse-variance mean of the fits that join: on noise, support and lower
    degrees join (error well below the fixed quartic's); on a clean surface the quartic's accuracy
    stays (the cubic and quadric, biased there — 0.09 and 0.03 on the coarse ellipsoid against the
    quartic's 0.004 — must not join)."""
    for subdivisions in (3, 4):
        mesh, k_min, k_max = analytic.ellipsoid((1.0, 0.7, 0.5), subdivisions)
        noisy = analytic.add_noise(mesh, 0.05, seed=1)
        fixed = estimate_curvature(noisy, adaptive=False, smoothing=0, cache=False)
        adaptive = estimate_curvature(noisy, adaptive=True, smoothing=0, cache=False)
        assert mean_relative_error(adaptive.k_max, k_max) < 0.6 * mean_relative_error(fixed.k_max, k_max)
        clean_fixed = estimate_curvature(mesh, adaptive=False, smoothing=0, cache=False)
        clean = estimate_curvature(mesh, adaptive=True, smoothing=0, cache=False)
        for got, fit, want in ((clean.k_min, clean_fixed.k_min, k_min), (clean.k_max, clean_fixed.k_max, k_max)):
            assert mean_relative_error(got, want) < 2 * mean_relative_error(fit, want) + 1e-4


def test_tensor_smoothing_transports_neighbours_so_a_sphere_stays_exact():
    """Each neighbour's tensor is rotated into the vertex's tangent plane before averaging: on a
    sphere every transported tensor is (1/R)·I, so five passes change nothing measurable (averaged
    without the rotation, the tangential parts shrink: sphere-3's error grew 0.004 → 0.02)."""
    mesh, k_min, k_max = analytic.icosphere(3, 0.5)
    raw = estimate_curvature(mesh, smoothing=0, cache=False)
    smooth = estimate_curvature(mesh, smoothing=5, cache=False)
    for got, fit, want in ((smooth.k_min, raw.k_min, k_min), (smooth.k_max, raw.k_max, k_max)):
        assert mean_relative_error(got, want) < mean_relative_error(fit, want) + 2e-4
    np.testing.assert_allclose(np.abs((smooth.e_min * smooth.e_max).sum(1)), 0, atol=1e-5)


def test_tensor_smoothing_removes_noise_left_by_the_fits():
    """Averaging the fits' tensors over the 1-ring, three times: on noise the error falls well
    below the raw quartic's, also on the coarse torus (768 vertices, a ring spans 22° of the tube)
    at 10 % noise, where every single fit was poor (libigl's 5-ring quadric: 0.36, benchmarks)."""
    for make, amount, bound in (
        (lambda: analytic.ellipsoid((1.0, 0.7, 0.5), 4), 0.05, None),
        (lambda: analytic.torus(1.0, 0.35, 96, 32), 0.05, None),
        (lambda: analytic.torus(1.0, 0.35, 48, 16), 0.1, 0.25),
    ):
        mesh, k_min, k_max = make()
        noisy = analytic.add_noise(mesh, amount, seed=2)
        raw = estimate_curvature(noisy, smoothing=0, cache=False)
        smooth = estimate_curvature(noisy, cache=False)
        error = (mean_relative_error(smooth.k_min, k_min) + mean_relative_error(smooth.k_max, k_max)) / 2
        raw_error = (mean_relative_error(raw.k_min, k_min) + mean_relative_error(raw.k_max, k_max)) / 2
        assert error < 0.7 * raw_error
        if bound is not None:
            assert error < bound


def test_curvature_derivative_on_a_torus():
    """dcurv[1] = C(e_min, e_min, e_max) = D_e_max k_min: along the tube, the ring curvature
    cos φ / (R + r cos φ) changes at (1/r)·(−R sin φ)/(R + r cos φ)² per unit length (sign up to e_max's
    orientation); the other three vanish by the torus's symmetry."""
    major, minor = 1.0, 0.35
    mesh, _, _ = analytic.torus(major, minor, 192, 64)
    c = estimate_curvature(mesh, cache=False)
    v = mesh.vertices.astype(np.float64)
    phi = np.arctan2(v[:, 2], np.hypot(v[:, 0], v[:, 1]) - major)
    expected = (1 / minor) * (-major * np.sin(phi)) / (major + minor * np.cos(phi)) ** 2
    scale = np.abs(expected).max()
    assert np.mean(np.abs(np.abs(c.dcurv[:, 1]) - np.abs(expected))) < 0.02 * scale
    for k in (0, 2, 3):
        assert np.mean(np.abs(c.dcurv[:, k])) < 0.03 * scale


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


@pytest.mark.parametrize("degree", [2, 3, 4])
def test_normal_equations_from_power_sums_are_the_design_matrix_products(degree, rng):
    """The fit's AᵀA and Aᵀh, summed as the 45 power sums Σ x^p y^q and 15 Σ h x^p y^q, equal the
    plain products of the jet's design matrix (`jet_monomials`) on random points in a random frame."""
    from illusio.lines.curvature import _accumulate, _frame, jet_monomials

    count = int(rng.integers(12, 60))
    vertices = rng.normal(size=(count + 1, 3))
    n0 = rng.normal(size=3)
    n0 /= np.linalg.norm(n0)
    t1, t2 = np.empty(3), np.empty(3)
    _frame(n0, t1, t2)
    scale = float(rng.uniform(0.5, 2.0))
    unknowns = (degree + 1) * (degree + 2) // 2
    gram, moment = np.zeros((unknowns, unknowns)), np.zeros(unknowns)
    ring = np.arange(1, count + 1)
    hh = _accumulate(
        vertices,
        0,
        n0,
        t1,
        t2,
        scale,
        ring,
        0,
        count,
        unknowns,
        gram,
        moment,
        (np.empty(45), np.empty(45), np.empty(15)),
    )
    local = (vertices[1:] - vertices[0]) * scale
    x, y, h = local @ t1, local @ t2, local @ n0
    a = jet_monomials(x, y, degree)
    np.testing.assert_allclose(np.triu(gram), np.triu(a.T @ a), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(moment, a.T @ h, rtol=1e-10, atol=1e-12)
    assert hh == pytest.approx(h @ h, rel=1e-12)


def test_adjacency_and_area_normals_match_their_plain_statements(rng):
    """The numba adjacency (unique sorted neighbours, CSR) and area normals equal the NumPy ones on a
    random triangle soup with repeated, reversed and degenerate faces."""
    from illusio.lines.curvature import _adjacency, _area_normals, adjacency_reference, area_normals_reference

    count = 200
    faces = rng.integers(0, count, size=(600, 3))
    faces = np.concatenate([faces, faces[:50, ::-1], faces[:20]])  # repeated edges both ways
    faces[:10, 1] = faces[:10, 0]  # degenerate faces: no self-loop in the adjacency
    vertices = rng.normal(size=(count, 3))
    for got, want in zip(_adjacency(count, faces), adjacency_reference(count, faces)):
        np.testing.assert_array_equal(got, want)
    np.testing.assert_allclose(_area_normals(vertices, faces), area_normals_reference(vertices, faces), atol=1e-12)
