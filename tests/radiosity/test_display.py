"""The radiosity display and renderer: the GPU pass against rays cast through the pixel centres, the
corner gather against the element values, the Renderer protocol (re-solve without rebuilding), the
Mitsuba ground truth and the command."""

import numpy as np
import pytest

from illusio.core.images import read_image
from illusio.core.renderer import Frame
from illusio.radiosity import HierarchyParams, Radiosity, RadiosityParams, RadiosityRenderer, reference, scene_polygons
from illusio.radiosity.display import DisplayPass, leaf_mesh
from illusio.scene import load_scene
from tests.conftest import call_cli, tolerance

SIZE = (96, 96)
COARSE = HierarchyParams(epsilon=3e-4)


@pytest.fixture(scope="module")
def cornell():
    scene = load_scene("cornell-box")
    return scene, Radiosity(scene_polygons(scene), COARSE).build()


@pytest.mark.parametrize("smooth", [True, False])
def test_display_pass_matches_ray_cast_reference(ctx, cornell, rng, smooth):
    """Every pixel whose 3×3 neighbourhood hits one leaf (no element edge within a pixel) has the
    radiance interpolated at the ray's hit; the exposure is a random factor."""
    scene, sol = cornell
    mesh = leaf_mesh(sol.hierarchy, sol.links, sol.exitance(), smooth=smooth)
    exposure = float(rng.uniform(0.5, 2.0))
    display = DisplayPass(ctx)
    display.load(mesh)
    size = (192, 192)
    colour, element = display(scene.camera("main"), size, exposure)
    got = ctx.readback_image(colour, 3, clip=False)
    got_element = ctx.readback_image(element, 1, clip=False)[..., 0]
    ctx.release(colour, element)
    display.release()
    want, face = reference.display(mesh.positions, mesh.radiance * exposure, mesh.faces, scene.camera("main"), size)
    from scipy import ndimage

    leaf = np.where(face >= 0, mesh.face_element[np.maximum(face, 0)], -1)
    inner = (face >= 0) & (ndimage.maximum_filter(leaf, 3) == ndimage.minimum_filter(leaf, 3))
    assert inner.mean() > 0.2
    np.testing.assert_allclose(got[inner], want[inner], **tolerance("hit point"))
    assert (got_element[inner] == mesh.face_element[face[inner]]).all()
    assert (got_element[face < 0] == -1).all()


def test_corner_gather_of_a_constant_field(cornell):
    """Where B is the same everywhere the corners gather E + ρ Σ F V B = the element's own B, up to
    the form factors' quadrature; on the back wall's leaves the corners agree with the leaves within 5 %."""
    scene, sol = cornell
    h = sol.hierarchy
    from illusio.radiosity.display import corner_gather

    leaves = h.leaves()
    wall = leaves[h.polygon[leaves] == sol.polygons.names.index("back-wall")]
    corners = corner_gather(h, sol.links, wall, sol.exitance())
    ratio = corners.mean(axis=1)[:, 0] / h.radiosity[wall, 0]
    assert np.median(np.abs(ratio - 1)) < 0.05


def test_renderer_protocol_and_lamp_resolves(ctx):
    scene = load_scene("cornell-box")
    renderer = RadiosityRenderer(ctx)
    assert renderer.prepare(scene)
    assert not renderer.prepare(load_scene("cornell-box"))  # the same scene by value
    bright = renderer.render(Frame(None, SIZE), RadiosityParams(COARSE))
    built = renderer.result()
    dim = renderer.render(Frame(None, SIZE), RadiosityParams(COARSE, lamp_scales=(("lamp", 0.5),)))
    assert renderer.result() is built  # links kept: re-solved, not rebuilt
    lit = bright.max(axis=-1) > 0.02
    ratio = dim[lit & (bright < 0.99).all(axis=-1)] / bright[lit & (bright < 0.99).all(axis=-1)]
    assert np.median(ratio) == pytest.approx(0.5, abs=0.02)  # B is linear in the lamp's exitance
    mesh = renderer.render(Frame(None, SIZE), RadiosityParams(COARSE, show="mesh"))
    links = renderer.render(Frame(None, SIZE), RadiosityParams(COARSE, show="links"))
    assert np.abs(mesh - bright).mean() > 1e-3 and np.abs(links - bright).mean() > 1e-3
    element = ctx.readback_image(renderer.maps()["element"], 1, clip=False)[..., 0]
    assert (element >= 0).mean() > 0.8 and element.max() < len(renderer.result().hierarchy)
    renderer.release()


