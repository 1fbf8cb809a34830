"""illusio: perception-driven rendering on one headless OpenGL core.

Quick start::

    from illusio.core import Context, Frame, write_image
    from illusio.scene import load_scene
    from illusio.passes import SceneRenderer
    renderer = SceneRenderer(Context())          # every technique's renderer works the same way
    renderer.prepare(load_scene("living-room"))
    write_image("living-room.png", renderer.render(Frame(size=(960, 600))))

In a notebook, ``illusio.show(image, ...)`` draws images inline::

    import illusio, trimesh
    from illusio.lines import line_drawing
    illusio.show(line_drawing(trimesh.creation.icosphere(3), size=(256, 256)))
"""

import os as _os

__version__ = "0.1.0"

# numba's parallel kernels run on GNU OpenMP, whose idle workers spin by default; they take turns
# on the same cores with Embree's ray threads, and the spinning cost a radiosity build 7–17 % of
# its time and a fifth to a third of its CPU (benchmarks/RESULTS.md, mgf_scenes). OpenMP reads this when
# numba first loads it, after this import; a value the user set is kept.
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


def show(*images, gap: int = 8):
    """Images (linear float, row 0 on top) drawn inline in a notebook, side by side
    (:func:`illusio.core.show.show`)."""
    from .core.show import show as _show

    return _show(*images, gap=gap)


__all__ = ["show", "__version__"]
