"""The solve cannot amplify light: where an element's form factor estimates add up past 1/ρ (surfaces
nearly touching, as in the Graz office's doubled walls), its gathered light is scaled back to a
gain ρ·Σ F of MAX_GAIN, and the iteration converges; elements whose gain is below it are untouched."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from illusio.radiosity.hierarchy import Hierarchy
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
    plain iteration grows without bound; the scaled one converges to B ≤ E / (1 − MAX_GAIN)."""
    h = Hierarchy(closed_cube(0.97, 1.0))
    k = _gather(len(h), [1.2] * len(h))
    exitance = np.ones((len(h), 3))
    result = solve(h, k, exitance, tolerance=1e-6, max_iterations=5000)
    assert result.converged and np.isfinite(h.radiosity).all()
    assert h.radiosity.max() <= 1.0 / (1.0 - MAX_GAIN) + 1e-6
    b = exitance.copy()  # the same iteration without the scale
    for _ in range(200):
        b = exitance + 0.97 * (k @ b)
    assert b.max() > 1e3  # it diverges
