"""The depth-of-field passes against dof.reference on fresh random inputs."""

import numpy as np
import pytest

from illusio.dof import reference
from illusio.dof.accumulation import AccumulatePass
from illusio.dof.coc import CocPass
from illusio.dof.gather import GatherPass
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
    np.testing.assert_allclose(out[:, :10], 1.0, atol=1e-6)  # the foreground stays as it is
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
