"""Relighting, first landing (Loscos 4.2.1–4.2.2): the estimates of eqs. (4.1) and (4.2), the
display of eq. (4.3) reproducing the photograph, and the baseline's limitation measured."""

import dataclasses

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.images import read_image
from illusio.relight import RealScene, RelightSession, estimate
from tests.conftest import call_cli
from tests.relight.conftest import COARSE, prepared


def test_eq_4_1_reflectance_from_the_photograph(rng):
    """ρ_i = B̂_i / B̂_A × ρ̂; then ρ̂ is the mean of those ρ and eq. (4.1) is applied again."""
    pixels = rng.uniform(0.05, 0.3, (6, 3))
    scene = pixels.mean(axis=0)
    areas = rng.uniform(0.5, 2, 6)
    assert np.allclose(estimate.reflectance_from_photograph(pixels, scene, 0.4), np.clip(pixels / scene * 0.4, 0, 0.95))
    rho, rho_hat = estimate.reestimated_reflectance(pixels, scene, 0.4, areas)
    first = np.clip(pixels / scene * 0.4, 0, 0.95)
    assert np.allclose(rho_hat, (first * areas[:, None]).sum(axis=0) / areas.sum())
    assert np.allclose(rho, np.clip(pixels / scene * rho_hat, 0, 0.95))


def test_eq_4_2_lamp_exitance_balances_the_ambient_term():
    """Σ_lamps E·A = (1 − ρ̂)·B̂_A·Σ A, with B̂_A = π × the mean radiance."""
    e = estimate.lamp_exitance(np.array([0.5, 0.4, 0.3]), np.array([0.2, 0.2, 0.1]), 150.0, 3.0)
    assert np.allclose(e * 3.0, (1 - np.array([0.5, 0.4, 0.3])) * np.pi * np.array([0.2, 0.2, 0.1]) * 150.0)


@pytest.fixture
def session(sessions):
    return sessions("baseline")


def test_eq_4_3_shows_the_photograph_when_nothing_changed(session):
    """With every lamp as estimated, B = D and (B/D)·T is the photograph itself."""
    image = session.image({})
    seen = session.pixel_polygon >= 0
    assert np.abs(image - session.real.photograph)[seen].mean() < 1e-4
    doubled = session.image({n: 2.0 for n in session.lamp_names})  # B is linear in E: twice the light
    ratio = doubled[seen].sum() / session.real.photograph[seen].sum()
    assert ratio == pytest.approx(2.0, rel=0.01)


def test_the_estimates_are_near_the_truth(session):
    """The estimated reflectances of the walls and floor are within 35 % of the true ones (eq. 4.1
    counts their lighting as colour: the chapter's very limitation), and ρ̂ is re-estimated."""
    truth = session.real.polygons
    model = session.model
    for name in ("back-wall", "floor", "right-wall"):
        rows = model.group == model.names.index(name)
        assert model.reflectance[rows].mean() == pytest.approx(truth.reflectance[rows].mean(), rel=0.35)
    assert session.mean_reflectance.shape == (3,) and 0.2 < session.mean_reflectance.mean() < 0.8


FIGURE_4_17 = (
    {"lamp-0": 0.0, "lamp-1": 0.0},
    {"lamp-0": 0.0, "lamp-2": 0.0, "lamp-1": 2.0, "lamp-3": 2.0},
    {"lamp-1": 0.0, "lamp-3": 0.0, "lamp-0": 2.0, "lamp-2": 2.0},
)


@pytest.fixture(scope="module")
def figure_4_17_truths(photograph):
    """Mitsuba's renders of the edits of Figure 4.17 (256 paths), with the scored pixels and the
    photographed shadows (more than 10 % of the true direct light blocked), as the benchmark scores."""
    from benchmarks.relight import shadow_pixels
    from illusio.radiosity.mitsuba import render_mitsuba

    p = photograph.polygons
    geometry, shadow = shadow_pixels(p, photograph.view, photograph.size)
    truths = []
    for edit in FIGURE_4_17:
        factor = np.array([edit.get(n, 1.0) for n in p.names])[p.group]
        edited = dataclasses.replace(p, exitance=p.exitance * factor[:, None])
        truths.append(render_mitsuba(edited, photograph.view, photograph.size, 256, seed=5))
    return truths, geometry, shadow


