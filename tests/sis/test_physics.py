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
    s = Screen(diagonal_cm=float(rng.uniform(20, 150)), aspect=float(rng.uniform(1.2, 2.4)),
               viewing_distance_cm=float(rng.uniform(40, 300)))
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
