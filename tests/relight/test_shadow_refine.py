"""Loscos 4.3.1: the texture-based refinement of Figure 4.7 on a scene small enough to reason about —
a floor, a square board above it and one small lamp, "photographed" by direct lighting computed per
pixel (relight.per_pixel, independent of the radiosity links), with a dark poster painted on the lit
floor (Figure 4.8a: a change of colour that is not a shadow)."""

import dataclasses

import numpy as np
import pytest

from illusio.radiosity import HierarchyParams, Polygons
from illusio.radiosity.hierarchy import Hierarchy
from illusio.radiosity.visibility import INVISIBLE, PARTIAL, VISIBLE
from illusio.relight import RealScene, RelightParams, RelightSession
from illusio.relight.per_pixel import lamp_irradiance, surface_points
from illusio.relight.shadow_refine import lamp_visibility, split_decision
from illusio.scene.camera import Camera, Pose, View

POSTER = (slice(20, 32), slice(70, 84))  # rows, columns of the photograph painted dark


def _quad(centre, half_u, half_v, down=False):
    c, u, v = (np.asarray(x, float) for x in (centre, half_u, half_v))
    q = np.array([c - u + v, c + u + v, c + u - v, c - u - v])  # facing +y for u = x, v = z
    return q[::-1] if down else q


@pytest.fixture(scope="module")
def board_scene():
    corners = np.array(
        [
            _quad((0, 0, 0), (2, 0, 0), (0, 0, 2)),  # floor, facing up
            _quad((0, 0.8, 0), (0.4, 0, 0), (0, 0, 0.4), down=True),  # board, facing down
            _quad((1.0, 2.0, 0), (0.15, 0, 0), (0, 0, 0.15), down=True),
        ]
    )  # lamp, facing down
    polygons = Polygons(
        corners,
        np.zeros(3, bool),
        np.array([[0.5] * 3, [0.5] * 3, [0.0] * 3]),
        np.array([[0.0] * 3, [0.0] * 3, [60.0] * 3]),
        np.arange(3),
        ["floor", "board", "lamp"],
        [2],
    )
    view = View(Pose((-0.4, 5.0, 0.0), (-0.4, 0.0, 0.0), up=(0.0, 0.0, -1.0)), Camera(fov_y=50.0))
    size = (96, 96)
    points, normals, polygon = surface_points(polygons, view, size)
    seen = polygon >= 0
    direct = lamp_irradiance(polygons, np.array([2]), polygons.exitance[[2]], points, normals, seen, samples=64)[:, 0]
    radiance = np.zeros((96, 96, 3))
    radiance[seen] = polygons.reflectance[polygon[seen]] * (direct + 0.5) / np.pi
    radiance[POSTER] *= 0.3
    return RealScene(polygons, view, radiance.astype(np.float32))


# BFV (B·F·V·A): a first mesh as coarse in the shadow as the criterion allows, so what follows the
# shadow is the texture refinement (BF, B·F·A, would refine the shadow region already)
PARAMS = RelightParams(
    method="loscos", hierarchy=HierarchyParams(criterion="bfv", epsilon=3e-2, min_area=1e-3, clusters=False)
)


@pytest.fixture(scope="module")
def sessions(ctx, board_scene):
    made = {
        flag: RelightSession(board_scene, dataclasses.replace(PARAMS, texture_refinement=flag), ctx)
        for flag in (False, True)
    }
    yield made
    for s in made.values():
        s.release()


def within_leaf_spread(session) -> float:
    """Mean |pixel − mean of its leaf's pixels| / mean, over the floor's pixels: how much of the
    photograph's detail (its shadow) lies inside leaves rather than between them."""
    leaf = session.pixel_element
    floor = (session.pixel_polygon == 0) & (leaf >= 0)
    floor[POSTER] = False
    lum = session.real.photograph.mean(axis=-1)
    count = np.bincount(leaf[floor])
    mean = np.bincount(leaf[floor], weights=lum[floor]) / np.maximum(count, 1)
    return float(np.abs(lum[floor] - mean[leaf[floor]]).mean() / lum[floor].mean())


def test_figure_4_7_refinement_follows_the_photographed_shadow(sessions):
    """Leaves are split along the board's shadow (case 1 and the PARTIAL rule) and the photograph's
    spread inside the leaves drops by more than a third; the fully lit floor away from the shadow is
    left as the first refinement made it."""
    plain, refined = sessions[False], sessions[True]
    stats = refined.refine_stats
    assert stats.split > 0 and refined.solution.stats.leaves > plain.solution.stats.leaves
    assert within_leaf_spread(refined) < 0.67 * within_leaf_spread(plain)
    h = refined.solution.hierarchy
    leaves = h.leaves()
    vis, kind = lamp_visibility(h, refined.solution.links, leaves, [2], refined.model.group[h.polygon])
    floor = h.polygon[leaves] == 0
    partial = floor & (kind[:, 0] == PARTIAL)
    lit = floor & (kind[:, 0] == VISIBLE)
    assert partial.any() and lit.any()
    assert np.median(h.area[leaves[partial]]) < 0.5 * np.median(h.area[leaves[lit]])
    assert np.all(vis[kind[:, 0] == VISIBLE] == 1.0) and np.all(vis[kind[:, 0] == INVISIBLE] == 0.0)