def test_loscos_removes_the_photographed_shadows_where_the_baseline_keeps_them(sessions, figure_4_17_truths):
    """Loscos 4.2.2 against 4.3, scored against the path-traced truth of each edit inside the
    photographed shadows: the baseline relights the photograph's shadows with its elements' B/D and
    keeps what its mesh does not resolve; loscos's shadow-free textures do better on every edit
    (mean relative error measured 0.125 / 0.123 / 0.166 against 0.136 / 0.135 / 0.176). Without the
    reference correction (eqs. 4.8/4.9) loscos is worse than with it on every edit (0.139 / 0.140 /
    0.186), and worse than the baseline: 4.9 is what makes the difference here. Without eq. 4.6, or
    with the chapter's eq. 4.1 reflectances in place of the inverse estimate, this fails too
    (checked). (The chapter's full 4.9, w = 1, measures 0.122 / 0.119 / 0.164 at this size: the
    blocked-share weight is chosen at the CLI's 320×240, where it is the better, RESULTS.) (This replaces an
    inside-over-outside median ratio that rewarded any departure from the baseline's: the truth's
    own ratio departs from 1 by 0.13 on the first edit, the baseline's by 0.17, loscos's by 0.26.)"""
    from illusio.radiosity.mitsuba import score

    truths, _, shadow = figure_4_17_truths
    assert shadow.sum() > 300

    def errors(method, **changes):
        s = sessions(method, **changes)
        return np.array(
            [score(s.image(edit), truth, shadow).mean_relative_error for edit, truth in zip(FIGURE_4_17, truths)]
        )

    baseline, loscos, without_4_9 = errors("baseline"), errors("loscos"), errors("loscos", reference_correction=False)
    assert (loscos < 0.97 * baseline).all(), (loscos, baseline)
    assert (without_4_9 > 1.05 * loscos).all(), (without_4_9, loscos)
    with pytest.raises(InputError, match="no lamp named"):
        sessions("baseline").image({"lamp-9": 1.0})


def test_a_bad_real_scene_is_refused():
    from illusio.radiosity import scene_polygons
    from illusio.scene import load_scene

    p = scene_polygons(load_scene("office"))
    view = load_scene("office").camera()
    with pytest.raises(InputError, match="H×W×3"):
        RealScene(p, view, np.zeros((4, 4, 3)))
    with pytest.raises(InputError, match="non-finite"):
        RealScene(p, view, np.full((16, 16, 3), np.nan))
    negative = np.full((16, 16, 3), 0.5, np.float32)
    negative[3, 5, 1] = -0.01
    with pytest.raises(InputError, match="negative values .first at pixel x=5, y=3"):
        RealScene(p, view, negative)


def test_command(tmp_path, capsys):
    pytest.importorskip("mitsuba", reason="the built-in photograph is rendered by Mitsuba (photo extra)")
    out = tmp_path / "relit.png"
    code, cap = call_cli(
        [
            "relight",
            "office",
            "-o",
            str(out),
            "--size",
            "64x48",
            "--samples",
            "8",
            "--epsilon",
            "3e-4",
            "--set",
            "lamp-0=0",
            "--photograph",
            str(tmp_path / "photo.png"),
        ],
        capsys,
    )
    assert code == 0, cap.err
    relit, photo = read_image(out), read_image(tmp_path / "photo.png")
    assert relit.shape == photo.shape == (48, 64, 3)
    assert relit.mean() < photo.mean()  # lamp-0 off: darker than the photograph
    code, cap = call_cli(["relight", "office", "-o", str(out), "--size", "64x48", "--set", "lamp-7=0"], capsys)
    assert code == 2 and "no lamp named" in cap.err
    code, cap = call_cli(["relight", "office", "-o", str(out), "--size", "64x48", "--set", "lamp-0=inf"], capsys)
    assert code == 2 and "--set takes NAME=SCALE with a finite SCALE" in cap.err  # refused when parsed
    # prepare once, then edit from the saved session: the same image as preparing in the same command
    saved = tmp_path / "office.npz"
    code, cap = call_cli(
        ["relight", "prepare", "office", "-o", str(saved), "--size", "64x48", "--samples", "8", "--method", "loscos"],
        capsys,
    )
    assert code == 0, cap.err
    direct, again = tmp_path / "direct.npy", tmp_path / "again.npy"
    assert (
        call_cli(
            [
                "relight",
                "office",
                "-o",
                str(direct),
                "--size",
                "64x48",
                "--samples",
                "8",
                "--method",
                "loscos",
                "--set",
                "lamp-2=0.5",
            ],
            capsys,
        )[0]
        == 0
    )
    code, cap = call_cli(["relight", str(saved), "-o", str(again), "--set", "lamp-2=0.5"], capsys)
    assert code == 0 and "loaded in" in cap.out
    assert np.allclose(np.load(again), np.load(direct), atol=1e-5)
    code, cap = call_cli(["relight", str(saved), "-o", str(tmp_path / "mesh.png"), "--show", "mesh"], capsys)
    assert code == 0
    mesh = read_image(tmp_path / "mesh.png")
    assert mesh.shape == (48, 64, 3) and (mesh.max(axis=-1) < 0.02).mean() > 0.05  # the leaves' outlines
    code, cap = call_cli(["relight", str(saved), "-o", str(saved)], capsys)
    assert code == 2 and saved.stat().st_size > 0
    code, cap = call_cli(["relight", str(saved), "-o", str(out), "--show", "normals"], capsys)
    assert code == 2 and "--show" in cap.err


