"""The benchmark runner works and writes what RESULTS.md quotes (not a timing test)."""

import json
import subprocess
import sys

from tests.conftest import REPO


def test_quick_core_benchmark_writes_json_with_ratios(tmp_path):
    r = subprocess.run([sys.executable, "-m", "benchmarks", "core", "--quick", "--repeat", "1", "--out", str(tmp_path)],
                       capture_output=True, text=True, cwd=REPO, timeout=600)
    assert r.returncode == 0, r.stderr
    data = json.loads((tmp_path / "core.json").read_text())
    names = {t["name"] for t in data["timings"]}
    assert {"office/gbuffer", "office/gbuffer+shading+shadows", "mesh-1M/gbuffer"} <= names
    assert all(t["min_ms"] <= t["median_ms"] <= t["max_ms"] for t in data["timings"])
    assert "1,000,002 triangles" in next(t["notes"] for t in data["timings"] if t["name"] == "mesh-1M/gbuffer")
    assert data["ratios"] and data["machine"]["renderer"]