def test_score_against_mitsuba(ctx):
    """The Cornell box's radiosity against Mitsuba at few paths a pixel: within the noise of so few
    paths (the benchmark measures at converged sampling)."""
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    from illusio.radiosity.mitsuba import render_mitsuba, score

    scene = load_scene("cornell-box")
    renderer = RadiosityRenderer(ctx)
    renderer.prepare(scene)
    image, emitter = renderer.radiance(Frame(scene.camera("main"), (48, 48)), RadiosityParams(), 4)
    ref = render_mitsuba(renderer.polygons, scene.camera("main"), (48, 48), 128, seed=3)
    s = score(image, ref, ~emitter)
    assert s.mean_relative_error < 0.2 and s.psnr > 20
    assert emitter.sum() > 0 and s.pixels > 0.8 * (48 * 48)
    # and a wrong lamp power is seen
    worse = score(image * 1.3, ref, ~emitter)
    assert worse.mean_relative_error > s.mean_relative_error + 0.1
    renderer.release()


def test_command(tmp_path, capsys):
    out = tmp_path / "cb.png"
    code, cap = call_cli(
        [
            "radiosity",
            "cornell-box",
            "-o",
            str(out),
            "--size",
            "64x64",
            "--epsilon",
            "3e-4",
            "--set-lamp",
            "lamp=0.5",
            "--stats",
        ],
        capsys,
    )
    assert code == 0, cap.err
    assert read_image(out).shape == (64, 64, 3)
    assert "elements" in cap.out and "links" in cap.out and "refine" in cap.out
    mesh = tmp_path / "mesh.png"
    assert (
        call_cli(
            ["radiosity", "cornell-box", "-o", str(mesh), "--size", "64x64", "--epsilon", "3e-4", "--show", "mesh"],
            capsys,
        )[0]
        == 0
    )
    assert np.abs(read_image(mesh) - read_image(out)).mean() > 0.01


@pytest.mark.parametrize(
    "args, message",
    [
        (["--set-lamp", "lamp-9=1"], "no lamp named"),
        (["--set-lamp", "lamp"], "NAME=SCALE"),
        (["--set-lamp", "lamp=inf"], "finite SCALE"),  # not "image holds NaN values" later
        (["--criterion", "bff"], "criterion"),
        (["--epsilon", "0"], "--epsilon = 0 is out of range"),
        (["--show", "wires"], "show"),
        (["--reference", "SAME"], "choose another output path"),
    ],
)
def test_command_refuses_bad_input_and_writes_nothing(tmp_path, capsys, args, message):
    out = tmp_path / "x.png"
    args = [str(out) if a == "SAME" else a for a in args]
    code, cap = call_cli(
        ["radiosity", "cornell-box", "-o", str(out), "--size", "32x32", "--epsilon", "3e-4"] + args, capsys
    )
    assert code == 2 and message in cap.err and "Traceback" not in cap.err
    assert not out.exists()


BOX_ROOM = """
name: box-room
cameras:
  main: {{position: [0, 1, 2.5], target: [0, 1, 0], fov: 60}}
nodes:
  - name: floor
    shape: plane
    params: {{size: [4, 4]}}
    material: {{colour: {colour}}}
  - name: block
    shape: box
    position: [0, 0.25, 0]
    scale: 0.5
lights:
  - {{type: area, centre: [0, 2, 0], edge_u: [0.5, 0, 0], edge_v: [0, 0, 0.5], radiance: {radiance}}}
"""