def test_eq_4_4_colour_distance_in_lab():
    from illusio.relight.textures import colour_distance, srgb_to_lab

    lab = srgb_to_lab(np.array([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0], [0.18, 0.18, 0.18]]))
    assert np.allclose(lab[0], [100, 0, 0], atol=0.05) and np.allclose(lab[1], 0, atol=1e-9)
    assert lab[2, 0] == pytest.approx(49.5, abs=0.2) and np.allclose(lab[2, 1:], 0, atol=0.05)  # 18 % grey
    assert colour_distance(np.array([[0.5, 0.5, 0.5]]), np.array([[0.5, 0.5, 0.5]]))[0] == 0
    red, grey = np.array([[0.5, 0.05, 0.05]]), np.array([[0.2, 0.2, 0.2]])
    assert colour_distance(red, grey)[0] > 40 > colour_distance(grey, grey * 1.1)[0]


@pytest.fixture
def loscos(sessions):
    return sessions("loscos")


def test_loscos_textures(loscos):
    """Eq. (4.6)/(4.9): the shadowed leaves' textures are brightened (the blocked light added), the
    lit ones are left as they were, up to the little blocked light a leaf in no shadow has; every reference is a lit
    frontier leaf of the same object;
    with nothing changed the shadows are re-projected: the photograph comes back within a few per cent
    (Loscos 4.3.3, Figure 4.14)."""
    s = loscos
    h = s.solution.hierarchy
    leaves, ref = s.references
    factor = s.texture_factor[leaves].mean(axis=1)
    assert s.shadowed.any() and (~s.shadowed).any()
    # a leaf that is not shadowed has under BLOCKED_SHARE of its light blocked: eq. 4.6 adds at most that
    from illusio.relight.textures import BLOCKED_SHARE

    unchanged = BLOCKED_SHARE / (1 - BLOCKED_SHARE) + 0.01
    assert np.median(factor[s.shadowed]) > 1.0 and np.allclose(factor[~s.shadowed], 1.0, atol=unchanged)
    chosen = ref[ref >= 0]
    assert len(chosen) and not s.shadowed[chosen].any()
    group = s.model.group[h.polygon[leaves]]
    assert (group[ref >= 0] == group[chosen]).all()
    same = s.image({})
    seen = s.pixel_polygon >= 0
    rel = np.abs(same - s.real.photograph).mean(axis=-1)[seen] / np.maximum(s.real.photograph.mean(axis=-1)[seen], 1e-3)
    assert np.median(rel) < 0.03


def test_eq_4_6_the_blocked_light_is_added_where_no_reference_corrects(loscos):
    """T_inter = (B + ρĒ)/B × T_orig (eq. 4.6) is the final texture of a shadowed leaf without a
    reference (where a reference exists eq. 4.9 corrects it, test below). In the office those are
    the table and chair legs, keyboards and stands that no lamp lights wholly: their seen leaves are
    brightened (median factor measured 1.4; 1 without eq. 4.6)."""
    s = loscos
    h = s.solution.hierarchy
    leaves, ref = s.references
    seen = np.bincount(s.pixel_element[s.pixel_element >= 0], minlength=len(h))[leaves] > 0
    alone = s.shadowed & (ref < 0) & seen
    assert alone.sum() >= 5
    assert np.median(s.texture_factor[leaves][alone].mean(axis=1)) > 1.2


