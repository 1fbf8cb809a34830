"""Stereo composites: the GPU pass against passes.reference.stereo_composite on random images."""

import numpy as np
import pytest

from illusio.core.errors import InputError
from illusio.passes import reference
from illusio.passes.stereo import ANAGLYPH_MATRICES, COMPOSITES, StereoCompositePass, composite_size
from tests.conftest import tolerance


@pytest.mark.parametrize("mode", COMPOSITES)
def test_stereo_composite_matches_reference(ctx, rng, mode):
    left = rng.random((23, 31, 3)).astype(np.float32)
    right = rng.random((23, 31, 3)).astype(np.float32)
    lt, rt = ctx.upload(left, filter="nearest"), ctx.upload(right, filter="nearest")
    out = StereoCompositePass(ctx)(lt, rt, mode)
    got = ctx.readback(out, 3)
    ctx.release(out)
    lt.release(), rt.release()
    want = reference.stereo_composite(left, right, mode)
    assert got.shape[:2][::-1] == composite_size(mode, (31, 23)) == (want.shape[1], want.shape[0])
    np.testing.assert_allclose(got, want, **tolerance("uint8"))


def test_layouts_put_each_eye_where_it_belongs(rng):
    left, right = np.zeros((4, 5, 3)), np.ones((4, 5, 3))
    sbs = reference.stereo_composite(left, right, "side-by-side")
    assert sbs[:, :5].max() == 0 and sbs[:, 5:].min() == 1
    assert reference.stereo_composite(left, right, "cross-eyed")[:, :5].min() == 1  # right image first
    assert reference.stereo_composite(left, right, "top-bottom")[:4].max() == 0  # left image on top


def test_anaglyphs_send_each_eye_through_its_filter():
    """The left image reaches the red channel only, the right one green and blue (colour scheme);
    Dubois's matrices carry a white left image mostly to red and a white right image to cyan."""
    white, black = np.ones((2, 2, 3)), np.zeros((2, 2, 3))
    colour = reference.stereo_composite(white, black, "anaglyph-colour")
    np.testing.assert_allclose(colour[0, 0], (1, 0, 0))
    np.testing.assert_allclose(reference.stereo_composite(black, white, "anaglyph-colour")[0, 0], (0, 1, 1))
    grey = reference.stereo_composite(white * (0.2, 0.5, 0.9), black, "anaglyph-grey")[0, 0]
    assert grey[0] == pytest.approx(0.2126 * 0.2 + 0.7152 * 0.5 + 0.0722 * 0.9) and grey[1:].max() == 0
    lm, rm = ANAGLYPH_MATRICES["anaglyph"]
    assert lm.sum(axis=1)[0] > 1.0 and rm.sum(axis=1)[1:].min() > 1.0
    with pytest.raises(InputError, match="unknown stereo composite"):
        composite_size("wiggle", (4, 4))
