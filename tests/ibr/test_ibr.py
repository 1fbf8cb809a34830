"""Image-based rendering (Porquet 2005, 4.2): the per-pixel choice against its NumPy reference, the
references reproducing themselves, new views against ground truth, reference folders in and out."""

import json

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.core.images import read_image
from illusio.core.renderer import Frame
from illusio.ibr import IbrParams, IbrRenderer, capture, load_references, orbit_views, reference, save_references
from illusio.ibr.select import ReferenceArrays, SelectPass
from illusio.passes import reference as passes_reference
from illusio.passes.gbuffer import GBufferImages
from illusio.passes.lights import emitters_from_lights
from illusio.passes.scene_renderer import RenderSettings, SceneRenderer
from illusio.passes.shading import MAX_EMITTERS, ShadingParams
from illusio.scene import load_scene
from illusio.scene.scene import Node, Scene
from tests.conftest import call_cli, tolerance

SIZE = (128, 96)


@pytest.fixture(scope="module")
def room(ctx):
    scene = load_scene("living-room")
    return scene, capture(scene, orbit_views(scene, 3), SIZE, ctx)


def psnr(a, b):
    return 10 * np.log10(1 / np.mean((np.asarray(a, np.float64) - b) ** 2))


def _shifted(view):
    """The view through a photograph's lens: principal point off centre, f_x ≠ f_y."""
    from dataclasses import replace

    return replace(view, camera=replace(view.camera, shift=(0.07, -0.05), pixel_aspect=1.15))


@pytest.mark.parametrize(
    "use_3d, bilinear, single_pass, shifted",
    [(False, True, False, False), (True, False, False, False), (False, True, True, False), (False, True, True, True)],
)
def test_select_pass_matches_reference(ctx, room, rng, use_3d, bilinear, single_pass, shifted):
    """At a new view (and a random reconstructed depth near the true one), the GPU picks the same
    reference per pixel as reference.select, with the same corrected depth and attributes, in the
    multi-pass mode (a draw per reference, the depth test choosing) and in the single pass; the
    shaded resolve lights that choice as passes.reference.shading does. ``shifted``: every camera
    with its principal point off centre and f_x ≠ f_y (an imported capture's lens)."""
    scene, refs = room
    view = orbit_views(scene, 7)[int(rng.integers(1, 6))]
    if shifted:
        refs = capture(scene, [_shifted(v) for v in orbit_views(scene, 3)], SIZE, ctx)
        view = _shifted(view)
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    g = truth.gbuffer(Frame(view, SIZE))
    hit = ctx.readback(g["object_id"])[..., 0] > 0.5
    depth = np.where(hit, ctx.readback(g["depth"])[..., 0], 0.0) * rng.uniform(0.995, 1.005, SIZE[::-1])
    g.release()
    depth = depth.astype(np.float32)
    tex = ctx.upload(depth, filter="nearest")
    arrays = ReferenceArrays(ctx, refs.views)
    max_distance = 0.05 if use_3d else 3.0
    select = SelectPass(ctx)
    gbuf = select(tex, view, arrays, use_3d, bilinear, max_distance, single_pass=single_pass)
    source = np.rint(ctx.readback(gbuf["object_id"])[..., 0]).astype(int)
    got_depth = ctx.readback(gbuf["depth"])[..., 0]
    got_albedo = ctx.readback(gbuf["colour"])
    gbuf.release()
    emitters = emitters_from_lights(refs.lights, False, MAX_EMITTERS)
    shading = ShadingParams(refs.ambient, refs.background, 1.3)
    radiance, shaded_source = select.shaded(
        tex, view, arrays, emitters, shading, use_3d, bilinear, max_distance, single_pass=single_pass
    )
    got_radiance = ctx.readback(radiance)[..., :3]
    np.testing.assert_array_equal(np.rint(ctx.readback(shaded_source)[..., 0]).astype(int), source)
    ctx.release(radiance, shaded_source)
    tex.release()
    arrays.release()
    want = reference.select(depth, view, refs.views, use_3d, bilinear, max_distance)
    agree = source == want["source"]
    assert agree.mean() > 0.99  # ties between references within float precision may go either way
    both = agree & (source > 0)
    assert both.mean() > 0.8
    # a point projected onto a texel edge may take the neighbouring texel (nearest sampling) on one side
    far = ~np.isclose(got_depth[both], want["depth"][both], **tolerance("float32"))
    assert far.mean() < 1e-3, f"{far.sum()} of {far.size} depths differ"
    # half floats; a point whose four texels sit at the 1 % depth threshold may interpolate on one side only
    assert (np.abs(got_albedo[both] - want["albedo"][both]) > 2e-3).mean() < 1e-3
    # lit in the resolve draw: what the deferred shading (passes.reference.shading) makes of the choice
    chosen = GBufferImages(
        want["albedo"][..., :3],
        want["albedo"][..., 3],
        want["depth"],
        want["normal"][..., :3],
        want["normal"][..., 3],
        want["position"],
        want["source"],
        want["emission"],
    )
    lit = passes_reference.shading(chosen, emitters, view.pose.position, shading)
    assert np.median(lit[both]) > 0.05 and len(emitters) > 0  # lit, not black
    off = (np.abs(got_radiance - lit) > 1e-3 + 3e-3 * np.abs(lit)).any(-1)  # the G-buffer's half floats
    assert off[both].mean() < 2e-3, f"{off[both].sum()} of {both.sum()} pixels lit differently"
    # background where both find no reference (a pixel at a reference's edge may go either way, as above)
    empty = agree & (source == 0)
    np.testing.assert_allclose(got_radiance[empty], np.broadcast_to(refs.background, lit.shape)[empty], atol=1e-6)