def test_loscos_textures_are_modulated_at_the_vertices(loscos):
    """4.3.2 modulates the texture at the leaves' vertices: T/photograph is interpolated from the
    corners, so neighbouring pixels of the ceiling differ little (99th percentile of the steps,
    away from the lamps' rims: measured 0.046; flat per leaf, as before, 0.43 — the rectangular
    patches users saw)."""
    from scipy import ndimage

    s = loscos
    m = s.model
    ceiling = (s.pixel_polygon >= 0) & (m.group[np.maximum(s.pixel_polygon, 0)] == m.names.index("ceiling"))
    mask = ceiling & ~ndimage.binary_dilation(s._rims.coverage.sum(axis=-1) > 0, iterations=2)
    ratio = s.texture.mean(axis=-1) / np.maximum(s.real.photograph.mean(axis=-1), 1e-6)
    steps = np.r_[
        np.abs(np.diff(ratio, axis=1))[mask[:, 1:] & mask[:, :-1]], np.abs(np.diff(ratio, axis=0))[mask[1:] & mask[:-1]]
    ]
    assert mask.sum() > 500 and np.percentile(steps, 99) < 0.15, np.percentile(steps, 99)


@pytest.fixture
def per_pixel(sessions):
    return sessions("per-pixel")


def test_per_pixel_method(per_pixel):
    """Unchanged lamps give the photograph back exactly; each lamp's share is removed pixel by pixel:
    switching every lamp off leaves no direct light (only what the solution's indirect field gives:
    the monitors' light, they shine by themselves), the lamps' pixels go dark with them and the
    screens keep their photographed colour."""
    s = per_pixel
    same = s.image({})
    assert np.abs(same - s.real.photograph).max() < 1e-3 * s.real.photograph.max()  # up to the re-solve's tolerance
    dark = s.image({n: 0.0 for n in s.lamp_names})
    m = s.model
    polygon = np.maximum(s.pixel_polygon, 0)
    screen = (s.pixel_polygon >= 0) & np.isin(
        m.group[polygon], [m.names.index(n) for n in ("monitor-0-screen", "monitor-1-screen")]
    )
    lamp = (s.pixel_polygon >= 0) & np.isin(m.group[polygon], m.lamps)
    assert screen.any() and np.allclose(dark[screen], s.real.photograph[screen])
    whole = s._rims.coverage.sum(axis=-1) >= 1  # a pixel the lamps cover wholly: black with them
    assert (
        dark[lamp & whole].max() == 0 and dark[lamp].max() < 0.02 * same[s.pixel_seen].max()
    )  # edges: the ceiling's share
    assert np.median(dark[s.pixel_seen]) < 0.02 * np.median(same[s.pixel_seen])
    one = s.image({n: (1.0 if n == "lamp-3" else 0.0) for n in s.lamp_names})
    share = s.pixel_lamp[
        :, list(s.lamp_rows).index(int(np.flatnonzero(s.model.group == s.model.names.index("lamp-3"))[0]))
    ]
    lit_by_it = share.sum(axis=1) > 0
    assert (one[s.pixel_seen][lit_by_it].sum(axis=1) > 0).mean() > 0.95


def test_per_pixel_indirect_light_has_no_seams(per_pixel):
    """The ceiling gets only indirect light (the lamps face down): with the left lamps off, its
    relit/photographed ratio is I'/I, interpolated from the leaves' corners, so neighbouring pixels
    differ little (99th percentile of the steps, away from the lamps' rims: measured 0.018; with I
    flat per leaf, as before, 0.084 — seams at the leaves' edges), while across the ceiling the ratio
    does change (range measured 0.26)."""
    from scipy import ndimage

    s = per_pixel
    m = s.model
    ceiling = (s.pixel_polygon >= 0) & (m.group[np.maximum(s.pixel_polygon, 0)] == m.names.index("ceiling"))
    rims = ndimage.binary_dilation(s._rims.coverage.sum(axis=-1) > 0, iterations=2)
    mask = ceiling & s.pixel_seen & ~rims
    assert mask.sum() > 500
    ratio = s.image({"lamp-0": 0.0, "lamp-1": 0.0}).mean(axis=-1) / np.maximum(s.real.photograph.mean(axis=-1), 1e-6)
    s.image({})
    steps = np.r_[
        np.abs(np.diff(ratio, axis=1))[mask[:, 1:] & mask[:, :-1]], np.abs(np.diff(ratio, axis=0))[mask[1:] & mask[:-1]]
    ]
    assert np.percentile(steps, 99) < 0.04 and np.ptp(ratio[mask]) > 0.15, (
        np.percentile(steps, 99),
        np.ptp(ratio[mask]),
    )


