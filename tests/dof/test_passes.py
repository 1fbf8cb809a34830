"""The depth-of-field passes against dof.reference on fresh random inputs."""

import numpy as np
import pytest

from illusio.dof import reference
from illusio.dof.accumulation import AccumulatePass
from illusio.dof.coc import CocPass
from illusio.dof.gather import CocTilesPass, GatherPass, SampledGatherPass
from illusio.dof.mipmap import mipmapped
from tests.conftest import tolerance


def random_depth(rng, h, w):
    depth = rng.uniform(0.5, 12.0, (h, w)).astype(np.float32)
    depth[rng.random((h, w)) < 0.1] = 0.0  # nothing there
    return depth


def test_coc_pass_matches_reference(ctx, rng):
    depth = random_depth(rng, 29, 41)
    focus, aperture, fov, max_coc = rng.uniform(1, 5), rng.uniform(0.01, 0.1), rng.uniform(30, 70), 12.0
    tex = ctx.upload(depth, filter="nearest")
    out = CocPass(ctx)(tex, focus, aperture, fov, max_coc)
    got = ctx.readback(out)[..., 0]
    ctx.release(out)
    tex.release()
    np.testing.assert_allclose(got, reference.coc(depth, focus, aperture, fov, max_coc), **tolerance("float32"))


@pytest.mark.parametrize("max_coc", [3.0, 7.0])
def test_gather_pass_matches_reference(ctx, rng, max_coc):
    h, w = 21, 27
    image = rng.random((h, w, 3)).astype(np.float32)
    depth = random_depth(rng, h, w)
    coc = (rng.random((h, w)) * max_coc).astype(np.float32)
    textures = [ctx.upload(a, filter="nearest") for a in (image, coc, depth)]
    out = GatherPass(ctx)(*textures, max_coc)
    got = ctx.readback(out, 3)
    ctx.release(out)
    for t in textures:
        t.release()
    want = reference.gather(image, coc, depth, int(np.ceil(max_coc / 2)))
    np.testing.assert_allclose(got, want, **tolerance("float32"))