@pytest.mark.parametrize("single_pass", [False, True])
def test_a_reference_that_saw_the_other_side_gives_way_to_the_next_nearest(ctx, room, single_pass):
    """A reference whose stored normal faces away from the new eye saw the other side of a thin
    surface: where it is the nearest candidate, the next nearest that faces us is chosen (the single
    pass tests only its nearest and looks again where that fails), as in reference.select. Here
    the first reference's normals are all turned round, so it is the other side everywhere."""
    from dataclasses import replace

    scene, refs = room
    turned = replace(
        refs, views=[replace(refs.views[0], normal=refs.views[0].normal * [-1, -1, -1, 1])] + refs.views[1:]
    )
    view = orbit_views(scene, 5)[1]  # between the first two references
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    g = truth.gbuffer(Frame(view, SIZE))
    depth = np.where(ctx.readback(g["object_id"])[..., 0] > 0.5, ctx.readback(g["depth"])[..., 0], 0.0)
    g.release()
    tex = ctx.upload(depth.astype(np.float32), filter="nearest")
    arrays = ReferenceArrays(ctx, turned.views)
    gbuf = SelectPass(ctx)(tex, view, arrays, single_pass=single_pass)
    source = np.rint(ctx.readback(gbuf["object_id"])[..., 0]).astype(int)
    gbuf.release()
    tex.release()
    arrays.release()
    assert (reference.select(depth, view, refs.views)["source"] == 1).mean() > 0.2  # it was the nearest
    want = reference.select(depth, view, turned.views)["source"]
    assert not (want == 1).any() and (want > 1).mean() > 0.5  # the others took its pixels
    assert (source == want).mean() > 0.99, f"{(source != want).sum()} pixels differ"


def test_references_reproduce_their_own_views_and_views_between_them(ctx, room):
    scene, refs = room
    renderer = IbrRenderer(ctx)
    renderer.prepare(refs)
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    settings = RenderSettings(shadows=False)
    for ref in refs.views:
        assert psnr(renderer.render(Frame(ref.view, SIZE)), truth.render(Frame(ref.view, SIZE), settings)) > 38
    between = orbit_views(scene, 5)[1]
    image = renderer.render(Frame(between, SIZE))
    assert psnr(image, truth.render(Frame(between, SIZE), settings)) > 27
    source = np.rint(ctx.readback(renderer.maps()["source"])[..., 0]).astype(int)
    assert (source == 0).mean() < 0.03 and len(np.unique(source[source > 0])) >= 2  # several views used
    # the G-buffer of the same frame: the same choice, the truth's geometry where a view was chosen
    g = renderer.gbuffer(Frame(between, SIZE))
    np.testing.assert_array_equal(np.rint(ctx.readback(g["object_id"])[..., 0]).astype(int), source)
    depth = ctx.readback(g["depth"])[..., 0]
    g.release()
    true_g = truth.gbuffer(Frame(between, SIZE))
    true_depth = ctx.readback(true_g["depth"])[..., 0]
    true_g.release()
    both = (source > 0) & (true_depth > 0)
    assert np.median(np.abs(depth[both] - true_depth[both]) / true_depth[both]) < 0.01
    debug = renderer.render(Frame(between, SIZE), IbrParams(show_sources=True))
    colours = {tuple(c) for c in np.unique((debug.reshape(-1, 3) * 100).round().astype(int), axis=0).tolist()}
    assert {(90, 15, 10), (15, 75, 20)} <= colours  # the first two references' colours (Figure 4.5)
    # moving the lights re-lights the view from the stored normals
    moved = renderer.render(Frame(between, SIZE), IbrParams(light_x=1.5, light_z=1.0))
    assert np.abs(moved - image).mean() > 0.005
    renderer.release()


