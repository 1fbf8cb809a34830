"""core.kernels: a first run says it is compiling numba's kernels, a later one says nothing; and the
OpenMP wait policy importing illusio sets for them."""

import importlib
import os
import subprocess
import sys


def test_a_kernel_is_announced_until_its_code_is_on_disk(tmp_path, monkeypatch):
    (tmp_path / "fresh_kernels.py").write_text(
        "import numba\n\n@numba.njit(cache=True)\ndef double(x):\n    return 2 * x\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("fresh_kernels")
    from illusio.core.kernels import cached_on_disk, compile_note

    assert not cached_on_disk(module.double)
    assert compile_note("the test kernel", 12, module.double) == (
        " (compiling the test kernel, once: about 12 s; later runs load them)"
    )
    assert module.double(21) == 42  # compiled, and written beside the source
    assert cached_on_disk(module.double) and compile_note("it", 1, module.double) == ""
    fresh_process = (
        "import fresh_kernels\nfrom illusio.core.kernels import cached_on_disk\n"
        "assert not fresh_kernels.double.signatures\nprint(cached_on_disk(fresh_kernels.double))"
    )
    out = subprocess.run(
        [sys.executable, "-c", fresh_process], cwd=tmp_path, capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "True"  # a later run finds it on disk: nothing to announce


def test_importing_illusio_lets_openmps_idle_workers_sleep_unless_the_user_chose():
    """numba's parallel kernels run on GNU OpenMP, whose idle workers spin between kernels on the
    cores Embree's ray threads need next: importing illusio sets OMP_WAIT_POLICY=PASSIVE (read when
    numba first loads OpenMP), and keeps a value the user set."""
    check = "import os, illusio.radiosity\nprint(os.environ.get('OMP_WAIT_POLICY'))"
    env = {key: value for key, value in os.environ.items() if key != "OMP_WAIT_POLICY"}
    unset = subprocess.run([sys.executable, "-c", check], env=env, capture_output=True, text=True, check=True)
    chosen = subprocess.run(
        [sys.executable, "-c", check],
        env={**env, "OMP_WAIT_POLICY": "ACTIVE"},
        capture_output=True,
        text=True,
        check=True,
    )
    assert (unset.stdout.strip(), chosen.stdout.strip()) == ("PASSIVE", "ACTIVE")