def test_virtual_object_and_lamp(ctx, photograph, tmp_path):
    """A virtual crate casts its shadow on the floor of the photograph (the floor around its foot gets
    darker) and is drawn with its own radiosity; a virtual lamp brightens the room; moving the crate
    moves the shadow. The per-pixel method refuses them (not yet)."""
    from illusio.core.progress import reporting
    from illusio.scene.builtin import shapes

    s = prepared(ctx, photograph, "baseline")
    before = s.image({})
    crate = shapes.box((0.6, 0.6, 0.6))
    heard = []
    with reporting(heard.append):  # each edit is a reported phase (a bar on a terminal, a log line)
        after = s.add_object(crate, "crate", at=(0.6, 0.3, 1.2))
    assert [p.phase for p in heard if p.finished] == ["relight: add the object crate"]
    changed = np.abs(after - before).mean(axis=-1) > 1e-3
    assert changed.mean() > 0.01
    darker = after.mean(axis=-1) < before.mean(axis=-1) - 1e-3
    assert darker.sum() > 0
    moved = s.move_object("crate", (-0.8, 0.0, -0.5))
    assert np.abs(moved - after).mean() > 1e-4
    # the edits gather only at the leaves the photograph shows (and their neighbours): the same image
    # as gathering at every leaf, from the same solution (both gathered directly, no lamp basis)
    s._geometry_key = s._basis_key = None
    culled = s.image()
    s._shown = lambda: np.ones(len(s.solution.hierarchy), bool)
    s._geometry_key = s._basis_key = None
    assert np.allclose(s.image(), culled, rtol=1e-6, atol=1e-7)
    del s._shown
    brighter = s.add_lamp((0.5, 2.5, 1.0), 0.4, (40.0, 40.0, 40.0), "virtual")
    assert brighter.mean() > moved.mean() * 1.02
    assert "virtual" in s.lamp_names and all(k in s.times for k in ("add object", "move object", "add lamp"))
    with pytest.raises(InputError, match="no virtual object"):
        s.move_object("floor", (0, 0, 0.1))
    # a session saved with its virtual crate and lamp loads and edits as the original (the elements
    # made by the edits have per-element arrays too: they once made the file unloadable)
    s.save(tmp_path / "edited.npz")
    loaded = RelightSession.load(tmp_path / "edited.npz", ctx)
    try:
        assert np.allclose(loaded.image({"virtual": 0.5}), s.image({"virtual": 0.5}), atol=1e-6)
        assert np.allclose(
            loaded.move_object("crate", (0.3, 0.0, 0.0)), s.move_object("crate", (0.3, 0.0, 0.0)), atol=1e-6
        )
    finally:
        loaded.release()
    s.release()


def test_a_virtual_object_s_shadow_lands_where_a_path_tracer_puts_it(ctx, photograph):
    """Against Mitsuba's render of the true office with the crate in it: the pixels the crate darkens
    by more than 20 % (3×3-smoothed, off the crate itself) overlap the path tracer's (intersection
    over union ≥ 0.4; measured 0.64 placed, 0.62 moved), and after a move the shadow follows: the
    new shadow overlaps the old place's truth by < 0.1 (measured 0). A move that does not redo the
    links whose shafts the crate left and entered fails it (measured 0.02)."""
    from scipy import ndimage

    from illusio.radiosity import Polygons
    from illusio.radiosity.mitsuba import render_mitsuba
    from illusio.radiosity.polygons import quads_from_triangles
    from illusio.relight.per_pixel import surface_points
    from illusio.scene.builtin import shapes

    crate = shapes.box((0.6, 0.6, 0.6))

    def truth(at):
        polygons = photograph.polygons
        if at is not None:
            corners, tri = quads_from_triangles(np.asarray(crate.vertices, np.float64) + np.asarray(at), crate.faces)
            n = len(corners)
            polygons = polygons.extended(
                Polygons(corners, tri, np.full((n, 3), 0.6), np.zeros((n, 3)), np.zeros(n, int), ["crate"]),
                "crate",
                False,
            )
        image = render_mitsuba(polygons, photograph.view, photograph.size, 128, seed=3)
        _, _, polygon = surface_points(polygons, photograph.view, photograph.size)
        return image, polygon >= len(photograph.polygons)

    def shadow(image, empty, on_crate):
        def smooth(a):
            return ndimage.uniform_filter(a.mean(axis=-1), 3)

        return (smooth(image) < 0.8 * smooth(empty)) & ~ndimage.binary_dilation(on_crate)

    def overlap(a, b):
        return (a & b).sum() / max((a | b).sum(), 1)

    s = prepared(ctx, photograph, "baseline")
    empty_truth, _ = truth(None)
    empty = s.image({})
    placed_truth, on_crate = truth((0.6, 0.3, 1.2))
    placed = s.add_object(crate, "crate", at=(0.6, 0.3, 1.2))
    true_placed = shadow(placed_truth, empty_truth, on_crate)
    assert true_placed.sum() > 20
    assert overlap(shadow(placed, empty, on_crate), true_placed) >= 0.4
    moved_truth, on_crate = truth((-0.2, 0.3, 0.7))
    moved = shadow(s.move_object("crate", (-0.8, 0.0, -0.5)), empty, on_crate)
    assert overlap(moved, shadow(moved_truth, empty_truth, on_crate)) >= 0.4
    assert overlap(moved, true_placed) < 0.1
    s.release()


