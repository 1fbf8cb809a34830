"""Shared fixtures: one GL context per worker, seeded random generators, test data, tolerances."""

from __future__ import annotations

import os
import secrets
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
MODELS = Path(os.environ.get("ILLUSIO_MODELS", REPO.parent / "shared" / "data" / "models"))
MGF_SCENES = Path(os.environ.get("ILLUSIO_MGF", REPO.parent / "shared" / "data" / "scenes" / "mgf"))

# Every tolerance of a GPU-vs-reference comparison comes from this table (tolerance(NAME)). The first
# three are keyed by the dtype the GPU result is stored in: float32 is GPU single precision against
# float64 NumPy, float16 a half-float render target, uint8 one step of an 8-bit one. The looser
# ones say why they are looser.
TOLERANCES = {
    "float32": {"rtol": 1e-4, "atol": 1e-4},
    "float16": {"rtol": 2e-3, "atol": 2e-3},
    "uint8": {"rtol": 0.0, "atol": 1.0 / 255 + 1e-6},
    # the same arithmetic on both sides (a copy, an exact rescale): far tighter than float32
    "same arithmetic": {"rtol": 0.0, "atol": 1e-5},
    # world positions (metres) rebuilt from an interpolated depth, against a float64 ray hit a few
    # metres away: float32's 1e-7 relative over that distance, and the interpolation's own rounding
    "position": {"rtol": 0.0, "atol": 2e-4},
    # shading of G-buffer samples: the reference reads the G-buffer's half-float colour and normals,
    # so its inputs already carry ~1e-3, and a specular power magnifies that: cos^n's relative error
    # is n·δcos, n up to 80 in the random scenes, δcos ~1e-4 from a half-float normal (a fresh-clone
    # CI run met 0.7 % on one highlight pixel under 5e-3)
    "shading half-float inputs": {"rtol": 1e-2, "atol": 2e-3},
    # a rasterised hit point against a ray-cast one: the two land ~1e-4 of the surface apart, and a
    # radiance interpolated across a leaf moves with them
    "hit point": {"rtol": 2e-3, "atol": 2e-4},
    # separations in pixels (up to ~200) by equation (3): the shader's float32 division and powers
    # differ from NumPy's by a few ulps of 200
    "separation px": {"rtol": 1e-5, "atol": 1e-3},
    # texture coordinates of a projected host, interpolated by the rasteriser (perspective-correct
    # in float32) against NumPy's exact projection
    "projected depth": {"rtol": 0.0, "atol": 1e-3},
    # the sampled gather (dof.gather.SampledGatherPass) against reference.gather_taps: a point on a
    # pixel's edge may fall on either side in float32, so a few pixels take another texel; bounds on
    # the 99th percentile and the mean of |GPU − NumPy|
    "sampled gather": {"p99": 1e-4, "mean": 1e-3},
    # a whole depth-of-field renderer against a 128-sample accumulation on a strongly blurred view
    # (tests/dof/test_renderer.py): the least PSNR gain over the unblurred image, dB. The gather is
    # a depth-aware disk convolution, close to the lens model (sampled by gather_taps points, the
    # default, or exact over every pixel of its kernel); mipmap and planes take a box-filtered level
    # (a square, not the lens's disk) and the planes blur a surface by the plane behind it, not its
    # own depth (the paper's approximation), so theirs are smaller. Measured: gather 6.9 (32
    # points; with half its disk radius 5.1), exact 8.6, mipmap 3.2, planes 2.2.
    "dof gain gather": {"min_db": 6.0},
    "dof gain gather-exact": {"min_db": 5.5},
    "dof gain mipmap": {"min_db": 2.0},
    "dof gain planes": {"min_db": 1.2},
}

# Fresh random inputs each session; ILLUSIO_TEST_SEED=N replays a failing run. The first process to
# import this file (pytest's, or xdist's controller) draws the seed and puts it in the environment, so
# the xdist workers it starts draw the same inputs as the seed it prints.
os.environ.setdefault("ILLUSIO_TEST_SEED", str(secrets.randbelow(2**31)))
SESSION_SEED = int(os.environ["ILLUSIO_TEST_SEED"])


def pytest_report_header(config):
    return f"illusio test seed: {SESSION_SEED} (set ILLUSIO_TEST_SEED to replay)"


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    # again at the end: a log cut to its tail still shows how to replay a failure
    if exitstatus:
        terminalreporter.write_line(f"illusio test seed: {SESSION_SEED} (ILLUSIO_TEST_SEED={SESSION_SEED} replays it)")


@pytest.fixture
def rng(request) -> np.random.Generator:
    """A generator seeded from the session seed and the test's name (fresh each session)."""
    name_hash = int.from_bytes(request.node.nodeid.encode()[-8:].rjust(8, b"\0"), "little") % 2**31
    return np.random.default_rng([SESSION_SEED, name_hash])


_SESSION_CONTEXT: list = []


@pytest.fixture(scope="session")
def ctx():
    from illusio.core import Context, GLUnavailable

    try:
        context = Context()
    except GLUnavailable as exc:  # tests need GL: say why loudly instead of skipping silently
        pytest.exit(f"no OpenGL 4.3 context: {exc}", returncode=3)
    _SESSION_CONTEXT.append(context)
    yield context


@pytest.fixture(autouse=True)
def gl_error_flag_is_clean():
    """After every test, the GL error flag of each context still open (the session's, the one-shot
    default, the CLI's) is clean, as moderngl's own suite checks around each test: a pass that
    raises GL_INVALID_OPERATION and draws nothing would otherwise be seen only by what it draws."""
    yield
    import illusio.core.context as core_context

    current = core_context.current_context()  # reading another context's flag makes that one current
    live = {id(c): c for c in [c for c in _SESSION_CONTEXT if c.gl is not None] + core_context.live_contexts()}
    raised = [
        f"{err} on {'the session context' if c in _SESSION_CONTEXT else 'a context'}"
        for c in live.values()
        if (err := c.gl_error())
    ]  # read once each: reading clears it
    if current is not None:
        current.make_current()  # the next test finds the context this one left current
    if raised:
        pytest.fail("GL error flag set after the test: " + "; ".join(raised), pytrace=False)


@pytest.fixture(scope="session")
def models() -> Path:
    if not MODELS.is_dir():
        pytest.skip(f"test meshes not found at {MODELS} (set ILLUSIO_MODELS)")
    return MODELS


@pytest.fixture(scope="session")
def mgf_scenes() -> Path:
    """The classic MGF scenes (../shared/data/scenes/mgf: read from there, never copied)."""
    if not MGF_SCENES.is_dir():
        pytest.skip(f"MGF test scenes not found at {MGF_SCENES} (set ILLUSIO_MGF)")
    return MGF_SCENES


def prepared(renderer, subject):
    """``renderer`` after ``prepare(subject)`` (one line in tests)."""
    renderer.prepare(subject)
    return renderer


def tolerance(dtype: str) -> dict:
    return TOLERANCES[dtype]


def call_cli(args, capsys):
    """Run the illusio command in-process: (exit status, captured stdout/stderr)."""
    from illusio.cli.main import run

    try:
        run(args)
        code = 0
    except SystemExit as exc:
        code = exc.code or 0
    return code, capsys.readouterr()