def test_reference_folders_round_trip_and_bad_folders_say_what(ctx, room, tmp_path):
    _, refs = room
    folder = save_references(refs, tmp_path / "refs")
    back = load_references(folder)
    for a, b in zip(refs.views, back.views):
        np.testing.assert_array_equal(a.depth, b.depth)
        np.testing.assert_array_equal(a.albedo, b.albedo)
        assert a.view.pose == b.view.pose
    doc = json.loads((folder / "references.json").read_text())
    with np.load(folder / "view-0.npz") as d:
        arrays = dict(d)
    np.savez(folder / "view-0.npz", **{**arrays, "depth": arrays["depth"][:10]})
    with pytest.raises(InputError, match=r"views\[0\]: view-0.npz: reference albedo is"):
        load_references(folder)
    arrays["depth"][3, 3] = np.nan
    np.savez(folder / "view-0.npz", **arrays)
    with pytest.raises(InputError, match="non-finite"):
        load_references(folder)
    (folder / "view-1.npz").unlink()
    np.savez(folder / "view-0.npz", **{**arrays, "depth": np.nan_to_num(arrays["depth"])})
    with pytest.raises(InputError, match=r"views\[1\]: view-1.npz is missing"):
        load_references(folder)
    del doc["views"][0]["camera"]["fov"]
    (folder / "references.json").write_text(json.dumps(doc))
    with pytest.raises(InputError, match=r"views\[0\]: a camera needs eye, target, fov"):
        load_references(folder)


def test_ibr_commands(tmp_path, capsys):
    refs = tmp_path / "refs"
    code, cap = call_cli(["ibr", "capture", "office", "-o", str(refs), "--views", "3", "--size", "64x48"], capsys)
    assert code == 0, cap.err
    out = tmp_path / "new.png"
    code, cap = call_cli(
        ["ibr", "render", str(refs), "-o", str(out), "--camera", "between:0,2,0.25", "--show-sources"], capsys
    )
    assert code == 0, cap.err
    shown = read_image(out)
    assert shown.shape[:2] == (48, 64)
    # the source-view colouring: more than one reference's colour among the pixels
    assert len(np.unique((shown[..., :3] * 4).round().reshape(-1, 3), axis=0)) >= 3
    for args, message in (
        (["--camera", "ref:7"], "reference 7 does not exist"),
        (["--light-x", "40"], "--light-x = 40 m is out of range"),
        (["--distance", "4d"], "distance"),
        (["--selection", "one"], "selection"),
    ):
        code, cap = call_cli(["ibr", "render", str(refs), "-o", str(tmp_path / "x.png"), *args], capsys)
        assert code == 2 and message in cap.err and cap.err.count("\n") == 1, cap.err
    # cameras from a file: a references.json gives the same cameras again; a bad entry is named
    again = tmp_path / "again"
    code, cap = call_cli(
        ["ibr", "capture", "office", "-o", str(again), "--cameras", str(refs / "references.json"), "--size", "32x24"],
        capsys,
    )
    assert code == 0, cap.err
    cameras = lambda folder: [v["camera"] for v in json.loads((folder / "references.json").read_text())["views"]]  # noqa: E731
    assert cameras(again) == cameras(refs)
    bad = tmp_path / "cameras.json"
    bad.write_text(json.dumps([cameras(refs)[0], {"eye": [0, 1, 2], "target": [0, 1, 0]}]))
    code, cap = call_cli(["ibr", "capture", "office", "-o", str(tmp_path / "bad"), "--cameras", str(bad)], capsys)
    assert code == 2 and "camera 2" in cap.err and "fov" in cap.err and not (tmp_path / "bad").exists(), cap.err
    # a camera path played into a video: duration × fps + 1 frames
    walk = tmp_path / "walk.json"
    eye = cameras(refs)
    walk.write_text(
        json.dumps(
            [
                {"t": 0, "eye": eye[0]["eye"], "target": eye[0]["target"]},
                {"t": 0.25, "eye": eye[2]["eye"], "target": eye[2]["target"]},
            ]
        )
    )
    video = tmp_path / "walk.gif"
    code, cap = call_cli(["ibr", "render", str(refs), "-o", str(video), "--path", str(walk), "--fps", "8"], capsys)
    assert code == 0, cap.err
    from PIL import Image

    with Image.open(video) as gif:
        assert gif.n_frames == 3 and gif.size == (64, 48)
    code, cap = call_cli(["ibr", "render", str(refs), "-o", str(tmp_path / "w.png"), "--path", str(walk)], capsys)
    assert code == 2 and ".mp4 or .gif" in cap.err, cap.err