@pytest.mark.parametrize("method", ["baseline", "loscos"])
def test_session_image_matches_its_reference(ctx, photograph, method, rng):
    """The GPU image of eq. (4.3) (through the per-lamp basis) against relight.reference (B gathered
    directly, rays through the pixel centres), on random lamp scales, over the pixels whose 3×3
    neighbourhood is one leaf."""
    from scipy import ndimage

    from illusio.relight.reference import displayed_image

    s = prepared(ctx, photograph, method)
    scales = {name: float(rng.uniform(0, 2)) for name in s.lamp_names}
    got = s.image(scales)
    want, element = displayed_image(s, scales)
    inner = (element >= 0) & (ndimage.maximum_filter(element, 3) == ndimage.minimum_filter(element, 3))
    assert inner.mean() > 0.1
    np.testing.assert_allclose(got[inner], want[inner], rtol=5e-3, atol=1e-4)  # rasterised vs ray-cast points
    s.release()


def _triangulated(polygons):
    """Every quad of ``polygons`` cut along its 0–2 diagonal into two triangles."""
    from illusio.radiosity import Polygons

    c, quad = polygons.corners, ~polygons.triangle
    first = np.stack([c[:, 0], c[:, 1], c[:, 2], c[:, 2]], axis=1)
    second = np.stack([c[:, 0], c[:, 2], c[:, 3], c[:, 3]], axis=1)[quad]
    rows = np.r_[np.arange(len(polygons)), np.flatnonzero(quad)]
    return Polygons(
        np.concatenate([np.where(quad[:, None, None], first, c), second]),
        np.ones(len(rows), bool),
        polygons.reflectance[rows],
        polygons.exitance[rows],
        polygons.group[rows],
        polygons.names,
        polygons.lamps,
    )


def test_relighting_the_triangulated_office_matches_the_quad_office(ctx, photograph):
    """The office with every quad split in two, relit (lamp-0 off), scored against the path-traced
    truth over 4×4 blocks: each method as on the quads, within 5 % (measured: baseline 0.050 against
    0.052, loscos 0.051 against 0.052). Loscos was 32 % above the quads until a leaf counted as
    shadowed only when its blocked light is a real share of its light (textures.BLOCKED_SHARE): the
    monitors' light grazing the ceiling made 105 of the triangulated ceiling's 182 leaves
    "shadowed", each then re-textured from a reference (eq. 4.9)."""
    from illusio.radiosity.mitsuba import render_mitsuba, score

    p = photograph.polygons
    off = np.array([0.0 if n == "lamp-0" else 1.0 for n in p.names])[p.group]
    truth = render_mitsuba(
        dataclasses.replace(p, exitance=p.exitance * off[:, None]), photograph.view, (96, 72), 256, seed=5
    )
    blocks = lambda a: a.reshape(18, 4, 24, 4, -1).mean(axis=(1, 3))  # noqa: E731
    triangles = RealScene(_triangulated(p), photograph.view, photograph.photograph)
    error = {}
    for method in ("baseline", "loscos"):
        for label, real in (("quads", photograph), ("triangles", triangles)):
            s = RelightSession(real, dataclasses.replace(COARSE, method=method), ctx)
            try:
                whole = blocks((s.pixel_polygon >= 0).astype(float)[..., None])[..., 0] == 1
                error[method, label] = score(blocks(s.image({"lamp-0": 0.0})), blocks(truth), whole).mean_relative_error
            finally:
                s.release()
    assert error["baseline", "triangles"] < 1.05 * error["baseline", "quads"], error
    assert error["loscos", "triangles"] < 1.05 * error["loscos", "quads"], error


