"""Nothing lost: an interrupted command leaves no partial output, and two processes filling the same
curvature cache entry leave one valid entry."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from tests.conftest import REPO

ILLUSIO = [sys.executable, "-c", "from illusio.cli.main import run; run()"]


def environment(tmp_path):
    env = dict(os.environ, ILLUSIO_CACHE=str(tmp_path / "cache"), PYTHONPATH=str(REPO / "src"))
    env.pop("DISPLAY", None)
    return env


def interrupt(args, tmp_path, signum, wait):
    """Run ``illusio args``, ``wait(proc)`` until it is where the test wants it (still running), send
    ``signum``: (return code, stderr text, seconds from the signal to the exit)."""
    proc = subprocess.Popen(
        ILLUSIO + list(args), env=environment(tmp_path), stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    try:
        wait(proc)
        assert proc.poll() is None, proc.communicate()[1].decode()
        sent = time.monotonic()
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
        took = time.monotonic() - sent
    finally:
        proc.kill()
    return proc.returncode, err.decode(), took


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_an_interrupted_video_leaves_nothing_behind(tmp_path, signum):
    """A turntable video interrupted while its frames are being written: the command says so in one
    line and exits 130, the video does not exist and its temporary file is gone."""
    out = tmp_path / "spin.mp4"

    def encoding(proc):
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None and not list(tmp_path.glob(".spin.tmp-*")):
            time.sleep(0.05)
        time.sleep(2.0)  # frames are being drawn and encoded

    args = ["render", "living-room", "--turntable", "3600", "--size", "96x72", "-o", str(out)]
    returncode, err, _ = interrupt(args, tmp_path, signum, encoding)
    assert returncode == 130, err
    assert err.strip().splitlines() == ["illusio: interrupted: nothing written"], err
    assert not out.exists()
    assert not list(tmp_path.glob(".spin.tmp-*")), "a temporary file was left"


def test_two_processes_filling_one_curvature_entry_leave_one_valid_entry(tmp_path):
    script = (
        "from illusio.scene.builtin.shapes import torus_knot; from illusio.lines.curvature import estimate_curvature;"
        "estimate_curvature(torus_knot())"
    )
    env = environment(tmp_path)
    procs = [subprocess.Popen([sys.executable, "-c", script], env=env, stderr=subprocess.PIPE) for _ in range(2)]
    for p in procs:
        assert p.wait(timeout=300) == 0, p.stderr.read().decode()
    files = sorted((tmp_path / "cache" / "curvature").iterdir())
    assert [f.suffix for f in files] == [".npz"], files  # one entry, no temporary file
    from illusio.lines.curvature import Curvature, estimate_curvature
    from illusio.scene.builtin.shapes import torus_knot

    cached = Curvature.load(files[0])
    fresh = estimate_curvature(torus_knot(), cache=False)
    np.testing.assert_allclose(cached.k_max, fresh.k_max, rtol=1e-5, atol=1e-6)


def test_an_interrupted_path_traced_photograph_stops_at_once(tmp_path):
    """Ctrl-C while Mitsuba path-traces relighting's photograph (65,536 paths a pixel: hours):
    Mitsuba keeps the signal to itself while it renders, and took minutes to wind down; the render
    runs in a worker thread (passes.mitsuba.render), so the command says its one line and exits 130
    within seconds, writing nothing."""
    out = tmp_path / "relit.png"
    args = ["relight", "office", "--samples", "65536", "--size", "160x120", "-o", str(out)]
    # 20 s: past the imports and the scene, in the path tracer (it has hours to go)
    returncode, err, took = interrupt(args, tmp_path, signal.SIGINT, lambda proc: time.sleep(20.0))
    assert returncode == 130, err
    # one line: Mitsuba's own red "Received interrupt signal" is kept quiet
    assert err.strip().splitlines() == ["illusio: interrupted: nothing written"], err
    assert took < 10, took
    assert not out.exists()
