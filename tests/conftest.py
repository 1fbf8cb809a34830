"""Shared fixtures: one GL context per worker, seeded random generators, test data, tolerances."""

from __future__ import annotations

import os
import secrets
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
MODELS = Path(os.environ.get("ILLUSIO_MODELS", REPO.parent / "shared" / "data" / "models"))

# Tolerances for GPU-vs-reference comparisons, keyed by the dtype the GPU result is stored in.
# float32: GPU single precision against float64 NumPy; float16: half-float render targets.
TOLERANCES = {
    "float32": {"rtol": 1e-4, "atol": 1e-4},
    "float16": {"rtol": 2e-3, "atol": 2e-3},
    "uint8": {"rtol": 0.0, "atol": 1.0 / 255 + 1e-6},
}

# Fresh random inputs each session; ILLUSIO_TEST_SEED=N replays a failing run.
SESSION_SEED = int(os.environ.get("ILLUSIO_TEST_SEED", secrets.randbelow(2**31)))


def pytest_report_header(config):
    return f"illusio test seed: {SESSION_SEED} (set ILLUSIO_TEST_SEED to replay)"


@pytest.fixture
def rng(request) -> np.random.Generator:
    """A generator seeded from the session seed and the test's name (fresh each session)."""
    name_hash = int.from_bytes(request.node.nodeid.encode()[-8:].rjust(8, b"\0"), "little") % 2**31
    return np.random.default_rng([SESSION_SEED, name_hash])


@pytest.fixture(scope="session")
def ctx():
    from illusio.core import Context, GLUnavailable

    try:
        context = Context()
    except GLUnavailable as exc:  # tests need GL: say why loudly instead of skipping silently
        pytest.exit(f"no OpenGL 4.3 context: {exc}", returncode=3)
    yield context


@pytest.fixture(scope="session")
def models() -> Path:
    if not MODELS.is_dir():
        pytest.skip(f"test meshes not found at {MODELS} (set ILLUSIO_MODELS)")
    return MODELS


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
