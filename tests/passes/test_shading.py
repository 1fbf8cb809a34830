import numpy as np
import pytest

from illusio.core.renderer import Frame
from illusio.passes import Emitters, SceneRenderer, ShadingParams, emitters_from_lights, reference
from illusio.passes.gbuffer import GBuffer, GBufferImages
from illusio.scene import AreaLight, Camera, Material, Node, PointLight, Pose, Scene, View
from illusio.scene.builtin import shapes
from illusio.scene.transforms import translate
from tests.conftest import prepared, tolerance


def _random_gbuffer(rng, w, h) -> GBufferImages:
    n = rng.normal(size=(h, w, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    mask = rng.random((h, w)) > 0.1
    return GBufferImages(
        colour=rng.random((h, w, 3)).astype(np.float32),
        specular=rng.random((h, w)).astype(np.float32),
        depth=np.where(mask, 1.0, np.inf).astype(np.float32),
        normal=n.astype(np.float32),
        shininess=rng.uniform(1, 60, (h, w)).astype(np.float32),
        position=rng.uniform(-1, 1, (h, w, 3)).astype(np.float32),
        object_id=mask.astype(np.int32),
        emission=(rng.random((h, w, 3)) * 0.2).astype(np.float32),
    )


def _upload_gbuffer(ctx, g: GBufferImages) -> GBuffer:
    h, w = g.mask.shape
    tex = {
        "colour": ctx.upload(np.dstack([g.colour, g.specular]), filter="nearest"),
        "normal": ctx.upload(np.dstack([g.normal, g.shininess]), filter="nearest"),
        "position": ctx.upload(np.dstack([g.position, g.mask.astype(np.float32)]), filter="nearest"),
        "emission": ctx.upload(np.dstack([g.emission, np.ones((h, w), np.float32)]), filter="nearest"),
    }
    return GBuffer(ctx, tex, (w, h))


def test_shading_pass_matches_reference_on_random_gbuffers(ctx, rng):
    w, h = 37, 23
    g = _random_gbuffer(rng, w, h)
    k = 5
    normals = np.zeros((k, 3), np.float32)
    normals[2:] = rng.normal(size=(k - 2, 3))
    normals[2:] /= np.linalg.norm(normals[2:], axis=1, keepdims=True)
    emitters = Emitters(
        rng.uniform(-3, 3, (k, 3)).astype(np.float32),
        normals,
        rng.uniform(0.1, 3, (k, 3)).astype(np.float32),
        np.full(k, -1, np.int32),
        np.zeros((k, 3), np.float32),
    )
    params = ShadingParams(tuple(rng.random(3) * 0.1), (0.2, 0.3, 0.4), float(rng.uniform(0.5, 2)), 0.1)
    camera = rng.uniform(-4, 4, 3)
    gpu_gb = _upload_gbuffer(ctx, g)
    out = ctx.readback(_shading(ctx)(gpu_gb, emitters, camera, params), 3)
    expected = reference.shading(g, emitters, camera, params)
    # pow() of the Phong lobe at high exponents is the least exact operation: relative tolerance
    np.testing.assert_allclose(out, expected, rtol=2e-4, atol=tolerance("float32")["atol"])


def _shading(ctx):
    from illusio.passes import ShadingPass

    return ShadingPass(ctx)


def _plane_scene(light) -> Scene:
    s = Scene(
        "lit-plane",
        nodes=[Node("floor", shapes.plane((40, 40)), material=Material((0.5, 0.5, 0.5)))],
        lights=[light],
        ambient=(0, 0, 0),
    )
    s.cameras["main"] = View(Pose((0, 6, 0.001), (0, 0, 0)), Camera(90.0, 0.1, 50.0))
    return s


def test_point_light_inverse_square_law(ctx):
    """Irradiance from a point light directly above falls as 1/h² (and as cos³θ across the plane)."""
    r = SceneRenderer(ctx)
    values = []
    for height in (1.0, 2.0):
        s = _plane_scene(PointLight((0, height, 0), intensity=4.0, shadows=False))
        r.prepare(s)
        img = r.render(Frame(size=(65, 65)))
        values.append(img[32, 32, 0])
    assert values[0] / values[1] == pytest.approx(4.0, rel=0.02)
    assert values[1] == pytest.approx(0.5 / np.pi * 4.0 / 4.0, rel=0.02)  # ρ/π · I / h²


def test_area_light_sampled_as_points_approaches_the_disc_formula(ctx):
    """A small square lamp of radiance L far above gives E ≈ L·A/h² (its samples sum to L·A)."""
    side, h, radiance = 0.2, 3.0, 50.0
    lamp = AreaLight((0, h, 0), (side, 0, 0), (0, 0, side), radiance=radiance, samples=4, shadows=False)
    img = prepared(SceneRenderer(ctx), _plane_scene(lamp)).render(Frame(size=(65, 65)))
    expected = 0.5 / np.pi * radiance * side * side / h**2
    assert img[32, 32, 0] == pytest.approx(expected, rel=0.01)


def test_emitters_carry_area_light_power():
    lamp = AreaLight((0, 2, 0), (1.0, 0, 0), (0, 0, 0.5), radiance=3.0, samples=3)
    e = emitters_from_lights([lamp])
    assert len(e) == 9
    np.testing.assert_allclose(e.weight.sum(axis=0), 3.0 * 0.5)
    np.testing.assert_allclose(e.normal, np.tile([0, -1, 0], (9, 1)), atol=1e-7)


def _random_scene(rng) -> Scene:
    """A few shapes with random materials (matte and glossy) lit by point and area lights."""
    makers = (lambda: shapes.sphere(0.5), lambda: shapes.box((0.8, 0.5, 0.6)), lambda: shapes.torus(0.5, 0.18))
    nodes = [Node("floor", shapes.plane((6, 6)), material=Material(tuple(rng.random(3)), specular=0.0))]
    for i in range(4):
        mat = Material(
            tuple(rng.random(3)),
            specular=float(rng.choice([0.0, rng.uniform(0.1, 0.8)])),
            shininess=float(rng.uniform(5, 80)),
        )
        nodes.append(
            Node(f"shape-{i}", makers[i % 3](), translate(rng.uniform((-1.5, 0.3, -1.5), (1.5, 1.0, 1.5))), mat)
        )
    lights = [
        PointLight(tuple(rng.uniform((-2, 1.5, -2), (2, 3, 2))), tuple(rng.random(3)), float(rng.uniform(2, 8))),
        AreaLight((0.0, 2.8, 0.0), (0.6, 0, 0), (0, 0, 0.6), (1, 1, 1), float(rng.uniform(5, 20)), samples=2),
    ]
    s = Scene("random", nodes=nodes, lights=lights, ambient=tuple(rng.random(3) * 0.1))
    s.cameras["main"] = View(
        Pose.orbit((0, 0.5, 0), 5.0, float(rng.uniform(0, 360)), float(rng.uniform(15, 50))), Camera(45.0, 0.1, 50.0)
    )
    return s


def test_forward_pass_matches_shading_reference_on_random_scenes(ctx, rng):
    """Forward (no G-buffer) against passes.reference.shading fed with the deferred path's G-buffer of
    the same view, on pixels both cover with the same object away from silhouettes."""
    from scipy import ndimage

    from illusio.passes import RenderSettings

    scene = _random_scene(rng)
    view, size = scene.camera(), (96, 72)
    renderer = prepared(SceneRenderer(ctx), scene)
    tex, ids = renderer.render_forward(Frame(view, size), RenderSettings(shadows=False), object_ids=True)
    forward = ctx.readback(tex, 3)
    forward_ids = np.rint(ctx.readback(ids)[..., 0]).astype(np.int32)
    ctx.release(tex, ids)
    gbuf = renderer.gbuffer(Frame(view, size))
    g = gbuf.read()
    gbuf.release()
    expected = reference.shading(
        g, emitters_from_lights(scene.lights, False), view.pose.position, ShadingParams(scene.ambient, scene.background)
    )
    interior = ndimage.minimum_filter(g.object_id, 3) == ndimage.maximum_filter(g.object_id, 3)
    same = interior & (forward_ids == g.object_id)
    assert same.mean() > 0.8
    np.testing.assert_allclose(forward[same], expected[same], **tolerance("shading half-float inputs"))


def test_forward_and_deferred_paths_agree_with_shadows(ctx, rng):
    from illusio.passes import RenderSettings

    scene = _random_scene(rng)
    renderer = prepared(SceneRenderer(ctx), scene)
    deferred = renderer.render(Frame(size=(80, 60)), RenderSettings(shadows=True))
    forward = renderer.render(Frame(size=(80, 60)), RenderSettings(shadows=True, forward=True))
    close = np.abs(forward - deferred) < 5e-3 + 5e-3 * np.abs(deferred)
    assert close.mean() > 0.97  # silhouettes may rasterise one pixel apart


def test_screen_material_colours_its_nodes_from_a_screen_space_texture(ctx, rng):
    from illusio.passes import RenderSettings, ScreenMaterial

    scene = _plane_scene(PointLight((0, 3, 0), (1, 1, 1), 0.0))
    size = (64, 48)
    screen = rng.random((size[1], size[0], 3)).astype(np.float32)
    tex = ctx.upload(screen, filter="nearest")
    renderer = prepared(SceneRenderer(ctx), scene)
    out, _ = renderer.render_forward(
        Frame(scene.camera(), size),
        RenderSettings(shadows=False),
        ScreenMaterial(tex, frozenset({0}), (0.5, 0.5, 0.5), emission=1.0),
    )
    got = ctx.readback(out, 3)
    ctx.release(out)
    tex.release()
    # no light reaches it (intensity 0), no ambient: what shows is the emission, texture × 1
    np.testing.assert_allclose(got, screen, **tolerance("same arithmetic"))


def test_reused_static_layer_gives_the_full_forward_frame(ctx, rng):
    """Frame after frame with only the screen texture changing, then a new view: each frame equals a
    whole forward render of the same inputs; the rest of the image is kept from the second frame of
    an unchanged view on, and a moved view drops it."""
    from illusio.passes import RenderSettings, ScreenMaterial

    scene = _random_scene(rng)
    size = (80, 60)
    renderer = prepared(SceneRenderer(ctx), scene)
    settings = RenderSettings(shadows=False)
    other = View(Pose.orbit((0, 0.5, 0), 5.0, 10.0, 30.0), Camera(45.0, 0.1, 50.0))
    views = [scene.camera()] * 3 + [other] * 2
    kept = []
    for view in views:
        screen = ctx.upload(rng.random((size[1], size[0], 3)).astype(np.float32), filter="nearest")
        material = ScreenMaterial(screen, frozenset({1, 3}), (0.8, 0.7, 0.6), emission=0.5)
        reused, _ = renderer.render_forward(Frame(view, size), settings, material, reuse_static=True)
        kept.append(renderer.static_layer_kept)
        whole, _ = renderer.render_forward(Frame(view, size), settings, material)
        a, b = ctx.readback(reused, 3), ctx.readback(whole, 3)
        ctx.release(reused, whole)
        screen.release()
        assert (np.abs(a - b) <= 1e-6).mean() > 0.999
    assert kept == [False, True, True, False, True]
    assert renderer.prepare(scene) is False  # the same scene by value: the layer stays
    assert renderer.static_layer_kept
    scene.nodes[0].material.colour = (0.1, 0.2, 0.3)  # an in-place edit: prepare sees it and drops the layer
    assert renderer.prepare(scene) is True
    assert not renderer.static_layer_kept


def test_gbuffer_hook_replaces_attachments_before_shading(ctx, rng):
    from illusio.core.errors import InputError
    from illusio.passes import RenderSettings

    scene = _random_scene(rng)
    scene.lights.clear()  # ambient only: radiance = ambient · albedo + emission
    renderer = prepared(SceneRenderer(ctx), scene)
    size = (48, 36)

    def white_albedo(gbuf):
        colour = ctx.acquire(size, 4, "f2")  # pooled, like the G-buffer's own, which gbuf.release() returns
        colour.write(np.ones((size[1], size[0], 4), np.float16).tobytes())
        ctx.release(gbuf.textures["colour"])
        gbuf.textures["colour"] = colour

    tex = renderer.render_texture(Frame(scene.camera(), size), RenderSettings(shadows=False), gbuffer_hook=white_albedo)
    got = ctx.readback(tex, 3)
    ctx.release(tex)
    g = renderer.gbuffer(Frame(scene.camera(), size))
    hit = g.read().mask
    g.release()
    np.testing.assert_allclose(
        got[hit], np.broadcast_to(np.asarray(scene.ambient, np.float32), got[hit].shape), **tolerance("same arithmetic")
    )
    with pytest.raises(InputError):
        renderer.render_texture(Frame(scene.camera(), size), RenderSettings(forward=True), gbuffer_hook=white_albedo)


def test_front_to_back_distances_match_each_transformed_bounding_box(ctx, rng):
    """GpuScene.box_distances (all nodes at once) against the plain per-node definition: the
    distance from the eye to the axis-aligned box around the node's transformed mesh corners."""
    from illusio.passes.gpu_scene import GpuScene
    from illusio.scene.transforms import rotate

    scene = _random_scene(rng)
    for node in scene.nodes:
        node.transform = translate(rng.normal(0, 2, 3)) @ rotate(rng.normal(0, 1, 3), rng.uniform(0, 360))
    gpu = GpuScene(ctx, scene)
    for eye in rng.normal(0, 3, (5, 3)):
        got = gpu.box_distances(eye)
        for node, d in zip(scene.nodes, got):
            lo, hi = node.mesh.bounds
            corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
            world = corners @ node.transform[:3, :3].T + node.transform[:3, 3]
            outside = np.maximum(0.0, np.maximum(world.min(0) - eye, eye - world.max(0)))
            assert d == pytest.approx(np.linalg.norm(outside), abs=1e-5)  # float32 transforms
    inside = scene.nodes[0]
    centre = inside.transform[:3, :3] @ np.mean(inside.mesh.bounds, axis=0) + inside.transform[:3, 3]
    assert gpu.box_distances(centre)[0] == 0.0
    gpu.release()


def test_frustum_culling_skips_only_nodes_that_draw_no_pixel(ctx, rng):
    """A node GpuScene.in_frustum rejects has every vertex beyond one and the same clip plane (it
    cannot reach a pixel); nodes with a vertex inside the frustum are kept; some views do cull."""
    from illusio.passes.gpu_scene import GpuScene

    scene = _random_scene(rng)
    gpu = GpuScene(ctx, scene)
    culled = 0
    for _ in range(20):
        view = View(
            Pose.orbit(
                tuple(rng.normal(0, 1, 3)),
                float(rng.uniform(0.5, 4)),
                float(rng.uniform(0, 360)),
                float(rng.uniform(-30, 60)),
            ),
            Camera(float(rng.uniform(20, 70)), 0.1, 50.0),
        )
        vp = view.view_projection((64, 48)).astype(np.float64)
        keep = gpu.in_frustum(vp)
        for node, kept in zip(scene.nodes, keep):
            v = np.c_[node.mesh.vertices, np.ones(len(node.mesh.vertices))] @ (vp @ node.transform).T
            beyond = ((v[:, :3] > v[:, 3:]).all(axis=0) | (v[:, :3] < -v[:, 3:]).all(axis=0)).any()
            inside = ((np.abs(v[:, :3]) <= v[:, 3:]).all(axis=1)).any()
            if not kept:
                assert beyond
                culled += 1
            if inside:
                assert kept
    assert culled > 0
    gpu.release()
