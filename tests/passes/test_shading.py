import numpy as np
import pytest

from illusio.passes import Emitters, SceneRenderer, ShadingParams, emitters_from_lights, reference
from illusio.passes.gbuffer import GBuffer, GBufferImages
from illusio.scene import AreaLight, Camera, Material, Node, PointLight, Pose, Scene, View
from illusio.scene.builtin import shapes
from illusio.scene.transforms import translate
from tests.conftest import tolerance


def _random_gbuffer(rng, w, h) -> GBufferImages:
    n = rng.normal(size=(h, w, 3))
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    mask = rng.random((h, w)) > 0.1
    return GBufferImages(colour=rng.random((h, w, 3)).astype(np.float32), specular=rng.random((h, w)).astype(np.float32),
                         depth=np.where(mask, 1.0, np.inf).astype(np.float32), normal=n.astype(np.float32),
                         shininess=rng.uniform(1, 60, (h, w)).astype(np.float32),
                         position=rng.uniform(-1, 1, (h, w, 3)).astype(np.float32), object_id=mask.astype(np.int32),
                         emission=(rng.random((h, w, 3)) * 0.2).astype(np.float32))


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
    emitters = Emitters(rng.uniform(-3, 3, (k, 3)).astype(np.float32), normals,
                        rng.uniform(0.1, 3, (k, 3)).astype(np.float32), np.full(k, -1, np.int32), np.zeros((k, 3), np.float32))
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
    s = Scene("lit-plane", nodes=[Node("floor", shapes.plane((40, 40)), material=Material((0.5, 0.5, 0.5)))],
              lights=[light], ambient=(0, 0, 0))
    s.cameras["main"] = View(Pose((0, 6, 0.001), (0, 0, 0)), Camera(90.0, 0.1, 50.0))
    return s


def test_point_light_inverse_square_law(ctx):
    """Irradiance from a point light directly above falls as 1/h² (and as cos³θ across the plane)."""
    r = SceneRenderer(ctx)
    values = []
    for height in (1.0, 2.0):
        s = _plane_scene(PointLight((0, height, 0), intensity=4.0, shadows=False))
        img = r.render(s, size=(65, 65))
        values.append(img[32, 32, 0])
    assert values[0] / values[1] == pytest.approx(4.0, rel=0.02)
    assert values[1] == pytest.approx(0.5 / np.pi * 4.0 / 4.0, rel=0.02)  # ρ/π · I / h²


def test_area_light_sampled_as_points_approaches_the_disc_formula(ctx):
    """A small square lamp of radiance L far above gives E ≈ L·A/h² (its samples sum to L·A)."""
    side, h, radiance = 0.2, 3.0, 50.0
    lamp = AreaLight((0, h, 0), (side, 0, 0), (0, 0, side), radiance=radiance, samples=4, shadows=False)
    img = SceneRenderer(ctx).render(_plane_scene(lamp), size=(65, 65))
    expected = 0.5 / np.pi * radiance * side * side / h**2
    assert img[32, 32, 0] == pytest.approx(expected, rel=0.01)


def test_emitters_carry_area_light_power():
    lamp = AreaLight((0, 2, 0), (1.0, 0, 0), (0, 0, 0.5), radiance=3.0, samples=3)
    e = emitters_from_lights([lamp])
    assert len(e) == 9
    np.testing.assert_allclose(e.weight.sum(axis=0), 3.0 * 0.5)
    np.testing.assert_allclose(e.normal, np.tile([0, -1, 0], (9, 1)), atol=1e-7)
