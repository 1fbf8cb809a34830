"""Each leaf's reach (Visibility.reach: Σ_j F_ij V_ij as cosine-weighted rays measure it), the
solve's scale of each leaf's gathered light to it (solve.form_factor_scale), and GMRES before the
gather iterations (solve.solve) against the iterations alone."""

import numpy as np
import pytest

from illusio.radiosity import HierarchyParams, Polygons, Radiosity
from illusio.radiosity.engine import REACH_MAX_RATIO, REACH_MIN_SUM, smoothed_reach
from illusio.radiosity.formfactor import point_polygon
from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.polygons import _cube
from illusio.radiosity.solve import MAX_GAIN, form_factor_scale, solve
from illusio.radiosity.visibility import Visibility


def _polygons(corners, reflectance=0.5, exitance=None) -> Polygons:
    corners = np.asarray(corners, float)
    n = len(corners)
    emit = np.zeros((n, 3)) if exitance is None else np.asarray(exitance, float)
    return Polygons(
        corners, np.zeros(n, bool), np.full((n, 3), reflectance), emit, np.arange(n), [f"p{k}" for k in range(n)]
    )


def test_reach_is_one_inside_a_closed_room_and_the_form_factor_to_what_is_there_outside():
    """Inside a closed cube every ray meets a wall (reach 1); a floor patch under one square
    ceiling panel reaches the exact form factor to it (point_polygon over the patch), within the
    noise of 1,024 rays."""
    inside = Hierarchy(_polygons(_cube((0, 0, 0), 1.0)[:, ::-1]))
    inside.subdivide(inside.roots)
    leaves = inside.leaves()
    assert np.array_equal(Visibility(inside).reach(leaves, 64), np.ones(len(leaves)))

    floor = [[-0.1, 0, 0.1], [0.1, 0, 0.1], [0.1, 0, -0.1], [-0.1, 0, -0.1]]  # facing +y
    panel = [[-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1]]  # facing -y, 1 m above
    h = Hierarchy(_polygons([floor, panel]))
    reach = Visibility(h, seed=3).reach(np.array([0]), 1024)[0]
    points = h.sample_points(np.array([0]), np.random.default_rng(0).random((1, 256, 2)))
    exact = point_polygon(points, h.normal[[0]], h.corners[[1]], h.triangle[[1]])[0]
    assert 0.3 < exact < 0.9 and reach == pytest.approx(exact, abs=0.04)
    assert Visibility(Hierarchy(_polygons([floor]))).reach(np.array([0]), 64)[0] == 0  # nothing above


def test_a_leafs_gathered_form_factors_are_scaled_to_its_reach_and_never_to_a_gain_over_the_cap(rng):
    """form_factor_scale: Σ F·V (K·1 pushed down) × the scale equals the reach at each leaf, and
    ρ·Σ F·V × the scale stays at most MAX_GAIN where the reach would pass it."""
    sol = Radiosity(
        _polygons(_cube((0, 0, 0), 1.0)[:, ::-1], 0.99, np.r_[[[4.0] * 3], np.zeros((5, 3))]),
        HierarchyParams(epsilon=1e-2),
    )
    sol.build()
    h = sol.hierarchy
    levels = h.by_level()
    total = np.asarray(sol.matrix() @ np.ones((len(h), 3)))[:, 0].copy()
    for level in levels[1:]:
        total[level] += total[h.parent[level]]
    leaves = h.leaves()
    reach = np.full(len(h), np.nan)
    reach[leaves] = rng.uniform(0.9, 1.0, len(leaves))
    scale = form_factor_scale(h, sol.matrix(), levels, reach)
    gain = 0.99 * reach[leaves]
    free = gain <= MAX_GAIN
    np.testing.assert_allclose((total * scale)[leaves][free], reach[leaves][free], rtol=1e-12)
    np.testing.assert_allclose(0.99 * (total * scale)[leaves][~free], MAX_GAIN, rtol=1e-12)
    assert (~free).any() and free.any()


def test_gmres_then_iterations_reach_the_fixed_point_of_the_iterations_alone_in_fewer_products():
    """A bright closed room (ρ 0.95, the gain near 0.95 everywhere): the gather iterations alone
    take over a hundred products to a tolerance of 1e-6 (141); GMRES first gives the same B (within it) in
    a fraction of them, and B stays linear in the exitances (twice the lamp, twice B)."""
    lamp = np.r_[[[3.0, 2.0, 1.0]], np.zeros((5, 3))]
    sol = Radiosity(_polygons(_cube((0, 0, 0), 1.0)[:, ::-1], 0.95, lamp), HierarchyParams(epsilon=1e-3))
    sol.build()
    h, matrix, exitance = sol.hierarchy, sol.matrix(), sol.exitance()
    reach = sol.reach()
    start = exitance.copy()
    plain = solve(h, matrix, exitance, 1e-6, 5000, start=start, reach=reach, krylov=False)
    b_plain = h.radiosity.copy()
    fast = solve(h, matrix, exitance, 1e-6, 5000, start=start, reach=reach)
    b_fast = h.radiosity.copy()
    assert plain.converged and fast.converged and plain.iterations > 100
    assert fast.iterations < plain.iterations / 3, (fast.iterations, plain.iterations)
    reflected = float(np.abs(b_plain - exitance).max())
    assert np.abs(b_fast - b_plain).max() < 2e-5 * reflected  # both within 1e-6 of the change's scale
    solve(h, matrix, 2 * exitance, 1e-6, 5000, start=start, reach=reach)
    assert np.abs(h.radiosity - 2 * b_fast).max() < 4e-5 * reflected


