"""The image-based rendering technique (Porquet 2005): novel views from reference views with depth."""

from __future__ import annotations

from pathlib import Path

from ..core.technique import Technique

#: references a built-in scene is captured with when no folder is given
CAPTURED_VIEWS = 3


def reference_subject(source: str, size: tuple[int, int], ctx):
    """A folder of reference views (``illusio ibr capture`` writes one), or CAPTURED_VIEWS views of
    the scene ``source`` along its main camera's right, captured at ``size``."""
    from ..scene.sources import resolve_scene
    from .reference_views import capture, load_references, orbit_views

    if Path(source).is_dir():
        return load_references(source)
    scene = resolve_scene(source)
    return capture(scene, orbit_views(scene, CAPTURED_VIEWS), size, ctx)


TECHNIQUES = (
    Technique(
        name="ibr",
        title="Image-based rendering from reference views with depth (Porquet 2005)",
        renderer="illusio.ibr.renderer:IbrRenderer",
        params="illusio.ibr.params:IbrParams",
        subject="illusio.ibr.technique:reference_subject",
        source_kind="scene or reference folder",
        default_source="office",
        presets=("reconstruction", "sources", "ground-truth"),
        viewer_mode="illusio.viewer.modes.ibr:IbrMode",
        commands=("ibr=illusio.cli.ibr:app",),
        showcase="illusio.gallery.ibr:ibr_showcase",
        benchmarks=("ibr",),
    ),
)