@pytest.mark.parametrize("method", ["baseline", "loscos", "per-pixel"])
def test_a_switched_off_lamp_leaves_no_bright_rim(sessions, method):
    """Lamp 0 off: the pixels its outline crosses keep only the surface's share (relight.lamp_rims),
    none brighter than the brightest lamp-free pixel around the lamp; they held the lamp's glow (a
    ring of its light around the black panel) when relit by what their centre saw."""
    from scipy import ndimage

    s = sessions(method)
    m = s.model
    lamp = m.names.index("lamp-0")
    relit = s.image({"lamp-0": 0.0}).mean(axis=-1)
    rims = s._rims
    cover = rims.coverage[..., list(rims.groups).index(lamp)]
    rim = (cover > 0) & (cover < 1)
    assert rim.sum() >= 4
    around = ndimage.binary_dilation(cover > 0, iterations=3) & (rims.coverage.sum(axis=-1) == 0)
    assert relit[rim].max() <= 1.05 * relit[around].max()
    assert s.real.photograph.mean(axis=-1)[rim].max() > 1.5 * relit[around].max()  # the photograph had the glow


def test_the_built_in_photograph_is_denoised_like_a_camera_s():
    """16 paths a pixel through Open Image Denoise (albedo and normal guides) are nearer a
    1024-path render than the raw 16 paths are, by two thirds (measured 0.075 against 0.25)."""
    pytest.importorskip("pyoidn", reason="the denoiser (photo extra)")
    from illusio.radiosity.mitsuba import score
    from illusio.relight import builtin_real_scene

    reference = builtin_real_scene("office", (96, 72), 1024, seed=3, denoise=False).photograph
    raw = builtin_real_scene("office", (96, 72), 16, denoise=False).photograph
    clean = builtin_real_scene("office", (96, 72), 16).photograph
    assert score(clean, reference).mean_relative_error < 0.5 * score(raw, reference).mean_relative_error


def test_inverse_estimate_reads_reflectance_as_light_explained(rng):
    """ρ = πB̂/H: a surface's radiance B̂ = ρH/π gives its ρ back whatever its lighting (eq. 4.1 would
    read a shadowed patch of the same paint as darker paint); clipped at MAX_REFLECTANCE, 0 unlit."""
    rho = rng.uniform(0.05, 0.9, (20, 3))
    irradiance = rng.uniform(0.1, 50, (20, 1)) * rng.uniform(0.5, 1.5, (20, 3))
    assert np.allclose(estimate.reflectance_from_irradiance(rho * irradiance / np.pi, irradiance), rho)
    assert estimate.reflectance_from_irradiance(np.array([[5.0, 0.0, 0.1]]), np.array([[1.0, 0.0, 1.0]])).tolist() == [
        [estimate.MAX_REFLECTANCE, 0.0, pytest.approx(0.1 * np.pi)]
    ]


def test_a_lamp_s_exitance_from_its_own_pixels():
    """E = π × the mean of the lamp's pixels in a high-dynamic-range photograph; none from fewer than
    4 pixels or from a photograph that clips at the lamp (eq. 4.2 then estimates it)."""
    pixels = np.array([[6.0, 5.5, 5.0]] * 8)
    assert np.allclose(estimate.lamp_exitance_from_pixels(pixels), np.pi * pixels[0])
    assert estimate.lamp_exitance_from_pixels(pixels[:3]) is None
    clipped = np.minimum(pixels, 1.0)
    assert estimate.lamp_exitance_from_pixels(clipped, saturation=1.0) is None
    assert np.allclose(estimate.lamp_exitance_from_pixels(pixels * 0.1, saturation=1.0), np.pi * 0.1 * pixels[0])


def test_the_inverse_estimate_is_nearer_the_truth_than_eq_4_1(ctx, photograph):
    """On the office photographed by Mitsuba (lamps HDR): the lamps the camera sees from the front
    read from their pixels within 8 % of their true exitance (measured 6 % at most at this 96×72
    size; eq. 4.2 gives one value for all), and
    the leaves' reflectances nearer the true ones than eq. 4.1's (area-weighted mean relative error
    measured 0.19 against 0.30), and the solution within 3 % of the photograph at the median leaf
    once the estimate settles (eq. 4.1's: 36 %)."""
    from benchmarks.relight import reflectance_error

    # sessions of its own: the shared ones' B is whatever the last test's edit left
    inverse, chapter = (
        prepared(ctx, photograph, "baseline"),
        prepared(ctx, photograph, "baseline", estimate="brightness"),
    )
    truth = inverse.real.polygons
    lamps = np.isin(truth.group, truth.lamps)
    read = np.isin(truth.group, [truth.names.index(n) for n in inverse.lamps_read])
    assert read.any() and (read <= lamps).all()
    np.testing.assert_allclose(inverse.model.exitance[read], truth.exitance[read], rtol=0.08)
    assert reflectance_error(inverse) < 0.8 * reflectance_error(chapter)

    def mismatch(session):
        """Median |B/(π·B̂) − 1| over the seen leaves: how far the solution is from the photograph."""
        h = session.solution.hierarchy
        count, mean_pixels = session._leaf_pixels()
        seen = h.leaves()[count[h.leaves()] > 0]
        return np.median(np.abs(h.radiosity[seen] / np.maximum(np.pi * mean_pixels[seen], 1e-9) - 1))

    # the estimate settles (INVERSE_TOLERANCE) with the solution explaining the photograph
    from illusio.relight.params import INVERSE_MAX_ITERATIONS

    assert inverse.inverse_iterations < INVERSE_MAX_ITERATIONS
    assert mismatch(inverse) < 0.03 and mismatch(chapter) > 0.1  # measured 0.009 (12 solves) and 0.36
    inverse.release()
    chapter.release()