def test_figure_4_8_a_poster_is_not_a_shadow(sessions):
    """The dark poster differs in colour from its neighbours with the same visibility (case 2), so
    its leaves are split — and the split is undone, the children seeing the lamp as their parent
    does: the leaves under the poster stay as large as without the refinement."""
    plain, refined = sessions[False], sessions[True]
    assert refined.refine_stats.undone > 0

    def poster_leaf_area(s):
        leaf = s.pixel_element[POSTER]
        return float(np.median(s.solution.hierarchy.area[leaf[leaf >= 0]]))

    assert poster_leaf_area(refined) == pytest.approx(poster_leaf_area(plain))


def test_figure_4_7_split_decision():
    """The three rules, row by row: 0–1 same colour, different visibility (case 1: both split);
    2–3 different colour, same visibility (case 2: both split); 4–5 same colour and visibility (no
    split); 6 PARTIAL (split); 7 without pixels (never split)."""
    grey, dark = [0.5, 0.5, 0.5], [0.1, 0.1, 0.1]
    colour = np.array([grey, grey, grey, dark, grey, grey, grey, grey])
    vis = np.array([[1.0], [0.0], [1.0], [1.0], [1.0], [1.0], [0.5], [0.0]])
    kind = np.array(
        [[VISIBLE], [INVISIBLE], [VISIBLE], [VISIBLE], [VISIBLE], [VISIBLE], [PARTIAL], [INVISIBLE]], np.int8
    )
    has = np.array([True] * 7 + [False])
    near = [
        np.array([1]),
        np.array([0]),
        np.array([3]),
        np.array([2]),
        np.array([5]),
        np.array([4]),
        np.array([5]),
        np.array([5]),
    ]
    split = split_decision(colour, has, vis, kind, near, 20.0, 0.3)
    assert split.tolist() == [True, True, True, True, False, False, True, False]
    assert split_decision(colour, has, vis, kind, near, 20.0, 0.3, rows=np.array([0])).tolist() == [True] + [False] * 7


def test_collapse_undoes_a_subdivision():
    h = Hierarchy(
        Polygons(
            _quad((0, 0, 0), (1, 0, 0), (0, 0, 1))[None],
            np.zeros(1, bool),
            np.full((1, 3), 0.5),
            np.zeros((1, 3)),
            np.zeros(1, int),
            ["floor"],
        )
    )
    first = h.subdivide(np.array([0]))[0]
    h.subdivide(np.array([first]))
    assert len(h.leaves()) == 7
    h.collapse(np.array([0]))
    assert h.leaves().tolist() == [0] and h.active.sum() == 1


def test_tone_step_recovers_gain_and_gamma(rng):
    """Loscos Figure 4.21's correction: a photograph made as 1.7·I^0.8 (with 1 % noise) gives back
    a = 1.7 and γ = 0.8, and the corrected image matches it."""
    from illusio.relight.tone import fit_tone

    image = rng.uniform(0.05, 1.0, (32, 32, 3))
    photo = 1.7 * image**0.8 * rng.normal(1.0, 0.01, image.shape)
    tone = fit_tone(image, photo)
    assert tone.gain == pytest.approx(1.7, rel=0.03) and tone.gamma == pytest.approx(0.8, rel=0.03)
    assert np.abs(tone.apply(image) - photo).mean() / photo.mean() < 0.02
    assert fit_tone(image, 2 * image, fit_gamma=False).gain == pytest.approx(2.0)


def test_a_saved_session_edits_as_the_original(ctx, sessions, tmp_path, rng):
    """relight prepare: a session saved and loaded gives the same image as the original under random
    lamp scales, without preparing again; a corrupt or foreign file is refused by name."""
    from illusio.core.errors import InputError

    original = sessions[True]
    path = tmp_path / "board.npz"
    original.save(path)
    loaded = RelightSession.load(path, ctx)
    try:
        assert loaded.solution.stats.leaves == original.solution.stats.leaves
        for _ in range(2):
            scales = {"lamp": float(rng.uniform(0, 2))}
            assert np.allclose(loaded.image(scales), original.image(scales), atol=1e-6)
        assert "prepare" in loaded.times and "load" in loaded.times
    finally:
        loaded.release()
    (tmp_path / "bad.npz").write_bytes(path.read_bytes()[:200])
    with pytest.raises(InputError, match="not a saved relighting session"):
        RelightSession.load(tmp_path / "bad.npz", ctx)
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(InputError, match="no 'record'"):
        RelightSession.load(tmp_path / "other.npz", ctx)