@pytest.mark.parametrize(
    "colour, radiance, shape, options, message",
    [
        ("[1.0, 0.5, 0.5]", 5, "box", [], "reflectance"),  # ρ = 1 would make energy grow
        ("[0.5, 0.5, 0.5]", 5, "sphere", ["--no-clusters"], "without clusters radiosity takes at most 4000"),
    ],
)
def test_command_refuses_scenes_radiosity_cannot_take(tmp_path, capsys, colour, radiance, shape, options, message):
    scene = tmp_path / "room.yaml"
    text = BOX_ROOM.format(colour=colour, radiance=radiance)
    if shape == "sphere":
        text = text.replace("shape: box", "shape: sphere\n    params: {segments: 128, rings: 64}")
    scene.write_text(text)
    out = tmp_path / "x.png"
    code, cap = call_cli(["radiosity", str(scene), "-o", str(out), "--size", "32x32", *options], capsys)
    assert code == 2 and message in cap.err and "Traceback" not in cap.err
    assert not out.exists()


def test_a_yaml_scene_solves(tmp_path, capsys):
    scene = tmp_path / "room.yaml"
    scene.write_text(BOX_ROOM.format(colour="[0.6, 0.6, 0.6]", radiance=5))
    out = tmp_path / "room.png"
    code, cap = call_cli(["radiosity", str(scene), "-o", str(out), "--size", "64x48", "--epsilon", "3e-4"], capsys)
    assert code == 0, cap.err
    image = read_image(out)
    assert image.max() > 0.2 and image.shape == (48, 64, 3)
    # the lamp (facing down: edge_u × edge_v) lights the floor, not only itself: the bottom quarter
    # of the picture, floor, is lit (measured 0.034; 0 with the lamp turned up)
    assert np.median(image[36:]) > 0.01


def test_display_pass_loads_into_its_own_context(ctx):
    """Two contexts in one process (a CLI call inside a script, the README commands in the suite): a
    solution loaded while the other context is current still draws in its own (it drew black, and
    once crashed the driver, when its buffers were made in the wrong one)."""
    from dataclasses import replace

    from illusio.core import Context

    other = Context()
    renderer = RadiosityRenderer(other)
    scene = load_scene("cornell-box")
    renderer.prepare(scene)
    frame = Frame(scene.camera("main"), (48, 48))
    params = RadiosityParams(HierarchyParams(epsilon=1e-3))
    first = other.readback_image(renderer.render_texture(frame, params), 3)
    ctx.make_current()  # the other context is current now
    dimmed = replace(params, lamp_scales=(("lamp", 0.5),))
    second = other.readback_image(renderer.render_texture(frame, dimmed), 3)
    other.make_current()
    fresh = RadiosityRenderer(other)
    fresh.prepare(scene)
    expected = other.readback_image(fresh.render_texture(frame, dimmed), 3)
    assert first.mean() > 0.01 and second.mean() < first.mean()
    np.testing.assert_allclose(second, expected, **tolerance("same arithmetic"))
    fresh.release()
    renderer.release()
    ctx.make_current()  # leave the suite's context current before the other one goes
    other.gl.release()


def test_corner_ids_group_equal_rows_as_lexsort_does(rng, monkeypatch):
    """display.corner_ids: rows get one id each distinct value (the same partition as lexsort's run
    numbering), through the hash path and, when hashes collide, the lexsort fallback."""
    import illusio.radiosity.display as display

    key = rng.integers(-3, 3, (4000, 4))
    key[:, 0] = rng.integers(0, 5, 4000)
    order = np.lexsort(key.T[::-1])
    starts = np.r_[True, np.any(key[order[1:]] != key[order[:-1]], axis=1)]
    want = np.empty(len(key), np.int64)
    want[order] = np.cumsum(starts) - 1

    def same_partition(ids):
        pairs = np.unique(np.c_[ids, want], axis=0)
        return len(pairs) == len(np.unique(ids)) == len(np.unique(want))

    assert 50 < len(np.unique(want)) < 4000
    assert same_partition(display.corner_ids(key))
    monkeypatch.setattr(display, "_row_hashes", lambda k: np.zeros(len(k), np.uint64))  # all collide
    assert same_partition(display.corner_ids(key))


