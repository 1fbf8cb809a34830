"""Polygons cut where other polygons meet them (radiosity.contacts): a floor or ceiling that runs
on under a wall (RenderPark's Graz office) is cut at the wall's face, so no element averages the lit
room with the part inside the wall."""

import numpy as np
import pytest

from illusio.radiosity import HierarchyParams, Polygons, Radiosity
from illusio.radiosity.contacts import contact_segments, cut_at_contacts
from illusio.radiosity.polygons import polygon_areas, rectangle


def _polygons(rects, exitance=None, reflectance=0.5, uv=None):
    corners = np.stack(rects)
    n = len(corners)
    e = np.zeros((n, 3)) if exitance is None else np.asarray(exitance, float)
    return Polygons(
        corners,
        np.zeros(n, bool),
        np.full((n, 3), reflectance),
        e,
        np.arange(n),
        [f"p{k}" for k in range(n)],
        uv=uv,
    )


FLOOR = rectangle((0, 0, 0), (4, 0, 0), (0, 0, -4))  # x, z in −2…2, facing +y


def test_a_wall_standing_across_a_floor_cuts_it_and_a_table_foot_does_not():
    """A wall standing on a 4 m floor across its whole depth at x = 1 cuts the floor in two along
    x = 1 (area, plane, group and material kept; the texture coordinates follow the cut); a 5 cm
    foot standing on it does not (it covers a sliver of the floor's chord), nor is the wall cut by
    the floor it stands on (their line is the wall's own edge)."""
    wall = rectangle((1, 0.5, 0), (0, 0, 4), (0, 1, 0))  # facing −x, its bottom edge on the floor
    foot = rectangle((-1, 0.2, -1), (0, 0.4, 0), (0, 0, 0.05))  # facing +x, 5 cm wide
    uv = np.full((3, 4, 2), np.nan)
    uv[0] = (FLOOR[:, [0, 2]] + 2) / 4  # u = (x + 2)/4, v = (z + 2)/4
    p = _polygons([FLOOR, wall, foot], uv=uv)
    assert np.allclose(p.normals()[:2], [[0, 1, 0], [-1, 0, 0]], atol=1e-12)
    cut = cut_at_contacts(p, min_area=0.01)
    assert len(cut) == 4
    pieces = np.flatnonzero(cut.group == 0)
    assert len(pieces) == 2
    x = cut.corners[pieces, :, 0]
    assert sorted((round(x.min(axis=1)[k], 9), round(x.max(axis=1)[k], 9)) for k in range(2)) == [(-2, 1), (1, 2)]
    assert polygon_areas(cut.corners, cut.triangle).sum() == pytest.approx(
        polygon_areas(p.corners, p.triangle).sum(), rel=1e-12
    )
    assert np.allclose(cut.normals()[pieces], [0, 1, 0]) and np.allclose(cut.reflectance, 0.5)
    assert np.allclose(cut.uv[pieces], (cut.corners[pieces][..., [0, 2]] + 2) / 4)
    assert np.array_equal(np.sort(cut.group), [0, 0, 1, 2])


def test_a_cut_that_would_leave_a_piece_under_the_minimum_area_is_not_made():
    """A wall 10 cm from the floor's edge: the strip would be 0.4 m², under A_ε = 1 m²: no cut."""
    wall = rectangle((1.9, 0.5, 0), (0, 0, 4), (0, 1, 0))
    p = _polygons([FLOOR, wall])
    assert len(contact_segments(p, 1.0)[0]) == 1  # the contact is found...
    assert cut_at_contacts(p, min_area=1.0) is p  # ...and left uncut
    assert len(cut_at_contacts(p, min_area=0.1)) == 3


def _room(ceiling_under_wall: bool):
    """A 2 m room lit by a lamp on its floor; its ceiling runs on 15 cm under the wall at x = 0
    (to the wall's outer face, as the Graz office's does) or stops at the room's side."""
    if ceiling_under_wall:
        ceiling = rectangle((0.925, 2, 1), (2.15, 0, 0), (0, 0, 2))  # x −0.15…2, facing −y
    else:
        ceiling = rectangle((1, 2, 1), (2, 0, 0), (0, 0, 2))
    rects = [
        ceiling,
        rectangle((1, 0, 1), (2, 0, 0), (0, 0, -2)),  # floor, +y
        rectangle((0, 1, 1), (0, 2, 0), (0, 0, 2)),  # x = 0, +x: the wall the ceiling runs under
        rectangle((-0.15, 1, 1), (0, 0, 2), (0, 2, 0)),  # that wall's outer face, −x
        rectangle((2, 1, 1), (0, 0, 2), (0, 2, 0)),  # x = 2, −x
        rectangle((1, 1, 0), (2, 0, 0), (0, 2, 0)),  # z = 0, +z
        rectangle((1, 1, 2), (0, 2, 0), (2, 0, 0)),  # z = 2, −z
        rectangle((1, 0.01, 1), (0.2, 0, 0), (0, 0, -0.2)),  # the lamp, facing up
    ]
    exitance = np.zeros((len(rects), 3))
    exitance[-1] = 50.0
    return _polygons(rects, exitance=exitance)


def test_the_ceiling_beside_a_wall_it_runs_under_reads_as_the_room_s_own_ceiling():
    """The ceiling's radiosity 5 cm from the wall, in a room whose ceiling runs on under that wall,
    against the same room whose ceiling stops at the wall: within 5 % with the cut. Uncut, the
    element there spans the wall's line and averages in the unlit part inside the wall."""

    def near_wall(polygons, contact_cuts):
        params = HierarchyParams(epsilon=1e-4, min_area=0.02, clusters=False, contact_cuts=contact_cuts)
        sol = Radiosity(polygons, params).build()
        h = sol.hierarchy
        leaves = h.leaves()
        leaves = leaves[sol.polygons.group[h.polygon[leaves]] == 0]  # the ceiling's
        c = h.corners[leaves]
        inside = (c[..., 0].min(axis=1) <= 0.05) & (c[..., 0].max(axis=1) >= 0.05)
        inside &= (c[..., 2].min(axis=1) <= 1.0) & (c[..., 2].max(axis=1) >= 1.0)
        return h.radiosity[leaves[inside]].mean()

    truth = near_wall(_room(False), True)
    assert near_wall(_room(True), True) == pytest.approx(truth, rel=0.05)
    assert near_wall(_room(True), False) < 0.8 * truth
