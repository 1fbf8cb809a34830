"""No test runs unbounded: pytest-timeout is active with the default pyproject states, and a test
that hangs is stopped with a message, not left to CI's 90-minute limit."""

import subprocess
import sys

import pytest

from tests.conftest import REPO

tomllib = pytest.importorskip("tomllib")  # Python 3.11+


def test_every_test_has_a_time_bound(tmp_path):
    settings = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["pytest"]["ini_options"]
    assert 60 <= int(settings["timeout"]) <= 600
    (tmp_path / "test_hangs.py").write_text("import time\n\ndef test_hangs():\n    time.sleep(600)\n")
    r = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-o", "timeout=2", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode != 0 and "Timeout (>2.0s)" in r.stdout, r.stdout[-2000:]
