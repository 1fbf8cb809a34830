"""Pairs that straddle a plane (a face standing on the floor and the floor) and polygons narrower than
√A_ε (a lamp's pole): the three ways the living room lost or misplaced light against Mitsuba
(issue 31), each with the test that fails without its fix."""

import numpy as np
import pytest

from illusio.radiosity import HierarchyParams, Polygons, Radiosity
from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.polygons import polygon_areas, rectangle
from illusio.radiosity.visibility import Visibility


def _polygons(rects, exitance=None, reflectance=0.5):
    corners = np.stack(rects)
    n = len(corners)
    e = np.zeros((n, 3)) if exitance is None else np.asarray(exitance, float)
    return Polygons(
        corners, np.zeros(n, bool), np.full((n, 3), reflectance), e, np.arange(n), [f"p{k}" for k in range(n)]
    )


def test_a_face_standing_on_the_floor_sees_the_floor_clear():
    """A 20 cm board standing upright in the middle of a 2 m floor: half the floor lies behind the
    board's plane, where its rays would go back through the board. Only rays front to front count
    in V, so the pair is clear (V = 1); counting the others as blocked gave V ≈ 0.5."""
    floor = rectangle((0, 0, 0), (2, 0, 0), (0, 0, -2))  # facing +y
    board = rectangle((0, 0.1, 0), (0, 0, -0.2), (0, 0.2, 0))  # facing +x, standing on the floor
    p = _polygons([floor, board])
    assert np.allclose(p.normals(), [[0, 1, 0], [1, 0, 0]], atol=1e-12)
    h = Hierarchy(p)
    vis = Visibility(h, samples=64, seed=2)
    form_factor, v = vis(np.array([1]), np.array([0]))
    assert v[0] == 1.0
    # the form factor is that of the floor's front half (clipped to the board's tangent plane):
    # a face standing on an infinite floor sees half of its hemisphere filled, F → 1/2
    assert 0.4 < form_factor[0] < 0.5


def test_split_slivers_keeps_area_plane_and_material():
    """Polygons.split_slivers cuts a 1 m × 1 cm strip into pieces of at least max(4 × width, L) and
    keeps its area, front and group; a square and a triangle are kept as they are."""
    strip = rectangle((0, 0.5, 0), (0.01, 0, 0), (0, 1.0, 0))
    square = rectangle((1, 0, 0), (0.5, 0, 0), (0, 0.5, 0))
    p = _polygons([strip, square], reflectance=0.3)
    cut = p.split_slivers(0.1)
    assert len(cut) == 1 + 10
    assert polygon_areas(cut.corners, cut.triangle).sum() == pytest.approx(
        polygon_areas(p.corners, p.triangle).sum(), rel=1e-12
    )
    assert np.allclose(cut.normals(), p.normals()[cut.group])
    assert np.array_equal(np.bincount(cut.group), [10, 1]) and np.allclose(cut.reflectance, 0.3)
    assert len(p.split_slivers(0.5)) == 1 + 2 and p.split_slivers(0.0) is p


def test_a_pole_lit_at_one_end_is_not_lit_along_its_length():
    """A 1.4 m × 1 cm pole under a small lamp at its top (the living room's floor lamp): its
    radiosity falls along it, near the lamp at least 20× what it is at its foot. With A_ε = 50 cm²
    (the living room's) and uncut (sliver_piece = 0) the pole is one element, lit uniformly."""
    floor = rectangle((0, 0, 0), (3, 0, 0), (0, 0, -3))
    pole = rectangle((0, 0.7, 0.005), (0.01, 0, 0), (0, 1.4, 0))  # facing +z
    lamp = rectangle((0, 1.4 + 1e-3, 0.03), (0.06, 0, 0), (0, 0, 0.06))  # facing down
    p = _polygons([floor, pole, lamp], exitance=[[0] * 3, [0] * 3, [500.0] * 3])
    assert p.normals()[2, 1] < -0.99 and p.normals()[1, 2] > 0.99

    def pole_radiosity(sliver_piece):
        sol = Radiosity(
            p, HierarchyParams(epsilon=1e-5, min_area=0.005, sliver_piece=sliver_piece, clusters=False)
        ).build()
        h = sol.hierarchy
        leaves = h.leaves()
        on_pole = leaves[sol.polygons.group[h.polygon[leaves]] == 1]
        low, high = h.corners[on_pole, :, 1].min(axis=1), h.corners[on_pole, :, 1].max(axis=1)
        b = h.radiosity[on_pole].mean(axis=1)
        return [b[(low <= y) & (y <= high)].mean() for y in (1.35, 0.1)]

    top, foot = pole_radiosity(0.5)
    assert top > 20 * foot
    top, foot = pole_radiosity(0.0)
    assert top == pytest.approx(foot)