def test_eq_4_9_weight_is_the_blocked_share_of_the_direct_light():
    """w of T_final = (ρ_corr/ρ_inter)^w · T_inter: 1 in a full shadow (the reference's texture, as
    the chapter), 0 in full light (the leaf's own), the blocked share between; a leaf no lamp reaches
    takes the reference in full."""
    from illusio.relight.textures import correction_weight

    free = np.array([[2.0, 2.0, 2.0], [2.0, 2.0, 2.0], [1.0, 2.0, 3.0], [0.0, 0.0, 0.0]])
    blocked = np.array([[2.0, 2.0, 2.0], [0.0, 0.0, 0.0], [0.5, 1.0, 1.5], [0.0, 0.0, 0.0]])
    assert correction_weight(blocked, free).tolist() == [1.0, 0.0, 0.5, 1.0]


def test_eq_4_9_is_taken_in_proportion_to_the_blocked_share(sessions):
    """Each shadowed leaf's final texture factor lies between T_inter's (no correction) and the
    chapter's full eq. 4.9 (w = 1), in log terms at w of the way: the umbra's leaves take the full
    correction, the penumbra's part of it (the three sessions share one mesh: 4.9 does not move it)."""
    weighted, full, none = (
        sessions("loscos"),
        sessions("loscos", reference_weight="full"),
        sessions("loscos", reference_correction=False),
    )
    h = weighted.solution.hierarchy
    leaves, ref = weighted.references
    assert len(h) == len(full.solution.hierarchy) and (full.references[1] == ref).all()
    f_w, f_full, f_none = (np.log(s.texture_factor[leaves].mean(axis=1)) for s in (weighted, full, none))
    corrected = (ref >= 0) & (np.abs(f_full - f_none) > 0.05)
    assert corrected.sum() >= 20
    share = (f_w - f_none)[corrected] / (f_full - f_none)[corrected]
    assert ((share > -0.05) & (share < 1.05)).all()
    partial = (share > 0.1) & (share < 0.9)
    assert partial.mean() > 0.3, partial.mean()  # measured 0.91 of 283 leaves; 0 with w = 1


def test_a_crate_moved_where_the_counts_come_out_the_same_is_not_drawn_with_the_old_lamps_basis(
    ctx, photograph, monkeypatch
):
    """The lamps' basis is kept under the geometry's counts (elements, links, lamps). A move that
    happens to give the same counts must not reuse the basis of where the crate was: emulated by one
    key for every geometry, the image after the move is the one gathered afresh."""
    from illusio.relight import corners
    from illusio.scene.builtin import shapes

    s = prepared(ctx, photograph, "baseline")
    try:
        s.add_object(shapes.box((0.6, 0.6, 0.6)), "crate", at=(0.6, 0.3, 1.2))
        monkeypatch.setattr(corners, "geometry_key", lambda s: ("one key for every geometry",))
        s.image({s.lamp_names[0]: 0.5})
        s.image({s.lamp_names[0]: 0.7})  # the second edit of this geometry makes the basis
        assert s.lamp_basis() is not None
        moved = s.move_object("crate", (-0.8, 0.0, -0.5))
        s._geometry_key = s._basis_key = None  # gathered directly, from the same solution
        fresh = s.image()
        assert np.abs(moved - fresh).max() < 1e-3  # (the kept corner sums' tolerance: ~1e-4)
        # and the edit after the move draws from a basis of the moved geometry
        assert np.abs(s.image({s.lamp_names[0]: 0.7}) - fresh).max() < 1e-3
    finally:
        s.release()
