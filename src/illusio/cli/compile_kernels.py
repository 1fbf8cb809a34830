"""illusio compile: numba's kernels compiled into their disk cache once, so that the first render
after an install costs what its work costs (scripts/setup.sh runs it after installing)."""

from __future__ import annotations

import time

import typer


def _curvature() -> None:
    from ..lines import estimate_curvature, line_drawing
    from ..scene import shape

    blob = shape("blob")
    estimate_curvature(blob, cache=False)  # the jet fits, the tensor averaging, the derivatives
    line_drawing(blob, size=(64, 64))  # object-space lines, the fragment filter, the page


def _radiosity() -> None:
    import numpy as np

    from ..radiosity import HierarchyParams, Radiosity, radiosity_image, scene_polygons
    from ..scene import builtin_scene

    box = builtin_scene("cornell-box")
    radiosity_image(box, (32, 32))  # form factors, rays, clusters, solve, display
    # the office: clusters' links and textures' means, which the box does not reach, and the edits'
    # own kernels (a moved object's shafts and relinking): the first move of a benchmark compiled
    # them, 1.9 s against 0.1 s warm
    solution = Radiosity(scene_polygons(builtin_scene("office")), HierarchyParams(epsilon=3e-4)).build()
    solution.set_lamps({"lamp-0": 0.5})
    move = np.eye(4)
    move[:3, 3] = (0.05, 0.0, 0.0)
    solution.move_object("chair-seat", move)


def _stereograms() -> None:
    import numpy as np

    from ..sis import StereogramParams, stereogram_cpu
    from ..sis.video import StereogramSequence

    depth = np.random.default_rng(0).random((32, 96)).astype(np.float32)
    params = StereogramParams(strip_width=20, depth_factor=10)
    stereogram_cpu(depth, params)  # the CPU reference's chains
    sequence = StereogramSequence(params)
    sequence.frame(depth)
    sequence.frame(depth[:, ::-1].copy())  # a held frame: the roots and the vote


#: what runs, by name: each step calls the kernels a first command would compile
STEPS = {"curvature and line drawings": _curvature, "radiosity": _radiosity, "stereograms": _stereograms}


def compile_kernels() -> None:
    """Compile numba's kernels into their disk cache (beside the installed package, or under
    NUMBA_CACHE_DIR) by running each technique's CPU work once at a small size: later processes
    load them in milliseconds. About 45 s on 2 cores; a few when they are cached."""
    from ..core.progress import phase

    for name, step in STEPS.items():
        start = time.perf_counter()
        with phase(f"compile: {name}"):
            step()
        typer.echo(f"{name}: {time.perf_counter() - start:.1f} s")
