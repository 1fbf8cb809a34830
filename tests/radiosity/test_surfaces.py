"""Surfaces: input polygons joined across shared edges in one plane (Polygons.surfaces), what
relighting's neighbourhoods and the display's smoothing run over, so a triangulated model behaves
as its quads would."""

import numpy as np

from illusio.radiosity import Polygons, scene_polygons
from illusio.radiosity.hierarchy import Hierarchy
from illusio.relight.textures import neighbours
from illusio.scene import load_scene
from tests.relight.test_relight import _triangulated


def test_a_triangulated_model_has_the_surfaces_of_its_quads():
    quads = scene_polygons(load_scene("office"))
    tris = _triangulated(quads)
    assert len(tris) > len(quads)
    s = tris.surfaces()
    assert len(np.unique(s)) == len(np.unique(quads.surfaces())) == len(quads)
    quad = ~quads.triangle
    assert np.array_equal(s[: len(quads)][quad], s[len(quads) :])  # the two halves of each quad


def test_only_flat_neighbours_join():
    def fold(degrees):
        a = np.radians(degrees)
        flat = [[0, 0, 0], [1, 0, 0], [1, 0, -1], [0, 0, -1]]  # facing +y
        bent = [[1, 0, 0], [2, np.sin(a), 0], [2, np.sin(a), -1], [1, 0, -1]]  # shares the edge x = 1
        return Polygons(
            np.array([flat, bent], float), np.zeros(2, bool), np.full((2, 3), 0.5), np.zeros((2, 3)), [0, 0], ["sheet"]
        )

    assert len(np.unique(fold(0.5).surfaces())) == 1
    assert len(np.unique(fold(2.0).surfaces())) == 2
    apart = fold(0.0)
    apart.corners[1] += (0.001, 0, 0)  # no shared edge
    assert (
        len(
            np.unique(
                Polygons(
                    apart.corners, apart.triangle, apart.reflectance, apart.exitance, apart.group, apart.names
                ).surfaces()
            )
        )
        == 2
    )


def test_neighbours_cross_the_diagonal_of_a_split_quad():
    """A leaf touching the cut of a split wall has neighbours in the other triangle."""
    quads = scene_polygons(load_scene("cornell-box"))
    tris = _triangulated(quads)
    h = Hierarchy(tris)
    wall = quads.names.index("back-wall")
    halves = np.flatnonzero(tris.group == wall)
    assert len(halves) == 2
    h.subdivide(halves)
    leaves = h.leaves()
    near = neighbours(h, leaves)
    row = {int(e): k for k, e in enumerate(leaves)}
    first = [e for e in leaves if h.polygon[e] == halves[0]]
    crossing = [e for e in first if any(h.polygon[leaves[n]] == halves[1] for n in near[row[int(e)]])]
    assert len(crossing) >= 2  # the leaves along the cut


def test_a_two_sided_walls_faces_join_as_do_their_twins_but_not_across_materials(tmp_path):
    """An MGF wall of two quads (two-sided: each quad with its reversed twin, so each edge has four
    owners) is two surfaces, its front and its back; a quad of another material in the same plane
    sharing an edge with them stays apart."""
    from illusio.scene.mgf import load_mgf

    points = "".join(f"v p{k} =\n\tp {x} 0 {z}\n" for k, (x, z) in enumerate([(0, 0), (1, 0), (2, 0), (3, 0)]))
    points += "".join(f"v q{k} =\n\tp {x} 0 1\n" for k, x in enumerate(range(4)))
    text = points + "m white =\n\tc\n\trd 0.8\nf p0 p1 q1 q0\nf p1 p2 q2 q1\nm black =\nf p2 p3 q3 q2\n"
    (tmp_path / "wall.mgf").write_text(text)
    polygons = scene_polygons(load_mgf(tmp_path / "wall.mgf", up="z"))
    surface = polygons.surfaces()
    white = polygons.group == polygons.names.index("scene/white")
    fronts, twins = white & (polygons.side == 1), white & (polygons.side == 2)
    assert len(set(surface[fronts])) == 1 and len(set(surface[twins])) == 1
    assert set(surface[fronts]) != set(surface[twins])
    assert not set(surface[~white]) & set(surface[white])


def test_a_group_moved_keeps_its_surfaces_where_the_move_keeps_angles():
    """Polygons.moved carries the surfaces through a rotation with a translation and a uniform
    scale (they equal the surfaces found afresh), and finds them afresh after a non-uniform scale: a
    0.5° fold within a group, one surface before, is two once stretched past 1°."""
    a = np.radians(0.5)
    flat = [[0, 0, 0], [1, 0, 0], [1, 0, -1], [0, 0, -1]]
    bent = [[1, 0, 0], [2, np.sin(a), 0], [2, np.sin(a), -1], [1, 0, -1]]
    floor = [[-5, -1, 5], [5, -1, 5], [5, -1, -5], [-5, -1, -5]]
    sheet = Polygons(
        np.array([flat, bent, floor], float),
        np.zeros(3, bool),
        np.full((3, 3), 0.5),
        np.zeros((3, 3)),
        [0, 0, 1],
        ["sheet", "floor"],
    )
    assert len(np.unique(sheet.surfaces()[:2])) == 1
    turn = np.eye(4)
    c, s = np.cos(0.7), np.sin(0.7)
    turn[:3, :3] = 1.5 * np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    turn[:3, 3] = (0.3, 0.1, -2.0)
    moved = sheet.moved(0, turn)
    assert moved is not sheet and np.array_equal(sheet.corners[0], flat)  # the caller's kept
    assert np.allclose(moved.corners[2], floor) and np.allclose(
        moved.corners[0, 1], turn[:3, :3] @ [1, 0, 0] + turn[:3, 3]
    )
    fresh = Polygons(moved.corners, moved.triangle, moved.reflectance, moved.exitance, moved.group, moved.names)
    assert getattr(moved, "_surfaces", None) is not None  # carried, not recomputed
    assert np.array_equal(moved.surfaces(), fresh.surfaces())
    stretch = np.diag([1.0, 4.0, 1.0, 1.0])  # the fold opens to ~2°
    stretched = sheet.moved(0, stretch)
    assert getattr(stretched, "_surfaces", None) is None
    assert len(np.unique(stretched.surfaces()[:2])) == 2
