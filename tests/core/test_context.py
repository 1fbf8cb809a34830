"""Two Contexts in one process: each entry point makes its own GL context current again."""

import numpy as np

from illusio.core import Context


def test_a_second_context_does_not_receive_the_first_ones_work(ctx, rng):
    before = rng.random((24, 32, 4), dtype=np.float32)
    tex = ctx.upload(before)
    other = Context()  # becomes current, as a CLI call inside a script would
    try:
        theirs = other.upload(np.zeros((8, 8, 4), np.float32))
        after = rng.random((24, 32, 4), dtype=np.float32)
        mine = ctx.upload(after)
        np.testing.assert_array_equal(ctx.readback(tex), before)
        np.testing.assert_array_equal(ctx.readback(mine), after)
        np.testing.assert_array_equal(other.readback(theirs), 0.0)
    finally:
        other.release_all()
    np.testing.assert_array_equal(ctx.readback(tex), before)  # still usable after the other is gone
    tex.release()
    mine.release()