def test_fresh_bfv_solution_reprojects_the_shadows(ctx, board_scene, sessions):
    """Loscos 4.3.3, the chapter's usual end: a new BFV mesh over the final textures (not the 4.3.1
    mesh), D from a first pass with the lamps' links at the leaves, B from a second with the links
    where BFV puts them; with nothing changed the photograph comes back (the shadows re-projected,
    Figure 4.15b), and switching the lamp off still darkens the floor."""
    params = dataclasses.replace(
        PARAMS, fresh_solution=True, final_hierarchy=HierarchyParams(epsilon=1e-3, min_area=1e-3, clusters=False)
    )
    s = RelightSession(board_scene, params, ctx)
    try:
        refined = sessions[True]
        assert s.solution.stats.leaves != refined.solution.stats.leaves
        lamp_links = np.isin(s.solution.polygons.group[s.solution.hierarchy.polygon[s.solution.links.source]], [2])
        assert (s.solution.hierarchy.child[s.solution.links.receiver[lamp_links]] >= 0).any()  # not all at leaves
        same = s.image({})
        floor = (s.pixel_polygon == 0) & (s.pixel_element >= 0)
        photo = s.real.photograph
        rel = np.abs(same - photo).mean(axis=-1)[floor] / photo.mean(axis=-1)[floor]
        assert np.median(rel) < 0.05
        dark = s.image({"lamp": 0.0})
        assert dark[floor].mean() < 0.5 * same[floor].mean()
        assert "fresh solution" in s.times
    finally:
        s.release()


BOARD_YAML = """
name: board
cameras:
  main: {position: [-0.4, 5.0, 0.01], target: [-0.4, 0, 0], fov: 50}
nodes:
  - {name: floor, shape: plane, params: {size: [4, 4]}, material: {colour: [0.5, 0.5, 0.5]}}
  - {name: board, shape: plane, params: {size: [0.8, 0.8]}, position: [0, 0.8, 0], rotation: [180, 0, 0],
     material: {colour: [0.5, 0.5, 0.5]}}
lights:
  - {type: area, centre: [1.0, 2.0, 0], edge_u: [0.3, 0, 0], edge_v: [0, 0, 0.3], radiance: 20}
"""


def test_a_real_scene_folder(tmp_path, capsys):
    """`illusio relight DIR`: scene.yaml + photograph + camera.json relit from the command line; a
    photograph whose size is not the camera's, or a folder without one, is refused in one line."""
    import json

    from illusio.radiosity import scene_polygons
    from illusio.scene import load_scene
    from tests.conftest import call_cli

    (tmp_path / "scene.yaml").write_text(BOARD_YAML)
    scene = load_scene(tmp_path / "scene.yaml")
    polygons = scene_polygons(scene)
    view = scene.camera("main")
    points, normals, polygon = surface_points(polygons, view, (64, 48))
    seen = polygon >= 0
    lamp = np.flatnonzero(np.isin(polygons.group, polygons.lamps))
    direct = lamp_irradiance(polygons, lamp, polygons.exitance[lamp], points, normals, seen).sum(axis=1)
    photo = np.zeros((48, 64, 3), np.float32)
    photo[seen] = 0.5 * (direct + 1.0) / np.pi
    np.save(tmp_path / "photograph.npy", photo)
    (tmp_path / "camera.json").write_text(
        json.dumps({"position": [-0.4, 5.0, 0.01], "target": [-0.4, 0, 0], "fov": 50, "width": 64, "height": 48})
    )
    out = tmp_path.parent / f"{tmp_path.name}-relit.npy"
    lamp_name = polygons.names[polygons.lamps[0]]
    code, cap = call_cli(
        ["relight", str(tmp_path), "-o", str(out), "--method", "loscos", "--set", f"{lamp_name}=0.5"], capsys
    )
    assert code == 0, cap.err
    relit = np.load(out)
    floor = seen & (polygon == polygons.names.index("floor"))
    assert relit.shape == photo.shape and 0.4 < relit[floor].sum() / photo[floor].sum() < 0.8
    (tmp_path / "camera.json").write_text(
        json.dumps({"position": [0, 5, 0.01], "target": [0, 0, 0], "fov": 50, "width": 640, "height": 480})
    )
    code, cap = call_cli(["relight", str(tmp_path), "-o", str(out)], capsys)
    assert code == 2 and "64x48 pixels but camera.json says 640x480" in cap.err
    (tmp_path / "photograph.npy").unlink()
    code, cap = call_cli(["relight", str(tmp_path), "-o", str(out)], capsys)
    assert code == 2 and "no photograph" in cap.err
    code, cap = call_cli(["relight", str(tmp_path), "-o", str(tmp_path / "scene.yaml")], capsys)
    assert code == 2 and "overwrite" in cap.err
