"""The solve cannot amplify light: where an element's form factor estimates add up past 1/ρ (surfaces
nearly touching, as in the Graz office's doubled walls), its gathered light is scaled back to a
gain ρ·Σ F of MAX_GAIN, and the iteration converges; elements whose gain is below it are untouched."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.polygons import Polygons
from illusio.radiosity.solve import MAX_GAIN, form_factor_scale, solve
from tests.radiosity.test_engine import closed_cube


def _gather(n, rows):
    """A gather operator K whose row i spreads ``rows[i]`` (its Σ F) evenly over the other elements."""
    k = np.zeros((n, n))
    for i, total in enumerate(rows):
        k[i, [j for j in range(n) if j != i]] = total / (n - 1)
    return sp.csr_matrix(k)


def test_an_overestimated_gather_is_scaled_to_the_largest_gain():
    h = Hierarchy(closed_cube(0.9, 1.0))
    rows = [1.0, 1.0, 1.6, 1.0, 2.5, 0.7]  # two faces whose estimates pass 1/ρ = 1.11
    scale = form_factor_scale(h, _gather(len(h), rows), h.by_level())
    gain = 0.9 * np.asarray(rows) * scale
    assert np.allclose(scale[[0, 1, 3, 5]], 1.0)  # a gain of 0.9 or 0.63: left alone
    assert np.allclose(gain[[2, 4]], MAX_GAIN)


def test_the_solve_converges_where_it_would_amplify_light():
    """A closed box of ρ 0.97 whose gather overestimates Σ F by 20 % everywhere (gain 1.16): the
    plain iteration grows without bound; the scaled one converges, the lamps' light unscaled, to
    B ≤ E + ρ·ΣF·E / (1 − MAX_GAIN)."""
    h = Hierarchy(closed_cube(0.97, 1.0))
    k = _gather(len(h), [1.2] * len(h))
    exitance = np.ones((len(h), 3))
    result = solve(h, k, exitance, tolerance=1e-6, max_iterations=5000)
    assert result.converged and np.isfinite(h.radiosity).all()
    assert h.radiosity.max() <= 1.0 + 0.97 * 1.2 / (1.0 - MAX_GAIN) + 1e-6
    b = exitance.copy()  # the same iteration without the scale
    for _ in range(200):
        b = exitance + 0.97 * (k @ b)
    assert b.max() > 1e3  # it diverges


def test_the_lamps_light_is_never_scaled_only_the_reflected_light_is():
    """A face 8 cm over a lamp's top (the Graz office's ceiling) sees the black lamp over most of its
    hemisphere, and its estimates to the reflecting faces add up past 1/ρ. The cap scales what it
    gathers from reflecting faces; the lamp's light reaches it whole: B = E + ρ·F_lamp·E_lamp +
    ρ·s·Σ F·B over the reflecting faces, with ρ·s·Σ F = MAX_GAIN. (Scaling the lamp's light too
    made the Graz ceiling's direct light 8 % dark; break it by passing the lamp through the scale.)"""
    cube = closed_cube(0.9, 0.0)
    reflectance = cube.reflectance.copy()
    exitance = cube.exitance.copy()
    reflectance[5], exitance[5] = 0.0, 2.0  # face 5: a black lamp
    h = Hierarchy(Polygons(cube.corners, cube.triangle, reflectance, exitance, cube.group, cube.names))
    k = np.zeros((6, 6))
    k[0, 5] = 0.7  # face 0 sees the lamp over 70 % of its hemisphere …
    k[0, 1:5] = 1.5 / 4  # … and its estimates to the reflecting faces add up to 1.5 (gain 1.35)
    for i in range(1, 5):
        k[i, [j for j in range(5) if j != i]] = 0.2
        k[i, 5] = 0.1
    k = sp.csr_matrix(k)
    scale = form_factor_scale(h, k, h.by_level())
    assert scale[0] == pytest.approx(MAX_GAIN / (0.9 * 1.5))
    assert np.allclose(scale[1:5], 1.0)  # ρ·Σ F = 0.72 over the reflecting faces: left alone
    result = solve(h, k, exitance, tolerance=1e-10, max_iterations=5000)
    assert result.converged
    b = h.radiosity
    lamp = 0.9 * 0.7 * 2.0
    reflected = 0.9 * scale[0] * (k[0, 1:5].toarray() @ b[1:5])[0]
    np.testing.assert_allclose(b[0], lamp + reflected, rtol=1e-8)


def test_the_engine_keeps_the_scale_while_the_links_and_reflectances_stay():
    """A lamp change re-solves with the same links: the engine hands the solve the scale it kept (the
    same array, equal to a fresh form_factor_scale); once the reflectances change (relight estimates
    them) it is computed again."""
    from illusio.radiosity import HierarchyParams, Radiosity

    sol = Radiosity(closed_cube(0.999, 1.0), HierarchyParams(epsilon=1e-3)).build()
    h, matrix = sol.hierarchy, sol.matrix()
    kept = sol.result.scale
    assert (kept < 1).any()  # the cap acts in a closed white box
    sol.solve()
    assert sol.result.scale is kept
    np.testing.assert_array_equal(kept, form_factor_scale(h, matrix, h.by_level()))
    h.reflectance[:] *= 0.5
    sol.solve()
    assert sol.result.scale is not kept
    np.testing.assert_array_equal(sol.result.scale, form_factor_scale(h, matrix, h.by_level()))
    assert (sol.result.scale == 1).all()  # a gain of 0.5: nothing capped
