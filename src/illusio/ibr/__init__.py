"""Image-based rendering from reference views with per-pixel view selection (Porquet 2005, 4.2).

refs = capture(scene, orbit_views(scene, 3), (512, 384), ctx)    # or load_references(folder)
renderer = IbrRenderer(ctx)
renderer.prepare(refs)
image = renderer.render(Frame(view, (512, 384)), IbrParams(show_sources=True))
"""

from ..core.lazy import lazy_exports

_EXPORTS = {
    "TECHNIQUES": "technique",
    **dict.fromkeys(("IbrRenderer", "render_views", "source_view"), "renderer"),
    **dict.fromkeys(("IbrParams", "DISTANCES", "SELECTIONS"), "params"),
    **dict.fromkeys(
        (
            "ReferenceView",
            "ReferenceSet",
            "capture",
            "save_references",
            "load_references",
            "load_cameras",
            "orbit_views",
        ),
        "reference_views",
    ),
}

__all__ = list(_EXPORTS)

__getattr__ = lazy_exports(__name__, _EXPORTS)
