"""docs/architecture.md's "Adding a technique", walked once: a toy technique in a package of its own
(tests/core/toy), registered from outside illusio, is in the registry, the command line (its
options made from its Params), the viewer's modes and the renderer protocol, with no edit to
illusio; in a fresh process, so nothing of it stays in this one."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

SCRIPT = """
import sys
from illusio.core.technique import register, techniques
from tests.core.toy import TOY
register(TOY)
assert list(techniques())[-1] == "toy"
from illusio.viewer.modes import MODES
assert MODES["toy"].name == "toy"
from illusio.cli.main import run
run(["toy", "0.25", "--brightness", "0.5", "-o", sys.argv[1]])
"""


def test_a_toy_technique_plugs_in_through_the_registry_alone(tmp_path):
    import numpy as np

    from illusio.core.images import read_image
    from tests.core.toy.renderer import reference

    out = tmp_path / "toy.png"
    result = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(out)], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 0, result.stderr[-2000:]
    assert f"wrote {out}" in result.stdout
    image = read_image(out)
    assert np.abs(image[..., :3] - reference((32, 16), 0.25, 0.5)).max() <= 1 / 255 + 1e-3
    # and out of range, refused by the option's name before anything is drawn
    bad = SCRIPT.replace('"0.5"', '"1.5"')
    result = subprocess.run([sys.executable, "-c", bad, str(out)], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 2 and "--brightness" in result.stderr
