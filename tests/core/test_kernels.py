"""core.kernels: a first run says it is compiling numba's kernels, a later one says nothing."""

import importlib
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
