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


def test_releasing_the_bound_framebuffer_leaves_no_gl_error(ctx):
    """moderngl binds the framebuffer it had bound back after making a new one: when that one was
    released while bound, the bind of its deleted name raises GL_INVALID_OPERATION (what every dof
    planes frame did). Context.release_framebuffer parks the binding on framebuffer 0 first."""
    assert ctx.gl_error() is None
    texture = ctx.acquire((8, 8), 4, "f1")  # acquire makes ctx current for the raw calls below
    fbo = ctx.gl.framebuffer(color_attachments=[texture])
    fbo.use()
    ctx.release_framebuffer(fbo)
    other = ctx.acquire((8, 8), 4, "f1")
    ctx.framebuffer([other]).use()
    assert ctx.gl_error() is None
    ctx.release(texture, other)


def test_gl_error_reads_and_clears_the_flag(ctx):
    ctx.make_current()  # a raw GL call goes to whichever context is current
    ctx.gl.enable_direct(0x1234)  # not an enum glEnable takes
    assert ctx.gl_error() == "GL_INVALID_ENUM"
    assert ctx.gl_error() is None  # read once: cleared
