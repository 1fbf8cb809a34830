"""A virtual X server for the window tests (README's test command installs xvfb and xauth)."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest


@pytest.fixture(scope="session")
def x_display():
    """DISPLAY of a running X server: the one given, else a fresh Xvfb for this test worker. Without
    Xvfb the window tests skip, except in CI (CI=true), where that is a setup error."""
    if os.environ.get("DISPLAY"):
        yield os.environ["DISPLAY"]
        return
    if shutil.which("Xvfb") is None:
        if os.environ.get("CI"):
            pytest.fail("Xvfb is not installed: scripts/setup.sh test installs xvfb and xauth")
        pytest.skip("no X server for the window tests (apt-get install xvfb xauth)")
    read, write = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write), "-screen", "0", "1600x1000x24", "-nolisten", "tcp"],
        pass_fds=(write,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write)
    with os.fdopen(read) as f:
        number = f.readline().strip()
    if not number:
        proc.kill()
        pytest.fail("Xvfb did not start")
    display = f":{number}"
    os.environ["DISPLAY"] = display
    try:
        yield display
    finally:
        import glfw

        glfw.terminate()  # close GLFW's X connection before its server goes (else Xlib aborts the process)
        del os.environ["DISPLAY"]
        proc.terminate()
        proc.wait(timeout=10)