def test_points_scatter_into_the_depth_as_the_reference_draws_them(ctx, room, rng):
    """The first pass's points (points.glsl, one invocation a point, atomics on the depth's bits)
    against reference.point_depth on fresh random points: squares from 1 to ~9 pixels wide, many
    landing on one pixel (the nearest must win), some behind the near plane, some off the image, over
    the depth a mesh wrote first (a point farther than the mesh loses). Exact but where a pixel centre
    lies within float32's rounding of a square's edge."""
    from illusio.ibr.depth_pass import ReconstructPass
    from illusio.ibr.proxy_mesh import Reconstruction
    from illusio.scene.mesh import Mesh

    scene, _ = room
    view = orbit_views(scene, 5)[1]
    size = (64, 48)
    eye = np.asarray(view.pose.position, np.float64)
    right, up, forward = view.pose.axes()
    n = 4000
    depth = rng.uniform(-0.5, 6.0, n)  # some behind the near plane, some behind the eye
    across = rng.uniform(-1.2, 1.2, (n, 2)) * np.abs(depth)[:, None] * 0.8  # some off the image
    points = eye + depth[:, None] * np.asarray(forward) + across[:, :1] * right + across[:, 1:] * up
    footprint = rng.uniform(0.0, 0.15, n) * rng.choice([0.05, 1.0], n)  # most one pixel, some wide
    # a wall square to the view, 3 m ahead, over the left half of the image
    centre = eye + 3.0 * np.asarray(forward)
    corners = [centre + a * np.asarray(right) + b * np.asarray(up) for a, b in ((-9, -9), (0, -9), (0, 9), (-9, 9))]
    wall = Mesh(np.array(corners, np.float32), np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    rp = ReconstructPass(ctx)
    rp.load(Reconstruction(wall, points.astype(np.float32), footprint.astype(np.float32)))
    tex = rp(view, size, 0)
    got = ctx.readback(tex)[..., 0]
    ctx.release(tex)
    rp.release()
    dots = reference.point_depth(points.astype(np.float32), footprint.astype(np.float32), view, size)
    mesh_depth = passes_reference.gbuffer(Scene("m", nodes=[Node("m", wall)]), view, size).depth
    want = np.fmin(np.where(dots > 0, dots, np.nan), np.where(np.isfinite(mesh_depth), mesh_depth, np.nan))
    want = np.nan_to_num(want, nan=0.0)
    assert (dots > 0).mean() > 0.3 and (np.isfinite(mesh_depth) & (dots > 0) & (dots < mesh_depth)).any()
    same = np.isclose(got, want, rtol=1e-5, atol=0.0)
    assert (~same).mean() < 0.005, f"{(~same).sum()} of {got.size} pixels differ"


@pytest.mark.parametrize("step", [4, 8])
def test_reconstruct_pass_matches_ray_casting_and_fills_holes_like_the_reference(ctx, room, rng, step):
    """The first pass: the reconstruction mesh's depth against passes.reference.gbuffer ray-casting
    the same mesh, with the points it leaves out drawn as reference.point_depth squares (the nearer
    wins); hole filling against renderer.fill_holes on a depth with random holes. At step 8 the cut
    cells are meshed again at step 2 inside (proxy_mesh.FINER)."""
    from illusio.ibr.depth_pass import ReconstructPass
    from illusio.ibr.proxy_mesh import reconstruction
    from illusio.ibr.renderer import fill_holes

    scene, refs = room
    shape = reconstruction(refs, step=step)
    mesh, points, footprint = shape.mesh, shape.points, shape.footprint
    assert len(points) > 100
    view = orbit_views(scene, 5)[1]
    size = (48, 36)
    rp = ReconstructPass(ctx)
    rp.load(shape)
    tex = rp(view, size, 0)
    got = ctx.readback(tex)[..., 0]
    ctx.release(tex)
    want = passes_reference.gbuffer(Scene("m", nodes=[Node("m", mesh)]), view, size).depth
    want = np.where(np.isfinite(want), want, np.inf)
    dots = reference.point_depth(points, footprint, view, size)
    want = np.minimum(want, np.where(dots > 0, dots, np.inf))
    want = np.where(np.isfinite(want), want, 0.0)
    both = (got > 0) & (want > 0)
    assert both.mean() > 0.8 and ((got > 0) != (want > 0)).mean() < 0.02  # edges may rasterise apart
    # the points land where the reference puts them (no rasteriser's subpixel snapping: 0 of the
    # pixels differ at either step, measured); a pixel centre on a triangle's edge may go either way
    far = ~np.isclose(got[both], want[both], **tolerance("float32"))
    assert far.mean() < 0.005, f"{far.sum()} of {both.sum()} depths differ"
    assert np.median(np.abs(got[both] / want[both] - 1)[far]) < 0.01 if far.any() else True
    holes = rng.uniform(1, 5, (36, 48)).astype(np.float32)
    holes[rng.random((36, 48)) < 0.3] = 0.0
    holes[10:20, 10:20] = 0.0  # a hole wider than the radius stays partly open
    filled = rp.fill(ctx.acquire_upload(holes), 3)
    np.testing.assert_array_equal(ctx.readback(filled)[..., 0], fill_holes(holes, 3))
    ctx.release(filled)
    rp.release()


def test_disocclusion_fill_matches_reference(ctx, rng):
    """The GPU's filling of the selection's holes (rings up to 5 pixels) equals renderer.fill_hits
    on random hits, exactly: the same neighbour wins."""
    from illusio.ibr.renderer import fill_hits

    h, w = 36, 48
    hits = np.dstack([rng.random((h, w, 2)), rng.uniform(1, 9, (h, w)), rng.integers(1, 4, (h, w))]).astype(np.float32)
    hits[rng.random((h, w)) < 0.3] = 0.0
    hits[6:28, 10:32] = 0.0  # its middle is farther than 5 pixels from any hit
    reconstructed = rng.uniform(1, 5, (h, w)).astype(np.float32)
    reconstructed[rng.random((h, w)) < 0.1] = 0.0
    want = fill_hits(hits, reconstructed, 5)
    assert (want[..., 3] > 0).sum() > (hits[..., 3] > 0).sum() + 150
    assert ((want[..., 3] == 0) & (reconstructed > 0)).any()  # the block's middle stays open
    np.testing.assert_array_equal(want[reconstructed <= 0], hits[reconstructed <= 0])
    select = SelectPass(ctx)
    depth = ctx.acquire_upload(reconstructed)
    got = ctx.readback(select.fill_hits(ctx.acquire_upload(hits), depth, 5))
    np.testing.assert_array_equal(got, want)
    ctx.release(depth)


def test_single_lit_pass_fills_disocclusions_as_the_separate_passes(ctx, room):
    """The single pass lit in its own draw (SelectPass.shaded, single_pass) and its fill draw over the
    marked pixels only give what the separate selection, fill (tested against renderer.fill_hits)
    and lit resolve give: one reference seen from another view leaves disocclusions to fill."""
    scene, refs = room
    view = orbit_views(scene, 7)[5]
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    g = truth.gbuffer(Frame(view, SIZE))
    hit = ctx.readback(g["object_id"])[..., 0] > 0.5
    depth = np.where(hit, ctx.readback(g["depth"])[..., 0], 0.0).astype(np.float32)
    g.release()
    tex = ctx.upload(depth, filter="nearest")
    arrays = ReferenceArrays(ctx, refs.views[:1])  # one reference: no ties between references
    emitters = emitters_from_lights(refs.lights, False, MAX_EMITTERS)
    shading = ShadingParams(refs.ambient, refs.background, 1.0)
    select = SelectPass(ctx)
    out = {}
    for single_pass in (True, False):
        for fill in (0, 6):
            radiance, source = select.shaded(tex, view, arrays, emitters, shading, fill=fill, single_pass=single_pass)
            out[single_pass, fill] = ctx.readback(radiance)[..., :3], np.rint(ctx.readback(source)[..., 0])
            ctx.release(radiance, source)
    select.release()
    tex.release()
    arrays.release()
    unfilled, filled = out[True, 0][1], out[True, 6][1]
    opened = (unfilled == 0) & (depth > 0)
    assert opened.sum() > 200 and (filled[opened] > 0).mean() > 0.5  # disocclusions, most of them filled
    assert ((filled == 0) & (depth > 0)).any()  # some farther than 6 pixels from any hit stay open
    for fill in (0, 6):
        np.testing.assert_array_equal(out[True, fill][1], out[False, fill][1])
        # the single pass finds the seen point along the reference's ray, the resolve unprojects it:
        # float32 rounding apart (measured up to 3.4e-5 relative), lit alike
        np.testing.assert_allclose(out[True, fill][0], out[False, fill][0], rtol=1e-4, atol=1e-6)
    np.testing.assert_array_equal(filled[~opened], unfilled[~opened])  # only the opened pixels change
    background = np.broadcast_to(np.asarray(refs.background, np.float32), (*SIZE[::-1], 3))
    np.testing.assert_allclose(out[True, 6][0][depth <= 0], background[depth <= 0], atol=1e-6)


@pytest.mark.parametrize("name, emits", [("cornell-box", False), ("living-room", True)])
def test_emission_fetch_compiled_out_only_where_no_reference_emits(ctx, name, emits):
    """ReferenceArrays.emits says whether any reference texel emits; the lit pass without the
    emission's fetch draws what the one with it draws where nothing emits, and not where lamps do."""
    scene = load_scene(name)
    refs = capture(scene, orbit_views(scene, 3), (96, 72), ctx)
    view = orbit_views(scene, 5)[1]
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    g = truth.gbuffer(Frame(view, (96, 72)))
    hit = ctx.readback(g["object_id"])[..., 0] > 0.5
    depth = np.where(hit, ctx.readback(g["depth"])[..., 0], 0.0).astype(np.float32)
    g.release()
    tex = ctx.upload(depth, filter="nearest")
    arrays = ReferenceArrays(ctx, refs.views)
    assert arrays.emits == emits
    emitters = emitters_from_lights(refs.lights, False, MAX_EMITTERS)
    shading = ShadingParams(refs.ambient, refs.background, 1.0)
    select = SelectPass(ctx)
    images = []
    for arrays.emits in (True, False):
        radiance, source = select.shaded(tex, view, arrays, emitters, shading, single_pass=True, fill=4)
        images.append(ctx.readback(radiance)[..., :3])
        ctx.release(radiance, source)
    select.release()
    tex.release()
    arrays.release()
    differ = (np.abs(images[0] - images[1]) > 1e-6).any(-1)
    assert differ.any() == emits


def test_reference_arrays_hold_half_floats_without_loss_where_the_values_fit(ctx, room):
    """The rasteriser's captures come from a half-float G-buffer: their albedo, normals and emission
    go to the GPU as half floats and read back exactly; depth stays float32; an emission past
    half's range (a path-traced capture's bright lamp) keeps its array in float32, its values whole."""
    from dataclasses import replace

    _, refs = room
    arrays = ReferenceArrays(ctx, refs.views)
    w, h = arrays.size

    def layers(tex, components):
        dtype = {"f2": np.float16, "f4": np.float32}[tex.dtype]
        return np.frombuffer(tex.read(), dtype).reshape(len(refs.views), h, w, components)[:, ::-1].astype(np.float32)

    assert (arrays.albedo.dtype, arrays.normal.dtype, arrays.emission.dtype, arrays.depth.dtype) == (
        "f2",
        "f2",
        "f2",
        "f4",
    )
    for tex, name, components in (
        (arrays.albedo, "albedo", 4),
        (arrays.normal, "normal", 4),
        (arrays.emission, "emission", 3),
    ):
        np.testing.assert_array_equal(layers(tex, components), np.stack([getattr(v, name) for v in refs.views]))
    np.testing.assert_array_equal(layers(arrays.depth, 1)[..., 0], np.stack([v.depth for v in refs.views]))
    assert any(v.emission.max() > 0 for v in refs.views)  # the living room's lamps: something to keep
    arrays.release()
    bright = [replace(v, emission=v.emission * 1e5 + 1e-3) for v in refs.views]
    arrays = ReferenceArrays(ctx, bright)
    assert arrays.emission.dtype == "f4" and arrays.albedo.dtype == "f2"
    np.testing.assert_array_equal(layers(arrays.emission, 3), np.stack([v.emission for v in bright]))
    arrays.release()


def test_mitsuba_photographs_agree_with_the_rasteriser_and_render_as_recorded(ctx, tmp_path, capsys):
    """Path-traced references: depth along the view axis, normals and albedo agree with our
    G-buffer away from edges; drawn at a reference's own view, the photographic output is the
    photograph; the command captures them."""
    pytest.importorskip("mitsuba", reason="the photo extra (pip install mitsuba)")
    from scipy import ndimage

    from illusio.ibr.mitsuba import capture_mitsuba
    from illusio.scene.builtin import builtin_scene, shape, turntable

    scene = turntable(shape("sphere"))
    views = orbit_views(scene, 2, 0.5)
    size = (64, 48)
    raster = capture(scene, views, size, ctx)
    photo = capture_mitsuba(scene, views, size, samples=8)
    r, p = raster.views[0], photo.views[0]
    depth = r.depth
    interior = ndimage.minimum_filter(depth, 3) > 0.9 * ndimage.maximum_filter(depth, 3)  # no silhouette inside
    assert interior.mean() > 0.5
    relative = np.abs(p.depth[interior] / depth[interior] - 1)
    assert np.median(relative) < 0.002 and relative.max() < 0.02  # a pixel's mean depth vs its centre's
    assert np.median(np.abs(p.normal[..., :3] - r.normal[..., :3])[interior]) < 0.05
    # the sphere is plain (principled: k_s 0.25); the floor is textured, and Mitsuba gets the texture
    subject = interior & np.all(np.abs(r.albedo[..., :3] - scene.nodes[1].material.colour) < 0.01, axis=-1)
    assert subject.sum() > 0.2 * interior.sum()
    assert np.median(np.abs(p.albedo[..., :3] - r.albedo[..., :3])[subject]) < 0.01
    floor = interior & ~subject
    np.testing.assert_allclose(p.albedo[floor][:, :3].mean(0), r.albedo[floor][:, :3].mean(0), atol=0.05)
    # pixel by pixel, the checker where the raster draws it (not its mean: the light and dark cells)
    assert np.median(np.abs(p.albedo[..., :3] - r.albedo[..., :3])[floor]) < 0.03
    assert np.ptp(p.albedo[floor][:, 0]) > 0.15
    office = builtin_scene("office")  # lamp panels and screens: emission comes from the shape hit
    lamps = capture(office, office_views := [office.camera()], (48, 36), ctx).views[0].emission
    shot = capture_mitsuba(office, office_views, (48, 36), samples=2).views[0].emission
    lit = lamps.max(axis=-1) > 0
    assert lit.sum() > 20 and np.median(np.abs(shot - lamps)[lit]) < 0.01
    assert abs(shot.sum() / lamps.sum() - 1) < 0.1  # pixel coverage (Mitsuba) vs centre sample
    assert np.mean(shot[~lit].max(axis=-1) > 0.01) < 0.05  # edge pixels may take part of a lamp
    renderer = IbrRenderer(ctx)
    renderer.prepare(photo)
    again = renderer.render(Frame(p.view, size), IbrParams(relight=False))
    assert np.abs(again - np.clip(p.colour, 0, 1))[interior].mean() < 0.01
    renderer.release()
    code, cap = call_cli(
        [
            "ibr",
            "capture",
            "sphere",
            "-o",
            str(tmp_path / "photo"),
            "--views",
            "2",
            "--size",
            "32x24",
            "--renderer",
            "mitsuba",
            "--samples",
            "4",
        ],
        capsys,
    )
    assert code == 0, cap.err
    code, cap = call_cli(
        ["ibr", "render", str(tmp_path / "photo"), "-o", str(tmp_path / "p.png"), "--photographic"], capsys
    )
    assert code == 0, cap.err
    assert read_image(tmp_path / "p.png").shape[:2] == (24, 32) and read_image(tmp_path / "p.png").max() > 0.05


@pytest.mark.parametrize("step", [2, 8])
def test_the_first_pass_keeps_what_a_reference_saw_at_its_own_view(ctx, room, step):
    """Drawn at a reference's own camera, that reference's reconstruction (its mesh and the points
    the mesh leaves out) has its depth wherever it saw something — thin objects, the pixels along
    occlusion edges whose triangles were all cut as bridges, and what the grid steps over (at step 8
    with the cut cells meshed again finer inside, and fewer points)."""
    from dataclasses import replace

    from illusio.ibr.depth_pass import ReconstructPass
    from illusio.ibr.proxy_mesh import reconstruction

    _, refs = room
    rp = ReconstructPass(ctx)
    for ref in refs.views:
        rp.load(reconstruction(replace(refs, views=[ref]), step))
        tex = rp(ref.view, ref.size, 0)
        got = ctx.readback(tex)[..., 0]
        ctx.release(tex)
        seen = ref.depth > 0
        kept = np.abs(got - ref.depth) <= 0.01 * ref.depth
        assert kept[seen].mean() > 0.999, f"{(~kept[seen]).sum()} of {seen.sum()} seen pixels lost"
    rp.release()


def test_photographic_colour_is_resampled_bilinearly_like_the_reference(ctx, room, rng):
    """Drawn as recorded, the chosen reference's colour is read bilinearly everywhere — across
    silhouettes too, where a camera's pixels blend what they cover — as reference.select(...,
    photographic=True) states it (the attributes keep the nearest texel there)."""
    scene, refs = room
    view = orbit_views(scene, 7)[int(rng.choice([1, 2, 4, 5]))]  # 3 is reference 1's own view
    truth = SceneRenderer(ctx)
    truth.prepare(scene)
    g = truth.gbuffer(Frame(view, SIZE))
    hit = ctx.readback(g["object_id"])[..., 0] > 0.5
    depth = (np.where(hit, ctx.readback(g["depth"])[..., 0], 0.0) * rng.uniform(0.995, 1.005, SIZE[::-1])).astype(
        np.float32
    )
    g.release()
    tex = ctx.upload(depth, filter="nearest")
    arrays = ReferenceArrays(ctx, refs.views)
    gbuf = SelectPass(ctx)(tex, view, arrays, photographic=True)
    source = np.rint(ctx.readback(gbuf["object_id"])[..., 0]).astype(int)
    got = ctx.readback(gbuf["emission"])[..., :3]
    gbuf.release()
    tex.release()
    arrays.release()
    want = reference.select(depth, view, refs.views, photographic=True)
    # the attributes' rule (the nearest texel off one surface) applied to the colour
    from dataclasses import replace

    nearest = reference.select(depth, view, [replace(r, emission=np.asarray(r.colour)[..., :3]) for r in refs.views])
    both = (source == want["source"]) & (source > 0)
    assert both.mean() > 0.8
    off = (np.abs(got - want["emission"]) > 3e-3).any(-1)  # half floats
    assert off[both].mean() < 2e-3, f"{off[both].sum()} of {both.sum()} pixels differ"
    # the rule matters: the nearest texel would differ on a measurable share of the pixels
    assert (np.abs(nearest["emission"] - want["emission"]) > 3e-3).any(-1)[both].mean() > 0.05


def test_cut_cells_are_meshed_again_finer_so_fewer_pixels_become_points(room):
    """At step 8 every coarse cell a thin object cuts is meshed again at step 2 inside: the fine
    triangles lie inside cut coarse cells only (no surface drawn twice), and the points are the
    pixels the single-level mesh leaves out, fewer."""
    from illusio.ibr import proxy_mesh

    _, refs = room
    ref = refs.views[0]
    coarse = proxy_mesh._grid(ref, 8, 85.0)
    vertices, faces, covered = proxy_mesh._adaptive(ref, 8, 85.0)
    extra = faces[int(coarse.keep.sum()) :]
    assert len(extra) > 0
    # every fine triangle's centre lies in a coarse cell that was cut
    centre = vertices[extra].mean(axis=1)
    w, h = ref.size
    view = ref.view
    clip = np.c_[centre, np.ones(len(centre))] @ (view.projection_matrix(w / h) @ view.view_matrix()).T
    xs = (clip[:, 0] / clip[:, 3] + 1) / 2 * w - 0.5
    ys = (1 - clip[:, 1] / clip[:, 3]) / 2 * h - 0.5
    i = np.clip(np.searchsorted(coarse.rows, ys, "right") - 1, 0, len(coarse.rows) - 2)
    j = np.clip(np.searchsorted(coarse.cols, xs, "right") - 1, 0, len(coarse.cols) - 2)
    assert not coarse.cell_ok[i, j].any()
    seen = np.asarray(ref.depth) > 0
    assert (seen & ~covered).sum() < (seen & ~coarse.covered).sum()
    assert (covered | ~coarse.covered).all()  # the fine mesh only adds covered pixels
