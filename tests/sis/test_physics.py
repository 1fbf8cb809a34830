"""Equations (1)–(4) of Dehos et al. 2014, one test each, and the round trip."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.scene.camera import Screen
from illusio.sis import physics
from illusio.sis.params import StereogramParams


def test_eq1_separation_cm():
    # e' = f'e/(f+f'): zero at the screen, e/2 at f' = f, → e as f' → ∞
    assert physics.separation_cm(0.0) == 0.0
    assert physics.separation_cm(100.0, 100.0, 6.5) == pytest.approx(3.25)
    assert physics.separation_cm(1e9, 100.0, 6.5) == pytest.approx(6.5, rel=1e-6)
    # by similar triangles: the eyes (e apart, f in front) and P (f' behind) see the screen points
    f, e, fp = 80.0, 6.3, 37.0
    assert physics.separation_cm(fp, f, e) == pytest.approx(e * fp / (f + fp))


def test_eq2_screen_width():
    # w = a·d/√(1+a²): a 53 cm 16/9 screen is 46.19 cm wide; 16/10 is 44.94 cm; w² + h² = d²
    assert physics.screen_width_cm(53, 16 / 9) == pytest.approx(46.194, abs=1e-3)
    assert physics.screen_width_cm(53, 16 / 10) == pytest.approx(44.944, abs=1e-3)
    s = Screen(diagonal_cm=53, aspect=16 / 9)
    assert s.width_cm**2 + s.height_cm**2 == pytest.approx(53**2)


def test_eq3_separation_px():
    s = Screen()
    fp = np.array([10.0, 74.0, 175.0, 1000.0])
    expected = fp * s.width_px * s.eye_separation_cm / ((s.viewing_distance_cm + fp) * s.width_cm)
    np.testing.assert_allclose(physics.separation_px(fp, s), expected, rtol=1e-12)


def test_eq4_depth_from_separation_inverts_eq3(rng):
    s = Screen(
        diagonal_cm=float(rng.uniform(20, 150)),
        aspect=float(rng.uniform(1.2, 2.4)),
        viewing_distance_cm=float(rng.uniform(40, 300)),
    )
    fp = rng.uniform(1, 500, 50)
    np.testing.assert_allclose(physics.depth_from_separation(physics.separation_px(fp, s), s), fp, rtol=1e-9)
    # and the other way round, for separations below e_p
    sep = rng.uniform(1, physics.max_separation_px(s) - 1, 50)
    np.testing.assert_allclose(physics.separation_px(physics.depth_from_separation(sep, s), s), sep, rtol=1e-9)
    assert np.isinf(physics.depth_from_separation(physics.max_separation_px(s) + 1, s))


def test_limit_e_p_for_both_aspects():
    # Table 1 gives 16/9, for which e_p = 270 px; the paper's ≈ 277 px is the 16/10 value
    assert physics.max_separation_px(Screen(aspect=16 / 9)) == pytest.approx(270.2, abs=0.1)
    assert physics.max_separation_px(Screen(aspect=16 / 10)) == pytest.approx(277.7, abs=0.1)
    assert physics.separation_px(1e12, Screen()) == pytest.approx(physics.max_separation_px(Screen()), rel=1e-6)


def test_depth_range_of_the_paper_example():
    # the paper: e'_p ∈ [100, 150] ↔ f' ∈ [74, 175] cm. That holds with w = 53 cm (the diagonal taken
    # as the width); the true widths give smaller depths.
    near, far = physics.depth_range(100, 50, Screen(), width_cm=53.0)
    assert (round(near), round(far)) == (74, 175)
    near, far = physics.depth_range(100, 50, Screen(aspect=16 / 9))
    assert near == pytest.approx(58.76, abs=0.01) and far == pytest.approx(124.83, abs=0.01)
    near, far = physics.depth_range(100, 50, Screen(aspect=16 / 10))
    assert near == pytest.approx(56.28, abs=0.01) and far == pytest.approx(117.48, abs=0.01)


@pytest.mark.parametrize("strip_width, depth_factor", [(0, 50), (280, 10), (100, 0), (100, 200)])
def test_parameters_out_of_the_paper_ranges_are_refused(strip_width, depth_factor):
    with pytest.raises(InputError, match="must lie in"):
        StereogramParams(strip_width=strip_width, depth_factor=depth_factor)


def test_section_3_4_linear_approximation_error(rng):
    """The linear mode's depth error, against an independent reference: for each D, the depth whose
    equation-(1) separation (in pixels) is W_s + β·D, found by bisection instead of equation (4).
    Zero at both ends, negative between (the viewer sees every point nearer), a few cm for the
    paper's screen."""
    screen = Screen()
    strip_width, depth_factor = float(rng.uniform(60, 120)), float(rng.uniform(20, 80))
    d, error = physics.linear_depth_error(strip_width, depth_factor, screen, samples=41)
    near, far = physics.depth_range(strip_width, depth_factor, screen)
    px_per_cm = screen.width_px / screen.width_cm
    for k in (5, 20, 33):
        target = strip_width + depth_factor * d[k]
        lo, hi = 0.0, 10 * far
        for _ in range(200):
            mid = (lo + hi) / 2
            if physics.separation_cm(mid, screen.viewing_distance_cm, screen.eye_separation_cm) * px_per_cm < target:
                lo = mid
            else:
                hi = mid
        assert error[k] == pytest.approx(mid - (near + d[k] * (far - near)), abs=1e-6)
    assert abs(error[0]) < 1e-9 and abs(error[-1]) < 1e-9
    assert (error[1:-1] < 0).all()
    # the paper's example (W_s = 100, β = 50): at worst some ten centimetres nearer, in the middle
    d, error = physics.linear_depth_error(100, 50, screen)
    assert 5 < -error.min() < 30 and 0.3 < d[np.argmin(error)] < 0.7