def test_corner_means_and_exposure_sums_equal_their_plain_numpy(rng):
    """display._average_at (one numba pass) against the weighted bincount mean it replaced, and
    _received_sums against two bincounts: the same bits."""
    import illusio.radiosity.display as display

    vertex = rng.integers(0, 300, 4000)
    counted = rng.random(4000) < 0.8
    values, weight = rng.random((1000, 4, 3)), rng.random(1000)
    w = np.repeat(weight, 4)
    b = values.reshape(-1, 3)
    total = np.stack([np.bincount(vertex[counted], (w * b[:, c])[counted], 300) for c in range(3)], axis=1)
    count = np.bincount(vertex[counted], w[counted], 300)
    want = (total / np.maximum(count, 1e-300)[:, None])[vertex].reshape(-1, 4, 3)
    np.testing.assert_array_equal(display._average_at(vertex, counted, values, weight), want)
    receiver = rng.integers(0, 50, 5000).astype(np.int32)
    form_factor, visibility = rng.random(5000), rng.random(5000)
    seen, total = display._received_sums(receiver, form_factor, visibility, 60)
    np.testing.assert_array_equal(seen, np.bincount(receiver, form_factor * visibility, 60))
    np.testing.assert_array_equal(total, np.bincount(receiver, form_factor, 60))


def test_a_solution_with_no_leaf_shown_draws_black(ctx):
    """A loaded session whose display has no triangle (seen in the saved-session fuzz): GL refuses an
    empty buffer, so the pass keeps none and draws the clear colour, element −1 everywhere."""
    from illusio.radiosity.display import LeafMesh
    from illusio.scene.builtin import builtin_scene

    empty = LeafMesh(
        *(np.zeros((0, 3), np.float32) for _ in range(3)),
        np.zeros(0, np.float32),
        np.zeros((0, 3), np.int32),
        np.zeros(0, np.int64),
    )
    display = DisplayPass(ctx)
    display.load(empty)
    colour, element = display(builtin_scene("cornell-box").camera("main"), (16, 12))
    try:
        assert not ctx.readback(colour).any() and (ctx.readback(element) == -1).all()
    finally:
        ctx.release(colour, element)
        display.release()


def test_block_score_averages_pixel_noise_out(rng):
    """score(block=4): a 30 % bias reads 0.3 at any block size; 20 % per-pixel noise reads ~0.16
    per pixel and under 0.05 over 4×4 blocks; a square partly outside the mask is not scored."""
    from illusio.radiosity.mitsuba import score

    truth = np.full((64, 64, 3), 0.5)
    noisy = truth * (1 + 0.2 * rng.standard_normal((64, 64, 1)))
    assert score(truth * 1.3, truth).mean_relative_error == pytest.approx(0.3)
    assert score(truth * 1.3, truth, block=4).mean_relative_error == pytest.approx(0.3)
    assert score(noisy, truth).mean_relative_error > 0.14
    assert score(noisy, truth, block=4).mean_relative_error < 0.05
    mask = np.ones((64, 64), bool)
    mask[0, 0] = False
    assert score(noisy, truth, mask, block=4).pixels == 16 * 16 - 1


def test_score_leaves_the_callers_mask_alone(rng):
    """score drops dark pixels from its own copy of the mask: a caller scoring twice with one mask
    (per pixel, then over blocks, as the benchmark does) scores the second time over the same pixels.
    (It once narrowed the caller's array in place, so the block score left out every block with a
    dark pixel in it.)"""
    from illusio.radiosity.mitsuba import score

    truth = rng.random((32, 32, 3)) + 0.01
    truth[:4] = 0.0  # below the floor: not scored, in either call
    mask = np.ones((32, 32), bool)
    before = mask.copy()
    first = score(truth * 1.1, truth, mask, block=1)
    assert (mask == before).all()
    assert score(truth * 1.1, truth, mask, block=4).pixels == 8 * 7
    assert first.pixels == 28 * 32