def test_a_warm_start_finishes_with_gather_steps_and_a_cold_bright_room_takes_gmres(monkeypatch):
    """solve's probe: from a converged B (an edit) the first gather steps finish it, GMRES unused
    (its set-up cost as much as the rest of a relighting drag's move); from the lamps alone in a bright
    room the steps contract slowly and GMRES is taken."""
    import illusio.radiosity.solve as solve_module

    lamp = np.r_[[[3.0, 2.0, 1.0]], np.zeros((5, 3))]
    sol = Radiosity(_polygons(_cube((0, 0, 0), 1.0)[:, ::-1], 0.95, lamp), HierarchyParams(epsilon=1e-3))
    sol.build()
    h, matrix, exitance, reach = sol.hierarchy, sol.matrix(), sol.exitance(), sol.reach()
    calls = []
    real = solve_module._krylov
    monkeypatch.setattr(solve_module, "_krylov", lambda *a: calls.append(1) or real(*a))
    cold = solve(h, matrix, exitance, 1e-6, 5000, start=exitance.copy(), reach=reach)
    assert cold.converged and calls == [1]
    warm = solve(h, matrix, exitance, 1e-6, 5000, start=h.radiosity.copy(), reach=reach)
    assert warm.converged and warm.iterations <= solve_module.PROBE_STEPS and calls == [1]


def _floor_leaves(levels: int) -> Hierarchy:
    """A 4 × 4 m floor split ``levels`` times into a grid of equal leaves."""
    h = Hierarchy(_polygons([[[0, 0, 0], [4, 0, 0], [4, 4, 0], [0, 4, 0]]]))
    for _ in range(levels):
        h.subdivide(h.leaves())
    return h


def test_the_reach_is_averaged_over_neighbours_and_a_region_the_links_miss_survives(rng):
    """engine.smoothed_reach: the rays' noise on each leaf's reach is shared out over its
    neighbours (its spread at least halved), while a region where the reach differs (a ceiling over
    a lamp: a third) keeps it inside; the factor on a leaf stays within REACH_MAX_RATIO, and a leaf
    whose links reach under REACH_MIN_SUM is left alone (NaN)."""
    h = _floor_leaves(4)  # 16 × 16 leaves of 25 cm
    leaves = h.leaves()
    x, y = h.centre[leaves, 0], h.centre[leaves, 1]
    truth = np.where((x < 1.5) & (y < 1.5), 0.3, 0.9)
    reach = np.full(len(h), np.nan)
    reach[leaves] = truth + rng.normal(0.0, 0.05, len(leaves))
    sums = np.full(len(h), 0.9)
    smooth = smoothed_reach(h, reach, sums)[leaves]
    away = (np.minimum(np.abs(x - 1.5), np.abs(y - 1.5)) > 0.6) | (x > 2.1) | (y > 2.1)
    assert np.std((smooth - truth)[away]) < 0.5 * np.std((reach[leaves] - truth)[away])
    inner = (x < 0.9) & (y < 0.9)
    # the region survives: without noise its inner leaves keep 0.3 (smoothing 4 times would pull
    # them 0.04 towards the 0.9 around); with noise, a leaf's smoothed noise is at most half the
    # rays' σ (a corner leaf averages the fewest: 0.49σ), so 5 of those bound it (2 % of seeds
    # passed a flat 0.06, 4σ at a corner)
    noise_free = reach.copy()
    noise_free[leaves] = truth
    assert np.abs(smoothed_reach(h, noise_free, sums)[leaves][inner] - 0.3).max() < 0.01
    assert np.abs(smooth[inner] - 0.3).max() < 5 * 0.5 * 0.05
    bright = np.flatnonzero(truth == 0.9)
    sums[leaves[bright[:5]]] = REACH_MIN_SUM / 2  # links that reach almost nothing: left as they are
    sums[leaves[bright[5:10]]] = 0.01 + REACH_MIN_SUM  # a tiny sum under a reach of 0.9: capped
    smooth = smoothed_reach(h, reach, sums)[leaves]
    assert np.isnan(smooth[bright[:5]]).all()
    np.testing.assert_allclose(smooth[bright[5:10]] / sums[leaves[bright[5:10]]], REACH_MAX_RATIO)


def test_an_edit_measures_the_reach_of_the_leaves_it_made_or_moved_only(monkeypatch):
    """Radiosity.reach after a build measures every leaf once; a lamp change measures none; a moved
    chair seat measures its own leaves and the leaves refinement made, and every other leaf keeps the
    reach it had (measuring all again cost the move 0.12 of a rebuild; the goal is 0.1)."""
    from illusio.radiosity import scene_polygons
    from illusio.radiosity.visibility import Visibility as Rays
    from illusio.scene import load_scene

    polygons = scene_polygons(load_scene("office"))
    sol = Radiosity(polygons, HierarchyParams(reach_rays=32)).build()
    measured = []
    original = Rays.reach
    monkeypatch.setattr(
        Rays, "reach", lambda self, elements, rays=64: measured.append(elements) or original(self, elements, rays)
    )
    before_raw, _, _ = sol._reach
    sol.set_lamps({"lamp-0": 0.5})
    assert measured == []
    h = sol.hierarchy
    seat = np.flatnonzero(sol.polygons.group == sol.polygons.names.index("chair-seat"))
    move = np.eye(4)
    move[:3, 3] = (0.3, 0.0, 0.2)
    sol.move_object("chair-seat", move)
    again = np.concatenate(measured)
    leaves = h.leaves()
    assert 0 < len(again) < 0.2 * len(leaves)
    assert np.isin(h.polygon[again], seat).any()  # the seat's own leaves, moved
    kept = np.setdiff1d(leaves[leaves < len(before_raw)], again)
    after_raw, _, _ = sol._reach
    np.testing.assert_array_equal(after_raw[kept], before_raw[kept])