@pytest.mark.parametrize("max_coc", [5.0, 14.0])
def test_coc_tiles_pass_matches_reference(ctx, rng, max_coc):
    h, w = 37, 45  # not a whole number of tiles
    coc = (rng.random((h, w)) ** 4 * max_coc).astype(np.float32)  # mostly small, a few large
    tex = ctx.upload(coc, filter="nearest")
    out = CocTilesPass(ctx)(tex, max_coc)
    got = ctx.readback(out)[..., 0]
    ctx.release(out)
    tex.release()
    want = reference.coc_tiles(coc, max_coc)
    assert got.shape == want.shape == (-(-h // reference.tile_size(max_coc)), -(-w // reference.tile_size(max_coc)))
    np.testing.assert_allclose(got, want, **tolerance("float32"))


def _sampled_gather(ctx, image, coc, depth, max_coc, taps):
    textures = [ctx.upload(a, filter="nearest") for a in (image, coc, depth)]
    mip = mipmapped(ctx, textures[0])
    tiles = CocTilesPass(ctx)(textures[1], max_coc)
    out = SampledGatherPass(ctx)(mip, textures[1], textures[2], tiles, max_coc, taps)
    got = ctx.readback(out, 3)
    for t in (out, mip, tiles):
        ctx.release(t)
    for t in textures:
        t.release()
    return got


@pytest.mark.parametrize("taps", [8, 32])
def test_sampled_gather_pass_matches_reference(ctx, rng, taps):
    """Power-of-two sizes (the reference pyramid's); tolerance table: "sampled gather"."""
    h, w, max_coc = 32, 64, 12.0
    image = rng.random((h, w, 3)).astype(np.float32)
    depth = random_depth(rng, h, w)
    coc = (rng.random((h, w)) * max_coc).astype(np.float32)
    got = _sampled_gather(ctx, image, coc, depth, max_coc, taps)
    want = reference.gather_taps(image, coc, depth, max_coc, taps)
    error, bound = np.abs(got - want), tolerance("sampled gather")
    assert np.percentile(error, 99) < bound["p99"] and error.mean() < bound["mean"], (
        np.percentile(error, 99),
        error.mean(),
    )


def test_sampled_gather_estimates_the_gather(rng):
    """The sampled gather is an estimate of the exact one: on a smooth image behind a sharp edge its
    error falls as the points grow, and in focus (CoC 0) it is the image itself."""
    h, w, max_coc = 32, 32, 12.0
    ys, xs = np.mgrid[0:h, 0:w]
    image = np.stack([np.sin(xs / 3.0), np.cos(ys / 4.0), (xs + ys) / (h + w)], -1) * 0.5 + 0.5
    image = image.astype(np.float32)
    depth = np.where(xs < 12, 1.0, 6.0).astype(np.float32)
    coc = np.where(xs < 12, 0.0, 10.0).astype(np.float32)
    exact = reference.gather(image, coc, depth, 6)
    errors = [np.abs(reference.gather_taps(image, coc, depth, max_coc, n) - exact).mean() for n in (4, 16, 64)]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 0.02, errors
    np.testing.assert_allclose(
        reference.gather_taps(image, np.zeros((h, w), np.float32), depth, max_coc, 16), image, atol=1e-6
    )


def test_gather_keeps_focus_sharp_and_a_sharp_foreground_out_of_the_background(rng):
    """In focus (CoC 0) the image is unchanged; a sharp object in front of a blurred background keeps
    its edge: background pixels next to it take nothing from it, and it takes nothing from them."""
    image = rng.random((16, 20, 3)).astype(np.float32)
    flat = np.full((16, 20), 2.0, np.float32)
    np.testing.assert_allclose(reference.gather(image, np.zeros((16, 20)), flat, 3), image, atol=1e-6)
    depth = np.full((16, 20), 8.0, np.float32)
    depth[:, :10] = 1.0  # the foreground, in focus
    coc = np.where(depth > 2, 6.0, 0.0)
    image = np.zeros((16, 20, 3), np.float32)
    image[:, :10] = 1.0  # a white foreground before a black background
    out = reference.gather(image, coc, depth, 3)
    np.testing.assert_allclose(out[:, :10], 1.0, **tolerance("same arithmetic"))  # the foreground stays as it is
    assert out[:, 10:].max() < 1e-6  # and does not bleed onto the blurred background


def test_accumulate_pass_averages_the_views(ctx, rng):
    views = [rng.random((13, 17, 3)).astype(np.float32) for _ in range(5)]
    acc = AccumulatePass(ctx)
    target = acc.begin((17, 13))
    for v in views:
        tex = ctx.upload(v, filter="nearest")
        acc.add(target, tex, 1 / len(views))
        tex.release()
    got = ctx.readback(target, 3)
    ctx.release(target)
    np.testing.assert_allclose(got, reference.accumulate(views), **tolerance("float32"))


def test_lens_samples_cover_the_disk_evenly():
    s = reference.lens_samples(256, seed=3)
    r = np.hypot(*s.T)
    assert r.max() <= 1.0 and abs(np.mean(s, axis=0)).max() < 0.02
    assert abs((r < np.sqrt(0.5)).mean() - 0.5) < 0.01  # half the samples inside half the area
    np.testing.assert_array_equal(s, reference.lens_samples(256, seed=3))  # seeded


def test_mipmap_pass_matches_reference(ctx, rng):
    """Trilinear mipmap lookups against reference.mipmap (box pyramid, GL's bilinear and level
    blending) at a power-of-two size; llvmpipe's filter weights have 8 bits of fraction."""
    from illusio.dof.mipmap import MipmapPass, mipmapped

    image = rng.random((64, 64, 3)).astype(np.float32)
    coc = (rng.random((64, 64)) * 24).astype(np.float32)
    sharp = ctx.upload(np.dstack([image, np.ones((64, 64), np.float32)]), filter="nearest")
    coc_t = ctx.upload(coc, filter="nearest")
    mip = mipmapped(ctx, sharp)
    out = MipmapPass(ctx)(mip, coc_t)
    got = ctx.readback(out, 3)
    ctx.release(out, mip)
    sharp.release(), coc_t.release()
    want = reference.mipmap(image, coc)
    assert np.abs(got - want).max() < 0.02 and np.abs(got - want).mean() < 2e-3


def test_planes_pass_matches_reference(ctx, rng):
    """The planes drawn far to near with the depth test GREATER against the scene's depth pick, at
    every pixel, the nearest plane behind the surface (reference.planes), and show its mipmap level."""
    from illusio.dof.mipmap import mipmapped
    from illusio.dof.planes import PlanesPass, plane_distances
    from illusio.scene.camera import Camera

    camera = Camera(50.0, 0.1, 20.0)
    image = rng.random((64, 64, 3)).astype(np.float32)
    depth = rng.uniform(0.2, 19.5, (64, 64)).astype(np.float32)
    depth[rng.random((64, 64)) < 0.05] = 0.0
    distances = plane_distances(rng.uniform(1, 5), 5, 3, camera.near, camera.far)
    lods = rng.uniform(0, 5, distances.size)
    sharp = ctx.upload(np.dstack([image, np.ones((64, 64), np.float32)]), filter="nearest")
    depth_t = ctx.upload(depth, filter="nearest")
    mip = mipmapped(ctx, sharp)
    out = PlanesPass(ctx)(mip, depth_t, camera, distances, lods)
    got = ctx.readback(out, 3)
    ctx.release(out, mip)
    sharp.release(), depth_t.release()
    want = reference.planes(image, depth, distances, lods)
    close = np.abs(got - want).max(axis=-1) < 0.02
    assert close.mean() > 0.995  # a surface within float precision of a plane may fall either side
    assert np.abs(got - want)[close].mean() < 2e-3


def test_equation_plane_law_exponential_density_around_the_focus():
    """Piranda & de Sorbier 3.1, f(x) = e^(−x/z0)/z0: the planes have that density in x, their
    distance from the focal plane, z0 the focus distance by default. So behind, the k-th plane sits
    where the law's distribution function reaches k/(m + 1); in front, where the law truncated at
    the near plane reaches j/(n + 1). Gaps grow away from the focus; z0 scales the offsets; linear
    spreading keeps the outermost planes and evens the gaps; the farthest is drawn at the far plane."""
    from illusio.dof.planes import covering, plane_distances

    focus, near, far, m, n = 3.0, 0.05, 40.0, 6, 4
    z = plane_distances(focus, m, n, near, far)
    assert z.size == m + n + 1 and (np.diff(z) < 0).all() and z[m] == pytest.approx(focus)
    behind = z[:m][::-1] - focus  # offsets, nearest the focus first
    front = focus - z[m + 1 :]
    cdf = lambda x, z0: 1 - np.exp(-x / z0)  # noqa: E731
    assert np.allclose(cdf(behind, focus), np.arange(1, m + 1) / (m + 1))
    assert np.allclose(cdf(front, focus) / cdf(focus - near, focus), np.arange(1, n + 1) / (n + 1))
    assert (np.diff(behind) > 0).all() and (np.diff(np.diff(behind)) > 0).all()  # gaps grow outwards
    assert (np.diff(front) > 0).all() and front[-1] < focus - near
    wide = plane_distances(focus, m, n, near, far, scale=2 * focus)
    assert np.allclose(wide[:m][::-1] - focus, 2 * behind)
    assert np.allclose(plane_distances(focus, m, n, near, far, scale=focus), z)
    linear = plane_distances(focus, m, n, near, far, "linear")
    assert np.allclose(np.diff(linear[: m + 1]), np.diff(linear[: m + 1])[0]) and linear[0] == pytest.approx(z[0])
    assert np.allclose(np.diff(linear[m:]), np.diff(linear[m:])[0]) and linear[-1] == pytest.approx(z[-1])
    drawn = covering(z, far)
    assert drawn[0] == far and np.array_equal(drawn[1:], z[1:])
